"""Scale (issue 49, item 6): the loading study's counted budget of dQJ/dq entries, its reuse of the solves a
refinement repeats, and a 30-joint serial scene (bench/scale_scenes.py) that ends with decided verdicts or
INCONCLUSIVEs that say why."""

import importlib.util
from pathlib import Path

import pytest

from inertiaproof.result import Verdict
from inertiaproof.scene import robots
from inertiaproof.scene.format import load_scene
from inertiaproof.sim import capture
from inertiaproof.sim.control import controller
from inertiaproof.suite import runner
from inertiaproof.suite.profiles import PROFILES

ROOT = Path(__file__).resolve().parents[1]
spec = importlib.util.spec_from_file_location("bench_scale_scenes", ROOT / "bench" / "scale_scenes.py")
scale = importlib.util.module_from_spec(spec)
spec.loader.exec_module(scale)


def _study(scene, **kw):
    control = controller(scene.chain, scene.trajectory, scene.control)
    return capture.study(scene.chain, scene.trajectory, control, (4, 8, 16, 32, 64), 128, horizon=scene.horizon(),
                         max_steps=2048, max_count=256, **kw)  # the ci profile's settings (checks.physics)


def test_a_study_the_entries_do_not_pay_for_is_inconclusive_and_names_the_count():
    scene = robots.BUILTIN["planar-2r-payload"]()
    free = _study(scene)
    assert free.verdict == Verdict.HOLDS and free.entries > 0
    paid = _study(scene, max_entries=free.entries)  # exactly what it spent: the same answer
    assert (paid.verdict, paid.at_rest, paid.history, paid.entries) == (free.verdict, free.at_rest, free.history,
                                                                         free.entries)
    least = capture.jacobian_entries(scene.chain, capture.least_points(free.history[0][0], capture.fixedstep.RK4))
    assert least <= free.entries
    short = _study(scene, max_entries=least - 1)  # a solve starts only when the entries left pay for its least cost
    assert short.verdict == Verdict.INCONCLUSIVE and "dQJ/dq entries does not pay for" in short.why
    assert short.entries == 0 and not short.history


def test_a_refinement_integrates_only_the_captures_it_has_not_seen():
    scene = robots.BUILTIN["planar-2r-payload"]()
    control = controller(scene.chain, scene.trajectory, scene.control)
    pieces = [capture.Pieces(k) for k in (4, 8)]
    memo = {}
    horizon = scene.horizon()
    first = capture.solve(scene.chain, scene.trajectory, control, pieces, 64, horizon=horizon, memo=memo)
    again = capture.solve(scene.chain, scene.trajectory, control, pieces + [capture.Pieces(16)], 64, horizon=horizon,
                          memo=memo)
    alone = capture.solve(scene.chain, scene.trajectory, control, pieces + [capture.Pieces(16)], 64, horizon=horizon)
    assert again.equation_points == 0 < first.equation_points == alone.equation_points
    assert again.work.evaluations < alone.work.evaluations
    for piece in alone.captures:
        assert (again.captures[piece] == alone.captures[piece]).all()
    assert (again.equation == alone.equation).all() and again.mode == alone.mode


def test_the_scale_generators_write_a_30_joint_scene_and_a_500_link_tree(tmp_path):
    scene_path, tree_path = scale.write(tmp_path)
    scene = load_scene(scene_path)
    assert scene.chain.n == 30 and "mass_change" in scene.features()
    assert tree_path.read_text().count("<joint ") == 500


@pytest.mark.slow
def test_a_30_joint_scene_ends_with_decided_or_explained_verdicts(tmp_path):
    scene_path, _ = scale.write(tmp_path / "scale")  # the APP checks read the scene again from its file
    scene = load_scene(scene_path)
    run = runner.run_checks(profile=PROFILES["ci"], scene=scene, out_dir=tmp_path,
                            counterexample_dir=tmp_path / "found")
    assert run.results
    for r in run.results:
        assert not r.evidence.get("crashed"), f"{r.check} crashed: {r.summary}"
        assert r.verdict != Verdict.VIOLATED, f"{r.check}: {r.summary}"
        assert r.verdict == Verdict.HOLDS or r.summary, r.check
    loading = next(r for r in run.results if r.check == "GRE-physics:loading")
    assert loading.verdict == Verdict.INCONCLUSIVE and "dQJ/dq entries" in loading.summary  # the count, not the clock
