"""Judging a bound of Section 4: pointwise inequalities, verdicts from brackets, evidence, replayable points.

Each bound has a pointwise form that its proof establishes at every (q, t),
e.g. Theorem 3's lambda_max(M(q, Theta)) <= k max_l lambda_max(f(Phi_l)) sigma_max(QJ(q))^2
with k = 2. ``POINTWISE[id](chain, q, state, k)`` returns (lhs, rhs) batched
over configurations; ``state`` holds Theta, Thetadot, Psi, Psidot at one time.
"""

from __future__ import annotations

import numpy as np

from .chain import Chain, Coordinate, Joint
from .dynamics import lumped_acceleration_force, lumped_velocity_matrix, mass_matrix
from .inertia import pseudo_inertia
from .result import Verdict, quantity

RESOLUTION = 1e-9  # relative: margins below this fraction of the compared sizes are not resolved


def _svd(a):
    return np.linalg.svd(a, compute_uv=False)


def _eig(f):
    return np.linalg.eigvalsh(f)


def thm2_pointwise(chain, q, state, k):
    """(LowerBoundedness) at q: lambda_min(M) >= k min_l lambda_min(f(Phi_l)) sigma_min(QJ)^2 (lower-bound form)."""
    qj = chain.body_jacobian(q)
    lhs = _eig(mass_matrix(qj, state["theta"]))[..., 0]
    rhs = k * _eig(pseudo_inertia(state["theta"]))[..., 0].min(-1) * _svd(qj)[..., -1] ** 2
    return lhs, rhs


def thm3_pointwise(chain, q, state, k):
    """(UpperBoundedness) at q: lambda_max(M) <= k max_l lambda_max(f(Phi_l)) sigma_max(QJ)^2."""
    qj = chain.body_jacobian(q)
    lhs = _eig(mass_matrix(qj, state["theta"]))[..., -1]
    rhs = k * _eig(pseudo_inertia(state["theta"]))[..., -1].max(-1) * _svd(qj)[..., 0] ** 2
    return lhs, rhs


def thm4_pointwise(chain, q, state, k):
    """(BoundedEffectofVaryingParam) at q: sigma_max(M(q, Thetadot)) <= k max_l sigma_max(f(Phidot_l)) sigma_max(QJ)^2."""
    qj = chain.body_jacobian(q)
    lhs = np.abs(_eig(mass_matrix(qj, state["theta_dot"]))).max(-1)
    rhs = k * np.abs(_eig(pseudo_inertia(state["theta_dot"]))).max(-1).max(-1) * _svd(qj)[..., 0] ** 2
    return lhs, rhs


def acc_pointwise(chain, q, state, k):
    """(LumpedAccelerationBounding) at q: ||J^T Q^T Psidot|| <= k ||Psidot|| sigma_max(QJ)."""
    qj = chain.body_jacobian(q)
    lhs = np.linalg.norm(lumped_acceleration_force(qj, state["psi_dot"]), axis=-1)
    rhs = k * np.linalg.norm(state["psi_dot"], axis=-1) * _svd(qj)[..., 0]
    return lhs, rhs


def thm5_pointwise(chain, q, state, k):
    """(BoundedEffectOfLumpedVel) at q: sigma_max(H(q, Psi)) <= k ||Psi|| max_p sigma_max(Y_p(q))."""
    dqj = chain.body_jacobian_derivative(q)
    lhs = _svd(lumped_velocity_matrix(dqj, state["psi"]))[..., 0]
    y = dqj - np.swapaxes(dqj, -1, -2)
    rhs = k * np.linalg.norm(state["psi"], axis=-1) * _svd(y)[..., 0].max(-1)
    return lhs, rhs


POINTWISE = {  # id: (function, sense of the bound: "upper" means lhs <= rhs)
    "Thm2": (thm2_pointwise, "lower"),
    "Thm3": (thm3_pointwise, "upper"),
    "Thm4": (thm4_pointwise, "upper"),
    "EQ-acc": (acc_pointwise, "upper"),
    "Asm3/Thm5": (thm5_pointwise, "upper"),
}


def pointwise_margin(check_id, chain, q, state, k):
    """Relative slack of the pointwise inequality at every configuration: (slack, lhs, rhs); slack < 0 is a violation."""
    fn, sense = POINTWISE[check_id]
    lhs, rhs = fn(chain, q, state, k)
    scale = np.maximum(np.abs(lhs) + np.abs(rhs), np.finfo(float).tiny)
    slack = (rhs - lhs) / scale if sense == "upper" else (lhs - rhs) / scale
    return slack, lhs, rhs


