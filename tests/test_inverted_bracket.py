"""An inverted bracket (a certified side beyond a value attained at its witness) or a pointwise failure refutes a
bound whatever else holds (issue 25), and the counterexample of an inverted bracket replays VIOLATED."""

import json

import numpy as np
import pytest

from inertiaproof.bounds.extremes import Bracket
from inertiaproof.bounds.spectral import spectral
from inertiaproof.checks.bound_verdicts import (
    case_result,
    inverted_bracket,
    judge,
    parameter_stack,
    replay_bound_bracket,
)
from inertiaproof.dynamics import composite
from inertiaproof.result import Verdict
from inertiaproof.scene import robots
from inertiaproof.suite.outputs import COUNTEREXAMPLE_SCHEMA
from inertiaproof.suite.replay import replay


def _sup(observed, certified):
    return Bracket("sup lambda_max(M)", "max", observed, certified, np.zeros(2), [[0.0, observed, certified]], 1)


def _inf(observed, certified):
    return Bracket("inf lambda_min(M)", "min", observed, certified, np.zeros(2), [[0.0, certified, observed]], 1)


def test_inverted_upper_bracket_is_violated():
    # the planar-2r case of the issue: certified sup 3.70 < attained 9.15, with a constant above both
    lhs = _sup(9.15, 3.70)
    assert inverted_bracket(lhs)
    for covers in (False, True):
        verdict, why = judge("upper", lhs, 10.0, 12.0, proof_covers=covers, pointwise_violated=False)
        assert verdict == Verdict.VIOLATED
        assert "certificate is refuted" in why and "upper side" in why


def test_inverted_lower_bracket_is_violated():
    lhs = _inf(0.5, 1.0)  # certified inf 1.0 above the value 0.5 attained at the witness
    assert inverted_bracket(lhs)
    verdict, why = judge("lower", lhs, 0.1, 0.2, proof_covers=True, pointwise_violated=False)
    assert verdict == Verdict.VIOLATED
    assert "certificate is refuted" in why and "lower side" in why


def test_bracket_within_resolution_is_not_inverted():
    assert not inverted_bracket(_sup(1.0, 1.0 - 1e-13))
    assert not inverted_bracket(_inf(1.0, 1.0 + 1e-13))
    assert not inverted_bracket(_sup(1.0, None))  # no certified side
    assert not inverted_bracket(_inf(1.0, None))


@pytest.mark.parametrize("sense, lhs, constants", [("upper", _sup(1.0, 1.1), (2.0, 3.0)),
                                                   ("lower", _inf(1.0, 0.9), (0.1, 0.2))])
def test_pointwise_violation_beats_a_certified_side(sense, lhs, constants):
    """The certified side lies within the constant (HOLDS by itself), and the proof covers it: a pointwise failure
    (or a reported constant failing against samples) still makes it VIOLATED."""
    verdict, _ = judge(sense, lhs, *constants, proof_covers=True, pointwise_violated=False)
    assert verdict == Verdict.HOLDS
    verdict, why = judge(sense, lhs, *constants, proof_covers=True, pointwise_violated=True)
    assert verdict == Verdict.VIOLATED
    assert "pointwise" in why


def test_normal_bracket_holds():
    verdict, why = judge("upper", _sup(1.0, 1.1), 2.0, 3.0, proof_covers=False, pointwise_violated=False)
    assert verdict == Verdict.HOLDS and "certified upper side" in why
    verdict, why = judge("lower", _inf(1.0, 0.9), 0.1, 0.2, proof_covers=False, pointwise_violated=False)
    assert verdict == Verdict.HOLDS and "certified lower side" in why
    verdict, _ = judge("upper", _sup(1.0, 2.5), 2.0, 3.0, proof_covers=False, pointwise_violated=False)
    assert verdict == Verdict.INCONCLUSIVE


def test_attained_beyond_constant_still_violated():
    verdict, why = judge("upper", _sup(4.0, 4.5), 3.0, 3.5, proof_covers=True, pointwise_violated=False)
    assert verdict == Verdict.VIOLATED and "exceeds the largest value" in why


