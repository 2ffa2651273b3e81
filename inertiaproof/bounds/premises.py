"""Premises of Section 4.1's results that fail on a chain or a parameter trajectory, shown by an exact witness.

A theorem whose hypothesis fails is not refuted by the scene: it claims nothing there. The suite says so only where
the failure is certified, so a failed premise is never guessed from floating point:

- QJ normal (Definition 2, definition:NormalJacobian). By the chain rule through the coordinate maps
  (Kinematics), QJ(q) = QJ_theta(g(q)) diag(g'(q)): where a map's derivative vanishes, g_k'(q_k) = 0 evaluated in
  exact rational arithmetic at a rational q_k of the coordinate's range, column k of QJ vanishes for every q with
  that q_k, so lambda_min((QJ)^T QJ) = 0 there and inf_q lambda_min((QJ)^T QJ) = 0 (the first counterexample,
  CX-normal: theta_1 = q_1^3).
- uniformly physically consistent and upper bounded (Definition 3, definition:PropertiesInertialParameters). With
  at most one payload or scaling on a body, Phi_l(t) runs monotonically along the segment Theta_base + s Phi_load
  (every profile is monotone), so the ends of the segment are attained at the ends of the span or approached as
  t -> inf (s there is the profile's value in floating point: exact for the ramps' 0 and 1 and for the limits of
  exp). Where f(Phi_l) at an end is not positive definite (Sylvester's leading minors of the rational matrix,
  :func:`inertiaproof.model.exact.definiteness`), inf_t lambda_min(f(Phi_l(t))) <= 0 (the second counterexample,
  CX-sphere: m(t) = exp(-t/2) -> 0); where s grows without bound on a load whose f has a positive diagonal entry
  (so a positive eigenvalue), sup_t lambda_max(f(Phi_l(t))) = inf.

Each function returns the failures it certifies, ``[]`` when it certifies none (the premise holds, or it cannot be
decided here: the caller's brackets say which).
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np

from inertiaproof.dynamics.trajectory import MovingMass, Payload, Scaling
from inertiaproof.model.exact import definiteness, integer_matrix
from inertiaproof.result import quantity

from .certificate import pseudo_exact

__all__ = ["NORMAL", "UNIFORMLY_CONSISTENT", "UPPER_BOUNDED", "failed_premises", "normality_failures",
           "parameter_failures", "unsimulable"]

NORMAL = "QJ is normal (Definition 2)"
UNIFORMLY_CONSISTENT = "the inertial parameters are uniformly physically consistent (Definition 3)"
UPPER_BOUNDED = "the inertial parameters are upper bounded (Definition 3)"
GRID = 4097  # points of a coordinate's range searched for a zero of its map's derivative
DENOMINATOR = 1000  # a candidate zero is snapped to the nearest rational with at most this denominator


def _exact_zero(derivative, lo, hi):
    """A rational q in [lo, hi] with derivative(q) == 0 exactly (Fractions), or None."""
    grid = np.linspace(lo, hi, GRID)
    with np.errstate(all="ignore"):
        near = float(grid[np.argmin(np.abs(derivative(grid)))])
    q = Fraction(near).limit_denominator(DENOMINATOR)
    if not lo <= q <= hi:
        return None
    try:
        value = derivative(q)
    except TypeError:  # a map that is not rational arithmetic: no exact value here
        return None
    return q if isinstance(value, (int, Fraction)) and value == 0 else None


def normality_failures(chain):
    """Certified failures of Definition 2 on ``chain``: a joint whose coordinate map's derivative vanishes exactly
    at a rational point of its range, with the configuration (that coordinate there, the others mid-range) where
    column k of QJ vanishes; sigma_min(QJ) there in floating point is reported beside it."""
    lo, hi = chain.coordinate_box()
    out = []
    for k, joint in enumerate(chain.joints):
        zero = _exact_zero(joint.coordinate.derivative, float(lo[k]), float(hi[k]))
        if zero is None:
            continue
        q = 0.5 * (lo + hi)
        q[k] = float(zero)
        sigma = float(np.linalg.svd(chain.body_jacobian(q[None])[0], compute_uv=False)[-1])
        out.append({
            "premise": NORMAL,
            "why": (f"joint {k + 1} ({joint.coordinate.name} map): g'(q_{k + 1}) = 0 exactly at q_{k + 1} = {zero}, so "
                    f"column {k + 1} of QJ(q) = QJ_theta(g(q)) diag(g'(q)) vanishes at every q with q_{k + 1} = {zero} "
                    f"and inf_q lambda_min((QJ)^T QJ) = 0"),
            "witness": {"q": q.tolist(), "joint": k + 1,
                        "derivative": quantity(0, "exact", f"g'(q_{k + 1}) at q_{k + 1} = {zero}, rational arithmetic"),
                        "sigma_min_QJ": quantity(sigma, "value", "sigma_min(QJ) at the witness, in floating point")}})
    return out


def _ends(profile, span):
    """[(t, s(t))] at the two ends of the span: a monotone profile's extremes (t = inf: the limit)."""
    t0, t1 = span
    s0 = float(profile.derivatives(t0)[0])
    if np.isfinite(t1):
        return [(t0, s0), (t1, float(profile.derivatives(t1)[0]))]
    if profile.shape == "exp":
        return [(t0, s0), (np.inf, 0.0 if profile.rate < 0 else np.inf if profile.rate > 0 else 1.0)]
    return [(t0, s0), (np.inf, float(profile.derivatives(profile.start + profile.duration)[0]))]


