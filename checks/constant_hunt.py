"""The constants a check reports, hunted on random chains: the numbers themselves, not only their formulas.

checks.pointwise tests each constant's formula at single (q, t). Here the whole computation a check runs on a
scene (brackets over configurations, extremes over time, the formulas of inertiaproof.bounds.formulas, the
choice of the sharpest certified constant) runs on random scenes: a random chain (1 to 8 joints, revolute and
prismatic, random geometry) carrying a random consistent trajectory, with a light profile
(``HUNT_SAMPLES`` configurations, ``HUNT_ROUNDS`` rounds of narrowing per bracket: the brackets are
wider, the certified sides still certified). The check's own case function (e.g.
checks.mass_matrix_bounds.upper_bound_case) computes the constants it reports for that scene (the paper's with
certified ingredients and the sharpest certified one) and compares them with the left-hand side at random
(q, t) of the scene (checks.bound_verdicts.pointwise_on_scene). A reported constant beyond a sampled value is a
"bound-constant" counterexample: the chain, the trajectory, (q, t) and the light profile, which
``inertiaproof replay`` runs through the case function again with the current code.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from inertiaproof.checks.pointwise import (
    HUNT_JOINTS,
    INGREDIENTS,
    NO_SHRINK,
    RESOLUTION,
    SENSE,
    hunt_cases,
    relative_margin,
    state_at,
)

from inertiaproof.checks.bound_verdicts import REPORTED_KINDS, scene_digest
from inertiaproof.dynamics.chain import Chain
from inertiaproof.dynamics.trajectory_data import trajectory_from_data
from inertiaproof.result import Result, Verdict, quantity
from inertiaproof.scene.format import Scene
from inertiaproof.suite.context import Context
from inertiaproof.suite.hunt import hunt
from inertiaproof.suite.registry import replayer

__all__ = ["CASES", "case_function", "example_key", "HUNT_ROUNDS", "HUNT_SAMPLES", "HUNT_SHARE", "hunted_case",
           "hunted_scene", "light_context", "replay_bound_constant", "reported_hunt", "with_reported_hunt"]

HUNT_SAMPLES = 200  # configurations per bracket and (q, t) pairs per comparison on a hunted scene
HUNT_ROUNDS = 0.8  # rounds of narrowing per bracket on a hunted scene (under one: one round of as many boxes as
# it pays for; the local search's rounds 4)
HUNT_SHARE = {"Asm3/Thm5": 20}  # profile.examples // HUNT_SHARE scenes per check (default 12): 5 in ci, 166 in deep;
# Theorem 5's brackets of dK_p/dq are the costly ones (3 in ci, 100 in deep). Each scene computes every bracket of
# the check, so ci keeps this hunt small: the pointwise hunt draws 20 chains

LOADS = {True: "moving masses", False: "payload ramps", None: "payload ramps or moving masses"}


CASES = {}  # check id -> its case function, registered by the module that defines it (:func:`hunted_case`)


def hunted_case(check_id):
    """Register the decorated function as the case function of ``check_id`` (the modules of the checks register
    theirs, so that this module imports none of them: issue 25)."""
    def register(fn):
        CASES[check_id] = fn
        return fn
    return register


def case_function(check_id):
    """The function a check runs on one scene: (ctx, scene, k) -> (verdict, why, evidence, counterexample).

    Registered with :func:`hunted_case` by the check's module (checks.mass_matrix_bounds: Thm2, Thm3;
    checks.other_components: Thm4, EQ-acc, Asm3/Thm5), which must have been imported (the runner's and
    ``inertiaproof replay``'s :func:`inertiaproof.suite.discovery.load_checks` imports them all)."""
    try:
        return CASES[check_id]
    except KeyError:
        raise KeyError(f"no case function registered for {check_id!r} (registered: {sorted(CASES)}); import the "
                       "module of its check first (inertiaproof.suite.discovery.load_checks)") from None


def light_context(ctx, samples=HUNT_SAMPLES, rounds=HUNT_ROUNDS, seed=None):
    """A context with the run's seed and budget and a light profile for hunted scenes."""
    return Context(replace(ctx.profile, samples=samples, rounds=rounds), seed=ctx.seed if seed is None else seed,
                   budget=ctx.budget)


def hunted_scene(example):
    """The scene of a hunted example (chain, trajectory, seed): named by its seed, which several examples share (the
    brackets are cached under the scene's chain and trajectory too, see checks.bound_verdicts.cached)."""
    chain, traj, seed = example
    return Scene(f"hunted-{seed}", chain, traj, description=f"random {chain.name}, {chain.n} joints")


def example_key(example):
    """What tells hunted examples apart: the seed and a digest of the chain and the trajectory."""
    return example[2], scene_digest(hunted_scene(example))


def reported_hunt(check_id, ctx, moving_mass, examples=None):
    """Hunt random scenes for one where a constant the check reports lies beyond a sampled left-hand side.

    Returns the ``constant_hunt`` evidence and a replayable counterexample (None when none was found)."""
    case = case_function(check_id)
    light = light_context(ctx)
    found_cx, tally = {}, {"compared": 0, "nothing to compare": 0}

    def margin(example):
        scene = hunted_scene(example)
        verdict, _, evidence, cx = case(light, scene, 1.0)
        if verdict == Verdict.VIOLATED:
            found_cx[example_key(example)] = cx  # the seed alone names many examples (Hypothesis draws 0 often)
            return -1.0, 0.0
        against = evidence["pointwise"].get("against_reported", {})
        values = [float(v["value"]) for v in against.values()]
        if not values:  # every reported constant infinite (no certified side), or both sides vanish everywhere
            tally["nothing to compare"] += 1
            return 1.0, RESOLUTION
        tally["compared"] += 1
        # the case judged every margin with its own resolution: one it did not call violated is no violation here
        return max(min(values), -0.5 * RESOLUTION), RESOLUTION

    examples = examples or max(ctx.profile.examples // HUNT_SHARE.get(check_id, 12), 3)
    found = hunt(hunt_cases(moving_mass), margin, ctx, label=f"{check_id} reported constants", tolerance=RESOLUTION,
                 max_examples=examples, phases=NO_SHRINK)
    evidence = {**found.summary(),
                "scenes_compared": quantity(tally["compared"], "count", "hunted scenes with a finite reported constant"),
                "scenes_without_constant": quantity(tally["nothing to compare"], "count",
                                                    "hunted scenes whose reported constants are all infinite (no "
                                                    "certified side) or whose both sides vanish"),
                "what": f"random scenes (chains of 1 to {HUNT_JOINTS} joints, revolute and prismatic, consistent "
                        f"{LOADS[moving_mass]}), each run through the check's own "
                        f"case function with {HUNT_SAMPLES} samples and {HUNT_ROUNDS:g} rounds of narrowing per bracket; "
                        "margin: the smallest relative margin of sampled left-hand sides against the constants it "
                        "reports (paper's with certified ingredients, sharpest certified)"}
    cx = found_cx.get(example_key(found.violation)) if found.violation is not None else None
    return evidence, cx


def with_reported_hunt(ctx, result, moving_mass, examples=None):
    """Attach :func:`reported_hunt`; a found counterexample makes the result VIOLATED."""
    evidence, cx = reported_hunt(result.id, ctx, moving_mass, examples)
    result.evidence["constant_hunt"] = evidence
    if cx is not None and result.verdict != Verdict.VIOLATED:
        result.verdict = Verdict.VIOLATED
        data = cx["data"]
        joints = len(data["chain"]["joints"])
        if cx["kind"] == "bound-constant":
            what = f"the reported {data['constant']} constant fails"
        elif cx["kind"] == "bound-bracket":
            what = "the bracket of the extreme refutes the bound (see the counterexample)"
        else:
            what = f"the pointwise inequality of {data.get('constant', 'a constant')} fails"
        result.summary = f"on a hunted random chain ({joints} joints) {what}: " + result.summary
        result.counterexample = cx
    return result


@replayer("bound-constant")
def replay_bound_constant(data, ctx):
    """Recompute the scene's reported constant with the current code (the check's case function, the saved light
    profile and seed) and compare it with the left-hand side at the saved (q, t)."""
    chain = Chain.from_data(data["chain"])
    traj = trajectory_from_data(data["trajectory"])
    scene = Scene(data["scene"], chain, traj, description=data.get("description", ""))
    light = light_context(ctx, data["samples"], data["rounds"], data["seed"])
    _, _, evidence, _ = case_function(data["id"])(light, scene, data["factor"])
    value = float(evidence["pointwise"]["reported"][data["constant"]]["value"])
    lhs, _, size = INGREDIENTS[data["id"]](chain, np.asarray(data["q"], float)[None],
                                           state_at(traj, np.array([data["t"]])))
    lhs = float(lhs[0])
    margin, resolution = relative_margin(lhs, value, float(size[0]), SENSE[data["id"]])
    if not np.isfinite(margin):  # both sides vanish: nothing to compare
        margin, resolution = 0.0, RESOLUTION
    verdict = Verdict.VIOLATED if margin < -resolution else Verdict.HOLDS
    return Result(data["id"], verdict, f"{data['constant']} constant recomputed for the saved scene: {value:.6g}; "
                  f"left-hand side at the saved (q, t): {lhs:.6g}; relative margin {margin:.3g} (resolution "
                  f"{resolution:.1g})", {"constant": quantity(value, REPORTED_KINDS.get(data["constant"], "value")),
                                         "lhs": quantity(lhs, "value"), "margin": quantity(margin, "margin"),
                                         "resolution": quantity(resolution, "tolerance")})
