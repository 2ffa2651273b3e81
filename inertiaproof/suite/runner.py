"""Run checks: select what a scene needs, run, save counterexamples, write results.json and JUnit XML.

results.json (schema ``inertiaproof.results/1``)::

    {
      "schema": "inertiaproof.results/1",
      "profile": "ci", "seed": 0, "scene": null | "path/to/scene.toml",
      "runtime_s": 41.2, "versions": {"python": ..., "numpy": ..., ...},
      "summary": {"HOLDS": 27, "VIOLATED": 0, "INCONCLUSIVE": 1},
      "checks": [
        {"id": "Thm2", "check": "Thm2", "verdict": "HOLDS", "summary": "...",
         "runtime_s": 0.8, "seed": 0, "profile": "ci", "scene": null,
         "evidence": {...}, "counterexample": null | {"kind": ..., "data": ..., "file": ...},
         "artifacts": ["data/thm2-bracket.json"],
         "certificates": [{"hash": ..., "file": "certificates/<name>.json", "claim": ..., "status": ..., ...}]}
      ],
      "skipped": [{"check": "Thm4", "reason": "..."}]
    }

Every number in ``evidence`` is either plain data or a quantity
``{"value": ..., "kind": ..., "note": ...}`` (see inertiaproof.result.KINDS); a certified one cites its certificate
by hash (``"certificate": {"hash": ..., "file", "claim", "status", ...}``, the record of that hash in the check's
``certificates`` repeated where it is cited, for readers of one number).
"""

from __future__ import annotations

import json
import sys
import time
import traceback
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

from inertiaproof.budget import Budget, OutOfBudget, enforced
from inertiaproof.errors import InputError
from inertiaproof.result import Result, Verdict

from . import catalog
from .certificates import certificate_tally, settle
from .context import Context
from .discovery import load_checks
from .environment import versions
from .execution import Executor
from .history import expected_seconds, remember_seconds
from .lanes import side_by_side
from .outputs import Outputs, journal_path
from .profiles import PROFILES

__all__ = [
    "FEATURE_WORDS", "format_table", "progress_printer", "results_document", "Run", "run_checks", "select",
    "write_execution_log", "write_junit", "write_results",
]

FEATURE_WORDS = {
    "chain": "a chain",
    "time_varying": "time-varying parameters (the scene's are constant, so no rate-of-change check applies)",
    "internal_motion": "internal motion (the scene has no moving mass, Psi = 0)",
    "mass_change": "mass added or removed (the scene has no payload or scaling)",
    "symbolic": "symbolic work (not asked for: add --symbolic)",
}


@dataclass
class Run:
    results: list = field(default_factory=list)
    skipped: list = field(default_factory=list)  # (check name, reason)
    runtime_s: float = 0.0

    def counts(self):
        return {v.value: sum(r.verdict == v for r in self.results) for v in Verdict}

    @property
    def violated(self):
        return any(r.verdict == Verdict.VIOLATED for r in self.results)


def select(checks, *, only=None, scene=None, symbolic=False):
    """(specs to run, [(name, reason)] left out), in the paper's order."""
    specs = sorted(checks.values(), key=lambda s: (catalog.order(s.id), s.name))
    if only:
        known = {s.id for s in specs} | {s.name for s in specs}
        unknown = [x for x in only if x not in known]
        if unknown:
            raise InputError(f"unknown check ID {', '.join(unknown)}; see 'inertiaproof list'")
        specs = [s for s in specs if s.id in only or s.name in only]
    if scene is None:
        scene_only = [s for s in specs if "symbolic" in s.needs]
        return ([s for s in specs if s not in scene_only],
                [(s.name, "derives a scene's own chain: run it with --scene FILE --symbolic") for s in scene_only])
    have = set(scene.features()) | ({"symbolic"} if symbolic else set())
    run, skipped = [], []
    for s in specs:
        if not s.needs:
            skipped.append((s.name, "a statement about the paper, not about one scene: it runs without --scene"))
        elif not s.needs <= have:
            missing = sorted(s.needs - have)
            skipped.append((s.name, "needs " + "; ".join(FEATURE_WORDS.get(m, m) for m in missing)))
        else:
            run.append(s)
    return run, skipped


