"""GRE and GRE-F: the generalized robotics equation re-derived symbolically (Section 3, Appendix)."""

from __future__ import annotations

from inertiaproof.symbolic import oracle
from inertiaproof.symbolic.claims import CLAIMS, entries
from inertiaproof.symbolic.derivations import derivation
from inertiaproof.symbolic.evidence import claim_result, profile_derivations, profile_outcomes
from inertiaproof.symbolic.identity import fixed_point, point_from_json
from inertiaproof.symbolic.systems import SystemKey

from inertiaproof.result import Result, Verdict, quantity
from inertiaproof.suite.registry import check, replayer

__all__ = [
    "chain_cross_checks", "generalized_robotics_equation", "ORACLE_TOLERANCE", "parameter_rate_matrix",
    "replay_symbolic_claim", "time_per_n",
]

ORACLE_TOLERANCE = 1e-9  # relative; the twin's transforms are within 1e-12 of the chain's


def time_per_n(ds, decided):
    rows = {}
    for d, o in zip(ds, decided):
        if d.key.kind != "abstract":
            continue
        derive = d.seconds.get("euler_lagrange", 0.0) + d.seconds.get("paper_form", 0.0)
        rows[f"n={d.key.n}"] = {
            "derive": quantity(round(derive, 4), "seconds", "Euler-Lagrange and paper form, when derived"
                               + (" (this run read them from the cache)" if d.cached else "")),
            "decide": quantity(round(o.exact.seconds, 4), "seconds", "exact decision, this run"),
            "terms": quantity(o.subject_terms, "count", "terms of the Euler-Lagrange left side"),
        }
    return rows


def chain_cross_checks(ds):
    """QJ against Chain.body_jacobian and tau + w against dynamics.generalized_forces at a rational point."""
    out, worst = {}, 0.0
    for d in ds:
        if d.key.kind != "chain":
            continue
        point = fixed_point(d.calc, 0)
        qj_error = oracle.body_jacobian_error(d, point)
        force_error, _, _ = oracle.generalized_forces_error(d, point)
        worst = max(worst, force_error, qj_error)
        out[d.key.label] = {
            "rationalisation_error": quantity(d.system.twin.rationalisation_error, "residual",
                                              "largest |exact - float| of the chain's fixed transforms"),
            "QJ_vs_Chain.body_jacobian": quantity(qj_error, "residual", "max abs difference, floats"),
            "tau_vs_dynamics.generalized_forces": quantity(force_error, "residual",
                                                           "max relative difference, floats (an extra, not the proof)"),
        }
    return out, worst


@check("GRE")
def generalized_robotics_equation(ctx):
    ds = profile_derivations(ctx)
    decided = profile_outcomes(ctx, "GRE")
    cross, worst = chain_cross_checks(ds)
    series = {"title": "abstract Euler-Lagrange derivation time per n", "x_label": "n", "y_label": "seconds",
              "x_log": False, "y_log": True,
              "lines": {"derive": [[d.key.n, round(d.seconds.get("euler_lagrange", 0) + d.seconds.get("paper_form", 0), 4)]
                                   for d in ds if d.key.kind == "abstract"]}}
    result = claim_result(CLAIMS["GRE"], decided, extra={
        "time_per_n": time_per_n(ds, decided), "series": series, "numeric_cross_check": cross,
        "numeric_tolerance": quantity(ORACLE_TOLERANCE, "tolerance", "relative, for the float cross-check"),
    })
    if result.verdict == Verdict.HOLDS and worst > ORACLE_TOLERANCE:
        result.verdict = Verdict.INCONCLUSIVE
        result.summary = (f"the symbolic identity holds, but the symbolic chain disagrees with the numeric model by "
                          f"{worst:.2e} (> {ORACLE_TOLERANCE:g}): the twin may not be the project's chain")
    return result


@check("GRE-F")
def parameter_rate_matrix(ctx):
    return claim_result(CLAIMS["GRE-F"], profile_outcomes(ctx, "GRE-F"))


@replayer("symbolic-claim")
def replay_symbolic_claim(data, ctx):
    """Re-derive the system with the current code and evaluate the failing entry at the saved point."""
    key = SystemKey(**data["system"])
    d = derivation(key)
    claim = CLAIMS[data["id"]]
    residual, impure = entries(claim.residual(d))
    if "entry" in data:
        value = d.calc.evaluate(residual[data["entry"]], point_from_json(data["point"]))
        if value != 0:
            return Result(data["id"], Verdict.VIOLATED, f"{claim.statement}: entry {data['entry']} on {key.label} is "
                          f"still {value} at the saved point", {"value": str(value)}, counterexample=
                          {"kind": "symbolic-claim", "data": data})
    if impure:
        return Result(data["id"], Verdict.VIOLATED, f"{len(impure)} regressor entries on {key.label} still depend on "
                      "inertial parameters", {}, counterexample={"kind": "symbolic-claim", "data": data})
    return Result(data["id"], Verdict.HOLDS, f"{claim.statement}: the saved point no longer fails on {key.label}",
                  {"value": "0"})
