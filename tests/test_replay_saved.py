"""Every counterexample a run saves carries all it needs and replays to the verdict its check gave (issue 25).

A ci run and a reduced deep run (``inertiaproof run --only ...``) of checks made to fail in distinct ways: the
paper's alpha1 overstated (a "bound-bracket" and a pointwise "bound-point" on a scene, a "bound-point" hunted on
random chains), a certified number that the independent checker refutes ("certificate-refuted") and one whose
certificate is malformed (INCONCLUSIVE, nothing saved: a bad certificate shows nothing false), the certified alpha2 computed a tenth too small ("bound-constant": falsified code, so its
file replays VIOLATED on that code and HOLDS on the real one); and a scene run of the real APP-euclidean-escape,
which HOLDS and saves the run that escapes, replayed after its scene file is gone. Every file in the run's
counterexample folder is read back (self-contained JSON naming its check and kind) and replayed by ``inertiaproof
replay`` in a fresh process, from another folder.
"""

import json
import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

from inertiaproof import cli
from inertiaproof.bounds.certificate import spectrum_certificate
from inertiaproof.result import Result, Verdict, quantity
from inertiaproof.scene import robots
from inertiaproof.suite import registry
from inertiaproof.suite.discovery import load_checks
from inertiaproof.suite.outputs import COUNTEREXAMPLE_SCHEMA
from inertiaproof.suite.registry import CheckSpec

TESTS = Path(__file__).resolve().parent
STATUS = {"HOLDS": 0, "VIOLATED": 1, "INCONCLUSIVE": 3}
SCENE = robots.planar_2r(payload=1.0)  # alpha1: paper 4.7e-4, observed inf lambda_min(M) 0.12 (ratio ~257)


def _light(ctx):
    from inertiaproof.checks.constant_hunt import light_context

    return light_context(ctx)


def _overstated(k):
    """Theorem 2 on the planar 2R arm with the paper's alpha1 times k: k = 1000 lies beyond the value attained at
    the bracket's witness (bound-bracket); k = 150 only beyond the proof's pointwise inequality (bound-point)."""
    def fn(ctx):
        from inertiaproof.checks.bound_verdicts import run_scenes
        from inertiaproof.checks.mass_matrix_bounds import lower_bound_case

        return run_scenes("Thm2", _light(ctx), lower_bound_case, [SCENE], k)
    return fn


def _hunted(ctx):
    """Theorem 2's pointwise inequality times 1000, hunted on random chains (Hypothesis)."""
    from inertiaproof.checks.pointwise import with_hunt

    return with_hunt(ctx, Result("Thm2", Verdict.HOLDS, "hunt only"), 1000.0, moving_mass=None, examples=3)


def _certificate(tamper):
    """A certified inf lambda_min(M) of the planar 2R arm cited in the evidence, tampered: the runner's independent
    checker refutes it (claim above the witness: VIOLATED) or rejects it (a box removed from the partition: a bad
    certificate, INCONCLUSIVE)."""
    def fn(ctx):
        chain = robots.planar_2r().chain
        theta = robots.planar_2r().trajectory.theta(np.array([0.0]))[0]
        lo, hi = chain.coordinate_box()
        from inertiaproof.dynamics import composite

        q = lo + (hi - lo) * np.random.default_rng(0).random((500, chain.n))
        values = np.linalg.eigvalsh(composite.mass_matrix(chain, q[:, None], theta[None]))[..., 0].min(-1)
        i = int(np.argmin(values))
        cert = spectrum_certificate(chain, theta, "lambda_min", 0.9 * values[i], witness=q[i])
        tamper(cert, values[i])
        return Result("Thm2", Verdict.HOLDS, "held", {"bracket": {"lower": quantity(0.0, "lower_bound", certificate=cert)}})
    return fn


def _raised(cert, inf):
    cert["claim"]["bound"] = str(Fraction(1.01 * inf))


def _gap(cert, inf):
    cert["tree"] = "1 ."


def _optimistic_constants(*args, **kwargs):
    from inertiaproof.bounds import constants

    out = constants.upper_constants(*args, **kwargs)
    out["certified"]["value"] = out["certified"]["value"] / 10
    return out


def falsify(setattr_):
    """The falsified code of the bound-constant check: the certified alpha2 a tenth of what it is. ``setattr_`` is
    a MonkeyPatch's setattr in the run, the builtin in the fresh process that replays its file."""
    from inertiaproof.checks import mass_matrix_bounds

    setattr_(mass_matrix_bounds, "upper_constants", _optimistic_constants)


def _optimistic(ctx):
    from inertiaproof.checks.constant_hunt import with_reported_hunt

    return with_reported_hunt(ctx, Result("Thm3", Verdict.HOLDS, "hunt only"), moving_mass=False, examples=5)


CHECKS = {  # name: (catalog ID, check, saved under falsified code)
    "Thm2:overstated-bracket": ("Thm2", _overstated(1000.0), False),
    "Thm2:overstated-pointwise": ("Thm2", _overstated(150.0), False),
    "Thm2:overstated-hunted": ("Thm2", _hunted, False),
    "Thm2:refuted-certificate": ("Thm2", _certificate(_raised), False),
    "Thm2:malformed-certificate": ("Thm2", _certificate(_gap), False),
    "Thm3:optimistic-constant": ("Thm3", _optimistic, True),
}
VERDICTS = {name: "INCONCLUSIVE" if name == "Thm2:malformed-certificate" else "VIOLATED" for name in CHECKS}


