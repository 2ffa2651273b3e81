"""The certificates of a check's certified numbers: completed, written under ``OUT/certificates/`` and re-proved
from those files by the independent checker in processes of its own (``python -m inertiaproof.verify``).

A check's :class:`~inertiaproof.result.Result` carries the certificates its evidence cites
(``Result.certificates``, :class:`inertiaproof.citation.Certificate`; the evidence cites each by hash).
:func:`settle` returns a new Result whose certificates are :class:`~inertiaproof.citation.Settled` (its file and the
checker's ``{claim, status, why, boxes, seconds}``, the claim in the checker's own words) and whose verdict follows
from their statuses; the evidence is not touched. A refuted certificate (a witness at which its claim fails) turns
the check VIOLATED, the witness its counterexample; one not re-proved, or malformed, turns HOLDS into INCONCLUSIVE
with the checker's reason: a proof that did not go through shows nothing false.
"""

from __future__ import annotations

import dataclasses
import functools
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from inertiaproof.bounds.completion import complete
from inertiaproof.citation import Certificate, Settled, entry_of
from inertiaproof.result import Result, Verdict, quantity
from inertiaproof.suite.execution import Executor
from inertiaproof.suite.registry import replayer

__all__ = ["certificate_name", "certificate_tally", "check_files", "cited_entries", "replay_refuted", "settle"]


def certificate_name(cert):
    """(file name, text) of a certificate (or its content): ``<hash>.json`` and its canonical text."""
    cert = Certificate.of(cert)
    return cert.name, cert.text


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


def _written(folder, certs):
    """Write each of ``certs`` (Certificates) into ``folder`` under its name; their names."""
    for cert in certs:
        (folder / cert.name).write_text(cert.text)
    return [cert.name for cert in certs]


def _verified(executor, folder, certs, memo):
    """Write ``certs`` into ``folder`` and re-prove the files not yet in ``memo`` (names to the checker's rows), in
    chunks over the executor's workers (:func:`_chunks`), one checker process each; their names."""
    names = _written(folder, certs)
    by_name = {cert.name: cert.content for cert in certs}
    chunks = [[folder / n for n in chunk] for chunk in _chunks({n: by_name[n] for n in sorted(set(names) - set(memo))},
                                                                executor.workers)]
    for chunk, rows in zip(chunks, executor.map(check_files, chunks, kind="verify", label="certificates")):
        memo.update({path.name: row for path, row in zip(chunk, rows)})
    return names


def _chunks(contents, workers):
    """The names of ``contents`` (file names to certificates) in at most ``workers`` chunks, balanced by what a
    checker process proves: each certificate it meets once (an ingredient embedded in several products, or also a
    file of its own, once per process), its cost the characters of its own part (a tree's size stands for its
    checking time). The largest first, each to the chunk it adds least to."""
    def parts(cert):  # {canonical text: own characters} of a certificate and those it embeds
        own = {k: v for k, v in cert.items() if k not in ("ingredients", "terms")}
        out = {json.dumps(cert, sort_keys=True): len(json.dumps(own))}
        for part in cert.get("ingredients", []) + cert.get("terms", []):
            out.update(parts(part))
        return out

    costs = {name: parts(cert) for name, cert in contents.items()}
    chunks = [([], {}) for _ in range(min(workers, len(contents)))]  # (names, {text: cost} proved there)
    for name in sorted(contents, key=lambda n: (-sum(costs[n].values()), n)):
        after = [sum({**seen, **costs[name]}.values()) for _, seen in chunks]
        names, seen = chunks[after.index(min(after))]
        names.append(name)
        seen.update(costs[name])
    return [names for names, _ in chunks if names]


def _complete(task, boxes):
    """(the certificate completed, growing the leaves and parts the checker named (its ``where``) where it named
    them, the seconds that took)."""
    cert, where = task
    start = time.perf_counter()
    grown = Certificate(complete(cert.content, boxes, where))
    return grown, time.perf_counter() - start


