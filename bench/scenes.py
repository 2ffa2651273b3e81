"""Every shipped scene in the ci profile: exit status, verdicts, wall time, and why each undecided check is undecided.

    python bench/scenes.py [--lanes 2] [--profile ci] [SCENE ...]     # default: scenes/*.toml, about 12 minutes

Runs ``inertiaproof run --scene SCENE --workers 1 --no-verify`` for each scene, ``--lanes`` at a time, each lane
pinned to its own core where the system allows it (so a scene's seconds are one core's, and OpenBLAS loads
with one thread as the command asks). Writes ``bench/results/scenes.json`` and ``bench/results/scenes.md``: per
scene the exit status, HOLDS / VIOLATED / INCONCLUSIVE counts and wall seconds, then every check that is not
HOLDS with its summary and notes, and the totals. Timings are wall-clock data on whatever machine runs this,
not assertions; the verdicts are decided by counts and are the same everywhere.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def run_scene(scene, out, profile, core):
    """One scene's run in a subprocess (pinned to ``core`` if possible): its row."""
    pin = (lambda: os.sched_setaffinity(0, {core})) if hasattr(os, "sched_setaffinity") and core is not None else None
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "inertiaproof", "run", "--scene", os.path.relpath(scene, ROOT),
                           "--profile", profile, "--workers", "1", "--no-verify", "--quiet", "--out", str(out)],
                          cwd=ROOT, capture_output=True, text=True, preexec_fn=pin)
    seconds = time.perf_counter() - start
    row = {"scene": scene.name, "exit": done.returncode, "seconds": round(seconds, 1)}
    results = out / "results.json"
    if not results.exists():
        return {**row, "error": (done.stderr or done.stdout).strip().splitlines()[-1:]}
    checks = json.loads(results.read_text())["checks"]
    row["counts"] = {v: sum(c["verdict"] == v for c in checks) for v in ("HOLDS", "VIOLATED", "INCONCLUSIVE")}
    row["undecided"] = [{"check": c["check"], "verdict": c["verdict"], "summary": c["summary"],
                         "notes": (c.get("evidence") or {}).get("notes") or []}
                        for c in checks if c["verdict"] != "HOLDS"]
    return row


def markdown(rows, profile):
    lines = [f"# Every shipped scene, `inertiaproof run --scene FILE --profile {profile} --workers 1`", "",
             "| scene | exit | HOLDS | VIOLATED | INCONCLUSIVE | s |", "|---|---|---|---|---|---|"]
    for r in rows:
        c = r.get("counts", {})
        lines.append(f"| {r['scene']} | {r['exit']} | {c.get('HOLDS', '-')} | {c.get('VIOLATED', '-')} | "
                     f"{c.get('INCONCLUSIVE', '-')} | {r['seconds']} |")
    total = {v: sum(r.get("counts", {}).get(v, 0) for r in rows) for v in ("HOLDS", "VIOLATED", "INCONCLUSIVE")}
    lines += ["", f"Totals: {total['HOLDS']} HOLDS, {total['VIOLATED']} VIOLATED, {total['INCONCLUSIVE']} "
                  f"INCONCLUSIVE over {len(rows)} scenes; exit 0 on {sum(r['exit'] == 0 for r in rows)}.", ""]
    for r in rows:
        for u in r.get("undecided", []):
            lines += [f"## {r['scene']}: {u['check']} {u['verdict']}", "", u["summary"], ""]
            lines += [f"- {note}" for note in u["notes"]] + ([""] if u["notes"] else [])
        if "error" in r:
            lines += [f"## {r['scene']}: no results", "", *r["error"], ""]
    return "\n".join(lines)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("scenes", nargs="*", type=Path, default=sorted((ROOT / "scenes").glob("*.toml")))
    p.add_argument("--lanes", type=int, default=2)
    p.add_argument("--profile", default="ci")
    args = p.parse_args(argv)
    cores = sorted(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else []
    with tempfile.TemporaryDirectory() as tmp, ThreadPoolExecutor(args.lanes) as pool:
        free = list(range(args.lanes))

        def lane(scene):
            slot = free.pop()
            try:
                row = run_scene(scene.resolve(), Path(tmp) / scene.stem, args.profile,
                                cores[slot % len(cores)] if cores else None)
            finally:
                free.append(slot)
            print(json.dumps({k: v for k, v in row.items() if k != "undecided"}), flush=True)
            return row

        rows = list(pool.map(lane, args.scenes))
    out = ROOT / "bench" / "results"
    (out / "scenes.json").write_text(json.dumps({"profile": args.profile, "scenes": rows}, indent=1) + "\n")
    (out / "scenes.md").write_text(markdown(rows, args.profile))
    print("written: bench/results/scenes.json, bench/results/scenes.md")
    return 0


if __name__ == "__main__":
    sys.exit(main())
