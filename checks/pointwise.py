"""The pointwise form of each Section 4 bound: margins at sampled (q, t), replayable points, and hunts.

Each bound's proof establishes an inequality at every (q, t), e.g. Theorem 3's
lambda_max(M(q, Theta(t))) <= k max_l lambda_max(f(Phi_l(t))) sigma_max(QJ(q))^2
with k = 2. ``POINTWISE[id](chain, q, state, k)`` returns (lhs, rhs, size)
batched over configurations, where ``state`` holds Theta, Thetadot, Psi,
Psidot at the sample times and ``size`` is the magnitude of the matrices
whose spectra gave lhs and rhs. A point violates the bound when its margin
(rhs - lhs) / (|lhs| + |rhs|) (sign flipped for a lower bound) is below
minus its resolution RESOLUTION + ROUNDING eps size / (|lhs| + |rhs|): what
rounding of the eigen- and singular values can do there.

Hunts draw random chains, consistent inertias near-degenerate to ordinary and
smooth trajectories (inertiaproof.counterexamples), evaluate the margin at
sampled (q, t) and steer toward the smallest one; a failure is a concrete
(chain, q, Theta(t), ...) saved as a replayable "bound-point" file.
"""

from __future__ import annotations

import numpy as np
from hypothesis import Phase
from hypothesis import strategies as st
from inertiaproof.counterexamples.chains import chains
from inertiaproof.counterexamples.trajectories import trajectories

from inertiaproof.dynamics import composite
from inertiaproof.dynamics.chain import Chain
from inertiaproof.dynamics.terms import lumped_acceleration_force, lumped_velocity_matrix
from inertiaproof.model.inertia import pseudo_inertia
from inertiaproof.result import Result, Verdict, quantity
from inertiaproof.suite.hunt import hunt
from inertiaproof.suite.registry import replayer

__all__ = [
    "acc_pointwise", "EPS", "hunt_cases", "hunt_samples", "HUNT_SHARE", "margins", "NO_SHRINK",
    "point_counterexample", "POINTS", "POINTWISE", "replay_bound_point", "replay_point", "RESOLUTION", "ROUNDING",
    "run_hunt", "state_at", "thm2_pointwise", "thm3_pointwise", "thm4_pointwise", "thm5_pointwise", "with_hunt",
    "worst_point",
]

RESOLUTION = 1e-9  # relative: a margin must exceed this fraction of |lhs| + |rhs| to count
ROUNDING = 64.0  # rounding of a computed eigen- or singular value, in units of eps times the matrix's size
EPS = np.finfo(float).eps
POINTS = 32  # (q, t) pairs per hunted example
HUNT_SHARE = 3  # a hunt draws profile.examples // HUNT_SHARE chains (20 in ci, 666 in deep): drawing dominates its cost
NO_SHRINK = (Phase.explicit, Phase.reuse, Phase.generate, Phase.target)  # a found point is concrete as it is;
# shrinking dozens of floats took minutes


def _svd(a):
    return np.linalg.svd(a, compute_uv=False)


def _eig(a):
    return np.linalg.eigvalsh(a)


def thm2_pointwise(chain, q, state, k):
    """(LowerBoundedness) at q: lambda_min(M) >= k min_l lambda_min(f(Phi_l)) sigma_min(QJ)^2."""
    s = _svd(chain.body_jacobian(q))
    w = _eig(composite.mass_matrix(chain, q, state["theta"]))
    f = _eig(pseudo_inertia(state["theta"]))
    rhs = k * f[..., 0].min(-1) * s[..., -1] ** 2
    return w[..., 0], rhs, np.abs(w).max(-1) + k * np.abs(f).max((-2, -1)) * s[..., 0] ** 2


def thm3_pointwise(chain, q, state, k):
    """(UpperBoundedness) at q: lambda_max(M) <= k max_l lambda_max(f(Phi_l)) sigma_max(QJ)^2."""
    s = _svd(chain.body_jacobian(q))
    w = _eig(composite.mass_matrix(chain, q, state["theta"]))
    rhs = k * _eig(pseudo_inertia(state["theta"]))[..., -1].max(-1) * s[..., 0] ** 2
    return w[..., -1], rhs, np.abs(w).max(-1) + np.abs(rhs)


