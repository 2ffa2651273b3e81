"""An inverted bracket (a certified side beyond the value attained at its witness) refutes the certificate in the
checks that decide from certified sides of QJ and M brackets outside checks/bound_verdicts.py: Def2, Lem1,
Asm2/Lem2, Cor2 (checks/normality.py) and APP-estimate-bounds (checks/applications.py). Each is VIOLATED with a
"bound-bracket" counterexample that replays VIOLATED from its file; with the real brackets each still HOLDS."""

import dataclasses
import json

import numpy as np
import pytest

from inertiaproof.bounds.extremes import Bracket
from inertiaproof.checks import applications as app
from inertiaproof.checks import normality
from inertiaproof.checks.bound_verdicts import replay_bound_bracket
from inertiaproof.result import Verdict
from inertiaproof.scene import robots
from inertiaproof.suite.outputs import COUNTEREXAMPLE_SCHEMA
from inertiaproof.suite.replay import replay

KEY = "planar-2r-payload"


def _inverted(real, factor=None):
    """``real`` with the certified side of its bracket put beyond the value attained at the witness: twice it for
    an inf, half of it for a sup (``factor`` overrides). A copy: the bracket ``real`` returns is left alone."""
    def fn(*args, **kwargs):
        found = real(*args, **kwargs)
        k = factor if factor is not None else (2.0 if found.sense == "min" else 0.5)
        return dataclasses.replace(found, certified=found.observed * k, convergence=[])
    return fn


def _replayed(result, tmp_path):
    """The result's counterexample through a file, as ``inertiaproof replay FILE`` reads it."""
    path = tmp_path / "cx.json"
    path.write_text(json.dumps({"schema": COUNTEREXAMPLE_SCHEMA, "id": result.id, "profile": "ci", "seed": 0,
                                **result.counterexample}))
    return replay(path)


def _assert_refuted(result, tmp_path, quantity=None):
    assert result.verdict == Verdict.VIOLATED, result.summary
    assert "certificate is refuted" in result.summary
    assert result.counterexample["kind"] == "bound-bracket"
    assert result.counterexample["data"]["id"] == result.id
    if quantity is not None:
        assert result.counterexample["data"]["quantity"] == quantity
    replayed = _replayed(result, tmp_path)
    assert replayed.verdict == Verdict.VIOLATED, replayed.summary
    assert "certificate is refuted" in replayed.summary
    # the same file with the certified side put back on the right side of the value: the replay holds
    data = dict(result.counterexample["data"])
    data["certified"] = data["observed"] * (0.5 if data["bracket_sense"] == "min" else 2.0)
    assert replay_bound_bracket(data, None).verdict == Verdict.HOLDS


def _checks(ctx):
    return {"Def2": lambda: normality.def2_result(ctx, [robots.planar_2r(), robots.non_normal_2r()]),
            "Lem1": lambda: normality.lem1_result(ctx, (robots.planar_2r(),)),
            "Asm2/Lem2": lambda: normality.asm2_lem2_result(ctx),
            "Cor2": lambda: normality.cor2_result(ctx, robots.non_normal_2r())}


@pytest.mark.parametrize("check_id", ["Def2", "Lem1", "Asm2/Lem2", "Cor2"])
def test_the_real_brackets_hold(ctx, check_id):
    result = _checks(ctx)[check_id]()
    assert result.verdict == Verdict.HOLDS, result.summary
    assert "refuted_certificates" not in result.evidence


@pytest.mark.parametrize("check_id, function, quantity", [
    ("Def2", "jacobian_normality", "inf_q sigma_min(QJ)^2"),
    ("Lem1", "jacobian_normality", "inf_q sigma_min(QJ)^2"),
    ("Lem1", "mass_inf", "inf lambda_min(M(q, Theta))"),
    ("Asm2/Lem2", "jacobian_sup", "(sup_q sigma_max(QJ))^2"),
    ("Asm2/Lem2", "mass_sup", "sup lambda_max(M(q, Theta))"),
    ("Cor2", "jacobian_normality", "inf_q sigma_min(QJ)^2"),
    ("Cor2", "mass_inf", "inf lambda_min(M(q, Theta))"),
    ("Cor2", "mass_sup", "sup lambda_max(M(q, Theta))"),
])
def test_an_inverted_bracket_is_violated_and_replays(ctx, monkeypatch, tmp_path, check_id, function, quantity):
    monkeypatch.setattr(normality, function, _inverted(getattr(normality, function)))
    result = _checks(ctx)[check_id]()
    _assert_refuted(result, tmp_path, quantity)
    assert result.evidence["refuted_certificates"]