def _verdicts_as_expected(doc):
    verdicts = {c["check"]: c["verdict"] for c in doc["checks"]}
    assert all(verdicts[name] == VERDICTS[name] for name in CHECKS), verdicts
    malformed = next(c for c in doc["checks"] if c["check"] == "Thm2:malformed-certificate")
    assert "bad certificate" in malformed["summary"], malformed["summary"]


def _run(tmp, profile, only, budget=None, scene=None):
    """Run ``only`` with the checks above registered; (results.json, {saved file: its check's entry})."""
    load_checks()
    out, found = tmp / "out", tmp / "found"
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("INERTIAPROOF_CACHE", str(tmp / "cache"))  # the deep run's example database
        for name, (check_id, fn, _) in CHECKS.items():
            mp.setitem(registry.CHECKS, name, CheckSpec(check_id, name, fn, frozenset()))
        falsify(mp.setattr)
        argv = ["run", "--profile", profile, "--only", *only, "--out", str(out), "--counterexamples", str(found),
                "--quiet", "--workers", "1"] + (["--budget", str(budget)] if budget else []) + (
                    ["--scene", str(scene)] if scene else [])
        assert cli.main(argv) in (0, 1, 3)
    doc = json.loads((out / "results.json").read_text())
    saved = {}
    for path in sorted(found.glob("*.json")):
        owners = [c for c in doc["checks"] if json.dumps(str(path)) in json.dumps(c)]
        assert len(owners) == 1, f"{path.name}: named by {len(owners)} checks of results.json"
        saved[path] = owners[0]
    for entry in doc["checks"]:  # every VIOLATED check saved its counterexample there
        if entry["verdict"] == "VIOLATED":
            assert Path((entry["counterexample"] or {}).get("file", "")) in saved, entry["check"]
    return doc, saved


def _replay(path, falsified, where):
    """Exit status and output of ``inertiaproof replay`` on a copy of ``path`` in the fresh folder ``where``, in a
    fresh process (with the falsified code of the run where the file was saved under it)."""
    copied = where / path.name
    copied.write_text(path.read_text())
    code = "import sys; from inertiaproof import cli; sys.exit(cli.main(['replay', sys.argv[1]]))"
    if falsified:
        code = f"import sys; sys.path.insert(0, {str(TESTS)!r}); import test_replay_saved; " \
               f"test_replay_saved.falsify(setattr); " + code
    done = subprocess.run([sys.executable, "-c", code, copied.name], cwd=where, capture_output=True, text=True,
                          timeout=300, check=False)
    return done.returncode, done.stdout + done.stderr


def _check_saved(doc, saved, tmp):
    where = tmp / "elsewhere"
    where.mkdir()
    wrong = []
    for path, entry in saved.items():
        body = json.loads(path.read_text())
        assert body["schema"] == COUNTEREXAMPLE_SCHEMA and body["id"] == entry["id"], path.name
        assert body["kind"] in registry.REPLAYERS and isinstance(body["data"], dict), path.name
        assert body["profile"] == doc["profile"] and body["seed"] == doc["seed"], path.name
        falsified = CHECKS.get(entry["check"], (None, None, False))[2]
        status, output = _replay(path, falsified, where)
        if status != STATUS[entry["verdict"]]:
            wrong.append(f"{path.name} ({entry['check']}, {body['kind']}): check {entry['verdict']}, replay exit "
                         f"{status}: {output.strip()[-300:]}")
        if falsified:  # on the real code the same point holds: the fault was the code's, not the file's
            status, output = _replay(path, False, where)
            if status != STATUS["HOLDS"]:
                wrong.append(f"{path.name} on the real code: exit {status}: {output.strip()[-300:]}")
    assert not wrong, "\n".join(wrong)
    return {json.loads(p.read_text())["kind"] for p in saved}


@pytest.fixture(scope="module")
def ci_run(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("ci")
    return tmp, *_run(tmp, "ci", list(CHECKS))


@pytest.fixture(scope="module")
def deep_run(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("deep")
    return tmp, *_run(tmp, "deep", list(CHECKS), budget=20)


def test_every_file_a_ci_run_saves_replays_to_its_verdict(ci_run):
    tmp, doc, saved = ci_run
    _verdicts_as_expected(doc)
    kinds = _check_saved(doc, saved, tmp)
    assert kinds == {"bound-bracket", "bound-point", "bound-constant", "certificate-refuted"}
    assert len(saved) >= sum(v == "VIOLATED" for v in VERDICTS.values())


@pytest.mark.slow
def test_every_file_a_deep_run_saves_replays_to_its_verdict(deep_run):
    tmp, doc, saved = deep_run
    _verdicts_as_expected(doc)
    kinds = _check_saved(doc, saved, tmp)
    assert {"bound-bracket", "bound-point", "bound-constant", "certificate-refuted"} <= kinds


def test_the_escape_a_scene_run_saves_replays_without_the_scene_file(tmp_path):
    scene = tmp_path / "scene.toml"
    scene.write_text((TESTS.parent / "scenes" / "planar_2r_payload.toml").read_text())
    doc, saved = _run(tmp_path, "ci", ["APP-euclidean-escape"], scene=scene)
    assert saved, doc["checks"]
    scene.unlink()  # the run is over: what its files need, they carry
    _check_saved(doc, saved, tmp_path)
