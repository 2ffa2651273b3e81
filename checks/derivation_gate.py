"""gate: the derived objects still mean what the committed lockfile says (inertiaproof.symbolic.gate)."""

from __future__ import annotations

from inertiaproof.symbolic import gate

from inertiaproof.result import Result, Verdict, quantity
from inertiaproof.suite.profiles import PROFILES
from inertiaproof.suite.registry import check, replayer

__all__ = ["derivation_gate", "gate_result", "replay_gate"]


def gate_result(report):
    """HOLDS when no meaning changed and every object is locked (form-only changes are warnings), else VIOLATED."""
    evidence = {
        "method": "fingerprints: sha256 of canonical forms under PYTHONHASHSEED=0 (form) and exact values at fixed "
                  "rational points (meaning), against the committed lockfile",
        "objects": quantity(report["objects"], "count", "derived objects fingerprinted"),
        "unchanged": quantity(report["unchanged"], "count"),
        "form_only_changes": quantity(len(report["warnings"]), "count", "warnings: same meaning, new form"),
        "failing": quantity(len(report["failures"]), "count"),
        "skipped": quantity(report["skipped"], "count", "locked objects of systems outside this profile"),
        "systems": report["systems"],
        "seconds": quantity(round(report["seconds"], 3), "seconds", "fingerprinting (derivations shared with the run)"),
        "warnings": report["warnings"],
    }
    if report["failures"]:
        first = report["failures"][0]
        ids = sorted({f["id"] for f in report["failures"]})
        return Result("gate", Verdict.VIOLATED, f"{len(report['failures'])} derived object(s) changed: first "
                      f"{first['object']} ({first['change']}); affects {', '.join(ids)}", evidence,
                      counterexample={"kind": "gate", "data": {"profile": report["profile"],
                                                               "lockfile": report["lockfile"],
                                                               "failures": report["failures"]}})
    note = f" ({len(report['warnings'])} form-only warnings)" if report["warnings"] else ""
    return Result("gate", Verdict.HOLDS, f"all {report['objects']} derived objects mean what the lockfile says{note}",
                  evidence)


@check("gate")
def derivation_gate(ctx):
    ctx.progress("fingerprinting derived objects against symbolic/derivations.lock.json")
    return gate_result(gate.run_gate(ctx.profile.name, progress=ctx.progress))


@replayer("gate")
def replay_gate(data, ctx):
    return gate_result(gate.run_gate(data.get("profile", "ci") if data.get("profile") in PROFILES else "ci",
                                     data.get("lockfile") or gate.LOCKFILE))
