"""Verdicts that do not depend on the machine (issue 26): the clock-sensitive checks of the stiff thin rod (the
adaptive runs, the escape hunt and the stability study, which stop at wall-clock safety nets) give the same
verdicts on a machine with two CPU hogs running as on an idle one, and none is VIOLATED."""

from __future__ import annotations

import json
import multiprocessing
import subprocess
import sys

CHECKS = ("APP-robustness", "APP-estimate-bounds", "APP-euclidean-escape", "stability")


def _burn():
    while True:
        pass


def _verdicts(out):
    subprocess.run([sys.executable, "-m", "inertiaproof", "run", "--scene", "scenes/stiff_thin_rod.toml", "--quiet",
                    "--no-verify", "--out", str(out), "--only", *CHECKS], capture_output=True, timeout=300)
    return {c["id"]: c["verdict"] for c in json.loads((out / "results.json").read_text())["checks"]}


def test_the_thin_rod_gives_the_same_verdicts_under_two_cpu_hogs(tmp_path):
    idle = _verdicts(tmp_path / "idle")
    hogs = [multiprocessing.Process(target=_burn, daemon=True) for _ in range(2)]
    for hog in hogs:
        hog.start()
    try:
        busy = _verdicts(tmp_path / "busy")
    finally:
        for hog in hogs:
            hog.terminate()
    assert set(idle) == set(CHECKS) and busy == idle
    assert "VIOLATED" not in idle.values()