def thm4_pointwise(chain, q, state, k):
    """(BoundedEffectofVaryingParam) at q: sigma_max(M(q, Thetadot)) <= k max_l sigma_max(f(Phidot_l)) sigma_max(QJ)^2."""
    s = _svd(chain.body_jacobian(q))
    lhs = np.abs(_eig(composite.mass_matrix(chain, q, state["theta_dot"]))).max(-1)
    rhs = k * np.abs(_eig(pseudo_inertia(state["theta_dot"]))).max((-2, -1)) * s[..., 0] ** 2
    return lhs, rhs, lhs + np.abs(rhs)


def acc_pointwise(chain, q, state, k):
    """(LumpedAccelerationBounding) at q: ||J^T Q^T Psidot|| <= k ||Psidot|| sigma_max(QJ)."""
    qj = chain.body_jacobian(q)
    lhs = np.linalg.norm(lumped_acceleration_force(qj, state["psi_dot"]), axis=-1)
    size = np.linalg.norm(state["psi_dot"], axis=-1)
    rhs = k * size * _svd(qj)[..., 0]
    return lhs, rhs, np.linalg.norm(qj, axis=(-2, -1)) * size + np.abs(rhs)


def thm5_pointwise(chain, q, state, k):
    """(BoundedEffectOfLumpedVel) at q: sigma_max(H(q, Psi)) <= k sqrt(6N) ||Psi|| max_p sigma_max(Y_p(q))."""
    dqj = chain.body_jacobian_derivative(q)
    lhs = _svd(lumped_velocity_matrix(dqj, state["psi"]))[..., 0]
    size = np.linalg.norm(state["psi"], axis=-1)
    rhs = k * np.sqrt(dqj.shape[-3]) * size * _svd(dqj - np.swapaxes(dqj, -1, -2))[..., 0].max(-1)
    return lhs, rhs, 2 * np.sqrt((dqj**2).sum((-3, -2, -1))) * size + np.abs(rhs)


POINTWISE = {  # id: (function, sense: "upper" means lhs <= rhs)
    "Thm2": (thm2_pointwise, "lower"),
    "Thm3": (thm3_pointwise, "upper"),
    "Thm4": (thm4_pointwise, "upper"),
    "EQ-acc": (acc_pointwise, "upper"),
    "Asm3/Thm5": (thm5_pointwise, "upper"),
}


def margins(check_id, chain, q, state, k):
    """Relative margin and resolution of the pointwise inequality at every configuration, with lhs and rhs.

    Where both sides vanish (no internal motion at that time, say) there is nothing to compare: margin NaN."""
    fn, sense = POINTWISE[check_id]
    lhs, rhs, size = fn(chain, q, state, k)
    scale = np.abs(lhs) + np.abs(rhs)
    with np.errstate(invalid="ignore", divide="ignore"):
        margin = (rhs - lhs) / scale if sense == "upper" else (lhs - rhs) / scale
        resolution = RESOLUTION + ROUNDING * EPS * size / scale
    return margin, resolution, lhs, rhs


def state_at(trajectory, t):
    """Theta, Thetadot, Psi, Psidot of a trajectory at times t (leading shape of t)."""
    theta, theta_dot = trajectory.theta(t)
    psi, psi_dot = trajectory.psi(t)
    return {"theta": theta, "theta_dot": theta_dot, "psi": psi, "psi_dot": psi_dot}


def worst_point(check_id, chain, q, state, k):
    """The sampled point closest to a resolved violation: (index, margin, resolution, lhs, rhs)."""
    margin, resolution, lhs, rhs = margins(check_id, chain, q, state, k)
    if np.all(np.isnan(margin)):
        return 0, np.nan, np.nan, float(lhs[0]), float(rhs[0])
    i = int(np.nanargmin(margin + resolution))
    return i, float(margin[i]), float(resolution[i]), float(lhs[i]), float(rhs[i])