def _filed(executor, folder, certs, boxes, memo):
    """The certificates as written and re-proved, and the prover's seconds completing each (None: not needed): each
    of ``certs``, or its completion where the checker did not re-prove it as written and re-proves the completion
    (:func:`inertiaproof.bounds.completion.complete`, ``boxes`` beyond each tree), so the checker walks every tree
    once and cuts nothing."""
    filed, spent = list(certs), [None] * len(certs)
    names = _verified(executor, folder, filed, memo)
    again = [i for i, name in enumerate(names) if memo[name]["status"] == "not re-proved"]
    grown = executor.map(functools.partial(_complete, boxes=boxes), [(certs[i], memo[names[i]]["where"])
                                                                     for i in again],
                         kind="verify", label="certificate trees")
    for i, (cert, seconds), name in zip(again, grown, _verified(executor, folder, [c for c, _ in grown], memo)):
        better = memo[name]["status"] != "not re-proved"  # else the prover's own tree stays cited
        if name != names[i]:
            (folder / (names[i] if better else name)).unlink(missing_ok=True)  # the file no one cites
        if better:
            filed[i] = cert
        spent[i] = round(seconds, 4)
    return filed, spent


def settle(result, *, out_dir, boxes, verify, memo, executor=None):
    """A new Result: ``result`` with its certificates written (into ``out_dir``/certificates, or a temporary folder)
    and, with ``verify``, re-proved once per run (``memo`` maps file names to the checker's rows; the files go to
    ``executor`` as tasks of kind "verify"), each a :class:`~inertiaproof.citation.Settled`; its verdict, summary and
    counterexample follow from their statuses. Its evidence is ``result``'s."""
    executor = executor or Executor()
    certs = [c if isinstance(c, Certificate) else c.certificate for c in result.certificates]
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(out_dir if out_dir is not None else scratch) / "certificates"
        folder.mkdir(parents=True, exist_ok=True)
        if not verify:
            _written(folder, certs)
            settled = [Settled(c, f"certificates/{c.name}", "not verified",
                               "the run was asked not to verify (--no-verify)") for c in certs]
            return dataclasses.replace(result, certificates=settled)
        filed, spent = _filed(executor, folder, certs, boxes, memo)
    settled = [Settled(c, f"certificates/{f.name}", memo[f.name]["status"], memo[f.name]["why"], memo[f.name]["claim"],
                       memo[f.name]["boxes"], memo[f.name]["seconds"], None if f is c else f, completion)
               for c, f, completion in zip(certs, filed, spent)]
    return dataclasses.replace(result, certificates=settled, **_verdict(result, settled, memo))


def _verdict(result, settled, memo):
    """{verdict, summary, counterexample} of ``result`` given the checker's answers on its ``settled``
    certificates: the first refuted one makes it VIOLATED; any not re-proved turns HOLDS into INCONCLUSIVE."""
    refuted = next((s for s in settled if s.status == "refuted"), None)
    if refuted is not None:
        return {"verdict": Verdict.VIOLATED,
                "summary": (f"a certified number is refuted by the independent checker: {refuted.claim}: "
                            f"{refuted.why}; " + result.summary),
                "counterexample": {"kind": "certificate-refuted", "data": {
                    "id": result.id, "certificate": refuted.written.content,
                    "where": memo[refuted.written.name]["where"]}}}
    unproved = list(dict.fromkeys(f"{s.file} ({s.status}: {s.why})" for s in settled if s.status != "re-proved"))
    if not unproved:
        return {}
    # certified means re-proved: a number the checker could not re-prove decides nothing
    return {"verdict": Verdict.INCONCLUSIVE if result.verdict == Verdict.HOLDS else result.verdict,
            "summary": (result.summary + f"; {len(unproved)} certified number(s) not re-proved by the independent "
                        "checker: " + ", ".join(unproved))}


def cited_entries(result):
    """The records ({hash, file, claim, status, ...}) of the certificates a check's result (results.json's entry,
    or a :class:`~inertiaproof.result.Result`) carries."""
    items = result.get("certificates") if isinstance(result, dict) else result.certificates
    return [entry_of(c) for c in items or []]


def certificate_tally(results):
    """({file: status} of the certificates the results (results.json entries or Results) carry, "N
    (OUT/certificates); k status, ..." in words)."""
    files = {entry.get("file") or entry["hash"]: entry.get("status", "not verified")
             for r in results for entry in cited_entries(r)}
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
