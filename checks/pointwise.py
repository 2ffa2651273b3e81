"""The pointwise form of each Section 4 bound: margins at sampled (q, t), replayable points, and hunts.

Each bound's proof establishes an inequality at every (q, t), e.g. Theorem 3's
lambda_max(M(q, Theta(t))) <= 2 max_l lambda_max(f(Phi_l(t))) sigma_max(QJ(q))^2.
The right-hand sides are the constants the suite computes and reports, evaluated by the very functions that
compute them (inertiaproof.bounds.formulas) with the ingredients at (q, t) in place of their extremes:
``CONSTANTS[id]`` names every constant of a check (the paper's and the sharpest certified ones) and how it
is evaluated from the ingredients ``INGREDIENTS[id](chain, q, state)`` returns. Every formula is monotone in
its ingredients, so the pointwise inequality at every (q, t) gives the bound; a formula made false in general
fails the pointwise inequality at some (q, t) of some chain.

``margins(id, chain, q, state, k)`` compares lhs with k times each constant (k = 1: the constants as the code
computes them); a point violates a constant when its margin (rhs - lhs) / (|lhs| + |rhs|) (sign flipped for a
lower bound) is below minus its resolution RESOLUTION + ROUNDING eps size / (|lhs| + |rhs|): what rounding of
the eigen- and singular values can do there, ``size`` being the magnitude of the matrices whose spectra gave
lhs and the ingredients.

Hunts draw random chains (1 to 8 joints, revolute and prismatic), consistent inertias near-degenerate to
ordinary and smooth trajectories (inertiaproof.counterexamples), evaluate the margin at sampled (q, t) and
steer toward the smallest one; a failure is a concrete (chain, q, Theta(t), ...) saved as a replayable
"bound-point" file naming the constant it breaks, which the replay evaluates with the current code.
"""

from __future__ import annotations

import numpy as np
from hypothesis import Phase
from hypothesis import strategies as st
from inertiaproof.counterexamples.chains import chains
from inertiaproof.counterexamples.trajectories import trajectories

from inertiaproof.bounds import formulas
from inertiaproof.dynamics import composite
from inertiaproof.dynamics.chain import Chain
from inertiaproof.dynamics.terms import lumped_acceleration_force, lumped_velocity_matrix
from inertiaproof.model.inertia import pseudo_inertia, spatial_inertia
from inertiaproof.result import Result, Verdict, quantity
from inertiaproof.suite.hunt import hunt
from inertiaproof.suite.registry import replayer

__all__ = [
    "acc_ingredients", "CONSTANTS", "constant_margins", "EPS", "hunt_cases", "hunt_samples", "HUNT_JOINTS",
    "HUNT_SHARE", "INGREDIENTS", "LEGACY", "margins", "named_margins", "NO_SHRINK", "point_counterexample", "POINTS", "relative_margin",
    "replay_bound_point", "replay_point", "RESOLUTION", "ROUNDING", "run_hunt", "SENSE", "state_at",
    "thm2_ingredients", "thm3_ingredients", "thm4_ingredients", "thm5_ingredients", "with_hunt", "worst_point",
]

RESOLUTION = 1e-9  # relative: a margin must exceed this fraction of |lhs| + |rhs| to count
ROUNDING = 64.0  # rounding of a computed eigen- or singular value, in units of eps times the matrix's size
EPS = np.finfo(float).eps
POINTS = 32  # (q, t) pairs per hunted example
HUNT_SHARE = 3  # a hunt draws profile.examples // HUNT_SHARE chains (20 in ci, 666 in deep): drawing dominates its cost
HUNT_JOINTS = 8  # hunted chains have 1 to 8 joints
NO_SHRINK = (Phase.explicit, Phase.reuse, Phase.generate, Phase.target)  # a found point is concrete as it is;
# shrinking dozens of floats adds no meaning to it


def _svd(a):
    return np.linalg.svd(a, compute_uv=False)