def state_at(trajectory, t):
    """Theta, Thetadot, Psi, Psidot of a trajectory at times t (leading shape of t)."""
    theta, theta_dot = trajectory.theta(t)
    psi, psi_dot = trajectory.psi(t)
    return {"theta": theta, "theta_dot": theta_dot, "psi": psi, "psi_dot": psi_dot}


def judge(sense, lhs, constant_lower, constant_upper, *, proof_covers, pointwise_slack):
    """Verdict of 'extreme of the left-hand side <= (upper) / >= (lower) constant' from brackets.

    ``lhs`` is a Bracket of the true extreme; the constant lies in
    [constant_lower, constant_upper] (its ingredients are bracketed too).
    VIOLATED: the observed (attained) value lies beyond every value the constant
    can have. HOLDS: the certified side lies within every value it can have, or
    the constant is covered by the certified proof (key step certified for all
    Phi) and the pointwise inequality held at every sample. Otherwise INCONCLUSIVE.
    """
    scale = abs(lhs.observed) + abs(constant_upper if np.isfinite(constant_upper) else constant_lower)
    tol = RESOLUTION * scale
    if sense == "upper":
        if lhs.observed > constant_upper + tol:
            return Verdict.VIOLATED, "the observed value exceeds the largest value the constant can have"
        if lhs.upper < constant_lower - tol:
            return Verdict.HOLDS, "the certified upper side of the extreme is below the constant"
    else:
        if lhs.observed < constant_lower - tol:
            return Verdict.VIOLATED, "the observed value lies below the smallest value the constant can have"
        if lhs.lower > constant_upper + tol:
            return Verdict.HOLDS, "the certified lower side of the extreme is above the constant"
    if pointwise_slack < -RESOLUTION:
        return Verdict.VIOLATED, "the pointwise inequality of the proof fails at a sampled configuration"
    if proof_covers:
        return Verdict.HOLDS, ("the certified proof covers this constant (key step certified for all Phi) and its "
                               "pointwise inequality held at every sample")
    return Verdict.INCONCLUSIVE, "the brackets of the extreme and of the constant overlap"


def constants_evidence(paper, certified, certified_how, observed, observed_note, paper_note):
    """The ``constants`` evidence the report plots."""
    return {"paper": quantity(paper, "paper_constant", paper_note),
            "certified": quantity(certified, "certified_constant", certified_how),
            "observed": quantity(observed, "sampled", observed_note)}


# -- chains as plain data (counterexample files) --------------------------------------------

def chain_to_data(chain):
    return {"name": chain.name, "gravity": list(chain.gravity), "joints": [
        {"kind": j.kind, "axis": list(j.axis), "before": np.asarray(j.before).tolist(),
         "after": np.asarray(j.after).tolist(), "coordinate": j.coordinate.name,
         "limits": None if j.limits is None else list(j.limits), "name": j.name} for j in chain.joints]}


def chain_from_data(data):
    return Chain(tuple(Joint(j["kind"], tuple(j["axis"]), np.array(j["before"]), np.array(j["after"]),
                             Coordinate(j["coordinate"]), None if j["limits"] is None else tuple(j["limits"]), j["name"])
                       for j in data["joints"]), name=data["name"], gravity=tuple(data["gravity"]))


def point_counterexample(check_id, chain, q, state, k, slack, lhs, rhs):
    """A replayable counterexample: the chain, the configuration, the parameters at that time and the factor."""
    return {"kind": "bound-point", "data": {
        "id": check_id, "chain": chain_to_data(chain), "q": np.asarray(q).tolist(), "factor": float(k),
        "state": {key: np.asarray(v).tolist() for key, v in state.items()},
        "slack": float(slack), "lhs": float(lhs), "rhs": float(rhs)}}


def replay_point(data):
    """(slack, lhs, rhs) of a saved bound-point counterexample recomputed with the current code."""
    chain = chain_from_data(data["chain"])
    state = {key: np.asarray(v, float) for key, v in data["state"].items()}
    slack, lhs, rhs = pointwise_margin(data["id"], chain, np.asarray(data["q"], float)[None],
                                       {key: v[None] for key, v in state.items()}, data["factor"])
    return float(slack[0]), float(lhs[0]), float(rhs[0])
