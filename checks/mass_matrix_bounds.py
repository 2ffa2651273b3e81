"""Boundedness of the mass matrix (Section 4.1): Def3, Thm2, Thm3, Cor1.

Each bound runs on ``ctx.scene`` or, without one, on the built-in planar 2R
and Panda arms picking up a payload, and is hunted on random chains
(checks.pointwise). Its evidence holds the paper's constant from certified
and from observed ingredients, the sharpest constant the suite certifies
and the observed worst case, the bracket of the true extreme with its
convergence, and the key-step certificate of inertiaproof.model.positive_map.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from inertiaproof.checks.bound_verdicts import (
    cached,
    case_result,
    constants_evidence,
    inverted_extreme,
    key_step_evidence,
    kw,
    parameter_stack,
    pointwise_on_scene,
    run_scenes,
    sampled_bracket,
    shown,
    time_quantities,
)
from inertiaproof.checks.constant_hunt import hunted_case, with_reported_hunt
from inertiaproof.checks.pointwise import with_hunt

from inertiaproof.bounds.certificate import SpectrumClaim
from inertiaproof.bounds.configuration import jacobian_normality, jacobian_sup, mass_inf, mass_sup
from inertiaproof.bounds.constants import lower_constants, upper_constants
from inertiaproof.bounds.premises import failed_premises
from inertiaproof.bounds.time import formation, moving_mass_hull, parameter_vertices, time_extreme
from inertiaproof.dynamics import composite
from inertiaproof.model.inertia import pseudo_inertia, spatial_inertia
from inertiaproof.model.positive_map import key_step_proof
from inertiaproof.presentation import bracket_evidence
from inertiaproof.result import Result, Verdict, combine, quantity
from inertiaproof.scene import robots
from inertiaproof.suite.registry import check

SHARES = "theorem 2-3 brackets"  # one lane with the other module that reuses these brackets (suite.lanes)
__all__ = [
    "bound_scenes", "cor1", "cor1_result", "def3", "def3_result", "lower_bound_case", "thm2", "thm2_result",
    "thm3", "thm3_result", "upper_bound_case",
]


def bound_scenes(ctx):
    return [ctx.scene] if ctx.scene is not None else [robots.panda(payload=2.0), robots.planar_2r(payload=1.0)]


def _extreme_over_time(ctx, scene, kind, what):
    """Bracket over q and over the parameter sets of the trajectory of lambda_min or lambda_max of M."""
    chain, traj = scene.chain, scene.trajectory
    verts = parameter_vertices(traj)
    if verts is not None:
        family = mass_inf if kind == "lmin" else mass_sup
        found = cached(ctx, scene, what, lambda: family(chain, verts[0], **kw(ctx, scene, what)))
        if isinstance(found.certify, SpectrumClaim):  # the certificate says how its parameter sets were formed
            found.certify = dataclasses.replace(found.certify, formation=formation(traj))
        return found
    thetas = parameter_stack(traj, rate=False)
    pick = (lambda w: w[..., 0].min(-1)) if kind == "lmin" else (lambda w: w[..., -1].max(-1))
    name = "inf lambda_min(M(q, Theta(t)))" if kind == "lmin" else "sup lambda_max(M(q, Theta(t)))"

    def bracket():
        """Sampled over 64 times; certified over the moving masses' hull (bounds.time.moving_mass_hull)."""
        found = sampled_bracket(lambda q: pick(np.linalg.eigvalsh(composite.mass_matrix(chain, q[:, None],
                                                                                         thetas[None]))),
                                chain, name, "min" if kind == "lmin" else "max", ctx, scene,
                                "moving mass: Theta(t) is not affine in the profile, the extreme over t is sampled on "
                                "64 times")
        hull = moving_mass_hull(traj, kind)
        if hull is not None:
            outer = (mass_inf if kind == "lmin" else mass_sup)(chain, hull, **kw(ctx, scene, what + " hull"))
            how = ("certified over the hull of the rest's vertices, where each moving body " +
                   ("adds f(Phi_p) >= 0" if kind == "lmin" else "is replaced by a row above f(Phi_p(c)) on its path"))
            if found.tighten(outer.certified, f"{how}: {outer.note}" if outer.note else how, outer.proof):
                found.certify, found.boxes = outer.certify, outer.boxes
        return found

    return cached(ctx, scene, what, bracket)