def _eig(a):
    return np.linalg.eigvalsh(a)


def thm2_ingredients(chain, q, state):
    """(LowerBoundedness) at q: lambda_min(M) and xi = min_l lambda_min(f(Phi_l)), z_min = min_l lambda_min(Z(Phi_l)),
    gamma = sigma_min(QJ)^2."""
    s = _svd(chain.body_jacobian(q))
    w = _eig(composite.mass_matrix(chain, q, state["theta"]))
    f, z = _eig(pseudo_inertia(state["theta"])), _eig(spatial_inertia(state["theta"]))
    size = np.abs(w).max(-1) + np.maximum(np.abs(f).max((-2, -1)), np.abs(z).max((-2, -1))) * s[..., 0] ** 2
    return w[..., 0], {"xi": f[..., 0].min(-1), "z_min": z[..., 0].min(-1), "gamma": s[..., -1] ** 2}, size


def thm3_ingredients(chain, q, state):
    """(UpperBoundedness) at q: lambda_max(M) and zeta = max_l lambda_max(f(Phi_l)), z_max = max_l
    lambda_max(Z(Phi_l)), s = sigma_max(QJ)."""
    s = _svd(chain.body_jacobian(q))
    w = _eig(composite.mass_matrix(chain, q, state["theta"]))
    f, z = _eig(pseudo_inertia(state["theta"])), _eig(spatial_inertia(state["theta"]))
    size = np.abs(w).max(-1) + np.maximum(np.abs(f).max((-2, -1)), np.abs(z).max((-2, -1))) * s[..., 0] ** 2
    return w[..., -1], {"zeta": f[..., -1].max(-1), "z_max": z[..., -1].max(-1), "s": s[..., 0]}, size


def thm4_ingredients(chain, q, state):
    """(BoundedEffectofVaryingParam) at q: sigma_max(M(q, Thetadot)) and mu = max_l sigma_max(f(Phidot_l)),
    zdot = max_l sigma_max(Z(Phidot_l)), s = sigma_max(QJ), N."""
    s = _svd(chain.body_jacobian(q))
    lhs = np.abs(_eig(composite.mass_matrix(chain, q, state["theta_dot"]))).max(-1)
    mu = np.abs(_eig(pseudo_inertia(state["theta_dot"]))).max((-2, -1))
    zdot = np.abs(_eig(spatial_inertia(state["theta_dot"]))).max((-2, -1))
    bodies = np.asarray(state["theta_dot"]).shape[-2]
    return lhs, {"mu": mu, "zdot": zdot, "s": s[..., 0], "bodies": bodies}, lhs + np.maximum(mu, zdot) * s[..., 0] ** 2


def acc_ingredients(chain, q, state):
    """(LumpedAccelerationBounding) at q: ||J^T Q^T Psidot|| and dpsi = ||Psidot||, s = sigma_max(QJ)."""
    qj = chain.body_jacobian(q)
    lhs = np.linalg.norm(lumped_acceleration_force(qj, state["psi_dot"]), axis=-1)
    size = np.linalg.norm(state["psi_dot"], axis=-1)
    return lhs, {"dpsi": size, "s": _svd(qj)[..., 0]}, np.linalg.norm(qj, axis=(-2, -1)) * size + lhs


def thm5_ingredients(chain, q, state):
    """(BoundedEffectOfLumpedVel) at q: sigma_max(H(q, Psi)) and psi = ||Psi||, y = max_p sigma_max(Y_p(q)),
    y_rss = (sum_p sigma_max(Y_p)^2)^(1/2), rows = 6N."""
    dqj = chain.body_jacobian_derivative(q)
    lhs = _svd(lumped_velocity_matrix(dqj, state["psi"]))[..., 0]
    size = np.linalg.norm(state["psi"], axis=-1)
    ys = _svd(dqj - np.swapaxes(dqj, -1, -2))[..., 0]  # (..., 6N)
    found = {"psi": size, "y": ys.max(-1), "y_rss": np.sqrt((ys**2).sum(-1)), "rows": dqj.shape[-3]}
    return lhs, found, 2 * np.sqrt((dqj**2).sum((-3, -2, -1))) * size + lhs


