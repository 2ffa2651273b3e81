"""Every shipped scene runs every check it selects with no crash and nothing VIOLATED, and big scenes end within
the profile's budget (inertiaproof.budget) with honest INCONCLUSIVEs instead of hanging or exhausting memory.

The runs use the ci profile with fewer samples and a short budget per check (a full ci run of a scene takes
10 s to 2 min; ``inertiaproof run --scene FILE`` is that run): every check still goes through to its verdict and
its summary, which is where the crashes were; the slow simulations end INCONCLUSIVE at their budget.
"""

import dataclasses
import json
import time
from pathlib import Path

import pytest

from inertiaproof import cli
from inertiaproof.budget import Budget, OutOfBudget, enforced
from inertiaproof.result import Verdict
from inertiaproof.scene.format import load_scene, parse_scene
from inertiaproof.suite import runner
from inertiaproof.suite.profiles import PROFILES

SCENES = sorted((Path(__file__).resolve().parent.parent / "scenes").glob("*.toml"))
QUICK = dataclasses.replace(PROFILES["ci"], samples=256, rounds=2, examples=8, check_s=1.5, run_s=4.0,
                            tree_boxes=500)  # the checker still runs on every certificate; the prover completes
# a tree it does not re-prove with at most 500 boxes (the ci profile's 2,000 would take much of the run on the 24-link
# scene), and a certificate left not re-proved is an honest INCONCLUSIVE (test_verify*.py re-prove them in full)
OVERSHOOT_S = 30.0  # a check stopped by force ends at its next Python bytecode, after the NumPy or solver call
# in hand; generous, since the machine may be loaded: a hang would take minutes


def assert_honest(run, profile, seconds):
    for r in run.results:
        assert not r.evidence.get("crashed"), f"{r.check} crashed: {r.summary}\n{r.evidence.get('traceback')}"
        assert r.verdict != Verdict.VIOLATED, f"{r.check}: {r.summary}"
        if r.verdict == Verdict.INCONCLUSIVE:
            assert r.summary
    assert seconds <= profile.run_s + profile.check_s + OVERSHOOT_S
    json.dumps(runner.results_document(run, profile=profile.name, seed=0, scene="x"), allow_nan=False)


def run_shipped_scene(path, tmp_path):
    start = time.monotonic()
    run = runner.run_checks(profile=QUICK, scene=load_scene(path), out_dir=tmp_path,
                            counterexample_dir=tmp_path / "found")
    assert_honest(run, QUICK, time.monotonic() - start)
    assert run.results


FIRST_HALF = SCENES[::2]  # the other half runs in test_scene_runs_more.py: a test file is a unit of pytest-xdist's
# --dist loadfile, and the scenes take 2-3 minutes in all


@pytest.mark.parametrize("path", FIRST_HALF, ids=[p.stem for p in FIRST_HALF])
def test_every_shipped_scene_runs_without_a_crash_or_a_violation(path, tmp_path):
    run_shipped_scene(path, tmp_path)


def snake(joints):
    """A spatial snake arm of ``joints`` revolute joints (10 cm links of 0.5 kg) with a tip payload."""
    joint = '[[chain.joint]]\ntype = "revolute"\na = 0.1\nalpha = {alpha}\nlimits = [-1.0, 1.0]\n'
    body = ('[[body]]\nmass = 0.5\nsolid = { shape = "cylinder", dims = [0.02, 0.1], '
            'rpy = [0.0, 1.5707963267948966, 0.0], position = [-0.05, 0.0, 0.0] }\n')
    return (f'name = "snake-{joints}"\ndescription = "a {joints}-joint snake"\n[chain]\n'
            + "".join(joint.format(alpha=1.5707963267948966 * (-1) ** k) for k in range(joints)) + body * joints
            + f'[[load]]\nkind = "payload"\nbody = {joints}\nmass = 0.5\nsolid = {{ shape = "sphere", dims = [0.03] }}\n'
              'profile = { shape = "smootherstep", start = 0.2, duration = 0.3 }\n[time]\nend = 1.0\n'
              '[control]\nkind = "computed_torque"\nhorizon = 0.6\n')


