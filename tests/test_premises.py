"""Issue 26, item 3: a scene built to break a premise of Section 4.1 gets a decided verdict with the failed premise
and its exact witness (Cor1 on CX-normal and CX-sphere), not INCONCLUSIVE; a scene whose premises hold is checked
as before, a misstated constant stays VIOLATED, and what cannot be decided stays INCONCLUSIVE, named."""

from dataclasses import replace

import numpy as np
from inertiaproof.checks.forward_kinematics import FORWARD_KINEMATICS_CONTROLS, PART, kinematics_result, off_by
from inertiaproof.checks.mass_matrix_bounds import _cor1_row, cor1_result
from inertiaproof.checks.normality import def2_result

from inertiaproof.bounds.certificate import SpectrumClaim, spatial_psd
from inertiaproof.bounds.premises import (
    NORMAL,
    UNIFORMLY_CONSISTENT,
    UPPER_BOUNDED,
    failed_premises,
    normality_failures,
    parameter_failures,
    unsimulable,
)
from inertiaproof.dynamics.chain import Chain, Coordinate, Joint
from inertiaproof.model.inertia import unit_body
from inertiaproof.result import Verdict, quantity
from inertiaproof.scene import robots
from inertiaproof.verify.cli import check as reprove


def test_the_cubic_shoulder_is_certified_not_normal_at_q1_zero():
    chain = robots.non_normal_2r().chain
    (found,) = normality_failures(chain)
    assert found["premise"] == NORMAL and found["witness"]["joint"] == 1
    q = np.array(found["witness"]["q"])
    assert q[0] == 0.0 and found["witness"]["derivative"]["kind"] == "exact"
    assert np.all(chain.body_jacobian(q[None])[0][:, 0] == 0.0)  # the column the chain rule says vanishes
    assert found["witness"]["sigma_min_QJ"]["value"] == 0.0


def test_normal_chains_and_maps_without_a_zero_derivative_show_no_failure():
    for scene in (robots.planar_2r(), robots.panda(), robots.spatial_3r()):
        assert normality_failures(scene.chain) == []
    arctan = Chain((Joint("revolute", (0, 0, 1), coordinate=Coordinate("arctan"), limits=(-2.0, 2.0)),))
    assert normality_failures(arctan) == []  # g' = 1 / (1 + q^2) > 0 on the range: nothing certified
    shifted = Chain((Joint("revolute", (0, 0, 1), coordinate=Coordinate("cubic"), limits=(0.5, 1.5)),))
    assert normality_failures(shifted) == []  # g' = 3 q^2 vanishes only outside the range


def test_a_decaying_sphere_is_certified_not_uniformly_consistent_and_a_growing_one_not_upper_bounded():
    (decaying,) = parameter_failures(robots.translating_sphere(-0.5).trajectory)
    assert decaying["premise"] == UNIFORMLY_CONSISTENT and decaying["witness"]["time"] == "inf"
    assert decaying["witness"]["s"] == 0.0 and decaying["witness"]["f_definiteness"] == "psd"
    (growing,) = parameter_failures(robots.translating_sphere(0.5).trajectory)
    assert growing["premise"] == UPPER_BOUNDED
    for scene in (robots.planar_2r(payload=1.0), robots.panda(payload=2.0), robots.trolley_2r()):
        assert parameter_failures(scene.trajectory) == []


def test_a_payload_that_empties_a_body_is_a_failure_at_a_finite_time():
    """A payload of -Phi_base ramping in leaves body 2 with f = 0 once the ramp ends: certified at that time."""
    scene = robots.planar_2r(payload=1.0)
    traj = scene.trajectory
    load = traj.loads[0]
    emptied = replace(traj, loads=(replace(load, phi=-traj.base[load.body]),))
    (found,) = parameter_failures(emptied)
    assert found["premise"] == UNIFORMLY_CONSISTENT and found["witness"]["s"] == 1.0
    assert np.isfinite(found["witness"]["time"])


def test_cor1_on_a_broken_premise_holds_with_the_witness_and_a_misstated_constant_stays_violated(ctx):
    for scene, premise in ((robots.non_normal_2r(), NORMAL), (robots.translating_sphere(-0.5), UNIFORMLY_CONSISTENT)):
        result = cor1_result(ctx, [scene])
        row = result.evidence["scenes"][scene.name]
        assert result.verdict == Verdict.HOLDS, result.summary
        assert not row["ordered"] and row["premises_failed"][0]["premise"] == premise
        assert "premise fails" in result.summary and "claims nothing here" in result.summary
    bad = cor1_result(ctx, [robots.translating_sphere(-0.5)], k_upper=0.01)
    assert bad.verdict == Verdict.VIOLATED  # Theorem 3 is still judged: a failed premise hides no violation


def test_cor1_on_a_scene_whose_premises_hold_is_the_normal_check(ctx):
    scene = robots.planar_2r(payload=1.0)
    result = cor1_result(ctx, [scene])
    row = result.evidence["scenes"][scene.name]
    assert result.verdict == Verdict.HOLDS and row["ordered"] and row["premises_failed"] == []
    assert cor1_result(ctx, [scene], k_upper=0.01).verdict == Verdict.VIOLATED