INGREDIENTS = {
    "Thm2": thm2_ingredients, "Thm3": thm3_ingredients, "Thm4": thm4_ingredients, "EQ-acc": acc_ingredients,
    "Asm3/Thm5": thm5_ingredients,
}
SENSE = {"Thm2": "lower", "Thm3": "upper", "Thm4": "upper", "EQ-acc": "upper", "Asm3/Thm5": "upper"}

# every constant a check reports, evaluated by the function that computes it (looked up at call time, so that a
# replaced formula is what the checks test)
CONSTANTS = {
    "Thm2": {"alpha1": lambda g: formulas.alpha1(g["xi"], g["gamma"]),
             "alpha1 (certified, Z)": lambda g: formulas.alpha1_z(g["z_min"], g["gamma"])},
    "Thm3": {"alpha2": lambda g: formulas.alpha2(g["zeta"], g["s"]),
             "alpha2 (certified, Z)": lambda g: formulas.alpha2_z(g["z_max"], g["s"])},
    "Thm4": {"chi": lambda g: formulas.chi(g["mu"], g["s"], g["bodies"]),
             "chi (certified, factor 2)": lambda g: formulas.chi_sharp(g["mu"], g["s"]),
             "chi (certified, Z)": lambda g: formulas.chi_z(g["zdot"], g["s"])},
    "EQ-acc": {"dPsi* S": lambda g: formulas.acceleration(g["dpsi"], g["s"])},
    "Asm3/Thm5": {"sqrt(6N) Psi* Y": lambda g: formulas.lumped_velocity(g["psi"], g["y"], g["rows"]),
                  "Psi* Y_rss (certified)": lambda g: formulas.lumped_velocity_sharp(g["psi"], g["y_rss"])},
}

# counterexamples saved before the constants were named: k multiplied these forms
LEGACY = {
    "Thm2": lambda g: g["xi"] * g["gamma"], "Thm3": lambda g: g["zeta"] * g["s"] ** 2,
    "Thm4": lambda g: g["mu"] * g["s"] ** 2, "EQ-acc": lambda g: g["dpsi"] * g["s"],
    "Asm3/Thm5": lambda g: np.sqrt(g["rows"]) * g["psi"] * g["y"],
}


def constant_margins(check_id, chain, q, state, k=1.0, constants=None):
    """{constant: (margin, resolution, lhs, rhs)} of the pointwise inequality of every constant of a check (or
    those named in ``constants``; "legacy" is the old unnamed form) with k times the constant on the right.

    Where both sides vanish (no internal motion at that time, say) there is nothing to compare: margin NaN."""
    lhs, found, size = INGREDIENTS[check_id](chain, q, state)
    names = list(CONSTANTS[check_id]) if constants is None else list(constants)
    out = {}
    for name in names:
        formula = LEGACY[check_id] if name == "legacy" else CONSTANTS[check_id][name]
        rhs = k * np.broadcast_to(formula(found), np.shape(lhs))
        out[name] = (*relative_margin(lhs, rhs, size + np.abs(rhs), SENSE[check_id]), lhs, rhs)
    return out


def relative_margin(lhs, rhs, size, sense):
    """(margin, resolution): (rhs - lhs) / (|lhs| + |rhs|), sign flipped for a lower bound, and what rounding of
    spectral values of matrices of magnitude ``size`` can do to it (NaN where both sides vanish)."""
    scale = np.abs(lhs) + np.abs(rhs)
    with np.errstate(invalid="ignore", divide="ignore"):
        margin = (rhs - lhs) / scale if sense == "upper" else (lhs - rhs) / scale
        return margin, RESOLUTION + ROUNDING * EPS * size / scale


