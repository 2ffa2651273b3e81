"""Scene files: every one loads, runs exactly the checks it needs, and mistakes are named by file, line, field."""

from pathlib import Path

import pytest

from inertiaproof import cli
from inertiaproof.scene.format import SceneError, load_scene, parse_scene
from inertiaproof.suite.discovery import load_checks
from inertiaproof.suite.registry import CheckSpec
from inertiaproof.suite.runner import select

SCENES = Path(__file__).resolve().parent.parent / "scenes"

CONSTANT = {"chain"}
LOADING = {"chain", "time_varying", "mass_change"}
INTERNAL = {"chain", "time_varying", "internal_motion"}
FEATURES = {
    "extreme_lengths": LOADING | INTERNAL,
    "giant_2r": LOADING,
    "many_links_24": LOADING,
    "micro_2r": LOADING,
    "near_singular_cubic": LOADING,
    "non_normal_2r": CONSTANT,
    "panda_payload_3kg": LOADING,
    "passenger_platform": INTERNAL,
    "planar_2r_payload": LOADING,
    "sphere_counterexample": LOADING,
    "stiff_mass_ratio_1e6": LOADING,
    "stiff_payload_1ms": LOADING,
    "stiff_thin_rod": LOADING,
    "trolley_2r": INTERNAL,
    "ur5_constant": CONSTANT,
}

# A registry of the kinds of checks the whole suite will have, independent of what has landed.
FAKE = {name: CheckSpec(name.split(":")[0], name, lambda ctx: None, frozenset(needs)) for name, needs in {
    "EQ-geom": (),
    "GRE": ("chain", "symbolic"),
    "GRE-physics:internal-motion": ("chain", "time_varying", "internal_motion"),
    "GRE-physics:loading": ("chain", "time_varying", "mass_change"),
    "Def2": ("chain",),
    "Thm2": ("chain", "time_varying"),
    "Thm4": ("chain", "time_varying"),
    "EQ-acc": ("chain", "internal_motion"),
    "Asm3/Thm5": ("chain", "internal_motion"),
    "stability": ("chain",),
}.items()}
RUNS = {  # what each kind of scene must run from FAKE, without --symbolic
    frozenset(CONSTANT): {"Def2", "stability"},
    frozenset(LOADING): {"Def2", "Thm2", "Thm4", "GRE-physics:loading", "stability"},
    frozenset(INTERNAL): {"Def2", "Thm2", "Thm4", "EQ-acc", "Asm3/Thm5", "GRE-physics:internal-motion", "stability"},
    frozenset(LOADING | INTERNAL): {"Def2", "Thm2", "Thm4", "EQ-acc", "Asm3/Thm5", "GRE-physics:internal-motion",
                                    "GRE-physics:loading", "stability"},
}


def test_every_scene_file_is_listed_here():
    assert {p.stem for p in SCENES.glob("*.toml")} == set(FEATURES)


@pytest.fixture(scope="module", params=sorted(FEATURES))
def scene(request):
    return request.param, load_scene(SCENES / f"{request.param}.toml")


def test_scene_has_the_features_it_describes(scene):
    stem, s = scene
    assert set(s.features()) == FEATURES[stem]
    assert s.description and s.source.endswith(f"{stem}.toml")


@pytest.mark.parametrize("symbolic", [False, True])
def test_selection_runs_exactly_what_the_scene_needs(scene, symbolic):
    stem, s = scene
    run, skipped = select(FAKE, scene=s, symbolic=symbolic)
    expected = RUNS[frozenset(FEATURES[stem])] | ({"GRE"} if symbolic else set())
    assert {spec.name for spec in run} == expected
    reasons = dict(skipped)
    assert set(reasons) == set(FAKE) - expected
    assert "runs without --scene" in reasons["EQ-geom"]
    if not symbolic:
        assert "--symbolic" in reasons["GRE"]
    if "time_varying" not in FEATURES[stem]:
        assert "constant" in reasons["Thm4"]
    if "internal_motion" not in FEATURES[stem]:
        assert "no moving mass" in reasons["EQ-acc"]
    if "mass_change" not in FEATURES[stem]:
        assert "no payload or scaling" in reasons["GRE-physics:loading"]


def test_selection_with_the_registered_checks(scene):
    stem, s = scene
    checks = load_checks()
    run, skipped = select(checks, scene=s)
    names = {spec.name for spec in run}
    assert "stability" in names and "EQ-geom" not in names
    assert ("GRE-physics:loading" in names) == ("mass_change" in FEATURES[stem])
    assert ("GRE-physics:internal-motion" in names) == ("internal_motion" in FEATURES[stem])
    assert all(not spec.needs <= set(s.features()) or not spec.needs for spec in checks.values()
               if spec.name in dict(skipped))