@hunted_case("Thm2")
def lower_bound_case(ctx, scene, k=1.0):
    """Theorem 2 (LowerBoundedness) on a scene; k multiplies the paper's alpha1 = xi gamma."""
    chain, traj = scene.chain, scene.trajectory
    xi = time_extreme(traj, "lmin_f")
    zmin = time_extreme(traj, "lmin_Z")
    gamma = cached(ctx, scene, "gamma", lambda: jacobian_normality(chain, **kw(ctx, scene, "gamma")))
    lhs = _extreme_over_time(ctx, scene, "lmin", "mass_inf")
    found = lower_constants(xi["certified"], zmin["certified"], gamma, lhs, xi_observed=xi["observed"],
                            xi_certificate=xi.get("certificate"), z_certificate=zmin.get("certificate"))
    paper, paper_observed = found["paper"]["lower"], found["paper"]["upper"]
    certified = found["certified"]["value"]
    constants = constants_evidence("lower", "alpha1 = min_l inf_t lambda_min(f(Phi_l)) inf_q lambda_min((QJ)^T QJ)",
                                   paper, paper_observed, certified, found["certified"]["how"], lhs.observed,
                                   "inf lambda_min(M) attained at the witness: an upper estimate of the true infimum",
                                   found["paper"].get("certificate"), found["certified"].get("certificate"))
    extra = {"ingredients": {"xi": time_quantities(xi, "min_l inf_t lambda_min(f(Phi_l(t)))"),
                             "lambda_min_Z": time_quantities(zmin, "min_l inf_t lambda_min(Z(Phi_l(t)))"),
                             "gamma": bracket_evidence(gamma)},
             "tightness": quantity(certified / lhs.observed if lhs.observed else np.nan, "ratio",
                                   "sharpest certified constant / observed worst case (1 = tight)")}
    reported = {"paper": k * paper, "certified": certified}
    return case_result("Thm2", scene, "lower", lhs, (k * paper, k * paper_observed), k, 1.0,
                       pointwise_on_scene("Thm2", ctx, scene, k, reported), constants, extra,
                       replay={"thetas": parameter_stack(traj, False), "spectral": "lmin"})


@hunted_case("Thm3")
def upper_bound_case(ctx, scene, k=1.0):
    """Theorem 3 (UpperBoundedness) on a scene; k multiplies the paper's alpha2 = 2 zeta S^2."""
    chain, traj = scene.chain, scene.trajectory
    zeta = time_extreme(traj, "lmax_f")
    zmax = time_extreme(traj, "lmax_Z")
    sigma = cached(ctx, scene, "sigma", lambda: jacobian_sup(chain, **kw(ctx, scene, "sigma")))
    lhs = _extreme_over_time(ctx, scene, "lmax", "mass_sup")
    found = upper_constants(zeta["certified"], zmax["certified"], sigma, lhs, zeta_observed=zeta["observed"],
                            zeta_certificate=zeta.get("certificate"), z_certificate=zmax.get("certificate"))
    paper, paper_observed = found["paper"]["upper"], found["paper"]["lower"]
    certified = found["certified"]["value"]
    constants = constants_evidence("upper", "alpha2 = 2 max_l sup_t lambda_max(f(Phi_l)) sup_q sigma_max(QJ)^2",
                                   paper, paper_observed, certified, found["certified"]["how"], lhs.observed,
                                   "sup lambda_max(M) attained at the witness: a lower estimate of the true supremum",
                                   found["paper"].get("certificate"), found["certified"].get("certificate"))
    extra = {"ingredients": {"zeta": time_quantities(zeta, "max_l sup_t lambda_max(f(Phi_l(t)))"),
                             "lambda_max_Z": time_quantities(zmax, "max_l sup_t lambda_max(Z(Phi_l(t)))"),
                             "sup_sigma_max_QJ": bracket_evidence(sigma)},
             "tightness": quantity(lhs.observed / certified if certified else np.nan, "ratio",
                                   "observed worst case / sharpest certified constant (1 = tight)")}
    reported = {"paper": k * paper, "certified": certified}
    return case_result("Thm3", scene, "upper", lhs, (k * paper_observed, k * paper), k, 1.0,
                       pointwise_on_scene("Thm3", ctx, scene, k, reported), constants, extra,
                       replay={"thetas": parameter_stack(traj, False), "spectral": "lmax"})