def run_checks(*, profile="ci", seed=0, only=None, scene=None, symbolic=False, out_dir=None,
               counterexample_dir=Path("counterexamples/found"), progress=None, executor=None, verify=True):
    """Run the selected checks and return a :class:`Run`.

    ``profile`` is a name of PROFILES or a :class:`Profile`; each check runs within its budget (the profile's
    ``check_s`` and ``memory_mb``, inside the run's ``run_s``) and ends INCONCLUSIVE when it runs out. Splittable
    work (hunt shards) goes to ``executor`` (:mod:`.execution`; default: this process). The certificates a check's
    evidence cites are written under ``out_dir``/certificates and, with ``verify``, re-proved by the independent
    checker (:mod:`.certificates`). An executor with lanes (:class:`~.execution.ForkExecutor`) runs the checks side by
    side in that many forked processes, the checks of one :func:`affinity` in one, the groups that took longest in the
    last run first (:mod:`.history`; :mod:`.lanes`); the results are the same, in the same order. Each batch of split
    work in the executor's log names its check."""
    profile = PROFILES[profile] if isinstance(profile, str) else profile
    checks = load_checks()
    specs, skipped = select(checks, only=only, scene=scene, symbolic=symbolic)
    if not specs:
        raise InputError("nothing to run: " + "; ".join(f"{name} is left out: {why}" for name, why in skipped))
    say = progress or (lambda message: None)
    if executor is None:
        executor = Executor()
    if progress is not None and executor.say is None:
        executor.say = lambda message: say(f"      {message}")
    if executor.log is None:
        executor.log = []  # each check's batches are named after it (and come back from its lane)
    if out_dir is not None:  # the journal of violations as they arrive, and the certificates, are this run's own
        journal_path(out_dir).unlink(missing_ok=True)
        for old in (Path(out_dir) / "certificates").glob("*.json"):
            old.unlink()
    run = Run(skipped=skipped)
    scene_name = getattr(scene, "source", None) or getattr(scene, "name", None)
    memo, proofs = {}, {}
    start = time.perf_counter()
    run_ends = time.monotonic() + profile.run_s

    def one(i):
        spec = specs[i]
        outputs = Outputs(out_dir, Path(counterexample_dir))
        budget = Budget.of(profile.check_s, profile.memory_mb * 2**20, until=run_ends)
        ctx = Context(profile, seed=seed, scene=scene, outputs=outputs, memo=memo, budget=budget, executor=executor,
                      progress=lambda message, name=spec.name: say(f"      {name}: {message}"))
        say(f"[{i + 1}/{len(specs)}] {spec.name} ...")
        batches = len(executor.log)
        with executor.computing():
            t0 = time.perf_counter()
            result = _run_one(spec, ctx, profile)
            result.runtime_s = time.perf_counter() - t0
            result = settle(result, out_dir=out_dir, boxes=profile.tree_boxes, verify=verify, memo=proofs,
                            executor=executor)
        for batch in executor.log[batches:]:
            batch["check"] = spec.name
        result.check, result.seed, result.profile = spec.name, seed, profile.name
        result.scene = scene_name
        result.artifacts = list(outputs.artifacts)
        if result.verdict == Verdict.VIOLATED and result.counterexample:
            try:
                result.counterexample["file"] = str(ctx.save_counterexample(result))
            except OSError as exc:  # it still goes into results.json
                result.counterexample["not_saved"] = f"{exc.filename or ''}: {exc.strerror or exc}"
        say(f"[{i + 1}/{len(specs)}] {spec.name}: {result.verdict} ({result.runtime_s:.2f} s)")
        return result, executor.log[batches:]

    groups = {}
    for i, spec in enumerate(specs):
        groups.setdefault(affinity(spec), []).append(i)
    lanes = min(executor.lanes, len(groups))
    if lanes > 1:
        found = {}

        def arrived(i, answer):
            found[i], batches = answer
            executor.log.extend(batches)

        def crashed(i, why):
            return Result(specs[i].id, Verdict.INCONCLUSIVE, f"the check crashed: {why}", evidence={"crashed": True},
                          check=specs[i].name, seed=seed, profile=profile.name), []

        def weight(group):  # the longest last time first; without a last time, checks on chains do the numeric work
            return (sum(last.get(specs[i].name, 0.0) for i in group), sum("chain" in specs[i].needs for i in group),
                    len(group))

        last = expected_seconds(profile.name, scene_name)

        side_by_side(sorted(groups.values(), key=weight, reverse=True), lanes, one, arrived, crashed)
        run.results.extend(found[i] for i in range(len(specs)))
    else:
        run.results.extend(one(i)[0] for i in range(len(specs)))
    run.runtime_s = time.perf_counter() - start
    remember_seconds(profile.name, scene_name, {r.check: r.runtime_s for r in run.results})
    return run


def affinity(spec):
    """The group a check runs in with ``lanes``: its module's ``SHARES`` (modules that reuse each other's shared
    results), else its module."""
    module = sys.modules[spec.fn.__module__]
    return getattr(module, "SHARES", module.__name__)


