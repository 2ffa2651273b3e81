"""Any input gives a result or exit 2 with one line naming the file (and the place): never a traceback, never a
hang. Hypothesis draws bytes, and mutations of good files, for every reader the command line has: inertial rows
(CSV, JSON), scenes (TOML), robots (URDF) and counterexamples given to ``replay``; the cases a bad-input pass over
the command line found are tests of their own below."""

import io
import json
import random
from contextlib import redirect_stderr, redirect_stdout
from datetime import timedelta
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from urdf_samples import two_link_arm

from inertiaproof import cli
from inertiaproof.scene.format import SceneError, parse_scene
from inertiaproof.suite.discovery import load_checks
from inertiaproof.suite.outputs import COUNTEREXAMPLE_SCHEMA
from inertiaproof.suite.registry import REPLAYERS

SCENES = sorted((Path(__file__).resolve().parent.parent / "scenes").glob("*.toml"))
FUZZ = settings(max_examples=60, derandomize=True, database=None, deadline=timedelta(seconds=20),
                suppress_health_check=list(HealthCheck))
CSV = ("name,m,h1,h2,h3,I11,I22,I33,I12,I23,I13\nbox,2.0,0,0,0.2,0.05,0.05,0.02,0,0,0\n"
       "plate,1,0,0,0,0.1,0.2,0.3,0,0,0\nbad,1,0,0,0,1,1,3,0,0,0\n")
JSON = json.dumps({"rows": [{"name": "rod", "mass": 1, "com_x": 0, "com_y": 0, "com_z": 0.5, "ixx": 0.1,
                             "iyy": 0.1, "izz": 0, "ixy": 0, "iyz": 0, "ixz": 0}]})
JUNK = ["", "nan", "inf", "-1e400", "1e-400", "1" * 5000, "0x10", "1_0", "true", "[1, 2]", "{}", '"', "\x00",
        "\u00e9", "-0", "1e60", "1e61", "[[[[[[[[[[[[[[[[]]]]]]]]]]]]]]]]", "\ufeff", "'a'", "\n[x]\n", "=", "#"]


def cli_run(*argv):
    """(exit status, stdout, stderr) of the command line, in this process; any exception fails the test."""
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        code = cli.main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


def assert_result_or_one_line(code, err, path, allowed=(0, 1)):
    """Either an answer (a status in ``allowed``) or exit 2 with one error line that names the file."""
    assert "Traceback" not in err
    errors = [line for line in err.splitlines() if line.startswith("inertiaproof: error:")]
    if code == 2:
        assert len(errors) == 1 and str(path) in errors[0], err
    else:
        assert code in allowed and not errors, (code, err)


def mutate(text, rng, junk=JUNK):
    """A few random edits of ``text``: a token replaced by junk, a line dropped or repeated, bytes spliced."""
    for _ in range(rng.randint(1, 4)):
        kind = rng.randrange(4)
        if kind == 0:
            tokens = [i for i, c in enumerate(text) if c in "=,\"'[ <>"]
            if tokens:
                i = rng.choice(tokens)
                j = min(len(text), i + 1 + rng.randrange(12))
                text = text[: i + 1] + rng.choice(junk) + text[j:]
        elif kind == 1:
            lines = text.splitlines(keepends=True)
            if lines:
                k = rng.randrange(len(lines))
                lines[k:k + 1] = [] if rng.random() < 0.5 else [lines[k]] * rng.randint(2, 3)
                text = "".join(lines)
        elif kind == 2:
            i = rng.randrange(len(text) + 1)
            text = text[:i] + rng.choice(junk) + text[i:]
        else:
            i, j = sorted(rng.randrange(len(text) + 1) for _ in range(2))
            text = text[:i] + text[j:] + text[i:j]
    return text


def encoded(text, rng):
    return text.encode(rng.choice(["utf-8", "utf-8-sig", "utf-16", "latin-1"]), errors="replace")


# -- inertial rows -------------------------------------------------------------------------------------------------

@FUZZ
@given(data=st.binary(max_size=3000), suffix=st.sampled_from([".csv", ".json", ".txt"]))
def test_any_bytes_as_rows(tmp_path_factory, data, suffix):
    path = tmp_path_factory.mktemp("rows") / f"rows{suffix}"
    path.write_bytes(data)
    code, _, err = cli_run("inertia", path, "--json")
    assert_result_or_one_line(code, err, path)