@pytest.mark.parametrize("joints", [30, 200])
def test_big_scenes_end_within_the_budget(joints, tmp_path):
    profile = dataclasses.replace(PROFILES["ci"], check_s=1.0, run_s=4.0)
    scene = parse_scene(snake(joints), f"snake-{joints}.toml")
    start = time.monotonic()
    run = runner.run_checks(profile=profile, scene=scene, out_dir=tmp_path, counterexample_dir=tmp_path / "found")
    assert_honest(run, profile, time.monotonic() - start)
    out_of_time = [r for r in run.results if r.evidence.get("budget") == "time" or "budget" in r.summary]
    assert out_of_time, [r.summary for r in run.results]


def test_a_check_past_its_budget_is_stopped_and_named(monkeypatch, tmp_path):
    from inertiaproof.suite import registry

    def forever(ctx):
        while True:
            pass

    spec = registry.CheckSpec("Def2", "Def2", forever, frozenset())
    monkeypatch.setattr(runner, "load_checks", lambda: {"Def2": spec})
    profile = dataclasses.replace(PROFILES["ci"], check_s=0.3, run_s=5.0)
    start = time.monotonic()
    run = runner.run_checks(profile=profile, out_dir=tmp_path)
    assert time.monotonic() - start < 3.0
    (r,) = run.results
    assert r.verdict == Verdict.INCONCLUSIVE and not r.evidence.get("crashed")
    assert r.summary.startswith("stopped without an answer: out of time (the ci profile allows 0.3 s per check")


def test_the_budget_wrapped_by_a_library_is_out_of_time_not_a_crash(monkeypatch, tmp_path):
    """The alarm striking inside a Hypothesis test comes back as FlakyStrategyDefinition raised while handling
    OutOfBudget (seen on the 24-link scene's APP-euclidean-escape): out of time, not a crash."""
    from inertiaproof.suite import registry

    def wrapped(ctx):
        try:
            raise OutOfBudget("no answer within the time budget")
        except OutOfBudget:
            raise RuntimeError("Inconsistent data generation!")

    monkeypatch.setattr(runner, "load_checks", lambda: {"Def2": registry.CheckSpec("Def2", "Def2", wrapped, frozenset())})
    (r,) = runner.run_checks(profile=PROFILES["ci"], out_dir=tmp_path).results
    assert r.verdict == Verdict.INCONCLUSIVE and r.evidence["budget"] == "time" and not r.evidence.get("crashed")
    assert r.evidence["wrapped_in"] == "RuntimeError"


def test_memory_past_the_budget_is_inconclusive_not_a_crash(monkeypatch, tmp_path):
    import numpy as np

    from inertiaproof.suite import registry

    def greedy(ctx):
        return np.ones((1 << 33,))  # 64 GiB

    monkeypatch.setattr(runner, "load_checks", lambda: {"Def2": registry.CheckSpec("Def2", "Def2", greedy, frozenset())})
    (r,) = runner.run_checks(profile=dataclasses.replace(PROFILES["ci"], memory_mb=512), out_dir=tmp_path).results
    assert r.verdict == Verdict.INCONCLUSIVE and r.evidence["budget"] == "memory" and not r.evidence.get("crashed")
    assert "512 MiB" in r.summary


def test_enforced_leaves_no_alarm_behind():
    with pytest.raises(OutOfBudget):
        with enforced(Budget.of(0.05), grace=0.05):
            while True:
                pass
    time.sleep(1.2)  # a stray periodic alarm would raise here


def test_the_budget_is_on_the_command_line_too(tmp_path, capsys):
    code = cli.main(["run", "--only", "EQ-geom", "--budget", "30", "--quiet", "--out", str(tmp_path)])
    assert code == 0 and "EQ-geom" in capsys.readouterr().out