def _run_one(spec, ctx, profile):
    """The check's Result; INCONCLUSIVE (why: the budget, or the crash with its traceback) when it ends otherwise."""
    budget = ctx.budget
    limits = f"the {profile.name} profile allows {profile.check_s:g} s per check and {profile.run_s:g} s per run"
    if budget.expired:
        return Result(spec.id, Verdict.INCONCLUSIVE, f"not run: the run's time was spent before it ({limits})",
                      evidence={"budget": "time"})
    try:
        with enforced(budget, grace=min(10.0, 0.25 * profile.check_s)):
            return spec.fn(ctx)
    except OutOfBudget:
        return Result(spec.id, Verdict.INCONCLUSIVE, f"stopped without an answer: out of time ({limits})",
                      evidence={"budget": "time"})
    except MemoryError as exc:
        return Result(spec.id, Verdict.INCONCLUSIVE, f"out of memory: the check needed more than the {profile.name} "
                      f"profile's {profile.memory_mb} MiB ({exc or 'an allocation failed'})",
                      evidence={"budget": "memory", "traceback": traceback.format_exc()})
    except Exception as exc:  # a crashed check is reported, never silently passed
        if _caused_by(exc, OutOfBudget):  # the alarm struck inside a library that wrapped it (Hypothesis: Flaky...)
            return Result(spec.id, Verdict.INCONCLUSIVE, f"stopped without an answer: out of time ({limits})",
                          evidence={"budget": "time", "wrapped_in": type(exc).__name__})
        return Result(spec.id, Verdict.INCONCLUSIVE, f"the check crashed: {type(exc).__name__}: {exc}",
                      evidence={"traceback": traceback.format_exc(), "crashed": True})


def _caused_by(exc, kind):
    """Whether ``exc`` or an exception it was raised from or while handling is a ``kind``."""
    seen = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, kind):
            return True
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return False


def results_document(run, *, profile, seed, scene):
    return {
        "schema": "inertiaproof.results/1",
        "profile": profile,
        "seed": seed,
        "scene": scene,
        "runtime_s": run.runtime_s,
        "versions": versions(),
        "summary": run.counts(),
        "checks": [r.to_json() for r in run.results],
        "skipped": [{"check": name, "reason": reason} for name, reason in run.skipped],
    }


def write_results(path, document):
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(document, indent=1, sort_keys=False, allow_nan=False))
    return path


def write_execution_log(path, executor):
    """``OUT/execution.json``: how the splittable work ran (workers, each batch's kind, tasks, seconds per task,
    bytes moved). Timings only: not part of the answer, so kept out of results.json."""
    doc = {"schema": "inertiaproof.execution/1", "workers": executor.workers, "where": executor.describe(),
           "dashboard": executor.dashboard, "batches": executor.log or []}
    return write_results(path, doc)


def write_junit(path, run):
    """JUnit XML: VIOLATED is a failure, INCONCLUSIVE and left-out checks are skipped."""
    suite = ET.Element("testsuite", name="inertiaproof", tests=str(len(run.results) + len(run.skipped)),
                       failures=str(sum(r.verdict == Verdict.VIOLATED for r in run.results)),
                       skipped=str(sum(r.verdict == Verdict.INCONCLUSIVE for r in run.results) + len(run.skipped)),
                       time=f"{run.runtime_s:.3f}")
    for r in run.results:
        case = ET.SubElement(suite, "testcase", classname=f"section{catalog.BY_ID[r.id].section}",
                             name=r.check or r.id, time=f"{r.runtime_s:.3f}")
        if r.verdict == Verdict.VIOLATED:
            failure = ET.SubElement(case, "failure", message=r.summary)
            failure.text = json.dumps(r.counterexample or r.to_json()["evidence"], indent=1)[:20000]
        elif r.verdict == Verdict.INCONCLUSIVE:
            ET.SubElement(case, "skipped", message=f"INCONCLUSIVE: {r.summary}")
        ET.SubElement(case, "system-out").text = r.summary
    for name, reason in run.skipped:
        case = ET.SubElement(suite, "testcase", classname="left-out", name=name, time="0")
        ET.SubElement(case, "skipped", message=reason)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    ET.ElementTree(suite).write(path, encoding="utf-8", xml_declaration=True)
    return path


def certificate_line(run):
    """How many certified numbers cite a certificate, and what the independent checker said of them."""
    return "certificates: " + certificate_tally(run.results)[1]


def format_table(run, width=110):
    """The run as a plain-text table, then what was left out."""
    names = [r.check or r.id for r in run.results] + [name for name, _ in run.skipped]
    w = max([len(n) for n in names] + [16])
    lines = [f"{'ID':<{w}} {'verdict':<13} {'time/s':>7}  summary", "-" * width]
    room = max(width - w - 24, 30)
    for name, r in zip(names, run.results):
        summary = r.summary if len(r.summary) <= room else r.summary[: room - 3] + "..."
        lines.append(f"{name:<{w}} {str(r.verdict):<13} {r.runtime_s:>7.2f}  {summary}")
        if r.counterexample and r.counterexample.get("file"):
            lines.append(f"{'':<{w}} replay: inertiaproof replay {r.counterexample['file']}")
    if run.skipped:
        lines.append("")
        lines.append("left out:")
        lines.extend(f"  {name:<{w}} {reason}" for name, reason in run.skipped)
    c = run.counts()
    lines.append("")
    lines.append(f"{c['HOLDS']} HOLDS, {c['VIOLATED']} VIOLATED, {c['INCONCLUSIVE']} INCONCLUSIVE "
                 f"in {run.runtime_s:.1f} s")
    return "\n".join(lines)


def progress_printer(stream=sys.stderr):
    def say(message):
        print(message, file=stream, flush=True)

    return say
