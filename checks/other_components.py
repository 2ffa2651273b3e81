"""Boundedness of the other components (Section 4.2): Thm4, EQ-acc, Asm3/Thm5, each with a Hypothesis hunt.

Thm4 runs on ctx.scene or the built-in Panda and planar 2R picking up a
payload; EQ-acc and Thm5 on ctx.scene or the planar 2R with a trolley. The
hunts draw random chains, consistent inertias and trajectories
(inertiaproof.counterexamples) and steer toward the smallest relative slack of
the proof's pointwise inequality.
"""

from __future__ import annotations

import numpy as np
from hypothesis import strategies as st

from inertiaproof import robots
from inertiaproof.bound_cases import acceleration_case, lumped_velocity_case, rate_case
from inertiaproof.bound_check import RESOLUTION, point_counterexample, pointwise_margin, state_at
from inertiaproof.counterexamples.chains import chains
from inertiaproof.counterexamples.trajectories import trajectories
from inertiaproof.hunt import hunt
from inertiaproof.registry import check
from inertiaproof.result import Result, Verdict, combine, quantity

from inertiaproof.checks.mass_matrix_bounds import certificate_evidence


@st.composite
def hunt_cases(draw, moving_mass):
    chain, length = draw(chains())
    traj = draw(trajectories(chain.bodies, length, moving_mass=moving_mass))
    return chain, traj, draw(st.integers(0, 2**32 - 1))


def hunt_margin(check_id, k, count=32):
    def margin(example):
        chain, traj, seed = example
        rng = np.random.default_rng(seed)
        lo, hi = chain.coordinate_box()
        q = lo + (hi - lo) * rng.random((count, chain.n))
        t = traj.times(count)
        slack, _, _ = pointwise_margin(check_id, chain, q, state_at(traj, t), k)
        return float(np.min(slack))
    return margin


def run_hunt(check_id, ctx, k, moving_mass):
    found = hunt(hunt_cases(moving_mass), hunt_margin(check_id, k), ctx, label=f"{check_id} x{k:g}",
                 tolerance=RESOLUTION)
    evidence = {**found.summary(), "margins": [float(m) for m in found.margins[:200]], "factor": k}
    cx = None
    if found.violation is not None:
        chain, traj, seed = found.violation
        rng = np.random.default_rng(seed)
        lo, hi = chain.coordinate_box()
        q = lo + (hi - lo) * rng.random((32, chain.n))
        t = traj.times(32)
        state = state_at(traj, t)
        slack, lhs, rhs = pointwise_margin(check_id, chain, q, state, k)
        i = int(np.argmin(slack))
        cx = point_counterexample(check_id, chain, q[i], {key: v[i] for key, v in state.items()}, k, slack[i], lhs[i], rhs[i])
    return evidence, cx


def with_hunt(check_id, ctx, result, k, moving_mass):
    evidence, cx = run_hunt(check_id, ctx, k, moving_mass)
    result.evidence["hunt"] = evidence
    if cx is not None:
        result.verdict = Verdict.VIOLATED
        result.summary = f"VIOLATED: a hunt found a chain where the pointwise inequality fails ({result.summary})"
        result.counterexample = cx
    return result


def run_scenes(check_id, ctx, case, scenes, k=1.0):
    verdicts, rows, first = [], {}, None
    for scene in scenes:
        ctx.progress(scene.name)
        verdict, why, evidence, cx = case(ctx, scene, k)
        verdicts.append(verdict)
        rows[scene.name] = evidence
        if first is None or (verdict == Verdict.VIOLATED and first[0] != Verdict.VIOLATED):
            first = (verdict, why, evidence, cx)
    verdict = combine(verdicts)
    c = first[2]["constants"]
    summary = (f"{verdict} on {', '.join(rows)}: paper {c['paper']['value']:.4g}, certified "
               f"{c['certified']['value']:.4g}, observed {c['observed']['value']:.4g} ({first[0]}: {first[1]})")
    evidence = {**first[2], "scenes": rows, "key_step": certificate_evidence()}
    return Result(check_id, verdict, summary, evidence, counterexample=first[3] if verdict == Verdict.VIOLATED else None)


def thm4_result(ctx, scenes=None, k=1.0, hunt_factor=None):
    scenes = scenes or ([ctx.scene] if ctx.scene is not None else [robots.panda(payload=2.0), robots.planar_2r(payload=1.0)])
    result = run_scenes("Thm4", ctx, rate_case, scenes, k)
    return with_hunt("Thm4", ctx, result, hunt_factor or 2.0 * k, False)


def acc_result(ctx, scenes=None, k=1.0):
    scenes = scenes or ([ctx.scene] if ctx.scene is not None else [robots.planar_2r_trolley()])
    return with_hunt("EQ-acc", ctx, run_scenes("EQ-acc", ctx, acceleration_case, scenes, k), k, True)


def thm5_result(ctx, scenes=None, k=1.0):
    scenes = scenes or ([ctx.scene] if ctx.scene is not None else [robots.planar_2r_trolley()])
    result = run_scenes("Asm3/Thm5", ctx, lumped_velocity_case, scenes, k)
    return result


@check("Thm4", needs={"chain", "time_varying"})
def thm4(ctx):
    """The hunt tests the sharp factor 2 (stronger than the paper's sqrt(69 N)) on random chains."""
    return thm4_result(ctx)


@check("EQ-acc", needs={"chain", "internal_motion"})
def eq_acc(ctx):
    return acc_result(ctx)


@check("Asm3/Thm5", needs={"chain", "internal_motion"})
def thm5(ctx):
    return thm5_result(ctx)
