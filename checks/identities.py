"""Symbolic identities of Section 2, decided exactly (EQ-geom, EQ-inverse, EQ-translation)."""

from __future__ import annotations

import numpy as np
import sympy as sp
from inertiaproof.symbolic import identities

from inertiaproof.errors import InputError
from inertiaproof.model.inertia import pseudo_inertia, pseudo_inertia_inverse
from inertiaproof.result import Result, Verdict, combine, quantity
from inertiaproof.suite.registry import CHECKS, check, replayer

__all__ = [
    "all_of", "bijection_result", "EPS", "eq_geom", "eq_inverse", "eq_translation", "identity_result",
    "nonzero_entries", "numeric_agreement_result", "replay_identity",
]

EPS = np.finfo(float).eps


def nonzero_entries(lhs, rhs):
    """[(index, expanded entry)] of lhs - rhs that do not expand to 0."""
    residual = sp.Matrix(lhs - rhs).applyfunc(sp.expand)
    return [(i, e) for i, e in enumerate(residual) if e != 0], len(residual)


def identity_result(check_id, lhs, rhs, symbols, statement):
    """HOLDS iff every entry of lhs - rhs expands to 0; otherwise VIOLATED with a rational point where they differ."""
    nonzero, entries = nonzero_entries(lhs, rhs)
    evidence = {
        "method": "expand lhs - rhs to a canonical polynomial; exact (no sampling, no floats)",
        "entries": quantity(entries, "count", "matrix entries compared"),
        "nonzero_entries": quantity(len(nonzero), "exact", "entries of lhs - rhs that do not vanish"),
    }
    if not nonzero:
        return Result(check_id, Verdict.HOLDS, f"{statement}: lhs - rhs expands to 0 exactly", evidence)
    index, expr = nonzero[0]
    point = {s: k + 2 for k, s in enumerate(symbols)}
    value = expr.subs(point)
    return Result(check_id, Verdict.VIOLATED, f"{statement}: entry {index} of lhs - rhs is {expr}, not 0", evidence,
                  counterexample={"kind": "identity", "data": {"id": check_id, "entry": index, "residual": str(expr),
                                                              "point": {str(s): v for s, v in point.items()},
                                                              "value": str(value)}})


def all_of(check_id, parts, statement):
    """One Result from named sub-results: the combined verdict, each part's evidence, the first counterexample."""
    verdict = combine(r.verdict for _, r in parts)
    failed = [(name, r) for name, r in parts if r.verdict != Verdict.HOLDS]
    summary = statement + (": " + "; ".join(f"{name}: {r.summary}" for name, r in failed) if failed else
                           ": " + ", ".join(name for name, _ in parts) + " all hold")
    evidence = {name: {"verdict": str(r.verdict), "summary": r.summary, **r.evidence} for name, r in parts}
    counterexample = next((r.counterexample for _, r in failed if r.counterexample), None)
    return Result(check_id, verdict, summary, evidence, counterexample=counterexample)


def bijection_result(check_id, coordinate_matrix, residual, symbols):
    """f is linear (residual 0) and a bijection R^10 -> sym(4) (det of its 10x10 coordinate matrix != 0), exactly."""
    nonlinear = [(i, e) for i, e in enumerate(residual.applyfunc(sp.expand)) if e != 0]
    det = coordinate_matrix.det(method="bareiss")
    evidence = {
        "method": "coordinates of f in the basis of sym(4) given by its upper triangle; exact rational determinant",
        "nonlinear_entries": quantity(len(nonlinear), "exact", "entries of f(Phi) - A Phi that do not vanish"),
        "determinant": quantity(str(det), "exact", "det A of the 10x10 coordinate matrix of f"),
    }
    if nonlinear:
        return Result(check_id, Verdict.VIOLATED, f"f is not linear: entry {nonlinear[0][0]} of f(Phi) - A Phi is "
                      f"{nonlinear[0][1]}", evidence, counterexample={"kind": "identity", "data": {"id": check_id}})
    if det == 0:
        kernel = coordinate_matrix.nullspace()[0]
        phi = {str(s): str(v) for s, v in zip(symbols, kernel)}
        return Result(check_id, Verdict.VIOLATED, "f is not injective: det A = 0, f(Phi) = 0 for a Phi != 0", evidence,
                      counterexample={"kind": "identity", "data": {"id": check_id, "kernel_phi": phi}})
    return Result(check_id, Verdict.HOLDS, f"f is a linear bijection R^10 -> sym(4): det A = {det}", evidence)


