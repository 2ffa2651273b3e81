"""The run/replay/list contract: exit codes, results.json, JUnit, counterexample files, scene selection."""

import json
import xml.etree.ElementTree as ET

import pytest

from inertiaproof import cli
from inertiaproof.result import Result, Verdict
from inertiaproof.suite import registry
from inertiaproof.suite.discovery import load_checks
from inertiaproof.suite.registry import CheckSpec

SCENE = """
name = "two links"
[chain]
convention = "standard"
[[chain.joint]]
type = "revolute"
a = 1.0
[[chain.joint]]
type = "revolute"
a = 0.5
[[body]]
mass = 1.0
com = [-0.5, 0, 0]
inertia = [0.01, 0.1, 0.1, 0, 0, 0]
[[body]]
mass = 0.5
com = [-0.25, 0, 0]
inertia = [0.005, 0.02, 0.02, 0, 0, 0]
"""


@pytest.fixture
def violating_check(monkeypatch):
    """A registered check that always finds a counterexample, with its replayer."""
    load_checks()

    def fn(ctx):
        return Result("Thm2", Verdict.VIOLATED, "alpha1 exceeded", {"margin": -1.0},
                      counterexample={"kind": "test-kind", "data": {"x": 1}})

    monkeypatch.setitem(registry.CHECKS, "Thm2:test", CheckSpec("Thm2", "Thm2:test", fn, frozenset()))
    monkeypatch.setitem(registry.REPLAYERS, "test-kind",
                        lambda data, ctx: Result("Thm2", Verdict.VIOLATED, f"replayed x={data['x']}"))


def test_run_writes_results_and_junit(tmp_path, capsys):
    code = cli.main(["run", "--only", "EQ-geom", "--out", str(tmp_path), "--junit", str(tmp_path / "j.xml"), "--quiet"])
    assert code == 0
    doc = json.loads((tmp_path / "results.json").read_text())
    assert doc["schema"] == "inertiaproof.results/1"
    assert doc["summary"] == {"HOLDS": 1, "VIOLATED": 0, "INCONCLUSIVE": 0}
    (entry,) = doc["checks"]
    assert {"id", "verdict", "runtime_s", "evidence", "summary", "check"} <= set(entry)
    assert entry["id"] == "EQ-geom" and entry["verdict"] == "HOLDS"
    case = ET.parse(tmp_path / "j.xml").getroot().find("testcase")
    assert case.get("name") == "EQ-geom" and case.find("failure") is None
    assert "EQ-geom" in capsys.readouterr().out


def test_violated_exits_1_and_saves_a_replayable_counterexample(tmp_path, violating_check, capsys):
    cx = tmp_path / "cx"
    code = cli.main(["run", "--only", "Thm2:test", "--out", str(tmp_path), "--counterexamples", str(cx), "--quiet",
                     "--junit", str(tmp_path / "j.xml")])
    assert code == 1
    (saved,) = cx.glob("Thm2-*.json")
    assert json.loads(saved.read_text())["kind"] == "test-kind"
    assert ET.parse(tmp_path / "j.xml").getroot().find("testcase/failure") is not None
    assert f"inertiaproof replay {saved}" in capsys.readouterr().out
    assert cli.main(["replay", str(saved)]) == 1
    assert "replayed x=1" in capsys.readouterr().out


@pytest.mark.parametrize("argv, message", [
    (["run", "--only", "NOPE"], "unknown check ID NOPE"),
    (["run", "--scene", "/nonexistent.toml"], "cannot read scene file"),
    (["replay", "/nonexistent.json"], "cannot read"),
    (["inertia", "/nonexistent.csv"], "cannot read"),
])
def test_bad_input_is_one_line_and_exit_2(argv, message, capsys, tmp_path):
    assert cli.main(argv + (["--out", str(tmp_path)] if argv[0] == "run" else [])) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("inertiaproof: error:") and message in err and "\n" not in err


def test_replay_rejects_a_file_that_is_not_a_counterexample(tmp_path, capsys):
    path = tmp_path / "x.json"
    path.write_text('{"hello": 1}')
    assert cli.main(["replay", str(path)]) == 2
    assert "not an inertiaproof counterexample" in capsys.readouterr().err