def test_without_a_scene_everything_but_scene_derivations_is_selected():
    run, skipped = select(FAKE)
    scene_only = {spec.name for spec in FAKE.values() if "symbolic" in spec.needs}
    assert {spec.name for spec in run} == set(FAKE) - scene_only
    assert {name for name, _ in skipped} == scene_only


def test_list_prints_what_a_scene_leaves_out(capsys):
    assert cli.main(["list", "--scene", str(SCENES / "ur5_constant.toml")]) == 0
    out = capsys.readouterr().out
    assert "GRE-physics:loading" in out and "left out: needs mass added or removed" in out
    assert "stability" in out


def test_run_with_a_scene_prints_what_it_left_out(tmp_path, capsys):
    code = cli.main(["run", "--scene", str(SCENES / "trolley_2r.toml"), "--only", "GRE-physics", "--quiet",
                     "--out", str(tmp_path)])
    out = capsys.readouterr().out
    assert code == 0
    assert "GRE-physics:internal-motion HOLDS" in out
    assert "left out:" in out and "GRE-physics:loading" in out.split("left out:")[1]


BASE = (SCENES / "planar_2r_payload.toml").read_text()
LINE = {n + 1: line for n, line in enumerate(BASE.splitlines())}


def line_of(text):
    return next(n for n, line in LINE.items() if text in line)


MISTAKES = [  # (what is changed, into what, the line the error must name, the field it must name)
    ('name = "forearm"', 'name = "forearm"\ncolour = "red"', line_of('name = "forearm"') + 1, "body[2].colour"),
    ("mass = 3.0", "mass = -3.0", line_of("mass = 3.0"), "body[1].mass"),
    ("gravity = [0.0, -9.81, 0.0]", "gravity = [0.0, -9.81]", line_of("gravity ="), "chain.gravity"),
    ("dims = [0.04, 0.8]", "dims = [0.04]", line_of("dims = [0.04, 0.8]"), "body[2].solid.dims"),
    ('mass = 3.0\nsolid = { shape = "cylinder", dims = [0.05, 1.0], rpy = [0.0, 1.5707963267948966, 0.0], '
     'position = [-0.5, 0.0, 0.0] }', "mass = 3.0\ninertia = [0.1, 0.1, 0.3, 0.0, 0.0, 0.0]",
     line_of("mass = 3.0") + 1, "body[1].inertia"),
    ('mass = 3.0\nsolid = { shape = "cylinder", dims = [0.05, 1.0], rpy = [0.0, 1.5707963267948966, 0.0], '
     'position = [-0.5, 0.0, 0.0] }', "mass = 3.0\ninertia = [[1.0, 0.5, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]",
     line_of("mass = 3.0") + 1, "body[1].inertia"),
    ('shape = "sphere"', 'shape = "torus"', line_of('shape = "sphere"'), "load[1].solid.shape"),
    ("start = 1.0, duration = 0.5", "start = 1.0, duration = -0.5", line_of("duration = 0.5"),
     "load[1].profile.duration"),
    ("body = 2", "body = 3", line_of("body = 2"), "load[1].body"),
    ('kind = "payload"', 'kind = "gift"', line_of('kind = "payload"'), "load[1].kind"),
    ("a = 0.8", 'a = "0.8"', line_of("a = 0.8"), "chain.joint[2].a"),
    ("home = [0.3, 0.6]", "home = [0.3]", line_of("home ="), "control.home"),
    ("bandwidth = 10.0", "bandwith = 10.0", line_of("bandwidth"), "control.bandwith"),
    ("end = 3.0", "end = -1.0", line_of("end = 3.0"), "time.end"),
]


@pytest.mark.parametrize("old, new, line, field", MISTAKES, ids=[m[3] + ":" + m[1][:12] for m in MISTAKES])
def test_a_mistake_names_file_line_and_field(old, new, line, field):
    assert old in BASE
    with pytest.raises(SceneError) as info:
        parse_scene(BASE.replace(old, new, 1), "scenes/planar_2r_payload.toml")
    message = str(info.value)
    assert message.startswith(f"scenes/planar_2r_payload.toml:{line}: {field}: "), message
    assert "\n" not in message


def test_broken_toml_and_unreadable_files_are_one_line_errors(tmp_path, capsys):
    with pytest.raises(SceneError, match=r"^x.toml:\d+: not valid TOML"):
        parse_scene(BASE.replace("[time]", "[time"), "x.toml")
    code = cli.main(["run", "--scene", str(tmp_path / "missing.toml")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "missing.toml: cannot read scene file" in err
    bad = tmp_path / "bad.toml"
    bad.write_text(BASE.replace("mass = 3.0", "mass = 0.0", 1))
    assert cli.main(["run", "--scene", str(bad)]) == 2
    assert f"{bad}:{line_of('mass = 3.0')}: body[1].mass: must be > 0" in capsys.readouterr().err
