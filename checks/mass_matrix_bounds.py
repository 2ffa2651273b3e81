"""Boundedness of the mass matrix (Section 4.1): Def3, Thm2, Thm3, Cor1.

Each bound runs on ``ctx.scene`` or, without one, on the built-in planar 2R
and Panda arms picking up a payload. Its evidence holds the paper's constant,
the sharpest constant the suite certifies and the observed worst case, the
bracket of the true extreme with its convergence, and the key-step
certificate of inertiaproof.positive_map.
"""

from __future__ import annotations

import numpy as np

from inertiaproof import bounds, robots
from inertiaproof.bound_cases import lower_bound_case, replay_bracket, upper_bound_case
from inertiaproof.bound_check import replay_point
from inertiaproof.inertia import pseudo_inertia, spatial_inertia
from inertiaproof.positive_map import key_step_certificate
from inertiaproof.registry import check, replayer
from inertiaproof.result import Result, Verdict, combine, quantity


def bound_scenes(ctx):
    return [ctx.scene] if ctx.scene is not None else [robots.panda(payload=2.0), robots.planar_2r(payload=1.0)]


def certificate_evidence():
    cert = key_step_certificate()
    return {k: v for k, v in cert.items() if k != "choi"}


def run_cases(check_id, ctx, case, scenes, k=1.0):
    verdicts, per_scene = [], {}
    first = None
    for scene in scenes:
        ctx.progress(f"{scene.name}")
        verdict, why, evidence, cx = case(ctx, scene, k)
        verdicts.append(verdict)
        per_scene[scene.name] = evidence
        if first is None or (verdict == Verdict.VIOLATED and first[0] != Verdict.VIOLATED):
            first = (verdict, why, evidence, cx)
    verdict = combine(verdicts)
    evidence = dict(first[2])
    evidence["scenes"] = per_scene
    evidence["key_step"] = certificate_evidence()
    c = first[2]["constants"]
    summary = (f"{verdict} on {', '.join(per_scene)}: paper {c['paper']['value']:.4g}, certified "
               f"{c['certified']['value']:.4g}, observed {c['observed']['value']:.4g} ({first[0]}: {first[1]})")
    return Result(check_id, verdict, summary, evidence, counterexample=first[3] if verdict == Verdict.VIOLATED else None)


def thm2_result(ctx, scenes=None, k=1.0):
    """Theorem 2 with the paper's alpha1 multiplied by k (k > 1 overstates it)."""
    return run_cases("Thm2", ctx, lower_bound_case, scenes or bound_scenes(ctx), k)


def thm3_result(ctx, scenes=None, k=1.0):
    """Theorem 3 with the paper's alpha2 multiplied by k (k < 1 shrinks it)."""
    return run_cases("Thm3", ctx, upper_bound_case, scenes or bound_scenes(ctx), k)


@check("Thm2", needs={"chain"})
def thm2(ctx):
    return thm2_result(ctx)


@check("Thm3", needs={"chain"})
def thm3(ctx):
    return thm3_result(ctx)


@check("Cor1", needs={"chain"})
def cor1(ctx):
    """Corollary 1: both bounds with 0 < alpha1 <= alpha2 < inf certified on scenes with normal, bounded QJ."""
    scenes = [ctx.scene] if ctx.scene is not None else [robots.planar_2r(payload=1.0), robots.spatial_3r()]
    low, high = thm2_result(ctx, scenes), thm3_result(ctx, scenes)
    rows, verdicts = {}, [low.verdict, high.verdict]
    for name in low.evidence["scenes"]:
        a1 = low.evidence["scenes"][name]["constants"]["certified"]["value"]
        a2 = high.evidence["scenes"][name]["constants"]["certified"]["value"]
        ok = 0 < a1 <= a2 < np.inf
        rows[name] = {"alpha1_certified": quantity(a1, "certified_constant", "Theorem 2, sharpest certified"),
                      "alpha2_certified": quantity(a2, "certified_constant", "Theorem 3, sharpest certified"),
                      "ordered": ok}
        verdicts.append(Verdict.HOLDS if ok else Verdict.INCONCLUSIVE)
    verdict = combine(verdicts)
    return Result("Cor1", verdict, f"{verdict}: certified 0 < alpha1 <= alpha2 < inf on {', '.join(rows)}",
                  {"scenes": rows, "Thm2": low.evidence, "Thm3": high.evidence},
                  counterexample=low.counterexample or high.counterexample)