def numeric_agreement_result(check_id, coordinate_matrix, rng, samples=1000):
    """The numeric pseudo_inertia / pseudo_inertia_inverse agree with the symbolic f, relative to ||Phi||."""
    a = np.array(coordinate_matrix.tolist(), dtype=float)
    phi = rng.normal(size=(samples, 10)) * 10.0 ** rng.uniform(-3, 3, size=(samples, 1))
    f = pseudo_inertia(phi)
    upper = f[:, *np.triu_indices(4)]
    scale = np.linalg.norm(phi, axis=1)
    forward = np.max(np.linalg.norm(upper - phi @ a.T, axis=1) / scale)
    round_trip = np.max(np.linalg.norm(pseudo_inertia_inverse(f) - phi, axis=1) / scale)
    tolerance = 64 * EPS
    worst = max(forward, round_trip)
    verdict = Verdict.HOLDS if worst <= tolerance else Verdict.VIOLATED
    evidence = {
        "samples": quantity(samples, "count", "random Phi over six decades of scale (fixed seed)"),
        "forward_residual": quantity(forward, "residual", "max ||coords(pseudo_inertia(Phi)) - A Phi|| / ||Phi||"),
        "round_trip_residual": quantity(round_trip, "residual", "max ||f^-1(f(Phi)) - Phi|| / ||Phi||"),
        "tolerance": quantity(tolerance, "tolerance", "64 eps, relative to ||Phi||"),
    }
    return Result(check_id, verdict, f"numeric f and f^-1 match the symbolic f (residual {worst:.1e} <= "
                  f"{tolerance:.1e})" if verdict == Verdict.HOLDS else
                  f"numeric f or f^-1 differ from the symbolic f by {worst:.1e} > {tolerance:.1e}", evidence)


@check("EQ-geom")
def eq_geom(ctx):
    lhs, rhs, symbols = identities.geometric_fact()
    return identity_result("EQ-geom", lhs, rhs, symbols, "S(x)^T S(x) = tr(x x^T) I3 - x x^T")


@check("EQ-inverse")
def eq_inverse(ctx):
    a, residual, symbols = identities.pseudo_inertia_coordinate_matrix()
    return all_of("EQ-inverse", [
        ("inverse after Sigma", identity_result("EQ-inverse", *identities.inverse_after_sigma(),
                                                "tr(Sigma) I3 - Sigma = I for Sigma = tr(I)/2 I3 - I")),
        ("Sigma after inverse", identity_result("EQ-inverse", *identities.sigma_after_inverse(),
                                                "tr(I)/2 I3 - I = Sigma for I = tr(Sigma) I3 - Sigma")),
        ("bijection", bijection_result("EQ-inverse", a, residual, symbols)),
        ("numeric f", numeric_agreement_result("EQ-inverse", a, ctx.rng("EQ-inverse"))),
    ], "I = tr(Sigma) I3 - Sigma inverts Sigma = tr(I)/2 I3 - I and f: R^10 -> sym(4) is a linear bijection")


@check("EQ-translation")
def eq_translation(ctx):
    lhs, rhs, symbols = identities.translation_invariance()
    return identity_result("EQ-translation", lhs, rhs, symbols,
                           "Sigma - h h^T/m = tr(I_CoM)/2 I3 - I_CoM with I_CoM = I - S(h)^T S(h)/m")


@replayer("identity")
def replay_identity(data, ctx):
    """Re-derive the identity with the current code."""
    if data.get("id") not in CHECKS:
        raise InputError(f"counterexample data: field 'id' names no check: {data.get('id')!r}")
    return CHECKS[data["id"]].fn(ctx)
