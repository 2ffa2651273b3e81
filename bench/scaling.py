"""How a run scales with workers (issues 16, 28): measured on this machine for 1 and 2 workers, estimated beyond.

    python bench/scaling.py [--profile deep] [--only ID ...] [--workers 1 2] [--timeout SECONDS]
    python bench/scaling.py --runs 1=DIR 2=DIR [--note TEXT]     # runs made by hand (OUT folders)

Runs ``inertiaproof run --profile P --workers W`` once per W, each with its own copy of the starting cache (the
deep profile's example database replays what earlier runs saved, so both runs must start from the same one), and
writes ``bench/results/scaling.json`` and ``scaling.md``:

- wall time and exit status per W, the machine's load average around each run (timings on a shared machine are
  inflated by the load);
- whether results.json is identical apart from its timing fields (``inertiaproof.suite.timings``), and where not;
- per kind of split work (``OUT/execution.json``): batches, tasks, seconds per task, bytes returned;
- an estimate for 1, 2, 8, 32 and 128 workers from the task graph of the run with the most workers (each check's
  own computation, its runtime less its batches' wall time, and its batches' tasks; each batch names its check):
  :func:`simulate` replays the run as the executor schedules it (lanes take the groups of checks longest first; a
  check computes holding a token, then its batches' tasks each take a free token) plus a per-task overhead and
  the bytes each task sends back at a cluster's bandwidth. The estimate for the measured worker counts is set
  beside the measurement.

Nothing is asserted; timings depend on the machine and its load.
"""

from __future__ import annotations

import argparse
import heapq
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from collections import deque
from pathlib import Path

from inertiaproof.suite.timings import without_timings

HERE = Path(__file__).resolve().parent
OVERHEAD_S = 5e-3  # overhead per task: a fork and its result's pickle here, a scheduler's round trip on Dask
BANDWIDTH = 100e6  # bytes per second between client and workers on a cluster network
ESTIMATE = (1, 2, 8, 32, 128)


