"""Prop1 and Prop2, symbolic side: skew symmetry and regressors of (RoboticEquation) (Section 4, Appendix)."""

from __future__ import annotations

from inertiaproof.symbolic.claims import CLAIMS
from inertiaproof.symbolic.evidence import claim_result, profile_outcomes

from inertiaproof.suite.registry import check

__all__ = ["regressors", "skew_symmetry"]


@check("Prop1", variant="symbolic")
def skew_symmetry(ctx):
    return claim_result(CLAIMS["Prop1"], profile_outcomes(ctx, "Prop1"))


@check("Prop2", variant="symbolic")
def regressors(ctx):
    return claim_result(CLAIMS["Prop2"], profile_outcomes(ctx, "Prop2"))
