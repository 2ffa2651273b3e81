"""The certificates of a check's certified numbers: written under ``OUT/certificates/`` and re-proved by the
independent checker (:mod:`inertiaproof.verify`), whose outcome joins the number's evidence.

A check's evidence cites a certificate as a ``certificate`` entry holding it (schema
``inertiaproof.certificate/1``, :mod:`inertiaproof.bounds.certificate`); :func:`settle` replaces each with
``{file, claim, status, why, boxes, seconds}``. A refuted certificate turns the check VIOLATED: the certified
number is wrong, and the box where the checker refuted it is the counterexample.
"""

from __future__ import annotations

import functools
import hashlib
import json
from pathlib import Path

from inertiaproof.result import Result, Verdict, quantity
from inertiaproof.suite.execution import Executor
from inertiaproof.suite.registry import replayer
from inertiaproof.verify.claims import SCHEMA
from inertiaproof.verify.cli import check

__all__ = ["certificate_name", "certificate_tally", "cited_entries", "replay_refuted", "settle"]


def certificate_name(cert):
    text = json.dumps(cert, sort_keys=True)
    return f"{hashlib.sha256(text.encode()).hexdigest()[:16]}.json", text


def _holders(node, key):
    """Every dict in ``node`` (evidence) whose ``certificate`` entry is a dict with ``key``."""
    if isinstance(node, dict):
        if isinstance(node.get("certificate"), dict) and key in node["certificate"]:
            yield node
        for value in node.values():
            yield from _holders(value, key)
    elif isinstance(node, list):
        for value in node:
            yield from _holders(value, key)


def _cited(node):
    """Every dict in ``node`` (evidence) whose ``certificate`` entry is a certificate."""
    return (holder for holder in _holders(node, "schema") if holder["certificate"]["schema"] == SCHEMA)


def settle(result, *, out_dir, budget, verify, memo, executor=None):
    """Write the certificates ``result``'s evidence cites (into ``out_dir``/certificates, when there is one) and,
    with ``verify``, re-prove each once per run (``memo`` maps names to outcomes; ``budget``: the work a
    certificate may spend beyond its tree; the certificates go to ``executor`` as tasks of kind "verify", so the answers
    do not depend on the workers). A refuted certificate, or a malformed one (the prover's own: its proof does not
    hold together), turns the result VIOLATED; one not decided within the budget is named in the summary and turns
    HOLDS into INCONCLUSIVE."""
    holders = list({id(holder): holder for holder in _cited(result.evidence)}.values())  # a dict cited twice: once
    named = [certificate_name(holder["certificate"]) for holder in holders]
    if out_dir is not None:
        for name, text in named:
            path = Path(out_dir) / "certificates" / name
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(text)
    if verify:
        fresh = {name: holder["certificate"] for holder, (name, _) in zip(holders, named) if name not in memo}
        outcomes = (executor or Executor()).map(functools.partial(check, budget=budget), fresh.values(),
                                                kind="verify", label="certificates")
        memo.update(zip(fresh, outcomes))
    failed, undecided = None, []
    for holder, (name, _) in zip(holders, named):
        cert = holder["certificate"]
        entry = {"file": f"certificates/{name}", "claim": cert["claim"]["statement"]}
        if verify:
            outcome = memo[name]
            entry.update({k: outcome[k] for k in ("status", "why", "boxes", "seconds")})
            if outcome["status"] in ("refuted", "bad certificate") and failed is None:
                failed = (cert, outcome)
            elif outcome["status"] == "not decided" and entry["file"] not in undecided:
                undecided.append(entry["file"])
        else:
            entry.update(status="not verified", why="the run was asked not to verify (--no-verify)")
        holder["certificate"] = entry
    if failed is not None:
        cert, outcome = failed
        result.verdict = Verdict.VIOLATED
        result.summary = (f"a certified number is {outcome['status'].replace('bad', 'a bad')} for the independent "
                          f"checker: {cert['claim']['statement']}: {outcome['why']}; " + result.summary)
        result.counterexample = {"kind": "certificate-refuted", "data": {"id": result.id, "certificate": cert,
                                                                         "budget": budget, "where": outcome["where"]}}
    elif undecided:  # certified means re-proved: a number the checker could not re-prove decides nothing
        if result.verdict == Verdict.HOLDS:
            result.verdict = Verdict.INCONCLUSIVE
        result.summary += (f"; {len(undecided)} certified number(s) not re-proved by the independent checker within "
                           f"its budget: {', '.join(undecided)}")
    return result


def cited_entries(node):
    """The settled certificate entries ({file, claim, status, ...}) of evidence, after :func:`settle`."""
    return (holder["certificate"] for holder in _holders(node, "file"))


def certificate_tally(evidences):
    """({file: status} of the certificates the evidences cite, "N (OUT/certificates); k status, ..." in words)."""
    files = {entry["file"]: entry.get("status", "not verified") for ev in evidences for entry in cited_entries(ev)}
    counts = {status: sum(s == status for s in files.values()) for status in dict.fromkeys(files.values())}
    return files, (f"{len(files)} (OUT/certificates)" + ("; " if counts else "")
                   + ", ".join(f"{n} {status}" for status, n in counts.items()))


@replayer("certificate-refuted")
def replay_refuted(data, ctx):
    """Re-prove the saved certificate: still refuted (or malformed) is VIOLATED."""
    outcome = check(data["certificate"], data.get("budget", 2000))
    verdict = {"refuted": Verdict.VIOLATED, "bad certificate": Verdict.VIOLATED,
               "re-proved": Verdict.HOLDS}.get(outcome["status"], Verdict.INCONCLUSIVE)
    return Result(data["id"], verdict, f"the independent checker: {outcome['status']}: {outcome['why']}",
                  {"boxes": quantity(outcome["boxes"], "count", "boxes the checker tested")})