def margins(check_id, chain, q, state, k=1.0, constants=None):
    """Relative margin and resolution of the pointwise inequality at every configuration, with lhs and rhs: at each
    point those of the constant closest to failing (margin + resolution smallest)."""
    return named_margins(check_id, chain, q, state, k, constants)[:4]


def named_margins(check_id, chain, q, state, k=1.0, constants=None):
    """:func:`margins` and, at each point, the name of the constant closest to failing."""
    found = constant_margins(check_id, chain, q, state, k, constants)
    names = list(found)
    stack = np.stack([np.asarray(found[n][0], float) + np.asarray(found[n][1], float) for n in names])
    with np.errstate(invalid="ignore"):
        pick = np.argmin(np.where(np.isnan(stack), np.inf, stack), axis=0)
    take = [np.choose(pick, [np.asarray(found[n][j], float) for n in names]) for j in range(4)]
    margin, resolution, lhs, rhs = take
    allnan = np.all(np.isnan(stack), axis=0)
    margin = np.where(allnan, np.nan, margin)
    return margin, resolution, lhs, rhs, np.asarray(names, dtype=object)[pick]


def state_at(trajectory, t):
    """Theta, Thetadot, Psi, Psidot of a trajectory at times t (leading shape of t)."""
    theta, theta_dot = trajectory.theta(t)
    psi, psi_dot = trajectory.psi(t)
    return {"theta": theta, "theta_dot": theta_dot, "psi": psi, "psi_dot": psi_dot}


def worst_point(check_id, chain, q, state, k=1.0, constants=None):
    """The sampled point closest to a resolved violation: (index, margin, resolution, lhs, rhs, constant)."""
    margin, resolution, lhs, rhs, names = named_margins(check_id, chain, q, state, k, constants)
    if np.all(np.isnan(margin)):
        return 0, np.nan, np.nan, float(lhs[0]), float(rhs[0]), str(names[0])
    i = int(np.nanargmin(margin + resolution))
    return i, float(margin[i]), float(resolution[i]), float(lhs[i]), float(rhs[i]), str(names[i])


def point_counterexample(check_id, chain, q, state, k, point):
    """A replayable counterexample: the chain, the configuration, the parameters at that time, the constant it
    breaks (evaluated again by the replay with the current code) and the factor k multiplying it."""
    i, margin, resolution, lhs, rhs = point[:5]
    name = point[5] if len(point) > 5 else None
    return {"kind": "bound-point", "data": {
        "id": check_id, "chain": chain.to_data(), "q": np.asarray(q[i]).tolist(), "factor": float(k),
        **({"constant": name} if name is not None else {}),
        "state": {key: np.asarray(v[i]).tolist() for key, v in state.items()},
        "margin": margin, "resolution": resolution, "lhs": lhs, "rhs": rhs}}


def replay_point(data):
    """(margin, resolution, lhs, rhs) of a saved bound-point counterexample recomputed with the current code: the
    saved constant (or, in files saved before constants were named, the old form) times the saved factor."""
    chain = Chain.from_data(data["chain"])
    state = {key: np.asarray(v, float)[None] for key, v in data["state"].items()}
    name = data.get("constant", "legacy")
    if name != "legacy" and name not in CONSTANTS.get(data["id"], {}):
        raise KeyError(f"{data['id']} has no constant {name!r}")
    point = worst_point(data["id"], chain, np.asarray(data["q"], float)[None], state, data["factor"], [name])
    return point[1:5]


@replayer("bound-point")
def replay_bound_point(data, ctx):
    margin, resolution, lhs, rhs = replay_point(data)
    verdict = Verdict.VIOLATED if margin < -resolution else Verdict.HOLDS
    what = data.get("constant", "the pointwise form")
    return Result(data["id"], verdict, f"pointwise inequality of {what} (times {data['factor']:g}) as the code "
                  f"computes it: lhs {lhs:.6g}, rhs {rhs:.6g}, relative margin {margin:.3g} (resolution "
                  f"{resolution:.1g})",
                  {"margin": quantity(margin, "margin"), "resolution": quantity(resolution, "tolerance")})