@FUZZ
@given(seed=st.integers(0, 2**32 - 1), which=st.sampled_from([(CSV, ".csv"), (JSON, ".json")]))
def test_mutated_rows(tmp_path_factory, seed, which):
    rng = random.Random(seed)
    text, suffix = which
    path = tmp_path_factory.mktemp("rows") / f"rows{suffix}"
    path.write_bytes(encoded(mutate(text, rng), rng))
    code, out, err = cli_run("inertia", path, "--json")
    assert_result_or_one_line(code, err, path)
    if code in (0, 1):
        assert all(entry["verdict"] in ("consistent", "degenerate", "inconsistent") for entry in json.loads(out))


# -- scenes --------------------------------------------------------------------------------------------------------

def parse_or_scene_error(text):
    try:
        parse_scene(text, "fuzz.toml")
    except SceneError as exc:
        message = str(exc)
        assert message.startswith("fuzz.toml") and "\n" not in message, message


@FUZZ
@given(data=st.binary(max_size=3000))
def test_any_bytes_as_a_scene(tmp_path_factory, data):
    path = tmp_path_factory.mktemp("scene") / "scene.toml"
    path.write_bytes(data)
    code, _, err = cli_run("list", "--scene", path)
    assert_result_or_one_line(code, err, path, allowed=(0,))


@settings(FUZZ, max_examples=150)
@given(seed=st.integers(0, 2**32 - 1), scene=st.sampled_from(SCENES))
def test_mutated_scenes(seed, scene):
    parse_or_scene_error(mutate(scene.read_text(), random.Random(seed)))


# -- robots --------------------------------------------------------------------------------------------------------

@FUZZ
@given(data=st.binary(max_size=3000))
def test_any_bytes_as_a_urdf(tmp_path_factory, data):
    path = tmp_path_factory.mktemp("urdf") / "robot.urdf"
    path.write_bytes(data)
    code, _, err = cli_run("audit", "--bounds", "none", path)
    assert_result_or_one_line(code, err, path)


@settings(FUZZ, max_examples=120)
@given(seed=st.integers(0, 2**32 - 1))
def test_mutated_urdfs(tmp_path_factory, seed):
    rng = random.Random(seed)
    path = tmp_path_factory.mktemp("urdf") / "robot.urdf"
    text = mutate(two_link_arm(tool='<inertial><mass value="0.1"/><inertia ixx="0" iyy="0" izz="0" ixy="0" iyz="0" '
                                    'ixz="0"/></inertial>'), rng, junk=JUNK + ["0.1", "-1", "1e-30", "0 0 0", "1 0"])
    path.write_bytes(text.encode() if rng.random() < 0.8 else encoded(text, rng))
    code, _, err = cli_run("audit", "--bounds", "arms", "--json", path)
    assert_result_or_one_line(code, err, path)
    assert all(line.startswith("inertiaproof: ") for line in err.splitlines())


# -- counterexamples -----------------------------------------------------------------------------------------------

VALUES = st.recursive(
    st.none() | st.booleans() | st.integers(-10**30, 10**30) | st.floats(allow_nan=False, allow_infinity=False)
    | st.text(max_size=8) | st.sampled_from([{"builtin": "planar-2r-payload"}, {"source": "/nonexistent.toml"}]),
    lambda inner: st.lists(inner, max_size=5) | st.dictionaries(st.text(max_size=6), inner, max_size=4),
    max_leaves=12)
FIELDS = ["id", "scene", "chain", "spectral", "sense", "resolution", "horizon", "density", "witness", "tolerances",
          "time", "thetas", "system", "steps", "state", "sigma", "reference_rtol", "q", "psi_dot", "psi", "property",
          "point", "pieces", "moments", "methods", "m", "inputs", "h", "factor", "entry", "constant_upper",
          "constant_lower", "rotation", "phi", "name", "lambda", "f", "example", "carrier_dimension", "qd", "qdd",
          "joint", "observed", "errors", "floor"]


VALID = {"kind": "pseudo_inertia", "id": "Thm1-nec",
         "data": {"f": [[2, 0, 0, 0.5], [0, 2, 0, 0], [0, 0, 2, 0], [0.5, 0, 0, 1]]}}


