"""The other half of the shipped scenes of :mod:`test_scene_runs` (a second file, so that pytest-xdist can run the
two halves on two workers)."""

import pytest
from test_scene_runs import SCENES, run_shipped_scene

SECOND_HALF = SCENES[1::2]


@pytest.mark.slow  # the first half runs in the default set (test_scene_runs.py)
@pytest.mark.parametrize("path", SECOND_HALF, ids=[p.stem for p in SECOND_HALF])
def test_every_shipped_scene_runs_without_a_crash_or_a_violation(path, tmp_path):
    run_shipped_scene(path, tmp_path)


def test_a_line_mass_scene_runs_the_escape_hunt_without_a_crash(tmp_path):
    """A planar 2R arm whose upper arm is a rod with no inertia about its axis (a line mass, degenerate): no
    adaptive run can start from it, and the escape hunt says so instead of crashing on a margin it never had."""
    import json
    import subprocess
    import sys

    scene = tmp_path / "rod.toml"
    scene.write_text("""name = "rod-2r"
[chain]
convention = "standard"
gravity = [0.0, -9.81, 0.0]
[[chain.joint]]
type = "revolute"
a = 1.0
[[chain.joint]]
type = "revolute"
a = 0.8
[[body]]
mass = 3.0
com = [-0.5, 0.0, 0.0]
inertia = [0.0, 0.25, 0.25, 0.0, 0.0, 0.0]
[[body]]
mass = 2.0
com = [-0.4, 0.0, 0.0]
inertia = [0.001, 0.1, 0.1, 0.0, 0.0, 0.0]
[time]
start = 0.0
end = 3.0
""")
    done = subprocess.run([sys.executable, "-m", "inertiaproof", "run", "--scene", str(scene), "--only",
                           "APP-euclidean-escape", "--out", str(tmp_path / "out")], capture_output=True, text=True)
    result = json.loads((tmp_path / "out" / "results.json").read_text())["checks"][0]
    assert done.returncode in (0, 3) and not result["evidence"].get("crashed"), result["summary"]
    assert "no run started" in result["summary"]
