"""From derivations to verdicts: run a claim and its negative controls, and write the evidence.

A claim HOLDS on a system when its entries vanish exactly (and, for Property 2,
the regressors are free of inertial parameters); a randomised test at rational
points confirms it with a stated error probability. The check as a whole is
VIOLATED when a claim fails on some system (with the rational point where an
entry is nonzero), INCONCLUSIVE when the exact and randomised decisions
disagree or a negative control was not detected where it changes something
(the check would then be blind to that mistake), HOLDS otherwise.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass, field

from inertiaproof.symbolic.claims import entries
from inertiaproof.symbolic.identity import Decision, decide_exact, decide_randomised, fixed_point, leaves, point_json

from inertiaproof.result import Result, Verdict, quantity

__all__ = [
    "claim_result", "ClaimOutcome", "decision_evidence", "outcome_evidence", "Probe", "profile_derivations",
    "profile_outcomes", "run_claim",
]


@dataclass
class ClaimOutcome:
    label: str
    key: dict  # the SystemKey as a dict (for replay)
    exact: Decision
    randomised: Decision | None
    impure: list
    subject_terms: int = 0  # terms of the derived objects the claim is about
    controls: dict = field(default_factory=dict)  # name -> "detected" | "vacuous" | "missed"
    seconds: dict = field(default_factory=dict)
    cached: bool = False
    kind: str = "symbolic-claim"  # of its counterexample

    @property
    def holds(self):
        return self.exact.holds and not self.impure

    @property
    def consistent(self):
        return self.randomised is None or self.randomised.holds == self.exact.holds


class Probe:
    """Exact values at one fixed rational point: a nonzero value certifies that an expression is not 0.

    Used for the negative controls: cheaper than a canonical form, and exact;
    only where the values agree does the canonical form decide.
    """

    def __init__(self, calc, salt=0):
        self.calc, self.point, self.memo = calc, fixed_point(calc, salt), {}

    def value(self, e):
        return self.calc.evaluate(e, self.point, self.memo)

    def nonzero(self, entries):
        return any(self.value(e) != 0 for e in entries) or not decide_exact(self.calc, entries).holds

    def differs(self, a, b):
        """Whether two nested objects of the same shape differ as functions."""
        la, lb = leaves(a), leaves(b)
        if len(la) != len(lb):
            return True
        pairs = list(zip(la, lb))
        return any(self.value(x) != self.value(y) for x, y in pairs) or \
            any(not self.calc.is_zero(x - y) for x, y in pairs)


def run_claim(claim, d, *, rng=None, randomised_points=2, controls=True):
    """Decide a claim on one derivation, with its negative controls."""
    calc = d.calc
    start = time.perf_counter()
    residual, impure = entries(claim.residual(d))
    formed = time.perf_counter() - start
    exact = decide_exact(calc, residual)
    exact.seconds += formed  # forming the residual (products, sums: expansion in the ring) is part of deciding
    randomised = None
    if rng is not None:
        randomised = decide_randomised(lambda at: entries(claim.residual(at))[0], d, rng, randomised_points)
    outcome = ClaimOutcome(d.key.label, dataclasses.asdict(d.key), exact, randomised, impure,
                           sum(calc.size(x) for x in leaves(claim.subject(d))), seconds=dict(d.seconds),
                           cached=d.cached, kind=claim.kind)
    if controls:
        correct, probe = claim.originals(d), Probe(calc)
        for name, variant in claim.controls.items():
            kwargs = variant(d)
            if not any(probe.differs(v, correct[k]) for k, v in kwargs.items()):
                outcome.controls[name] = "vacuous"
                continue
            wrong, wrong_impure = entries(claim.residual(d, **kwargs))
            caught = bool(wrong_impure) or probe.nonzero(wrong)
            outcome.controls[name] = "detected" if caught else "missed"
    return outcome


def decision_evidence(decision):
    ev = {
        "method": decision.method,
        "entries": quantity(decision.entries, "count", "expressions that must vanish"),
        "nonzero_entries": quantity(len(decision.nonzero), "exact" if decision.method == "exact" else "count"),
        "seconds": quantity(round(decision.seconds, 4), "seconds", "deciding, this run"),
    }
    if decision.method == "exact":
        ev["residual_terms"] = quantity(decision.terms, "exact", "terms of the canonical residuals")
    else:
        ev["points"] = quantity(decision.points, "count", "independent random points, coordinates uniform in [-2^31, 2^31)")
        ev["degree_bound"] = quantity(decision.degree, "count", "total degree bound D of the residual after "
                                      "t-substitution (cos = (1-t^2)/(1+t^2), sin = 2t/(1+t^2))")
        ev["error_probability"] = quantity(float(decision.error_probability), "error_probability",
                                           f"(D / 2^32)^points = {decision.error_probability}")
    return ev


def outcome_evidence(o):
    ev = {"verdict": "HOLDS" if o.holds else "VIOLATED",
          "derived_terms": quantity(o.subject_terms, "count", "terms of the derived objects the claim is about"),
          "exact": decision_evidence(o.exact)}
    if o.randomised is not None:
        ev["randomised"] = decision_evidence(o.randomised)
    if o.impure:
        ev["regressor_entries_depending_on_parameters"] = quantity(len(o.impure), "count")
    ev["derivation_seconds"] = {k: quantity(round(v, 4), "seconds", "when derived" + (" (read from the cache "
                                "this run)" if o.cached else "")) for k, v in o.seconds.items()}
    ev["from_cache"] = o.cached
    if o.controls:
        ev["negative_controls"] = dict(o.controls)
    return ev


def claim_result(claim, outcomes, *, extra=None, method_note=""):
    """The Result of a claim over several systems."""
    evidence = {
        "method": method_note or "exact canonical forms (expand; normal form modulo sin^2 + cos^2 = 1), confirmed "
                                 "by randomised polynomial identity testing at rational points on the unit circle",
        "systems": {o.label: outcome_evidence(o) for o in outcomes},
    }
    names = sorted({name for o in outcomes for name in o.controls})
    controls = {}
    for name in names:
        seen = {o.label: o.controls.get(name) for o in outcomes}
        detected = [s for s, v in seen.items() if v == "detected"]
        missed = [s for s, v in seen.items() if v == "missed"]
        controls[name] = {"detected": bool(detected) and not missed, "detected_on": detected, "missed_on": missed,
                          "vacuous_on": [s for s, v in seen.items() if v == "vacuous"]}
    evidence["negative_controls"] = controls
    if extra:
        evidence.update(extra)
    labels = ", ".join(o.label for o in outcomes)
    failed = [o for o in outcomes if not o.holds]
    if failed:
        o = failed[0]
        w = o.exact.witness
        data = {"id": claim.id, "system": o.key, "impure": o.impure[:5]}
        if w:
            data.update(entry=w["entry"], point=point_json(w["point"]), value=str(w["value"]))
        what = f"entry {w['entry']} is {w['value']} at a rational point, not 0" if w else \
            f"{len(o.impure)} regressor entries depend on inertial parameters"
        return Result(claim.id, Verdict.VIOLATED, f"{claim.statement}: fails on {o.label}: {what}", evidence,
                      counterexample={"kind": o.kind, "data": data})
    blind = [n for n, c in controls.items() if not c["detected"]]
    disagree = [o.label for o in outcomes if not o.consistent]
    if disagree:
        return Result(claim.id, Verdict.INCONCLUSIVE, f"{claim.statement}: exact and randomised decisions disagree on "
                      f"{', '.join(disagree)}", evidence)
    if blind:
        return Result(claim.id, Verdict.INCONCLUSIVE, f"{claim.statement}: holds on {labels}, but the negative "
                      f"control(s) {'; '.join(blind)} went undetected, so the check cannot vouch for itself", evidence)
    return Result(claim.id, Verdict.HOLDS, f"{claim.statement}: exactly, on {labels}; {len(controls)}/"
                  f"{len(controls)} negative controls detected", evidence)


def profile_derivations(ctx):
    """The profile's derivations, shared by every symbolic check of a run (process memo and disk cache)."""
    from inertiaproof.symbolic.derivations import derivation
    from inertiaproof.symbolic.systems import profile_systems

    return [derivation(key, progress=ctx.progress) for key in profile_systems(ctx.profile)]


def profile_outcomes(ctx, claim_id):
    """A claim decided on every system of the run's profile, with a seeded generator per system."""
    from inertiaproof.symbolic.claims import CLAIMS

    claim, out = CLAIMS[claim_id], []
    for d in profile_derivations(ctx):
        ctx.progress(f"on {d.key.label}: deciding with {len(claim.controls)} negative controls")
        out.append(run_claim(claim, d, rng=ctx.rng(f"{claim_id}:{d.key.label}")))
    return out
