"""Verdicts under load (issue 26): the clock-sensitive checks of a scene run idle and with CPU hogs running.

    python bench/cpu_hog.py [--hogs 2] [SCENE ...]      # default: the stiff thin rod and the 24-link snake

Runs ``inertiaproof run --scene SCENE --only APP-robustness APP-estimate-bounds APP-euclidean-escape stability``
once on the idle machine and once beside ``--hogs`` busy processes, and writes
``bench/results/cpu_hog.json``: per scene both runs' verdicts and wall times and whether the verdicts agree.
What decides a verdict is counted; the wall clock is a safety net, so the verdicts must agree and none may be
VIOLATED for a run that did not finish. (tests/test_cpu_hog.py runs the thin rod in CI; the snake takes a
minute a run, too long for the suite.)
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import subprocess
import sys
import tempfile
import time
from contextlib import contextmanager
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CHECKS = ("APP-robustness", "APP-estimate-bounds", "APP-euclidean-escape", "stability")
SCENES = ("scenes/stiff_thin_rod.toml", "scenes/many_links_24.toml")


def _burn():
    while True:
        pass


@contextmanager
def hogs(count):
    """``count`` busy processes running for the duration of the block."""
    busy = [multiprocessing.Process(target=_burn, daemon=True) for _ in range(count)]
    for hog in busy:
        hog.start()
    try:
        yield
    finally:
        for hog in busy:
            hog.terminate()


def verdicts(scene, out, timeout=1800):
    """The verdicts of CHECKS on ``scene`` (``inertiaproof run`` in a subprocess, results in ``out``) and its
    seconds."""
    start = time.perf_counter()
    subprocess.run([sys.executable, "-m", "inertiaproof", "run", "--scene", scene, "--quiet", "--no-verify",
                    "--out", str(out), "--only", *CHECKS], cwd=ROOT, capture_output=True, timeout=timeout)
    seconds = time.perf_counter() - start
    doc = json.loads((out / "results.json").read_text())
    return {"seconds": round(seconds, 1), "verdicts": {c["check"]: c["verdict"] for c in doc["checks"]}}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", nargs="*", default=SCENES)
    parser.add_argument("--hogs", type=int, default=2)
    args = parser.parse_args(argv)
    rows = {}
    with tempfile.TemporaryDirectory() as tmp:
        for scene in args.scenes:
            idle = verdicts(scene, Path(tmp) / "idle")
            with hogs(args.hogs):
                busy = verdicts(scene, Path(tmp) / "busy")
            rows[scene] = {"idle": idle, "busy": busy, "same": idle["verdicts"] == busy["verdicts"],
                           "violated": "VIOLATED" in {*idle["verdicts"].values(), *busy["verdicts"].values()}}
            print(scene, json.dumps(rows[scene]), flush=True)
    out = ROOT / "bench" / "results" / "cpu_hog.json"
    out.write_text(json.dumps({"hogs": args.hogs, "checks": CHECKS, "scenes": rows}, indent=1) + "\n")
    print(f"written: {out.relative_to(ROOT)}")
    return 0 if all(r["same"] and not r["violated"] for r in rows.values()) else 1


if __name__ == "__main__":
    sys.exit(main())
