"""Internal motion: (RoboticEquation) against an independent multibody engine (GRE-physics).

Along a prescribed motion q(t) of the chain, while each moving mass follows
its path:

- the generalized equation's torques use Theta, Thetadot, Psi, Psidot of the
  carrying body integrated from the moving body's density as Section 3
  defines them (:func:`inertiaproof.dynamics.motion.parameters_from_density`), and a
  second time from the closed forms of :class:`~inertiaproof.trajectory.MovingMass`;
- Pinocchio's RNEA gives the torques of the augmented model in which the
  moving mass is a rigid body on its own prismatic joints, driven along the
  same path (:mod:`inertiaproof.sim.multibody`).

The two must agree to round-off. The resolution is measured, not assumed:
both sides are recomputed in rescaled units of length
(:mod:`inertiaproof.sim.similarity`) and the spread of the results is their
round-off.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from inertiaproof.dynamics import motion
from inertiaproof.result import Verdict

from . import multibody, similarity

__all__ = ["cross_check", "CrossCheck", "EPS", "FLOOR", "SAFETY", "smooth_motion", "VIOLATION_RATIO"]

EPS = np.finfo(float).eps
SAFETY = 4.0  # resolution = SAFETY x measured spread + FLOOR eps of the scale
FLOOR = 32.0
VIOLATION_RATIO = 100.0  # residual above this many resolutions is a violation; between 1 and this, inconclusive


def smooth_motion(chain, times, rng):
    """q(t) = centre + amplitude sin(w t + phase) per coordinate inside the coordinate box, with qd and qdd."""
    lo, hi = chain.coordinate_box()
    centre = (lo + hi) / 2 + (hi - lo) * rng.uniform(-0.15, 0.15, chain.n)
    amplitude = (hi - lo) * rng.uniform(0.1, 0.3, chain.n)
    span = max(float(times[-1] - times[0]), 1e-9)
    w = 2 * np.pi * rng.uniform(0.5, 2.0, chain.n) / span
    phase = rng.uniform(0, 2 * np.pi, chain.n)
    arg = w * times[:, None] + phase
    return centre + amplitude * np.sin(arg), amplitude * w * np.cos(arg), -amplitude * w * w * np.sin(arg)


@dataclass
class CrossCheck:
    times: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    equation: np.ndarray  # (S, n) tau of (RoboticEquation), parameters integrated from the density
    closed_form: np.ndarray  # (S, n) the same with trajectory.MovingMass's closed forms
    engine: np.ndarray  # (S, n) Pinocchio's RNEA of the augmented model
    scale: np.ndarray  # (S, n) sum of |terms of the equation| and |engine torque|
    resolution: np.ndarray  # (S, n) round-off of the comparison
    spread_note: str

    def ratio(self, which="equation"):
        return np.abs(getattr(self, which) - self.engine) / self.resolution

    def relative_error(self, which="equation"):
        return np.abs(getattr(self, which) - self.engine) / self.scale

    def verdict(self):
        worst = max(self.ratio("equation").max(), self.ratio("closed_form").max())
        if worst <= 1.0:
            return Verdict.HOLDS
        return Verdict.VIOLATED if worst > VIOLATION_RATIO else Verdict.INCONCLUSIVE


def _equation(chain, trajectory, times, q, qd, qdd, forces, from_density=True):
    p = (motion.parameters_from_density if from_density else motion.parameters)(trajectory, times)
    return forces(motion.kinematics(chain, q), chain.gravity, p, qd, qdd)


def cross_check(chain, trajectory, times, q, qd, qdd, forces=motion.generalized_forces,
                factors=similarity.FACTORS):
    """Both sides along the motion, with the resolution from their spread over rescaled units."""
    kin = motion.kinematics(chain, q)
    terms = motion.equation_terms(kin, chain.gravity, motion.parameters_from_density(trajectory, times), qd, qdd)
    engine = multibody.inverse_dynamics(chain, trajectory, times, q, qd, qdd)
    scale = sum(np.abs(t) for t in terms.values()) + np.abs(engine)
    scale = np.where(scale > 0, scale, np.finfo(float).tiny)
    try:
        spread = _rescaled_spread(chain, trajectory, times, q, qd, qdd, forces, factors, scale)
        note = f"spread of both engines over lengths rescaled by {list(factors)}"
    except ValueError as exc:
        spread, note = np.zeros(chain.n), f"no rescaled spread ({exc}); resolution is the floor only"
    resolution = scale * (SAFETY * spread + FLOOR * EPS)
    return CrossCheck(times, q, qd, qdd, _equation(chain, trajectory, times, q, qd, qdd, forces),
                      _equation(chain, trajectory, times, q, qd, qdd, forces, from_density=False),
                      engine, scale, resolution, note)


def _rescaled_spread(chain, trajectory, times, q, qd, qdd, forces, factors, scale):
    """Per joint: max over samples of (spread of ours + spread of Pinocchio) / scale across rescaled units."""
    ours, theirs = [], []
    for factor in factors:
        c = similarity.rescaled_chain(chain, factor)
        tr = similarity.rescaled_trajectory(trajectory, factor)
        k = similarity.coordinate_factors(chain, factor)
        back = similarity.force_factors(chain, factor)
        ours.append(_equation(c, tr, times, q * k, qd * k, qdd * k, forces) / back)
        theirs.append(multibody.inverse_dynamics(c, tr, times, q * k, qd * k, qdd * k) / back)
    ours, theirs = np.array(ours), np.array(theirs)
    spread = (np.ptp(ours, axis=0) + np.ptp(theirs, axis=0)) / scale
    return spread.max(axis=0)