def test_cor1_without_certified_constants_and_no_failed_premise_is_inconclusive_and_says_why():
    c1 = quantity(-np.inf, "certified_constant", "no certified side")
    c2 = quantity(2.0, "certified_constant", "from lengths")
    row = _cor1_row(robots.planar_2r(payload=1.0), c1, c2)
    assert row["verdict"] == "INCONCLUSIVE" and "alpha1 > 0" in row["why"] and "no premise" in row["why"]
    row = _cor1_row(robots.non_normal_2r(), c1, c2)  # the same constants where the premise fails: decided
    assert row["verdict"] == "HOLDS" and "premise fails" in row["why"]


def test_def2_names_the_certified_witness_of_non_normality(ctx):
    result = def2_result(ctx, [robots.non_normal_2r()])
    row = result.evidence["chains"]["non-normal-2r"]
    assert row["status"].startswith("not normal (certified") and row["not_normal"][0]["witness"]["joint"] == 1


def test_negative_controls_are_never_null_and_bite_on_a_chain_whose_dqj_vanishes(ctx):
    zero = np.zeros((3, 6, 1, 1))
    size = np.ones(3)
    assert np.all(np.abs(off_by(zero, size)) == PART)
    x = np.array([[-2.0, 0.0, 3.0]])
    assert np.all(np.abs(off_by(x, np.ones(1)) - x) >= PART * np.abs(x))
    sphere = robots.translating_sphere(-0.5)
    assert np.all(sphere.chain.body_jacobian_derivative(np.zeros((1, 1))) == 0.0)  # a slide: dQJ/dq = 0
    result = kinematics_result(ctx, "Def2", {sphere.name: sphere.chain})
    assert result.verdict == Verdict.HOLDS, result.summary
    assert set(result.evidence["negative_controls"]) == set(FORWARD_KINEMATICS_CONTROLS)
    assert all(result.evidence["negative_controls"].values())


def test_a_zero_lower_side_is_certified_by_z_and_reproved_where_m_vanishes():
    """The sphere's hull holds Theta = 0 (t -> inf), where M = 0: lambda_min(M) >= 0 is certified as Z >= 0."""
    scene = robots.translating_sphere(-0.5)
    thetas = np.stack([scene.trajectory.base, 0 * scene.trajectory.base])
    cert = SpectrumClaim(scene.chain, thetas, "lambda_min")(0.0)
    assert cert["claim"]["kind"] == "body-spectrum" and cert["claim"]["bound"] == "0"
    assert reprove(cert)["status"] == "re-proved"
    inconsistent = thetas.copy()
    inconsistent[0, 0, 0] = -1.0  # a negative mass: Z is not PSD, so no such shortcut
    assert not spatial_psd(inconsistent)
    assert SpectrumClaim(scene.chain, inconsistent, "lambda_min")(0.0)["claim"]["kind"] == "mass-matrix-spectrum"
    assert SpectrumClaim(scene.chain, thetas, "lambda_min")(0.5)["claim"]["kind"] == "mass-matrix-spectrum"
    assert spatial_psd(np.tile(unit_body(), (2, 1)))


def test_failed_premises_is_cheap_and_empty_on_the_arms():
    for scene in (robots.panda(payload=2.0), robots.ur5()):
        assert failed_premises(scene) == []


class _Unfinished:
    """A stability study whose reference run stopped at its count: its power balance is not decided."""

    horizon, fastest_rate, substitute, runs = 1.0, 10.0, None, []
    reference = type("Reference", (), {"method": "Radau", "rtol": 1e-7, "status": "budget", "seconds": 1.0})()

    def balance_verdict(self):
        return Verdict.INCONCLUSIVE, 1e-6, np.nan, "the reference run ended as 'budget'"

    def work_precision_rows(self):
        return []

    def stability_rows(self):
        return []


def test_a_study_that_did_not_finish_where_m_is_singular_holds_with_the_witness_and_elsewhere_stays_open(ctx,
                                                                                                       monkeypatch):
    from inertiaproof.checks import physics

    monkeypatch.setattr(physics.study, "study", lambda *args, **kwargs: _Unfinished())
    singular, normal = robots.non_normal_2r(), robots.planar_2r()
    assert unsimulable(normal.chain) is None and unsimulable(singular.chain)[0] == normality_failures(singular.chain)
    decided = physics.stability_result([({"builtin": "non_normal_2r"}, singular, None)], ctx)
    assert decided.verdict == Verdict.HOLDS
    assert "premise fails" in decided.summary and "M(q) is singular" in decided.summary
    assert decided.evidence["scenes"]["non_normal_2r"]["premises_failed"][0]["witness"]["q"][0] == 0.0
    assert physics.stability_result([({"builtin": "planar_2r"}, normal, None)], ctx).verdict == Verdict.INCONCLUSIVE