@st.composite
def tampered_counterexamples(draw):
    load_checks()
    kinds = sorted(set(REPLAYERS) - {"gate", "symbolic-claim", "boundary"})  # these re-derive whole checks
    if draw(st.booleans()):
        body = {"schema": COUNTEREXAMPLE_SCHEMA, "kind": draw(st.sampled_from(kinds)), "profile": "ci", "seed": 0,
                "data": draw(st.dictionaries(st.sampled_from(FIELDS), VALUES, max_size=8))}
    else:  # a good one with one entry of f, or f itself, replaced
        body = json.loads(json.dumps({"schema": COUNTEREXAMPLE_SCHEMA, **VALID}))
        row = draw(st.integers(0, 4))
        if row == 4:
            body["data"]["f"] = draw(VALUES)
        else:
            body["data"]["f"][row][draw(st.integers(0, 3))] = draw(VALUES)
    for key in draw(st.lists(st.sampled_from(["kind", "data", "seed", "profile", "schema"]), max_size=2)):
        if draw(st.booleans()):
            body.pop(key, None)
        else:
            body[key] = draw(VALUES)
    return body


@settings(FUZZ, max_examples=80)
@given(body=tampered_counterexamples())
def test_tampered_counterexamples(tmp_path_factory, body):
    path = tmp_path_factory.mktemp("cx") / "cx.json"
    path.write_text(json.dumps(body))
    code, _, err = cli_run("replay", path)
    assert_result_or_one_line(code, err, path, allowed=(0, 1, 3))


@FUZZ
@given(data=st.binary(max_size=2000))
def test_any_bytes_as_a_counterexample(tmp_path_factory, data):
    path = tmp_path_factory.mktemp("cx") / "cx.json"
    path.write_bytes(data)
    code, _, err = cli_run("replay", path)
    assert_result_or_one_line(code, err, path)


# -- the cases of the bad-input pass --------------------------------------------------------------------------------

@pytest.mark.parametrize("name, data, message", [
    ("latin1.csv", CSV.replace("box", "b\u00f6x").encode("latin-1"), ":2: not UTF-8 text: byte 0xf6 at column 2"),
    ("deep.json", b"[" * 100000 + b"]" * 100000, "nested too deeply"),
    ("big.json", ('[{"m": ' + "9" * 5000 + ', "h1": 0, "h2": 0, "h3": 0, "I11": 1, "I22": 1, "I33": 1, "I12": 0, '
                  '"I23": 0, "I13": 0}]').encode(), None),
    ("dup.csv", b"m,h1,h2,h3,I11,I22,I33,I12,I23,I13,m\n1,0,0,0,1,1,1,0,0,0,2\n", "column 'm' appears 2 times"),
    ("dup.json", b'[{"m": 1, "m": 2, "h1": 0}]', "field 'm' appears 2 times"),
])
def test_bad_rows_files(tmp_path, name, data, message):
    path = tmp_path / name
    path.write_bytes(data)
    code, out, err = cli_run("inertia", path, "--json")
    assert_result_or_one_line(code, err, path)
    if message:
        assert code == 2 and message in err
    else:
        assert code == 2 and "not finite" in json.loads(out)[0]["reason"]  # the row, not the file, is bad
        assert f"{path}: row 1: field m is not finite" in err


@pytest.mark.parametrize("encoding", ["utf-8-sig", "utf-16"])
def test_a_byte_order_mark_is_not_part_of_the_first_column(tmp_path, encoding):
    path = tmp_path / "rows.csv"
    path.write_bytes(CSV.encode(encoding))
    code, out, err = cli_run("inertia", path, "--json")
    assert code == 1 and err == ""
    assert [e["verdict"] for e in json.loads(out)] == ["consistent", "degenerate", "inconsistent"]


@pytest.mark.parametrize("text, message", [
    ("\x00\x01\x02binary", "fuzz.toml"),
    ("a = " + "[" * 5000 + "]" * 5000, "nested too deeply"),
])
def test_binary_or_deeply_nested_scenes(text, message):
    with pytest.raises(SceneError, match=message):
        parse_scene(text, "fuzz.toml")


