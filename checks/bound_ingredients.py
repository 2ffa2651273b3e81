"""The ingredients of the Section 4 bounds, re-evaluated independently of inertiaproof.bounds (Cor1:ingredients).

Theorems 2 and 3 are judged from brackets and constants (checks.bound_verdicts);
their paper constants are conservative, so a wrong bracket or constant can
leave every verdict HOLDS. Here each ingredient is checked on its own, with
plain NumPy on the chain's QJ (never inertiaproof.bounds' spectral functions
or the composite mass matrix):

- configuration brackets (inf sigma_min(QJ)^2, sup sigma_max(QJ), inf
  lambda_min(M), sup lambda_max(M)): the observed value is the value at its
  witness, and neither the witness nor any sampled configuration (with
  Theta(t) at a sampled time of the trajectory itself) lies beyond the
  certified side (a certified side beyond the witness: an inverted bracket);
- time extremes (lambda_min/max of f(Phi_l(t)) and Z(Phi_l(t)), sigma_max of
  f(Phidot), Z(Phidot)) and the lumped velocity bounds Psi*, dPsi*: no time of a
  fine grid, nor the value the extreme attains, lies beyond the certified side;
- constants: the paper's alpha1 = xi gamma and alpha2 = 2 zeta S^2 from the
  bracketed ingredients by the paper's formulas, and the sharpest certified
  constants no sharper than their certified ingredients allow;
- the composite mass matrix (what the brackets evaluate) against (QJ)^T Z QJ,
  also on a chain with a coordinate map;
- the vertex bound of the branch and bound rounds outwards on families whose
  spectral values are exact in floats.

Beyond a tolerance of TOLERANCE relative, any failure is VIOLATED.
"""

from __future__ import annotations

import numpy as np
from inertiaproof.checks.bound_verdicts import cached, kw
from inertiaproof.checks.mass_matrix_bounds import bound_scenes

from inertiaproof.bounds.configuration import jacobian_normality, jacobian_sup, mass_inf, mass_sup, vertex_bound
from inertiaproof.bounds.constants import lower_constants, upper_constants
from inertiaproof.bounds.domain import search_box
from inertiaproof.bounds.time import BODY_FUNCTIONS, lumped_velocity_bounds, parameter_vertices, time_extreme
from inertiaproof.dynamics import composite, terms
from inertiaproof.dynamics.trajectory import MovingMass, ParameterTrajectory, Path, Profile
from inertiaproof.model import solids
from inertiaproof.model.inertia import inertia_com, pseudo_inertia, spatial_inertia
from inertiaproof.result import Result, Verdict, quantity
from inertiaproof.scene import robots
from inertiaproof.suite.registry import check, replayer

SHARES = "theorem 2-3 brackets"  # one lane with the other module that reuses these brackets (suite.lanes)
__all__ = [
    "bound_ingredients", "configuration_findings", "constants_findings", "flat_rider", "ingredients_result",
    "replay_ingredient", "time_extremes", "time_findings", "TOLERANCE", "vertex_findings",
]

TOLERANCE = 1e-9  # relative to the size of the quantity compared
TIME_GRID = 1001  # times over a span, its ends included (time_extreme itself samples 2001)


def _beyond(values, bound, sense):
    """How far (relative) the worst of ``values`` lies beyond ``bound`` (> 0: beyond); sense 'min' for a lower bound."""
    worst = float(np.min(values) if sense == "min" else np.max(values))
    excess = bound - worst if sense == "min" else worst - bound
    if not np.isfinite(excess):  # an infinite bound holds everything, an infinite value beyond a finite bound does not
        return -1.0 if np.isinf(bound) or np.isnan(excess) else 1.0
    return float(excess / max(abs(worst), abs(bound), 1e-300))


def _singular_values(chain, q):
    return np.linalg.svd(chain.body_jacobian(q), compute_uv=False)  # (K, n), descending


def _mass_eigenvalues(chain, q, thetas):
    """eigvalsh of (QJ)^T Z(Theta_v) QJ (K, V, n) from the chain's QJ."""
    qj = chain.body_jacobian(q)
    return np.linalg.eigvalsh(np.stack([terms.mass_matrix(qj, th) for th in thetas], 1))