def def3_result(trajectories, spatial=spatial_inertia):
    """Definition 3 on trajectories, and the key step on their samples: lambda_min(Z) >= lambda_min(f), lambda_max(Z) <= 2 lambda_max(f)."""
    rows, worst = {}, np.inf
    cert = key_step_certificate()
    for name, traj in trajectories.items():
        xi, zeta = bounds.time_extreme(traj, "lmin_f"), bounds.time_extreme(traj, "lmax_f")
        theta, _ = traj.theta(traj.times(2001))
        f, z = np.linalg.eigvalsh(pseudo_inertia(theta)), np.linalg.eigvalsh(spatial(theta))
        scale = np.abs(f).max(-1) + np.abs(z).max(-1)
        slack = np.minimum((z[..., 0] - cert["lower"] * f[..., 0]) / scale, (cert["upper"] * f[..., -1] - z[..., -1]) / scale)
        worst = min(worst, float(slack.min()))
        rows[name] = {
            "uniformly_consistent": bool(xi["certified"] > 0),
            "upper_bounded": bool(np.isfinite(zeta["certified"])),
            "inf_lambda_min_f": {"observed": quantity(xi["observed"], "sampled", "on a time grid"),
                                 "certified": quantity(xi["certified"], "lower_bound", xi["how"])},
            "sup_lambda_max_f": {"observed": quantity(zeta["observed"], "sampled", "on a time grid"),
                                 "certified": quantity(zeta["certified"], "upper_bound", zeta["how"])},
            "key_step_slack": quantity(float(slack.min()), "margin", "min over samples of the key steps' relative slack"),
        }
    verdict = Verdict.VIOLATED if worst < -1e-12 else Verdict.HOLDS
    return Result("Def3", verdict, f"{verdict}: " + "; ".join(
        f"{n}: {'uniformly consistent' if r['uniformly_consistent'] else 'NOT uniformly consistent'}, "
        f"{'upper bounded' if r['upper_bounded'] else 'NOT upper bounded'}" for n, r in rows.items()),
        {"trajectories": rows, "key_step": {k: v for k, v in cert.items() if k != "choi"}})


@check("Def3", needs={"chain"})
def def3(ctx):
    if ctx.scene is not None:
        return def3_result({ctx.scene.name: ctx.scene.trajectory})
    scenes = [robots.panda(payload=2.0), robots.planar_2r_trolley(), robots.translating_sphere(-0.5),
              robots.translating_sphere(0.5)]
    return def3_result({f"{s.name} ({s.description})": s.trajectory for s in scenes})


@replayer("bound-point")
def replay_bound_point(data, ctx):
    slack, lhs, rhs = replay_point(data)
    verdict = Verdict.VIOLATED if slack < -1e-9 else Verdict.HOLDS
    return Result(data["id"], verdict, f"pointwise inequality with factor {data['factor']:g}: lhs {lhs:.6g}, "
                  f"rhs {rhs:.6g}, relative slack {slack:.3g}", {"slack": quantity(slack, "margin")})


@replayer("bound-bracket")
def replay_bound_bracket(data, ctx):
    value, bound = replay_bracket(data)
    beyond = value > bound if data["sense"] == "upper" else value < bound
    tol = 1e-9 * (abs(value) + abs(bound))
    verdict = Verdict.VIOLATED if beyond and abs(value - bound) > tol else Verdict.HOLDS
    return Result(data["id"], verdict, f"at the witness the left-hand side is {value:.6g}; the constant (factor "
                  f"{data['factor']:g}) is at most {bound:.6g}" if data["sense"] == "upper" else
                  f"at the witness the left-hand side is {value:.6g}; the constant (factor {data['factor']:g}) is at "
                  f"least {bound:.6g}", {"value": quantity(value, "value"), "bound": quantity(bound, "upper_bound")})