def test_a_link_length_beyond_the_float_range_of_the_dynamics_is_named(tmp_path):
    scene = next(p for p in SCENES if p.stem == "non_normal_2r").read_text()
    path = tmp_path / "long.toml"
    path.write_text(scene.replace("xyz = [1.0, 0.0, 0.0]", "xyz = [1e300, 0.0, 0.0]", 1))
    code, _, err = cli_run("run", "--scene", path, "--out", tmp_path / "out", "--quiet")
    assert code == 2 and f"{path}:21: chain.joint[2].xyz: out of range (|x| <= 1e+60)" in err


def test_replay_of_an_indefinite_f_is_bad_input_not_a_violation(tmp_path):
    path = tmp_path / "cx.json"
    path.write_text(json.dumps({"schema": COUNTEREXAMPLE_SCHEMA, "kind": "pseudo_inertia", "id": "Thm1-nec",
                                "data": {"f": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, -1, 0], [0, 0, 0, 1]]}}))
    code, out, err = cli_run("replay", path)
    assert code == 2 and "VIOLATED" not in out and "Thm1-nec assumes f > 0" in err


@pytest.mark.parametrize("change", [
    lambda b: b.pop("data"), lambda b: b.update(data=None), lambda b: b.update(kind=7), lambda b: b.update(seed="x"),
    lambda b: b.update(profile=[1]), lambda b: b["data"].pop("f"), lambda b: b["data"].update(f="four"),
    lambda b: b["data"].update(f=[[1, 2], [3]]), lambda b: b.update(schema=None),
])
def test_tampered_counterexample_fields(tmp_path, change):
    body = {"schema": COUNTEREXAMPLE_SCHEMA, "kind": "pseudo_inertia", "id": "Thm1-nec", "profile": "ci", "seed": 0,
            "data": {"f": [[2, 0, 0, 0], [0, 2, 0, 0], [0, 0, 2, 0], [0, 0, 0, 1]]}}
    change(body)
    path = tmp_path / "cx.json"
    path.write_text(json.dumps(body))
    code, _, err = cli_run("replay", path)
    assert code == 2
    assert_result_or_one_line(code, err, path)


def test_only_a_scene_check_without_a_scene_runs_nothing_and_says_so(tmp_path):
    code, _, err = cli_run("run", "--only", "GRE:scene", "--out", tmp_path, "--quiet")
    assert code == 2 and "nothing to run: GRE:scene is left out" in err


def test_output_paths_are_checked_before_any_work(tmp_path, monkeypatch):
    from inertiaproof.suite import runner

    monkeypatch.setattr(runner, "run_checks", lambda **kw: pytest.fail("the checks ran before the paths were checked"))
    blocker = tmp_path / "file"
    blocker.write_text("")
    for argv in (["--out", blocker / "out"], ["--out", tmp_path / "o", "--junit", tmp_path],
                 ["--out", tmp_path / "o", "--junit", blocker / "j.xml"]):
        code, _, err = cli_run("run", "--only", "EQ-geom", "--quiet", *argv)
        assert code == 2 and err.count("\n") == 1, err


def test_counterexamples_are_never_lost(tmp_path, monkeypatch):
    from inertiaproof.result import Result, Verdict
    from inertiaproof.suite import registry

    load_checks()
    monkeypatch.setitem(registry.CHECKS, "Thm2:test", registry.CheckSpec(
        "Thm2", "Thm2:test", lambda ctx: Result("Thm2", Verdict.VIOLATED, "x", counterexample={
            "kind": "t", "data": {"x": 1}}), frozenset()))
    blocker = tmp_path / "file"
    blocker.write_text("")
    out = tmp_path / "out"
    code, printed, err = cli_run("run", "--only", "Thm2:test", "--quiet", "--out", out,
                                 "--counterexamples", blocker / "found")
    (saved,) = (out / "counterexamples").glob("Thm2-*.json")
    assert code == 1 and "they go to" in err and f"replay {saved}" in printed
    assert json.loads((out / "results.json").read_text())["checks"][0]["counterexample"]["file"] == str(saved)


def test_a_negative_audit_seed_is_one_line(tmp_path):
    path = tmp_path / "r.urdf"
    path.write_text(two_link_arm())
    code, _, err = cli_run("audit", "--seed", "-5", path)
    assert code == 2 and err.strip() == "inertiaproof: error: --seed must be a nonnegative integer, got -5"