def thm2_result(ctx, scenes=None, k=1.0, hunt_factor=1.0):
    """Theorem 2 with the paper's alpha1 multiplied by k (k > 1 overstates it); the hunt tests the constants as the
    code computes them (formulas.alpha1, alpha1_z) times hunt_factor."""
    result = run_scenes("Thm2", ctx, lower_bound_case, scenes or bound_scenes(ctx), k)
    return with_reported_hunt(ctx, with_hunt(ctx, result, hunt_factor, moving_mass=None), moving_mass=None)


def thm3_result(ctx, scenes=None, k=1.0, hunt_factor=1.0):
    """Theorem 3 with the paper's alpha2 multiplied by k (k < 1 shrinks it); the hunt tests the constants as the
    code computes them (formulas.alpha2, alpha2_z) times hunt_factor."""
    result = run_scenes("Thm3", ctx, upper_bound_case, scenes or bound_scenes(ctx), k)
    return with_reported_hunt(ctx, with_hunt(ctx, result, hunt_factor, moving_mass=None), moving_mass=None)


@check("Thm2", needs={"chain"})
def thm2(ctx):
    return thm2_result(ctx)


@check("Thm3", needs={"chain"})
def thm3(ctx):
    return thm3_result(ctx)


@check("Cor1", needs={"chain"})
def cor1(ctx):
    scenes = [ctx.scene] if ctx.scene is not None else [robots.planar_2r(payload=1.0), robots.spatial_3r(),
                                                         robots.panda(payload=2.0)]
    return cor1_result(ctx, scenes)


def cor1_result(ctx, scenes, k_lower=1.0, k_upper=1.0):
    """Corollary 1 (corollary:UniformBounds): both bounds with 0 < alpha1 <= alpha2 < inf certified on scenes with
    normal, bounded QJ; k_lower and k_upper multiply the paper's alpha1 and alpha2 (a test misstates one). On a scene
    where a premise certifiably fails (:func:`inertiaproof.bounds.premises.failed_premises`: QJ not normal, the
    parameters not uniformly consistent or not upper bounded) the corollary claims nothing: that scene HOLDS with the
    failed premise and its exact witness as the reason. Theorems 2 and 3 are judged on every scene all the same, so a
    violation of either stays VIOLATED."""
    low = run_scenes("Thm2", ctx, lower_bound_case, scenes, k_lower)
    high = run_scenes("Thm3", ctx, upper_bound_case, scenes, k_upper)
    rows, verdicts = {}, [low.verdict, high.verdict]
    for scene in scenes:
        rows[scene.name] = _cor1_row(scene, low.evidence["scenes"][scene.name]["constants"]["certified"],
                                     high.evidence["scenes"][scene.name]["constants"]["certified"])
        verdicts.append(Verdict(rows[scene.name]["verdict"]))
    return Result("Cor1", combine(verdicts), "; ".join(f"{n}: {r['why']}" for n, r in rows.items()),
                  {"scenes": rows, "Thm2": low.evidence, "Thm3": high.evidence},
                  counterexample=low.counterexample or high.counterexample)


