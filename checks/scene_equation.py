"""GRE, GRE-F, Prop1 and Prop2 derived symbolically on a scene's own chain (``--scene FILE --symbolic``)."""

from __future__ import annotations

from inertiaproof.checks.generalized_equation import THREE_ROUTES, particle_route
from inertiaproof.symbolic.claims import CLAIMS
from inertiaproof.symbolic.derivations import derivation
from inertiaproof.symbolic.evidence import claim_result, run_claim
from inertiaproof.symbolic.particles import particle_key
from inertiaproof.symbolic.systems import scene_key

from inertiaproof.errors import InputError
from inertiaproof.result import Result, Verdict
from inertiaproof.suite.registry import check

__all__ = ["decide_on_scene"]


def decide_on_scene(claim_id, ctx):
    """The claim decided exactly (and by randomised identity testing) on the scene's chain; GRE also by the
    particle route (:func:`~inertiaproof.checks.generalized_equation.particle_route`)."""
    try:
        key = scene_key(ctx.scene)
        d = derivation(key, progress=ctx.progress)
    except InputError as exc:
        return Result(claim_id, Verdict.INCONCLUSIVE, f"no exact symbolic twin of the scene's chain: {exc}")
    ctx.progress(f"on {key.label}: deciding with {len(CLAIMS[claim_id].controls)} negative controls")
    outcome = run_claim(CLAIMS[claim_id], d, rng=ctx.rng(f"{claim_id}:{key.label}"))
    if claim_id != "GRE":
        return claim_result(CLAIMS[claim_id], [outcome])
    particles, evidence = particle_route(ctx, [particle_key(key.name)])
    return claim_result(THREE_ROUTES, [outcome, *particles], extra={"particle_route": evidence})


for _claim in ("GRE", "GRE-F", "Prop1", "Prop2"):
    check(_claim, needs={"chain", "symbolic"}, variant="scene")(
        lambda ctx, claim_id=_claim: decide_on_scene(claim_id, ctx))
