"""Symbolic identities of Section 2, decided exactly (EQ-geom, ...)."""

from __future__ import annotations

import sympy as sp

from inertiaproof.registry import CHECKS, check, replayer
from inertiaproof.result import Result, Verdict, quantity
from inertiaproof.symbolic import identities


def identity_result(check_id, lhs, rhs, symbols, statement):
    """HOLDS iff every entry of lhs - rhs expands to 0; otherwise VIOLATED with a rational point where they differ."""
    residual = sp.Matrix(lhs - rhs).applyfunc(sp.expand)
    nonzero = [(i, e) for i, e in enumerate(residual) if e != 0]
    evidence = {
        "method": "expand lhs - rhs to a canonical polynomial; exact (no sampling, no floats)",
        "entries": quantity(len(residual), "count", "matrix entries compared"),
        "nonzero_entries": quantity(len(nonzero), "exact", "entries of lhs - rhs that do not vanish"),
    }
    if not nonzero:
        return Result(check_id, Verdict.HOLDS, f"{statement}: lhs - rhs expands to 0 exactly", evidence)
    index, expr = nonzero[0]
    point = {str(s): k + 2 for k, s in enumerate(symbols)}
    value = expr.subs({s: k + 2 for k, s in enumerate(symbols)})
    return Result(check_id, Verdict.VIOLATED, f"{statement}: entry {index} of lhs - rhs is {expr}, not 0", evidence,
                  counterexample={"kind": "identity", "data": {"id": check_id, "entry": index, "residual": str(expr),
                                                              "point": point, "value": str(value)}})


@check("EQ-geom")
def eq_geom(ctx):
    lhs, rhs, symbols = identities.geometric_fact()
    return identity_result("EQ-geom", lhs, rhs, symbols, "S(x)^T S(x) = tr(x x^T) I3 - x x^T")


@replayer("identity")
def replay_identity(data, ctx):
    """Re-derive the identity with the current code."""
    return CHECKS[data["id"]].fn(ctx)