# -- hunts over random chains ------------------------------------------------------------------

@st.composite
def hunt_cases(draw, moving_mass):
    """A random chain, a random trajectory of consistent bodies on it (a moving mass, a payload ramp, or either when
    ``moving_mass`` is None), and a seed for the (q, t) samples."""
    chain, length = draw(chains(max_joints=HUNT_JOINTS))
    moving = draw(st.booleans()) if moving_mass is None else moving_mass
    traj = draw(trajectories(chain.bodies, length, moving_mass=moving))
    return chain, traj, draw(st.integers(0, 2**32 - 1))


def hunt_samples(example, count=POINTS):
    """The (q, t) pairs of a hunted example: uniform in the chain's box, times over the trajectory's span."""
    chain, traj, seed = example
    lo, hi = chain.coordinate_box()
    q = lo + (hi - lo) * np.random.default_rng(seed).random((count, chain.n))
    return q, state_at(traj, traj.times(count))


def run_hunt(check_id, ctx, k=1.0, moving_mass=False, examples=None, constants=None):
    """Hunt for a chain, configuration and time where the pointwise inequality of one of the check's constants
    (times k; k = 1: as the code computes them) fails.

    Returns the ``hunt`` evidence and a replayable counterexample (None when none was found)."""
    def margin(example):
        q, state = hunt_samples(example)
        return worst_point(check_id, example[0], q, state, k, constants)[1:3]

    examples = examples or max(ctx.profile.examples // HUNT_SHARE, 10)
    names = list(CONSTANTS[check_id]) if constants is None else list(constants)
    found = hunt(hunt_cases(moving_mass), margin, ctx, label=f"{check_id} x{k:g}", tolerance=RESOLUTION,
                 max_examples=examples, phases=NO_SHRINK)
    evidence = {**found.summary(), "margins": [float(m) for m in found.margins[:500]],
                "factor": quantity(k, "value", "multiplier of the constants hunted (1: as the code computes them)"),
                "constants": names,
                "what": f"random chains (revolute and prismatic, 1 to {HUNT_JOINTS} joints, DH and general axes, 1 mm "
                        "to 30 m), consistent bodies near-degenerate to ordinary, "
                        f"{ {True: 'moving masses', False: 'smooth payload ramps', None: 'payload ramps or moving masses'}[moving_mass] }; {POINTS} (q, t) pairs per chain; every constant ({', '.join(names)}) evaluated by "
                        "the function that computes it (inertiaproof.bounds.formulas) with the ingredients at (q, t)"}
    cx = None
    if found.violation is not None:
        chain = found.violation[0]
        q, state = hunt_samples(found.violation)
        cx = point_counterexample(check_id, chain, q, state, k, worst_point(check_id, chain, q, state, k, constants))
    return evidence, cx


def with_hunt(ctx, result, k=1.0, moving_mass=False, examples=None):
    """Attach a hunt of the pointwise inequalities of the check's constants times k; a found counterexample makes
    the result VIOLATED."""
    evidence, cx = run_hunt(result.id, ctx, k, moving_mass, examples)
    result.evidence["hunt"] = evidence
    if cx is not None:
        result.verdict = Verdict.VIOLATED
        data = cx["data"]
        result.summary = (f"a hunted chain breaks the pointwise inequality of {data['constant']} (times {k:g}): lhs "
                          f"{data['lhs']:.6g} {'>' if SENSE[result.id] == 'upper' else '<'} rhs {data['rhs']:.6g} "
                          f"at q = {np.round(data['q'], 4).tolist()}; " + result.summary)
        result.counterexample = cx
    return result
