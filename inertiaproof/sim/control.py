"""Controllers of the chain: tau(t, q, qd) tracking a reference motion with nominal parameters.

:class:`Controller` is what a scene's ``[control]`` table describes; :class:`FeedforwardPD`
is the same law with its feedforward computed once per time grid, the same known input for
every model of the equation (GRE-physics, loading).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from inertiaproof.dynamics import motion, terms
from inertiaproof.dynamics.twists import chunks
from inertiaproof.scene.format import ControlSettings

__all__ = ["Controller", "FEEDFORWARD_CHUNK", "FeedforwardPD", "controller", "reference_motion"]

FEEDFORWARD_CHUNK = 64  # times per batch of the feedforward's kinematics


def reference_motion(home, amplitude, frequency, t):
    """(q_ref, qd_ref, qdd_ref) with q_ref(t) = home + amplitude sin(2 pi frequency t + k pi / 3) on joint k.

    Batched: ``home`` (..., n), ``amplitude`` and ``frequency`` scalars or (...), times ``t`` scalar or (...)."""
    t = np.asarray(t, dtype=float)[..., None]
    w = 2 * np.pi * np.asarray(frequency, dtype=float)[..., None]
    a = np.asarray(amplitude, dtype=float)[..., None]
    arg = w * t + np.arange(np.shape(home)[-1]) * np.pi / 3
    return home + a * np.sin(arg), a * w * np.cos(arg), -a * w * w * np.sin(arg)


@dataclass(frozen=True)
class Controller:
    """tau(t, q, qd) tracking q_ref(t) = home + amplitude sin(2 pi frequency t + k pi / 3) on joint k.

    ``pd``: tau = G(q, Theta_nom) + Kp e + Kd e'; ``computed_torque``: tau = M(q, Theta_nom)(qdd_ref + Kd e' + Kp e)
    + C(q, qd, Theta_nom) qd + G(q, Theta_nom); ``none``: tau = 0. Theta_nom are the scene's parameters at its start,
    so loads the controller does not know about disturb the tracking.
    """

    kind: str
    kp: np.ndarray
    kd: np.ndarray
    home: np.ndarray
    amplitude: float
    frequency: float
    nominal: np.ndarray  # (N, 10)

    KINDS = ("pd", "computed_torque", "none")

    def reference(self, t):
        return reference_motion(self.home, self.amplitude, self.frequency, t)

    def gain_matrices(self, chain):
        """(Kp, Kd) as matrices, frozen at the home posture: diagonal for PD, M_nom(home) diag(k) for computed
        torque, zero for none."""
        if self.kind == "computed_torque":
            m_home = terms.mass_matrix(chain.body_jacobian(self.home), self.nominal)
            return m_home * self.kp, m_home * self.kd
        if self.kind == "pd":
            return np.diag(self.kp), np.diag(self.kd)
        return np.zeros((chain.n, chain.n)), np.zeros((chain.n, chain.n))

    def torque(self, kin, gravity, t, q, qd):
        if self.kind == "none":
            return np.zeros_like(q)
        q_ref, qd_ref, qdd_ref = self.reference(t)
        e, e_dot = q_ref - q, qd_ref - qd
        g_nom = terms.gravity(kin.qj, kin.rotations, self.nominal, gravity)
        if self.kind == "pd":
            return g_nom + self.kp * e + self.kd * e_dot
        m_nom = terms.mass_matrix(kin.qj, self.nominal)
        command = qdd_ref + self.kd * e_dot + self.kp * e
        return (m_nom @ command[..., None])[..., 0] + terms.coriolis_force(kin.qj, kin.dqj, self.nominal, qd) + g_nom


def controller(chain, trajectory, settings=None):
    """The controller a scene's [control] table describes (:class:`inertiaproof.scene.ControlSettings`).

    Bandwidth w rad/s: Kp = w^2 m, Kd = 2 zeta w m with m the diagonal of M(home, Theta_nom) (``per_joint``)
    or its largest entry for every joint (``uniform``: tuned for the heaviest joint, which makes light joints
    stiff). Computed torque uses unit-mass gains. The default home is the middle of the coordinate box.
    """
    s = settings or ControlSettings()
    if s.kind not in Controller.KINDS:
        raise ValueError(f"controller kind must be one of {Controller.KINDS}, not {s.kind!r}")
    lo, hi = chain.coordinate_box()
    home = (lo + hi) / 2 if s.home is None else np.asarray(s.home, dtype=float)
    nominal, _ = trajectory.theta(np.array(trajectory.span[0]))
    if s.kind == "computed_torque":
        scale = np.ones(chain.n)
    else:
        diagonal = np.diagonal(terms.mass_matrix(chain.body_jacobian(home), nominal)).copy()
        scale = np.full(chain.n, diagonal.max()) if s.gains == "uniform" else diagonal
    w = s.bandwidth
    return Controller(s.kind, w**2 * scale, 2 * s.damping * w * scale, home, float(s.amplitude),
                      float(s.frequency), nominal)


class FeedforwardPD:
    """tau = tau_ff(t) + Kp (q_ref - q) + Kd (qd_ref - qd) with constant gain matrices: the same known input for
    every model. A PD law keeps its diagonal gains and gravity feedforward G(q_ref(t), Theta_nom); computed torque
    is frozen at its home posture, Kp = M_nom(home) diag(kp) (likewise Kd), with feedforward
    M_nom(q_ref) qdd_ref + C_nom(q_ref, qd_ref) qd_ref + G_nom(q_ref)."""

    def __init__(self, chain, control: Controller):
        self.chain, self.control = chain, control
        self.kp, self.kd = control.gain_matrices(chain)

    def feedforward(self, times):
        """tau_ff at ``times`` (any shape), in chunks of FEEDFORWARD_CHUNK times: dQJ/dq of a 24-link chain takes
        0.7 MB per time, so a whole RK4 grid at once took gigabytes."""
        q_ref, qd_ref, qdd_ref = self.control.reference(times)
        if self.control.kind == "none":
            return np.zeros_like(q_ref)
        nominal = motion.Parameters(self.control.nominal, np.zeros_like(self.control.nominal),
                                    np.zeros(self.chain.n * 6), np.zeros(self.chain.n * 6))
        acceleration = qdd_ref if self.control.kind == "computed_torque" else np.zeros_like(q_ref)
        velocity = qd_ref if self.control.kind == "computed_torque" else np.zeros_like(q_ref)
        shape, n = q_ref.shape, self.chain.n
        q_ref, velocity, acceleration = (x.reshape(-1, n) for x in (q_ref, velocity, acceleration))
        out = np.empty_like(q_ref)
        for part in chunks(len(q_ref), FEEDFORWARD_CHUNK):
            kin = motion.kinematics(self.chain, q_ref[part])
            out[part] = motion.generalized_forces(kin, self.chain.gravity, nominal, velocity[part], acceleration[part])
        return out.reshape(shape)

    def torque(self, feedforward, t, q, qd):
        """tau at one time t for states q, qd of shape (n,) or (m, n)."""
        q_ref, qd_ref, _ = self.control.reference(t)
        return feedforward + (q_ref - q) @ self.kp.T + (qd_ref - qd) @ self.kd.T
