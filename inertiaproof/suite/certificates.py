"""The certificates of a check's certified numbers: completed, written under ``OUT/certificates/`` and re-proved
from those files by the independent checker in processes of its own (``python -m inertiaproof.verify``), whose
answers join the numbers' evidence.

A check's evidence cites a certificate as a ``certificate`` entry holding it (schema
``inertiaproof.certificate/2``, :mod:`inertiaproof.bounds.certificate`); :func:`settle` replaces each with
``{file, claim, status, why, boxes, seconds}``, the claim in the checker's own words. A refuted certificate (a
witness at which its claim fails) turns the check VIOLATED, the witness its counterexample; one not re-proved, or
malformed, turns HOLDS into INCONCLUSIVE with the checker's reason: a proof that did not go through shows nothing
false.
"""

from __future__ import annotations

import functools
import hashlib
import json
import subprocess
import sys
import tempfile
from fractions import Fraction
from pathlib import Path

from inertiaproof.bounds.completion import complete
from inertiaproof.result import Result, Verdict, quantity
from inertiaproof.suite.execution import Executor
from inertiaproof.suite.registry import replayer

__all__ = ["certificate_name", "certificate_tally", "check_files", "cited_entries", "replay_refuted", "settle"]

SCHEMA = "inertiaproof.certificate/2"


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


def check_files(paths):
    """The checker's rows ({file, claim, status, why, ...}) of the certificate files ``paths``, from a process of
    its own that imports nothing but the checker, flint and the standard library."""
    if not paths:
        return []
    done = subprocess.run([sys.executable, "-m", "inertiaproof.verify", "--json", *map(str, paths)],
                          capture_output=True, text=True)
    rows = [json.loads(line) for line in done.stdout.splitlines() if line.startswith("{")]
    if len(rows) != len(paths):
        why = f"the checker's process ended with status {done.returncode}: {done.stderr.strip()[-300:]}"
        return [{"file": str(p), "claim": "", "status": "not re-proved", "why": why, "boxes": 0, "where": None,
                 "seconds": 0.0} for p in paths]
    return rows


def _root(holder, cert):
    """Whether the number holding ``cert`` is the square root of its claim's bound (sup sigma_max(QJ) of a claim
    on (QJ)^T QJ), as the checker reads results.json."""
    value, bound = holder.get("value"), cert["claim"].get("bound")
    return (isinstance(value, float) and bound is not None and Fraction(value) != Fraction(bound)
            and Fraction(value) ** 2 == Fraction(bound))


def _written(folder, certs):
    """The names of ``certs``, each written into ``folder`` under its name."""
    named = [certificate_name(cert) for cert in certs]
    for name, text in named:
        (folder / name).write_text(text)
    return [name for name, _ in named]


def _verified(executor, folder, certs, memo):
    """Write ``certs`` into ``folder`` and re-prove the files not yet in ``memo`` (names to the checker's rows), in
    chunks over the executor's workers, one checker process each; their names."""
    names = _written(folder, certs)
    todo = sorted(set(names) - set(memo))
    chunks = [[folder / n for n in todo[i::executor.workers]] for i in range(min(executor.workers, len(todo)))]
    for chunk, rows in zip(chunks, executor.map(check_files, chunks, kind="verify", label="certificates")):
        memo.update({path.name: row for path, row in zip(chunk, rows)})
    return names


def _complete(task, boxes):
    """The certificate completed, growing the leaves the checker named (``where["leaves"]``) where it named them."""
    cert, where = task
    return complete(cert, boxes, (where or {}).get("leaves"))


def settle(result, *, out_dir, boxes, verify, memo, executor=None):
    """Write the certificates ``result``'s evidence cites (into ``out_dir``/certificates, or a temporary folder)
    and, with ``verify``, re-prove each file once per run (``memo`` maps names to the checker's rows; the files go
    to ``executor`` as tasks of kind "verify"). A certificate the checker does not re-prove as written has its trees
    completed (:func:`inertiaproof.bounds.completion.complete`, ``boxes`` beyond each) and is cited as completed,
    so the checker walks every tree once and cuts nothing."""
    executor = executor or Executor()
    holders = list({id(holder): holder for holder in _cited(result.evidence)}.values())  # a dict cited twice: once
    certs = [holder["certificate"] for holder in holders]
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(out_dir if out_dir is not None else scratch) / "certificates"
        folder.mkdir(parents=True, exist_ok=True)
        if not verify:
            names = _written(folder, certs)
        else:
            names = _verified(executor, folder, certs, memo)
            again = [i for i, name in enumerate(names) if memo[name]["status"] == "not re-proved"]
            grown = executor.map(functools.partial(_complete, boxes=boxes), [(certs[i], memo[names[i]]["where"])
                                                                             for i in again],
                                 kind="verify", label="certificate trees")
            for i, cert, name in zip(again, grown, _verified(executor, folder, grown, memo)):
                better = memo[name]["status"] != "not re-proved"  # else the prover's own tree stays cited
                if name != names[i]:
                    (folder / (names[i] if better else name)).unlink(missing_ok=True)  # the file no one cites
                if better:
                    certs[i], names[i] = cert, name
    named = list(zip(names, certs))
    failed, unproved = None, []
    for holder, (name, cert) in zip(holders, named):
        entry = {"file": f"certificates/{name}", **({"as": "root"} if _root(holder, cert) else {})}
        if verify:
            row = memo[name]
            entry.update({k: row[k] for k in ("claim", "status", "why", "boxes", "seconds")})
            if row["status"] == "refuted" and failed is None:
                failed = (cert, row)
            elif row["status"] != "re-proved" and entry["file"] not in unproved:
                unproved.append(f"{entry['file']} ({row['status']}: {row['why']})")
        else:
            entry.update(status="not verified", why="the run was asked not to verify (--no-verify)")
        holder["certificate"] = entry
    if failed is not None:
        cert, row = failed
        result.verdict = Verdict.VIOLATED
        result.summary = (f"a certified number is refuted by the independent checker: {row['claim']}: {row['why']}; "
                          + result.summary)
        result.counterexample = {"kind": "certificate-refuted", "data": {"id": result.id, "certificate": cert,
                                                                         "where": row["where"]}}
    elif unproved:  # certified means re-proved: a number the checker could not re-prove decides nothing
        if result.verdict == Verdict.HOLDS:
            result.verdict = Verdict.INCONCLUSIVE
        result.summary += (f"; {len(unproved)} certified number(s) not re-proved by the independent checker: "
                           + ", ".join(unproved))
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
    """Re-prove the saved certificate in the checker's own process: still refuted is VIOLATED."""
    with tempfile.TemporaryDirectory() as scratch:
        path = Path(scratch) / "certificate.json"
        path.write_text(json.dumps(data["certificate"], sort_keys=True))
        row, = check_files([path])
    verdict = {"refuted": Verdict.VIOLATED, "re-proved": Verdict.HOLDS}.get(row["status"], Verdict.INCONCLUSIVE)
    return Result(data["id"], verdict, f"the independent checker: {row['status']}: {row['why']}",
                  {"boxes": quantity(row["boxes"], "count", "boxes the checker tested")})