def _cor1_row(scene, c1, c2):
    """Corollary 1 on one scene from the certified alpha1 (c1) and alpha2 (c2): HOLDS where 0 < alpha1 <= alpha2 <
    inf is certified, or where a premise certifiably fails (the corollary claims nothing there); INCONCLUSIVE where
    neither is shown, with what is missing."""
    a1, a2 = float(c1["value"]), float(c2["value"])  # "inf", "nan" as floats again
    ok = bool(0 < a1 <= a2 < np.inf)
    failed = [] if ok else failed_premises(scene)
    shown_pair = f"{shown(c1['value'])} <= {shown(c2['value'])}"
    if ok:
        verdict, why = Verdict.HOLDS, f"certified 0 < alpha1 <= alpha2 < inf ({shown_pair})"
    elif failed:
        verdict = Verdict.HOLDS
        why = ("premise fails: " + "; ".join(f"{f['premise']}: {f['why']}" for f in failed)
               + f"; so Corollary 1 claims nothing here (certified alpha1, alpha2: {shown_pair})")
    else:
        verdict = Verdict.INCONCLUSIVE
        missing = [side for side, bad in (("alpha1 > 0", not a1 > 0), ("alpha2 < inf", not a2 < np.inf),
                                          ("alpha1 <= alpha2", a1 > 0 and a2 < np.inf and a1 > a2)) if bad]
        why = (f"not decided: {', '.join(missing)} not certified ({shown_pair}) and no premise certified to fail "
               f"(alpha1 from: {c1.get('note', '')}; alpha2 from: {c2.get('note', '')})")
    return {"alpha1_certified": {**c1, "note": "Theorem 2, sharpest certified: " + c1["note"]},
            "alpha2_certified": {**c2, "note": "Theorem 3, sharpest certified: " + c2["note"]},
            "ordered": ok, "premises_failed": failed, "verdict": str(verdict), "why": why}


def def3_result(trajectories, spatial=spatial_inertia):
    """Definition 3 on trajectories, and the key step on their samples: lambda_min(Z) >= lambda_min(f), lambda_max(Z) <= 2 lambda_max(f)."""
    rows, worst, inverted = {}, np.inf, []
    cert = key_step_proof()
    for name, traj in trajectories.items():
        xi, zeta = time_extreme(traj, "lmin_f"), time_extreme(traj, "lmax_f")
        inverted += [f"{name}: {what}" for what, found in (("inf lambda_min(f)", xi), ("sup lambda_max(f)", zeta))
                     if inverted_extreme(found)]  # a certified side beyond the value attained: refuted
        theta, _ = traj.theta(traj.times(2001))
        f, z = np.linalg.eigvalsh(pseudo_inertia(theta)), np.linalg.eigvalsh(spatial(theta))
        scale = np.abs(f).max(-1) + np.abs(z).max(-1)
        slack = np.minimum((z[..., 0] - cert["lower"] * f[..., 0]) / scale, (cert["upper"] * f[..., -1] - z[..., -1]) / scale)
        worst = min(worst, float(slack.min()))
        rows[name] = {
            "uniformly_consistent": bool(xi["certified"] > 0),
            "upper_bounded": bool(np.isfinite(zeta["certified"])),
            "inf_lambda_min_f": time_quantities(xi, "min_l inf_t lambda_min(f(Phi_l(t)))"),
            "sup_lambda_max_f": time_quantities(zeta, "max_l sup_t lambda_max(f(Phi_l(t)))"),
            "key_step_slack": quantity(float(slack.min()), "margin", "min over samples of the key steps' relative slack"),
        }
    verdict = Verdict.VIOLATED if worst < -1e-12 or inverted else Verdict.HOLDS
    refuted = (f"; the certified side lies beyond the value attained on the time grid (the certificate is refuted): "
               f"{', '.join(inverted)}") if inverted else ""
    return Result("Def3", verdict, "; ".join(
        f"{n}: {'uniformly consistent' if r['uniformly_consistent'] else 'NOT uniformly consistent'}, "
        f"{'upper bounded' if r['upper_bounded'] else 'NOT upper bounded'}" for n, r in rows.items()) + refuted,
        {"trajectories": rows, "key_step": key_step_evidence(),
         "tolerance": quantity(1e-12, "tolerance", "relative slack below which the key step counts as broken")})


@check("Def3", needs={"chain"})
def def3(ctx):
    if ctx.scene is not None:
        return def3_result({ctx.scene.name: ctx.scene.trajectory})
    scenes = [robots.panda(payload=2.0), robots.trolley_2r(loop=True, mass=2.0), robots.translating_sphere(-0.5),
              robots.translating_sphere(0.5)]
    return def3_result({f"{s.name} ({s.description})": s.trajectory for s in scenes})