def test_scene_run_leaves_out_paper_level_checks_with_a_reason(tmp_path, capsys):
    scene = tmp_path / "s.toml"
    scene.write_text(SCENE)
    assert cli.main(["run", "--scene", str(scene), "--out", str(tmp_path), "--quiet", "--only", "Def2", "EQ-geom"]) == 0
    doc = json.loads((tmp_path / "results.json").read_text())
    reasons = {s["check"]: s["reason"] for s in doc["skipped"]}
    assert "runs without --scene" in reasons["EQ-geom"]
    assert "left out:" in capsys.readouterr().out


def test_inertia_command_classifies_rows(tmp_path, capsys):
    path = tmp_path / "rows.csv"
    path.write_text("name,mass,com_x,com_y,com_z,ixx,iyy,izz,ixy,iyz,ixz\n"
                    "box,1,0,0,0,0.1,0.1,0.1,0,0,0\n"
                    "bad,1,0,0,0,1,1,3,0,0,0\n")
    assert cli.main(["inertia", str(path), "--json"]) == 1
    rows = json.loads(capsys.readouterr().out)
    assert [r["verdict"] for r in rows] == ["consistent", "inconsistent"]
    assert "triangle inequality" in rows[1]["reason"]


def test_symbolic_work_on_a_scene_only_when_asked(tmp_path, capsys):
    scene = tmp_path / "s.toml"
    scene.write_text(SCENE)
    assert cli.main(["run", "--scene", str(scene), "--only", "GRE", "--out", str(tmp_path), "--quiet"]) == 2
    assert "GRE:scene is left out: needs symbolic work (not asked for: add --symbolic)" in capsys.readouterr().err
    assert cli.main(["run", "--scene", str(scene), "--symbolic", "--only", "GRE", "--out", str(tmp_path), "--quiet"]) == 0
    doc = json.loads((tmp_path / "results.json").read_text())
    (result,) = doc["checks"]
    assert result["check"] == "GRE:scene" and result["verdict"] == "HOLDS"
    assert all(v == "detected" or v == "vacuous" for v in
               next(iter(result["evidence"]["systems"].values()))["negative_controls"].values())


def test_an_unwritable_output_folder_is_one_line_and_exit_2(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    assert cli.main(["run", "--only", "EQ-geom", "--out", str(blocker / "out"), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("inertiaproof: error:") and "\n" not in err


def test_a_wrong_equation_on_a_scene_is_violated(tmp_path, monkeypatch):
    """The scene variant of GRE, handed the paper's equation without M(q, Thetadot), must say VIOLATED."""
    from dataclasses import replace

    from inertiaproof.checks import scene_equation
    from inertiaproof.symbolic.claims import CLAIMS

    from inertiaproof.scene.format import parse_scene
    from inertiaproof.suite.context import Context
    from inertiaproof.suite.outputs import Outputs
    from inertiaproof.suite.profiles import PROFILES

    claim = CLAIMS["GRE"]
    drop = claim.controls["drop M(q, Thetadot)"]
    wrong = replace(claim, residual=lambda d, **kw: claim.residual(d, **(kw or drop(d))))
    monkeypatch.setitem(scene_equation.CLAIMS, "GRE", wrong)
    ctx = Context(PROFILES["ci"], scene=parse_scene(SCENE), outputs=Outputs(counterexample_dir=tmp_path))
    assert scene_equation.decide_on_scene("GRE", ctx).verdict == Verdict.VIOLATED


def test_a_flat_solid_in_a_scene_is_a_one_line_error(tmp_path, capsys):
    scene = tmp_path / "flat.toml"
    scene.write_text('name = "flat"\n[chain]\n[[chain.joint]]\ntype = "revolute"\n[[body]]\nmass = 1.0\n'
                     'solid = { shape = "tetrahedron", dims = [0,0,0, 1,0,0, 0,1,0, 1,1,0] }\n')
    assert cli.main(["run", "--scene", str(scene), "--out", str(tmp_path), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert "body[1].solid.dims" in err and "coplanar" in err and "\n" not in err


def test_the_command_loads_blas_with_one_thread():
    """BLAS rounds by its thread count at load (extreme_lengths' Radau reference stopped at t = 0.076 with two
    threads, 0.077 with one): the command loads it with one on any machine, unless the user says otherwise."""
    import os
    import subprocess
    import sys

    probe = ("import inertiaproof.cli, numpy; from threadpoolctl import threadpool_info; "
             "print(sorted({i['num_threads'] for i in threadpool_info() if i['user_api'] == 'blas'}))")
    env = {k: v for k, v in os.environ.items() if k not in ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")}
    out = subprocess.run([sys.executable, "-c", probe], env=env, capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[1]"