def point_counterexample(check_id, chain, q, state, k, point):
    """A replayable counterexample: the chain, the configuration, the parameters at that time and the factor."""
    i, margin, resolution, lhs, rhs = point
    return {"kind": "bound-point", "data": {
        "id": check_id, "chain": chain.to_data(), "q": np.asarray(q[i]).tolist(), "factor": float(k),
        "state": {key: np.asarray(v[i]).tolist() for key, v in state.items()},
        "margin": margin, "resolution": resolution, "lhs": lhs, "rhs": rhs}}


def replay_point(data):
    """(margin, resolution, lhs, rhs) of a saved bound-point counterexample recomputed with the current code."""
    chain = Chain.from_data(data["chain"])
    state = {key: np.asarray(v, float)[None] for key, v in data["state"].items()}
    point = worst_point(data["id"], chain, np.asarray(data["q"], float)[None], state, data["factor"])
    return point[1:]


@replayer("bound-point")
def replay_bound_point(data, ctx):
    margin, resolution, lhs, rhs = replay_point(data)
    verdict = Verdict.VIOLATED if margin < -resolution else Verdict.HOLDS
    return Result(data["id"], verdict, f"pointwise inequality with factor {data['factor']:g}: lhs {lhs:.6g}, "
                  f"rhs {rhs:.6g}, relative margin {margin:.3g} (resolution {resolution:.1g})",
                  {"margin": quantity(margin, "margin"), "resolution": quantity(resolution, "tolerance")})


# -- hunts over random chains ------------------------------------------------------------------

@st.composite
def hunt_cases(draw, moving_mass):
    """A random chain, a random trajectory of consistent bodies on it, and a seed for the (q, t) samples."""
    chain, length = draw(chains())
    traj = draw(trajectories(chain.bodies, length, moving_mass=moving_mass))
    return chain, traj, draw(st.integers(0, 2**32 - 1))


def hunt_samples(example, count=POINTS):
    """The (q, t) pairs of a hunted example: uniform in the chain's box, times over the trajectory's span."""
    chain, traj, seed = example
    lo, hi = chain.coordinate_box()
    q = lo + (hi - lo) * np.random.default_rng(seed).random((count, chain.n))
    return q, state_at(traj, traj.times(count))


def run_hunt(check_id, ctx, k, moving_mass, examples=None):
    """Hunt for a chain, configuration and time where the pointwise inequality with factor k fails.

    Returns the ``hunt`` evidence and a replayable counterexample (None when none was found)."""
    def margin(example):
        q, state = hunt_samples(example)
        return worst_point(check_id, example[0], q, state, k)[1:3]

    examples = examples or max(ctx.profile.examples // HUNT_SHARE, 10)
    found = hunt(hunt_cases(moving_mass), margin, ctx, label=f"{check_id} x{k:g}", tolerance=RESOLUTION,
                 max_examples=examples, phases=NO_SHRINK)
    evidence = {**found.summary(), "margins": [float(m) for m in found.margins[:500]],
                "factor": quantity(k, "value", "factor of the pointwise inequality hunted"),
                "what": "random chains (revolute and prismatic, n <= 7, DH and general axes, 1 mm to 30 m), "
                        "consistent bodies near-degenerate to ordinary, smooth payload ramps or moving masses; "
                        f"{POINTS} (q, t) pairs per chain"}
    cx = None
    if found.violation is not None:
        chain = found.violation[0]
        q, state = hunt_samples(found.violation)
        cx = point_counterexample(check_id, chain, q, state, k, worst_point(check_id, chain, q, state, k))
    return evidence, cx


def with_hunt(ctx, result, k, moving_mass, examples=None):
    """Attach a hunt of the pointwise inequality with factor k; a found counterexample makes the result VIOLATED."""
    evidence, cx = run_hunt(result.id, ctx, k, moving_mass, examples)
    result.evidence["hunt"] = evidence
    if cx is not None:
        result.verdict = Verdict.VIOLATED
        data = cx["data"]
        result.summary = (f"a hunted chain breaks the pointwise inequality with factor {k:g}: lhs {data['lhs']:.6g} "
                          f"> rhs {data['rhs']:.6g} at q = {np.round(data['q'], 4).tolist()}; " + result.summary)
        result.counterexample = cx
    return result
