"""Exit status: 0 only when every check HOLDS, 1 VIOLATED or crashed, 3 INCONCLUSIVE and nothing VIOLATED."""

import json

import pytest

from inertiaproof import cli
from inertiaproof.cli.status import EXIT_STATUS, exit_status
from inertiaproof.result import Result, Verdict
from inertiaproof.suite import registry
from inertiaproof.suite.discovery import load_checks
from inertiaproof.suite.registry import CheckSpec


def _result(verdict, **evidence):
    return Result("Thm2", verdict, "test", evidence)


@pytest.mark.parametrize("verdicts, status", [
    ([], 0),
    ([Verdict.HOLDS, Verdict.HOLDS], 0),
    ([Verdict.HOLDS, Verdict.INCONCLUSIVE], 3),
    ([Verdict.INCONCLUSIVE, Verdict.VIOLATED], 1),
    ([Verdict.VIOLATED], 1),
])
def test_exit_status_of_verdicts(verdicts, status):
    assert exit_status(_result(v) for v in verdicts) == status


def test_a_crashed_check_is_status_1_although_its_verdict_is_inconclusive():
    assert exit_status([_result(Verdict.INCONCLUSIVE, crashed=True), _result(Verdict.HOLDS)]) == 1


@pytest.fixture
def checks(monkeypatch):
    """Registered checks that answer HOLDS, INCONCLUSIVE, VIOLATED or crash, and an INCONCLUSIVE replayer."""
    load_checks()

    def crash(ctx):
        raise RuntimeError("boom")

    answers = {
        "holds": lambda ctx: Result("Thm2", Verdict.HOLDS, "fine"),
        "unsure": lambda ctx: Result("Thm2", Verdict.INCONCLUSIVE, "margin below resolution",
                                     counterexample={"kind": "unsure-kind", "data": {}}),
        "wrong": lambda ctx: Result("Thm2", Verdict.VIOLATED, "wrong", counterexample={"kind": "unsure-kind",
                                                                                       "data": {}}),
        "crash": crash,
    }
    for name, fn in answers.items():
        monkeypatch.setitem(registry.CHECKS, f"Thm2:{name}", CheckSpec("Thm2", f"Thm2:{name}", fn, frozenset()))
    monkeypatch.setitem(registry.REPLAYERS, "unsure-kind",
                        lambda data, ctx: Result("Thm2", Verdict.INCONCLUSIVE, "still unsure"))


@pytest.mark.parametrize("only, status", [
    (["Thm2:holds"], 0),
    (["Thm2:holds", "Thm2:unsure"], 3),
    (["Thm2:unsure", "Thm2:wrong"], 1),
    (["Thm2:unsure", "Thm2:crash"], 1),
])
def test_run_exit_status(tmp_path, checks, only, status):
    argv = ["run", "--only", *only, "--out", str(tmp_path), "--counterexamples", str(tmp_path / "cx"), "--quiet"]
    assert cli.main(argv) == status
    summary = json.loads((tmp_path / "results.json").read_text())["summary"]
    assert summary["HOLDS"] + summary["INCONCLUSIVE"] + summary["VIOLATED"] == len(only)


def test_replay_of_an_inconclusive_answer_is_status_3(tmp_path, checks, capsys):
    cli.main(["run", "--only", "Thm2:wrong", "--out", str(tmp_path), "--counterexamples", str(tmp_path / "cx"),
              "--quiet"])
    (saved,) = (tmp_path / "cx").glob("Thm2-*.json")
    assert cli.main(["replay", str(saved)]) == 3
    assert "INCONCLUSIVE" in capsys.readouterr().out


@pytest.mark.parametrize("command", ["run", "replay", "inertia", "gate", "audit"])
def test_help_states_the_exit_status(command, capsys):
    with pytest.raises(SystemExit):
        cli.main([command, "--help"])
    out = " ".join(capsys.readouterr().out.split())
    assert "exit status:" in out and " ".join(EXIT_STATUS[command].split()) in out
    if command in ("run", "replay"):
        assert "3" in EXIT_STATUS[command] and "INCONCLUSIVE" in EXIT_STATUS[command]
