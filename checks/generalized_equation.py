"""GRE and GRE-F: the generalized robotics equation re-derived symbolically (Section 3, Appendix)."""

from __future__ import annotations

from dataclasses import replace

from inertiaproof.symbolic import oracle
from inertiaproof.symbolic.claims import CLAIMS, PARTICLE_GRE, entries
from inertiaproof.symbolic.derivations import derivation
from inertiaproof.symbolic.evidence import claim_result, profile_derivations, profile_outcomes, run_claim
from inertiaproof.symbolic.identity import fixed_point, point_from_json
from inertiaproof.symbolic.particles import ParticleKey, derivation_of_particles, particle_keys
from inertiaproof.symbolic.systems import SystemKey

from inertiaproof.result import Result, Verdict, quantity
from inertiaproof.suite.registry import check, replayer

__all__ = [
    "chain_cross_checks", "generalized_robotics_equation", "ORACLE_TOLERANCE", "parameter_rate_matrix",
    "particle_route", "replay_coordinate_polynomial", "replay_particle_claim", "replay_symbolic_claim",
    "THREE_ROUTES", "time_per_n",
]

ORACLE_TOLERANCE = 1e-9  # relative; the twin's transforms are within 1e-12 of the chain's

THREE_ROUTES = replace(CLAIMS["GRE"], statement="Lagrange's equations (LagrangeFormalism) of the bodies and of "
                                                "mass-carrying particles equal (RoboticEquation)")

PARTICLE_METHOD = (
    "a third route sharing nothing with Z(Phi) or QJ (inertiaproof.symbolic.particles): point masses m_li(t) at "
    "body-frame positions x_li(t), placed by the chain's homogeneous transforms; Lagrange's equations of "
    "T = sum 1/2 m |d/dt p|^2, U = -sum m a_g . p (the paper's g is -a_g) against the paper's form at Theta, "
    "Thetadot, Psi, Psidot of the same particles by (Defml)-(DefIl) and psi_l; exact in the symbolic masses and "
    "positions, so by linearity for any finite set of particles")
LOADING_ASSUMPTION = (
    "added mass arrives at rest in the inertial frame: per particle, Lagrange's equations with a time-varying mass "
    "give d/dt(m pdot) = F, which is Meshchersky's law m pddot = F + mdot (u - pdot) with arrival velocity u = 0 "
    "(checked: residual entries n+1..2n, against that law projected on dp/dq by d'Alembert)")
DIFFERENCE_WHEN_DROPPED = (
    "mass arriving with velocity u adds sum_i mdot_i (dp_i/dq)^T u_i to the true equation, which the Lagrangian "
    "misses; for mass arriving with its body's velocity (u = pdot) that is sum_i mdot_i (dp_i/dq)^T pdot_i, on pure "
    "loading (xdot = 0) exactly M(q, Thetadot) qd (checked: residual entries 2n+1..3n); negative control: the "
    "equations of that arrival differ from (RoboticEquation)")


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


def particle_route(ctx, keys):
    """The particle route decided on each key (:data:`PARTICLE_GRE`), and its evidence."""
    outcomes, rows = [], {}
    for key in keys:
        p = derivation_of_particles(key, progress=ctx.progress)
        ctx.progress(f"on {key.label}: deciding with {len(PARTICLE_GRE.controls)} negative controls")
        outcomes.append(run_claim(PARTICLE_GRE, p, rng=ctx.rng(f"GRE:{key.label}")))
        rows[key.label] = {
            "particles_per_body": quantity(key.particles, "count"),
            "lagrange_terms": quantity(sum(len(x) for x in p.euler_lagrange), "count",
                                       "terms of Lagrange's equations of the particles"),
            "difference_terms": quantity(p.difference_terms, "count", "terms of sum mdot J^T pdot (mass arriving "
                                         "with its body's velocity instead of at rest)"),
        }
    return outcomes, {"method": PARTICLE_METHOD, "loading_assumption": LOADING_ASSUMPTION,
                      "difference_when_dropped": DIFFERENCE_WHEN_DROPPED, "chains": rows}


@check("GRE")
def generalized_robotics_equation(ctx):
    ds = profile_derivations(ctx)
    decided = profile_outcomes(ctx, "GRE")
    particles, particle_evidence = particle_route(ctx, particle_keys(ctx.profile))
    cross, worst = chain_cross_checks(ds)
    series = {"title": "abstract Euler-Lagrange derivation time per n", "x_label": "n", "y_label": "seconds",
              "x_log": False, "y_log": True,
              "lines": {"derive": [[d.key.n, round(d.seconds.get("euler_lagrange", 0) + d.seconds.get("paper_form", 0), 4)]
                                   for d in ds if d.key.kind == "abstract"]}}
    maps = oracle.coordinate_polynomial_errors()
    result = claim_result(THREE_ROUTES, decided + particles, extra={
        "particle_route": particle_evidence,
        "coordinate_polynomials": {name: {"derivative_exact": same, "value_error": quantity(error, "residual",
                                          "max relative |symbolic g - chain's g| at rational points")}
                                   for name, (same, error) in maps.items()},
        "time_per_n": time_per_n(ds, decided), "series": series, "numeric_cross_check": cross,
        "numeric_tolerance": quantity(ORACLE_TOLERANCE, "tolerance", "relative, for the float cross-check"),
    })
    wrong = [name for name, (same, error) in maps.items() if not same or error > ORACLE_TOLERANCE]
    if wrong and result.verdict != Verdict.VIOLATED:
        result.verdict = Verdict.VIOLATED
        result.summary = (f"the symbolic coordinate map(s) {', '.join(wrong)} are not the chain's, or their rate "
                          f"factor g' is not the derivative of g: every symbolic route shares that chain rule")
        result.counterexample = {"kind": "coordinate-polynomial", "data": {"maps": wrong}}
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


@replayer("particle-claim")
def replay_particle_claim(data, ctx):
    """Re-derive the particle route with the current code and evaluate the failing entry at the saved point."""
    key = ParticleKey(**data["system"])
    p = derivation_of_particles(key)
    value = p.calc.evaluate(entries(PARTICLE_GRE.residual(p))[0][data["entry"]], point_from_json(data["point"]))
    if value != 0:
        return Result("GRE", Verdict.VIOLATED, f"{PARTICLE_GRE.statement}: entry {data['entry']} on {key.label} is "
                      f"still {value} at the saved point", {"value": str(value)},
                      counterexample={"kind": "particle-claim", "data": data})
    return Result("GRE", Verdict.HOLDS, f"{PARTICLE_GRE.statement}: the saved point no longer fails on {key.label}",
                  {"value": "0"})


@replayer("coordinate-polynomial")
def replay_coordinate_polynomial(data, ctx):
    maps = oracle.coordinate_polynomial_errors()
    wrong = [name for name in data["maps"] if name in maps and (not maps[name][0] or maps[name][1] > ORACLE_TOLERANCE)]
    return Result("GRE", Verdict.VIOLATED if wrong else Verdict.HOLDS,
                  f"symbolic coordinate maps not the chain's or with a wrong rate factor: {', '.join(wrong) or 'none'}",
                  {"maps": wrong})