def run_once(profile, workers, only, out, cache, timeout):
    cmd = [sys.executable, "-c", "import sys; from inertiaproof.cli import main; sys.exit(main())", "run",
           "--profile", profile, "--workers", str(workers), "--out", str(out), "--counterexamples",
           str(out / "found"), "--quiet"] + (["--only", *only] if only else [])
    env = {**os.environ, "INERTIAPROOF_CACHE": str(cache)}
    load = os.getloadavg()
    t0 = time.perf_counter()
    try:
        rc = subprocess.run(cmd, env=env, timeout=timeout, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode
    except subprocess.TimeoutExpired:
        rc = None
    return {"workers": workers, "wall_s": time.perf_counter() - t0, "exit_status": rc, "command": " ".join(cmd[3:]),
            "load_before": load, "load_after": os.getloadavg()}


def differences(a, b, path="", out=None, limit=40):
    out = [] if out is None else out
    if len(out) >= limit:
        return out
    if type(a) is not type(b):
        out.append(path)
    elif isinstance(a, dict):
        for k in sorted(set(a) | set(b)):
            differences(a.get(k), b.get(k), f"{path}/{k}", out, limit)
    elif isinstance(a, list):
        if len(a) != len(b):
            out.append(f"{path} (length {len(a)} vs {len(b)})")
        else:
            for i, (x, y) in enumerate(zip(a, b)):
                differences(x, y, f"{path}[{i}]", out, limit)
    elif a != b:
        out.append(path)
    return out


def kinds(batches):
    out = {}
    for b in batches:
        k = out.setdefault(b["kind"], {"batches": 0, "tasks": 0, "task_s": [], "wall_s": 0.0, "bytes_in": 0,
                                       "bytes_out": 0})
        k["batches"] += 1
        k["tasks"] += b["tasks"]
        k["task_s"] += b["task_s"]
        k["wall_s"] += b.get("wall_s", 0.0)
        k["bytes_in"] += b.get("bytes_in") or 0
        k["bytes_out"] += b.get("bytes_out") or 0
    for k in out.values():
        t = sorted(k.pop("task_s"))
        k["task_s"] = {"count": len(t), "sum": sum(t), "median": t[len(t) // 2] if t else None,
                       "max": t[-1] if t else None}
    return out


def task_graph(results, execution):
    """The run's work per check, in the order of results.json: {check, group, own_s (its computation outside its
    batches), batches: [[task seconds, ...], ...], bytes: [bytes per task of each batch]}; the groups as the
    runner forms them (:func:`inertiaproof.suite.runner.affinity`)."""
    from inertiaproof.suite.discovery import load_checks
    from inertiaproof.suite.runner import affinity

    specs = load_checks()
    batches = {}
    for b in execution["batches"]:
        batches.setdefault(b.get("check"), []).append(b)
    graph = []
    for c in results["checks"]:
        mine = [b for b in batches.get(c["check"], []) if b["task_s"]]
        graph.append({"check": c["check"], "group": affinity(specs[c["check"]]),
                      "own_s": max(c["runtime_s"] - sum(b["wall_s"] for b in mine), 0.0),
                      "batches": [b["task_s"] for b in mine],
                      "bytes": [(b.get("bytes_out") or 0) / max(len(b["task_s"]), 1) for b in mine]})
    return graph


def simulate(graph, workers, overhead_s=OVERHEAD_S, bandwidth=BANDWIDTH):
    """The run's wall time on ``workers`` tokens: ``workers`` lanes take the groups of checks (longest first, as the
    runner orders them after a run: :mod:`inertiaproof.suite.history`); a check's own computation holds a token,
    then its batches run one after the other, each task on the next free token (first come, first served) for its
    seconds plus ``overhead_s`` plus its bytes over ``bandwidth``. Returns {wall_s, busy_s: token-seconds computing,
    critical_s: the longest group alone, each batch as long as its longest task}."""
    groups = {}
    for c in graph:
        groups.setdefault(c["group"], []).append(c)
    order = deque(sorted(groups.values(), key=lambda g: sum(c["own_s"] + sum(map(sum, c["batches"])) for c in g),
                         reverse=True))  # the runner's order with a last run's times (suite.history)
    free, waiting, events, now, busy = workers, deque(), [], 0.0, 0.0
    seq = [0]

    def at(t, what):
        seq[0] += 1
        heapq.heappush(events, (t, seq[0], what))

    def request(what):  # what runs when a token is granted: (seconds, then)
        nonlocal free
        if free:
            free -= 1
            at(now + what[0], ("done", what))
        else:
            waiting.append(what)

    def lane_next(lane):
        if lane["checks"]:
            check = lane["checks"].popleft()
            request((check["own_s"], ("batches", lane, check, 0)))
        elif order:
            lane["checks"] = deque(order.popleft())
            lane_next(lane)

    def start_batch(lane, check, k):
        if k == len(check["batches"]):
            lane_next(lane)
            return
        tasks = check["batches"][k]
        left = {"n": len(tasks)}
        for t in tasks:
            request((t + overhead_s + check["bytes"][k] / bandwidth, ("task", lane, check, k, left)))

    for _ in range(workers):
        lane_next({"checks": deque()})
    while events:
        now, _, (_, (seconds, then)) = heapq.heappop(events)
        busy += seconds
        free += 1
        if waiting:
            request(waiting.popleft())
        if then[0] == "batches":
            start_batch(*then[1:])
        else:
            _, lane, check, k, left = then
            left["n"] -= 1
            if left["n"] == 0:
                start_batch(lane, check, k + 1)
    critical = max(sum(c["own_s"] + sum(max(b) + overhead_s for b in c["batches"]) for c in g)
                   for g in groups.values())
    return {"workers": workers, "wall_s": now, "busy_s": busy, "critical_s": critical}


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--profile", default="deep")
    p.add_argument("--only", nargs="+", default=None)
    p.add_argument("--workers", nargs="+", type=int, default=[1, 2])
    p.add_argument("--runs", nargs="+", metavar="W=DIR", help="runs made by hand: their OUT folders (W workers)")
    p.add_argument("--timeout", type=float, default=7200.0)
    p.add_argument("--out", default=str(HERE / "results"))
    p.add_argument("--note", default="", help="said in the results (how the runs were made)")
    args = p.parse_args(argv)
    results_dir = Path(args.out)
    results_dir.mkdir(parents=True, exist_ok=True)
    doc = {"schema": "inertiaproof.bench.scaling/2", "profile": args.profile, "only": args.only, "note": args.note,
           "cpus": os.cpu_count(), "overhead_s_per_task": OVERHEAD_S, "bandwidth_bytes_per_s": BANDWIDTH, "runs": []}
    docs, executions = {}, {}
    work = Path(tempfile.mkdtemp(prefix="inertiaproof-scaling-"))
    base_cache = Path(os.environ.get("INERTIAPROOF_CACHE", Path.home() / ".cache" / "inertiaproof"))
    made = [(int(w), Path(d)) for w, d in (r.split("=", 1) for r in args.runs)] if args.runs else None
    for w, out in made or [(w, work / f"out-{w}") for w in args.workers]:
        if made is None:
            cache = work / f"cache-{w}"
            if base_cache.is_dir():
                shutil.copytree(base_cache, cache, ignore=shutil.ignore_patterns("hypothesis"))
            print(f"running {args.profile} with {w} worker(s) ...", flush=True)
            r = run_once(args.profile, w, args.only, out, cache, args.timeout)
        else:
            r = {"workers": w, "command": f"by hand: {out}", "exit_status": None, "load_before": None,
                 "load_after": None}
        try:
            results = json.loads((out / "results.json").read_text())
            execution = json.loads((out / "execution.json").read_text())
        except (OSError, ValueError):
            results, execution = None, {"batches": []}
        if made is not None and results is not None:  # the run's own time; its exit status from its verdicts
            r["wall_s"] = results["runtime_s"]
            counts = results["summary"]
            r["exit_status"] = 1 if counts["VIOLATED"] else 3 if counts["INCONCLUSIVE"] else 0
        r["summary"] = results and results["summary"]
        r["check_s"] = results and {c["check"]: round(c["runtime_s"], 3) for c in results["checks"]}
        r["kinds"] = kinds(execution["batches"])
        docs[w], executions[w] = results, execution
        doc["runs"].append(r)
        print(f"  {w} worker(s): {r.get('wall_s', 0):.1f} s, exit {r['exit_status']}", flush=True)
    shutil.rmtree(work, ignore_errors=True)
    ones = next((r for r in doc["runs"] if r["workers"] == 1), None)
    for r in doc["runs"]:
        if ones is None or r is ones or docs.get(r["workers"]) is None or docs.get(1) is None:
            continue
        a, b = without_timings(docs[1]), without_timings(docs[r["workers"]])
        r["identical_to_one_worker"] = a == b
        r["differences"] = differences(a, b)
        r["speed_up"] = ones["wall_s"] / r["wall_s"]
    most = max((r for r in doc["runs"] if docs.get(r["workers"])), key=lambda r: r["workers"], default=None)
    if most is not None:
        graph = task_graph(docs[most["workers"]], executions[most["workers"]])
        doc["graph_from_workers"] = most["workers"]
        doc["graph"] = graph
        doc["estimate"] = [simulate(graph, w) for w in ESTIMATE]
    _write(doc, results_dir)
    return 0


def _write(doc, results_dir):
    (results_dir / "scaling.json").write_text(json.dumps(doc, indent=1))
    lines = [f"# Scaling of `inertiaproof run --profile {doc['profile']}`" + (f" --only {' '.join(doc['only'])}"
                                                                              if doc["only"] else ""), ""]
    if doc["note"]:
        lines += [doc["note"], ""]
    lines += ["| workers | wall s | exit | identical results.json | speed-up |", "|---|---|---|---|---|"]
    for r in doc["runs"]:
        lines.append(f"| {r['workers']} | {r['wall_s']:.1f} | {r['exit_status']} | "
                     f"{r.get('identical_to_one_worker', '-')} | {r.get('speed_up', 1.0):.2f} |")
    lines += ["", "| kind | workers | batches | tasks | median task s | max task s | sum task s | bytes out |",
              "|---|---|---|---|---|---|---|---|"]
    for r in doc["runs"]:
        for k, v in r["kinds"].items():
            t = v["task_s"]
            lines.append(f"| {k} | {r['workers']} | {v['batches']} | {v['tasks']} | {t['median'] or 0:.3g} | "
                         f"{t['max'] or 0:.3g} | {t['sum']:.1f} | {v['bytes_out']} |")
    lines += analysis(doc)
    (results_dir / "scaling.md").write_text("\n".join(lines) + "\n")


def analysis(doc):
    """The estimate and what bounds it."""
    if not doc.get("estimate"):
        return []
    graph = doc["graph"]
    own = sum(c["own_s"] for c in graph)
    split = sum(sum(b) for c in graph for b in c["batches"])
    one = next(e for e in doc["estimate"] if e["workers"] == 1)
    measured = {r["workers"]: r["wall_s"] for r in doc["runs"]}
    lines = ["", f"## Estimate (task graph of the {doc['graph_from_workers']}-worker run)", "",
             f"Work: {own + split:.0f} s, of which {split:.0f} s in {sum(len(b) for c in graph for b in c['batches'])}"
             f" split tasks and {own:.0f} s in the checks' own computations ({len(graph)} checks). Per task "
             f"{OVERHEAD_S * 1e3:g} ms plus its bytes at {BANDWIDTH / 1e6:g} MB/s.", "",
             "| workers | estimated wall s | measured wall s | speed-up (estimated) | longest group alone s |",
             "|---|---|---|---|---|"]
    for e in doc["estimate"]:
        m = measured.get(e["workers"])
        lines.append(f"| {e['workers']} | {e['wall_s']:.0f} | {'-' if m is None else f'{m:.0f}'} | "
                     f"{one['wall_s'] / e['wall_s']:.2f} | {e['critical_s']:.0f} |")
    longest = sorted(graph, key=lambda c: -c["own_s"])[:5]
    lines += ["", "What stays serial: the checks' own computations that no task splits, longest first:", ""]
    lines += [f"- {c['check']}: {c['own_s']:.0f} s own, {len(c['batches'])} batches ("
              f"{sum(len(b) for b in c['batches'])} tasks, {sum(sum(b) for b in c['batches']):.0f} s)" for c in longest]
    return lines


if __name__ == "__main__":
    sys.exit(main())
