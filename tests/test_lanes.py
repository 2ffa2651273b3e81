"""Checks side by side in forked lanes: the same answers as one after the other, and a lane that dies is a crash."""

import os

import pytest

from inertiaproof.result import Verdict
from inertiaproof.suite.execution import ForkExecutor
from inertiaproof.suite.lanes import side_by_side
from inertiaproof.suite.runner import affinity, run_checks
from inertiaproof.suite.discovery import load_checks

ONLY = ["EQ-geom", "EQ-translation", "Rem2", "Def1/Thm1-suff", "CX-normal", "Lem1", "Cor2", "GRE-physics"]


def _answers(run):
    return [(r.check, r.verdict, r.summary) for r in run.results]


@pytest.mark.slow
def test_lanes_give_the_answers_of_one_lane_in_the_same_order(tmp_path):
    one = run_checks(only=ONLY, out_dir=tmp_path / "one", verify=False)
    two = run_checks(only=ONLY, out_dir=tmp_path / "two", verify=False, executor=ForkExecutor(2))
    assert len(one.results) > 4 and all(r.verdict == Verdict.HOLDS for r in one.results)
    assert _answers(two) == _answers(one)


def test_checks_that_reuse_brackets_share_a_lane():
    checks = load_checks()
    assert affinity(checks["Thm2"]) == affinity(checks["Cor1:ingredients"]) == affinity(checks["Thm3"])
    assert affinity(checks["Def2"]) != affinity(checks["EQ-geom"])


def test_a_lane_that_dies_leaves_its_unfinished_checks_crashed_and_the_others_answered():
    found = {}

    def run_one(i):
        if i == 2:
            os._exit(9)  # the process is killed mid-group (a signal, the kernel's OOM killer)
        return f"answer {i}"

    side_by_side([[0], [1, 2, 3], [4]], 2, run_one, found.__setitem__, lambda i, why: f"crashed: {why}")
    assert found[0] == "answer 0" and found[1] == "answer 1"
    assert found[2].startswith("crashed") and found[3].startswith("crashed") and "exit code 9" in found[2]
    assert found[4] == "answer 4" and sorted(found) == [0, 1, 2, 3, 4]  # the lane left alive takes it


def test_the_workers_asked_for_are_the_lanes_run(tmp_path, monkeypatch, capsys):
    from inertiaproof.cli import main
    from inertiaproof.suite import runner

    seen = []
    real = runner.run_checks
    monkeypatch.setattr(runner, "run_checks", lambda **kw: seen.append(kw["executor"].lanes) or real(**kw))
    for workers in ("1", "3"):
        assert main(["run", "--only", "EQ-geom", "--workers", workers, "--no-verify", "--quiet",
                     "--out", str(tmp_path / workers)]) == 0
    assert seen == [1, 3]
    assert main(["run", "--only", "EQ-geom", "--workers", "0", "--out", str(tmp_path / "0")]) == 2
    assert "--workers must be at least 1" in capsys.readouterr().err


def test_the_groups_that_took_longest_last_time_start_first(tmp_path, monkeypatch):
    from inertiaproof.suite import history, runner

    monkeypatch.setenv("INERTIAPROOF_CACHE", str(tmp_path / "cache"))
    orders = []

    def in_order(groups, lanes, one, arrived, crashed):  # side_by_side, here: the groups in the order lanes take them
        orders.append([])
        for group in groups:
            orders[-1].append([])
            for i in group:
                answer = one(i)
                arrived(i, answer)
                orders[-1][-1].append(answer[0].check)

    only = ["EQ-geom", "Rem2", "CX-normal"]
    monkeypatch.setattr(runner, "side_by_side", in_order)
    runner.run_checks(only=only, verify=False, out_dir=tmp_path / "a", executor=ForkExecutor(2))
    assert set(history.last_seconds("ci")) == set(only)  # the run remembered its checks' times
    last = orders[0][-1]
    history.remember_seconds("ci", None, {last[0]: 100.0})
    runner.run_checks(only=only, verify=False, out_dir=tmp_path / "b", executor=ForkExecutor(2))
    assert orders[1][0] == last != orders[0][0]