QUIET = {"violated": False, "counterexample": None, "evidence": {}}


@pytest.mark.parametrize("check_id, sense, kind", [("Thm3", "upper", "lmax"), ("Thm2", "lower", "lmin")])
def test_inverted_bracket_counterexample_replays_violated(tmp_path, check_id, sense, kind):
    """A real chain: the value at the witness is the true value on the scene's parameter sets, the certified side
    is put beyond it, the constant is far on the safe side. The saved file replays VIOLATED from itself alone."""
    scene = robots.planar_2r(payload=1.0)
    thetas = parameter_stack(scene.trajectory, False)
    witness = np.array([0.3, 1.1])
    values = spectral(composite.mass_matrix(scene.chain, witness[None, None], thetas[None]), kind)[0]
    if sense == "upper":
        value = float(values.max())
        lhs = Bracket("sup lambda_max(M)", "max", value, 0.5 * value, witness, [[0.0, value, 0.5 * value]], 3)
        constant = (10 * value, 20 * value)
    else:
        value = float(values.min())
        lhs = Bracket("inf lambda_min(M)", "min", value, 2.0 * value, witness, [[0.0, 2.0 * value, value]], 3)
        constant = (0.05 * value, 0.1 * value)
    verdict, why, evidence, cx = case_result(check_id, scene, sense, lhs, constant, 1.0, 1.0, QUIET, {}, {},
                                             replay={"thetas": thetas, "spectral": kind})
    assert verdict == Verdict.VIOLATED, why
    assert "certificate is refuted" in why
    assert cx["kind"] == "bound-bracket"
    assert replay_bound_bracket(cx["data"], None).verdict == Verdict.VIOLATED
    # through a file, as `inertiaproof replay FILE` reads it
    path = tmp_path / "cx.json"
    path.write_text(json.dumps({"schema": COUNTEREXAMPLE_SCHEMA, "id": check_id, "profile": "ci", "seed": 0, **cx}))
    replayed = replay(path)
    assert replayed.verdict == Verdict.VIOLATED
    assert "certificate is refuted" in replayed.summary
    # the same witness with the certified side on the right side of the value: the replay holds
    cx["data"]["certified"] = 2.0 * value if sense == "upper" else 0.5 * value
    assert replay_bound_bracket(cx["data"], None).verdict == Verdict.HOLDS


def test_ingredients_audit_sees_an_inverted_bracket(ctx, monkeypatch):
    """Cor1:ingredients: a certified sup lambda_max(M) put just below the value attained at its witness (1e-6
    relative, below what most samples reach) is a failure of its own: "witness within the certified side"."""
    from inertiaproof.checks import bound_ingredients

    real = bound_ingredients.mass_sup

    def inverted(*args, **kwargs):
        found = real(*args, **kwargs)
        found.certified = found.observed * (1 - 1e-6)
        return found

    monkeypatch.setattr(bound_ingredients, "mass_sup", inverted)
    result = bound_ingredients.ingredients_result(ctx, [robots.planar_2r(payload=1.0)], {})
    assert result.verdict == Verdict.VIOLATED, result.summary
    found = result.evidence["findings"]["planar-2r"]
    assert found["sup lambda_max(M(q, Theta(t))): witness within the certified side"]["value"] > 1e-7


def test_def3_sees_an_inverted_time_extreme(monkeypatch):
    from inertiaproof.checks import mass_matrix_bounds

    trajectory = {"planar-2r": robots.planar_2r(payload=1.0).trajectory}
    assert mass_matrix_bounds.def3_result(trajectory).verdict == Verdict.HOLDS
    real = mass_matrix_bounds.time_extreme

    def inverted(traj, name, **kwargs):
        found = real(traj, name, **kwargs)
        if name == "lmin_f":  # a certified inf above the value attained on the time grid
            found = {**found, "certified": 2 * found["observed"]}
        return found

    monkeypatch.setattr(mass_matrix_bounds, "time_extreme", inverted)
    result = mass_matrix_bounds.def3_result(trajectory)
    assert result.verdict == Verdict.VIOLATED
    assert "certificate is refuted" in result.summary
