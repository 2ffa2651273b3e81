"""The other half of the shipped scenes of :mod:`test_scene_runs` (a second file, so that pytest-xdist can run the
two halves on two workers)."""

import pytest
from test_scene_runs import SCENES, run_shipped_scene

SECOND_HALF = SCENES[1::2]


@pytest.mark.parametrize("path", SECOND_HALF, ids=[p.stem for p in SECOND_HALF])
def test_every_shipped_scene_runs_without_a_crash_or_a_violation(path, tmp_path):
    run_shipped_scene(path, tmp_path)
