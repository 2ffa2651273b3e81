"""Verdicts that do not depend on the machine (issue 26): the clock-sensitive checks of the stiff thin rod (the
adaptive runs, the escape hunt and the stability study, which stop at wall-clock safety nets) give the same
verdicts on a machine with two CPU hogs running as on an idle one, and none is VIOLATED (bench/cpu_hog.py, which
also runs the 24-link snake)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow  # two runs of the scene, one of them beside two CPU hogs

ROOT = Path(__file__).resolve().parents[1]
spec = importlib.util.spec_from_file_location("bench_cpu_hog", ROOT / "bench" / "cpu_hog.py")
bench = importlib.util.module_from_spec(spec)
spec.loader.exec_module(bench)
SCENE = "scenes/stiff_thin_rod.toml"


def test_the_thin_rod_gives_the_same_verdicts_under_two_cpu_hogs(tmp_path):
    idle = bench.verdicts(SCENE, tmp_path / "idle", timeout=300)["verdicts"]
    with bench.hogs(2):
        busy = bench.verdicts(SCENE, tmp_path / "busy", timeout=300)["verdicts"]
    assert set(idle) == set(bench.CHECKS) and busy == idle
    assert "VIOLATED" not in idle.values()