def _exact_row(base, s, load, growing):
    """Phi_l at profile value s, in Fractions: base, s base (scaling) or base + s Phi_load (payload)."""
    s, base = Fraction(s), [Fraction(float(x)) for x in base]
    if load is None:
        return base
    if isinstance(load, Scaling):
        return [s * x for x in base]
    return [b + s * Fraction(float(x)) for b, x in zip(base, growing)]


def _body_failures(trajectory, body, load):
    """Certified failures of Definition 3 on one body with at most one payload or scaling (``load``, or None)."""
    base = np.asarray(trajectory.base[body], float)
    ends = _ends(load.profile, trajectory.span) if load is not None else [(trajectory.span[0], 1.0)]
    growing = base if isinstance(load, Scaling) else None if load is None else np.asarray(load.phi, float)
    out = []
    for t, s in ends:
        when = ("as t -> inf" if np.isinf(t) else f"at t = {t:g}") + (" the profile reaches" if load else " (no load)")
        if np.isinf(s):
            f = pseudo_exact(growing)
            if any(f[i][i] > 0 for i in range(4)):
                out.append({"premise": UPPER_BOUNDED, "why": (
                    f"body {body + 1}: the load's profile s(t) grows without bound {when} and f of what it scales has "
                    f"a positive diagonal entry, so sup_t lambda_max(f(Phi_{body + 1}(t))) = inf"),
                    "witness": {"body": body + 1, "time": "inf", "s": "inf"}})
            continue
        phi = _exact_row(base, s, load, growing)
        kind, rank = definiteness(integer_matrix(pseudo_exact(phi)))
        if kind != "pd":
            out.append({"premise": UNIFORMLY_CONSISTENT, "why": (
                f"body {body + 1}: {when} s = {s:g}, where f(Phi_{body + 1}) is {kind} "
                f"(rank {rank}; Sylvester's minors in rational arithmetic), so inf_t lambda_min(f(Phi_{body + 1}(t))) "
                f"<= 0"),
                "witness": {"body": body + 1, "time": "inf" if np.isinf(t) else t, "s": s,
                            "phi": [float(x) for x in phi],
                            "f_definiteness": kind}})
    return out


def parameter_failures(trajectory):
    """Certified failures of Definition 3 on ``trajectory``, body by body (bodies with a moving mass or with two
    loads are left undecided here)."""
    out = []
    for body in range(trajectory.bodies):
        loads = [load for load in trajectory.loads if load.body == body]
        if len(loads) > 1 or any(isinstance(load, MovingMass) for load in loads):
            continue
        if loads and not isinstance(loads[0], (Payload, Scaling)):
            continue
        out += _body_failures(trajectory, body, loads[0] if loads else None)
    return out


def failed_premises(scene):
    """Certified failures of the premises of Corollary 1 (corollary:UniformBounds) on ``scene``: normality of QJ,
    uniform physical consistency and upper boundedness of the parameters."""
    return normality_failures(scene.chain) + parameter_failures(scene.trajectory)


def unsimulable(chain):
    """(failures, reason) where M(q) is certified singular at a configuration of ``chain`` (:func:`normality_failures`:
    a column of QJ vanishes, and with it M(q) = QJ^T M_theta QJ's), else None. Forward dynamics, which every simulated
    run integrates, is undefined there, so a simulation study that did not finish claims nothing on such a chain."""
    failed = normality_failures(chain)
    if not failed:
        return None
    return failed, ("premise fails: " + "; ".join(f["why"] for f in failed) + ": M(q) is singular there, so forward "
                    "dynamics, which every run integrates, is undefined at that configuration and the study claims "
                    "nothing on this scene")