def _sampled_mass_eigenvalues(scene, q, rng):
    """eigvalsh of M(q_i, Theta(t_i)) (K, n) at the configurations paired with times over the trajectory's span
    (its ends included): from the trajectory itself, not from the parameter vertices the brackets use."""
    times = scene.trajectory.times(len(q), horizon=50.0)
    theta, _ = scene.trajectory.theta(rng.permutation(times))
    return np.linalg.eigvalsh(terms.mass_matrix(scene.chain.body_jacobian(q), theta))


def configuration_findings(ctx, scene, thetas):
    """{finding: relative excess (> TOLERANCE is a failure)} of the configuration brackets of a scene."""
    chain = scene.chain
    gamma = cached(ctx, scene, "gamma", lambda: jacobian_normality(chain, **kw(ctx, scene, "gamma")))
    sigma = cached(ctx, scene, "sigma", lambda: jacobian_sup(chain, **kw(ctx, scene, "sigma")))
    low = cached(ctx, scene, "mass_inf", lambda: mass_inf(chain, thetas, **kw(ctx, scene, "mass_inf")))
    high = cached(ctx, scene, "mass_sup", lambda: mass_sup(chain, thetas, **kw(ctx, scene, "mass_sup")))
    lo, hi = search_box(chain)
    rng = ctx.rng(f"Cor1:ingredients:{scene.name}")
    q = lo + (hi - lo) * rng.random((max(ctx.profile.samples // 4, 64), chain.n))
    s = _singular_values(chain, q)
    lam = _sampled_mass_eigenvalues(scene, q, rng)
    at = lambda b: np.asarray(b.witness, float)[None]  # noqa: E731
    witness = {"gamma": _singular_values(chain, at(gamma))[0, -1] ** 2,
               "sigma": _singular_values(chain, at(sigma))[0, 0],
               "low": _mass_eigenvalues(chain, at(low), thetas)[0, :, 0].min(),
               "high": _mass_eigenvalues(chain, at(high), thetas)[0, :, -1].max()}
    out = {
        "inf sigma_min(QJ)^2: value at the witness": _mismatch(witness["gamma"], gamma.observed),
        "sup sigma_max(QJ): value at the witness": _mismatch(witness["sigma"], sigma.observed),
        "inf lambda_min(M): value at the witness": _mismatch(witness["low"], low.observed),
        "sup lambda_max(M): value at the witness": _mismatch(witness["high"], high.observed),
        "M of the brackets = (QJ)^T Z QJ": _mismatch(composite.mass_matrix(chain, q[:, None], thetas[None]),
                                                     np.stack([terms.mass_matrix(chain.body_jacobian(q), th)
                                                               for th in thetas], 1)),
    }
    for name, key, bracket, values, sense in (("inf sigma_min(QJ)^2", "gamma", gamma, s[:, -1] ** 2, "min"),
                                              ("sup sigma_max(QJ)", "sigma", sigma, s[:, 0], "max"),
                                              ("inf lambda_min(M(q, Theta(t)))", "low", low, lam[..., 0], "min"),
                                              ("sup lambda_max(M(q, Theta(t)))", "high", high, lam[..., -1], "max")):
        side = bracket.lower if sense == "min" else bracket.upper
        if np.isfinite(side):
            out[f"{name}: samples within the certified side"] = _beyond(values, side, sense)
            # a certified side beyond the value attained at the witness (an inverted bracket) refutes the certificate
            at_witness = [v for v in (float(witness[key]), float(bracket.observed)) if np.isfinite(v)]
            if at_witness:
                out[f"{name}: witness within the certified side"] = _beyond(at_witness, side, sense)
    return out, {"gamma": gamma, "sigma": sigma, "low": low, "high": high, "q": q, "lam": lam}


def _mismatch(a, b):
    """max |a - b| relative to max |b| over the finite entries; 1 where one is infinite and the other not."""
    a, b = np.broadcast_arrays(np.asarray(a, float), np.asarray(b, float))
    if np.any(np.isfinite(a) != np.isfinite(b)) or np.any(a[~np.isfinite(a)] != b[~np.isfinite(b)]):
        return 1.0
    finite = np.isfinite(b)
    if not finite.any():
        return 0.0
    return float(np.max(np.abs(a[finite] - b[finite])) / max(float(np.max(np.abs(b[finite]))), 1e-300))


def time_findings(trajectory, extremes):
    """{finding: relative excess} of the time extremes (``extremes``: {name: time_extreme}) and the lumped velocity
    bounds on a fine time grid."""
    t = trajectory.times(TIME_GRID, horizon=50.0)
    theta, theta_dot = trajectory.theta(t)
    spectra = {}
    out = {}
    for name, (build, kind, rate) in BODY_FUNCTIONS.items():
        matrix = pseudo_inertia if build is pseudo_inertia else spatial_inertia
        key = (matrix, rate)
        if key not in spectra:
            spectra[key] = np.linalg.eigvalsh(matrix(theta_dot if rate else theta))
        w = spectra[key]
        values = w[..., 0] if kind == "lmin" else (w[..., -1] if kind == "lmax" else np.abs(w).max(-1))
        finite = np.isfinite(values)
        found = extremes[name]
        if np.isfinite(found["certified"]) and finite.any():
            out[f"{name}: grid within the certified side"] = _beyond(values[finite], found["certified"], found["sense"])
        if np.isfinite(found["certified"]) and np.isfinite(found["observed"]):  # the attained value: an inverted one
            out[f"{name}: attained value within the certified side"] = _beyond([found["observed"]], found["certified"],
                                                                               found["sense"])
    if trajectory.internal_motion:
        psi, psi_dot = trajectory.psi(t)
        bounds = lumped_velocity_bounds(trajectory)
        for name, values in (("psi", psi), ("psi_dot", psi_dot)):
            out[f"{name}*: grid within the certified side"] = _beyond(np.linalg.norm(values, axis=-1),
                                                                      bounds[name]["certified"], "max")
    return out


def time_extremes(trajectory):
    """{name: bounds.time.time_extreme} for every body function."""
    return {name: time_extreme(trajectory, name) for name in BODY_FUNCTIONS}


def constants_findings(extremes, brackets):
    """{finding: relative excess} of Theorems 2 and 3's constants against the paper's formulas and the samples."""
    xi, zmin, zeta, zmax = (extremes[name] for name in ("lmin_f", "lmin_Z", "lmax_f", "lmax_Z"))
    gamma, sigma, low, high = (brackets[k] for k in ("gamma", "sigma", "low", "high"))
    lower = lower_constants(xi["certified"], zmin["certified"], gamma, low, xi_observed=xi["observed"])
    upper = upper_constants(zeta["certified"], zmax["certified"], sigma, high, zeta_observed=zeta["observed"])
    alpha1 = (xi["certified"] * max(gamma.lower, 0.0), xi["observed"] * gamma.upper)
    alpha2 = (2 * zeta["observed"] * sigma.lower**2, 2 * zeta["certified"] * sigma.upper**2)
    justified1 = max(zmin["certified"] * max(gamma.lower, 0.0), low.lower, alpha1[0])
    justified2 = min(zmax["certified"] * sigma.upper**2, high.upper, alpha2[1])
    lam = brackets["lam"]
    return {
        "alpha1 = xi gamma (Theorem 2)": _mismatch([lower["paper"]["lower"], lower["paper"]["upper"]], alpha1),
        "alpha2 = 2 zeta S^2 (Theorem 3)": _mismatch([upper["paper"]["lower"], upper["paper"]["upper"]], alpha2),
        "certified alpha1 no sharper than its ingredients": _beyond([lower["certified"]["value"]], justified1, "max"),
        "certified alpha2 no sharper than its ingredients": _beyond([upper["certified"]["value"]], justified2, "min"),
        "certified alpha1 <= every sampled lambda_min(M(q, Theta(t)))": _beyond(lam[..., 0],
                                                                                lower["certified"]["value"], "min"),
        "certified alpha2 >= every sampled lambda_max(M(q, Theta(t)))": _beyond(lam[..., -1],
                                                                                upper["certified"]["value"], "max"),
    }


def vertex_findings(rng):
    """The vertex bound on a family with exact spectral values (a dyadic diagonal matrix without slope): its
    rounding allowance must put it strictly outside the exact extreme (1 where not, 0 where it does)."""
    a = np.diag(rng.integers(1, 2**10, 4) / 2.0**6)[None, None]  # (K, V, 4, 4)
    values = np.diag(a[0, 0])
    out = {}
    for kind, exact in (("lmax", values.max()), ("lmin", values.min())):
        bound = float(vertex_bound(a, np.zeros(a.shape + (2,)), np.full((1, 2), 0.5), np.ones(2, bool), kind)[0])
        outward = bound > exact if kind == "lmax" else bound < exact
        out[f"vertex bound {kind} strictly outside an exact value"] = 0.0 if outward else 1.0
    return out


def flat_rider():
    """A light body carrying a wide thin plate across it: lambda_max(Z) of the plate is near twice lambda_max(f),
    the case the key step's factor 2 (Z <= 2 zeta I6) is for."""
    base = solids.solid("box", 0.1, (0.1, 0.1, 0.1))[None]
    plate = inertia_com(solids.solid("box", 1.0, (6.0, 6.0, 0.01)))
    path = Path("line", Profile("smoothstep", 0.5, 1.0), start=(0.0, 0.0, 0.0), end=(0.1, 0.0, 0.0))
    return ParameterTrajectory(base, (MovingMass(0, 1.0, plate, path),), (0.0, 2.0))


def ingredients_result(ctx, scenes=None, trajectories=None):
    scenes = scenes if scenes is not None else (bound_scenes(ctx) if ctx.scene is not None else
                                                [*bound_scenes(ctx), robots.non_normal_2r()])
    trajectories = trajectories if trajectories is not None else (
        {} if ctx.scene is not None else {**{s.name: s.trajectory for s in (robots.trolley_2r(loop=True, mass=2.0),
                                                                             robots.passenger_platform(),
                                                                             robots.translating_sphere(-0.5))},
                                          "flat rider": flat_rider()})
    rows = {}
    for scene in scenes:
        verts = parameter_vertices(scene.trajectory)
        if verts is None:
            trajectories = {**trajectories, scene.name: scene.trajectory}
            continue
        extremes = time_extremes(scene.trajectory)
        findings, brackets = configuration_findings(ctx, scene, verts[0])
        findings.update(time_findings(scene.trajectory, extremes))
        findings.update(constants_findings(extremes, brackets))
        rows[scene.name] = findings
    for name, trajectory in trajectories.items():
        rows[name] = time_findings(trajectory, time_extremes(trajectory))
    rows["vertex bound"] = vertex_findings(ctx.rng("Cor1:ingredients:vertex"))
    failures = [(where, what, excess) for where, found in rows.items() for what, excess in found.items()
                if excess > TOLERANCE]
    evidence = {"method": "each bracket, time extreme and constant re-evaluated with NumPy on the chain's QJ and "
                          "the trajectory's Theta(t), Psi(t): witnesses, samples against certified sides, the paper's "
                          "formulas for the constants",
                "findings": {where: {what: quantity(excess, "margin", "relative excess beyond what is claimed; <= "
                                                    f"{TOLERANCE:g} holds") for what, excess in found.items()}
                             for where, found in rows.items()},
                "tolerance": quantity(TOLERANCE, "tolerance", "relative")}
    if failures:
        where, what, excess = max(failures, key=lambda f: f[2])
        return Result("Cor1", Verdict.VIOLATED, f"{len(failures)} ingredient(s) of the bounds are not what they "
                      f"claim; worst: {where}: {what} by {excess:.3g} (relative)", evidence,
                      counterexample={"kind": "bound-ingredient", "data": {"where": where, "what": what,
                                                                          "excess": excess}})
    count = sum(len(found) for found in rows.values())
    return Result("Cor1", Verdict.HOLDS, f"{count} ingredients of the bounds on {', '.join(rows)} are what they "
                  f"claim (witnesses, certified sides against samples, the paper's formulas)", evidence)


@check("Cor1", needs={"chain"}, variant="ingredients")
def bound_ingredients(ctx):
    return ingredients_result(ctx)


@replayer("bound-ingredient")
def replay_ingredient(data, ctx):
    """Re-run the audit (deterministic for the saved seed) and report the saved finding."""
    found = ingredients_result(ctx).evidence["findings"].get(data["where"], {}).get(data["what"])
    if found is None:
        return Result("Cor1", Verdict.INCONCLUSIVE, f"{data['where']}: {data['what']} is no longer audited")
    excess = found["value"]
    return Result("Cor1", Verdict.VIOLATED if excess > TOLERANCE else Verdict.HOLDS,
                  f"{data['where']}: {data['what']}: relative excess {excess:.3g}", {"excess": found})