def test_a_certified_side_within_the_resolution_still_holds(ctx, monkeypatch):
    """Certified sides on the wrong side of the attained value by 1e-13 relative (below the resolution, 1e-9):
    rounding, not a refutation."""
    monkeypatch.setattr(normality, "jacobian_normality", _inverted(normality.jacobian_normality, 1 + 1e-13))
    monkeypatch.setattr(normality, "mass_sup", _inverted(normality.mass_sup, 1 - 1e-13))
    for check_id in ("Def2", "Lem1", "Cor2"):
        result = _checks(ctx)[check_id]()
        assert result.verdict == Verdict.HOLDS, (check_id, result.summary)


def test_an_inverted_bracket_beats_a_violated_identity(ctx, monkeypatch):
    """Def2 VIOLATED by its Gram identity (a wrong Theta) keeps its verdict; the refuted certificate leads, with
    the counterexample a file can replay."""
    monkeypatch.setattr(normality, "jacobian_normality", _inverted(normality.jacobian_normality))
    scene = robots.planar_2r()
    wrong = 2 * normality.unit_bodies(scene.chain)
    result = normality.def2_result(ctx, [scene], theta_for_identity=wrong)
    assert result.verdict == Verdict.VIOLATED
    assert result.counterexample["kind"] == "bound-bracket"


def test_a_refutation_the_file_cannot_show_is_inconclusive(ctx):
    """The bound_verdicts rule: a bracket whose attained value was not computed on what the file saves (here a
    made-up observed value) refutes nothing on replay: INCONCLUSIVE, no counterexample."""
    scene = robots.planar_2r()
    witness = np.array([0.3, 1.1])
    value = float(np.linalg.svd(scene.chain.body_jacobian(witness[None]), compute_uv=False)[0, -1] ** 2)
    fake = Bracket("inf_q sigma_min(QJ)^2", "min", 0.5 * value, value, witness, [], 1)
    verdict, why, _, cx = normality.bracket_refuted("Def2", scene, fake, normality.unit_bodies(scene.chain)[None],
                                                    "lmin")
    assert verdict == Verdict.INCONCLUSIVE and cx is None
    assert "refutes nothing" in why
    real = Bracket("inf_q sigma_min(QJ)^2", "min", value, 2 * value, witness, [], 1)
    verdict, _, _, cx = normality.bracket_refuted("Def2", scene, real, normality.unit_bodies(scene.chain)[None],
                                                  "lmin")
    assert verdict == Verdict.VIOLATED and cx["kind"] == "bound-bracket"
    assert normality.bracket_refuted("Def2", scene, Bracket("x", "min", value, 0.5 * value, witness), None,
                                     "lmin") is None


def test_estimate_bounds_hold_with_the_real_brackets(ctx):
    result = app.estimate_bounds_result(ctx, [KEY])
    assert result.verdict == Verdict.HOLDS, result.summary
    assert "refuted_certificates" not in result.evidence


@pytest.mark.parametrize("function, quantity", [("jacobian_normality", "inf_q sigma_min(QJ)^2"),
                                                ("jacobian_sup", "(sup_q sigma_max(QJ))^2")])
def test_estimate_bounds_with_an_inverted_qj_bracket_is_violated(ctx, monkeypatch, tmp_path, function, quantity):
    """Whatever the runs' margins show against the constants built on it, the refuted certificate makes the check
    VIOLATED, and its counterexample (not a run's) leads."""
    monkeypatch.setattr(app, function, _inverted(getattr(app, function)))
    result = app.estimate_bounds_result(ctx, [KEY])
    _assert_refuted(result, tmp_path, quantity)
    assert list(result.evidence["refuted_certificates"])[0].startswith(app.scene_of(KEY).name)
