"""Section 4: the key-step certificate, the brackets, and every bound checker caught with a wrong constant."""

from fractions import Fraction

import numpy as np
import pytest
from inertiaproof.checks.mass_matrix_bounds import (
    def3_result,
    lower_bound_case,
    thm2_result,
    thm3_result,
    upper_bound_case,
)
from inertiaproof.checks.normality import cx_normal_result, def2_result
from inertiaproof.checks.other_components import acc_result, rate_case, thm4_result, thm5_result
from inertiaproof.checks.pointwise import margins, point_counterexample, replay_point, run_hunt, worst_point

from inertiaproof.bounds.configuration import REPROVABLE, apriori_bound, jacobian_sup, triangular_normality_floor
from inertiaproof.bounds.time import BODY_FUNCTIONS, lumped_velocity_bounds, moving_mass_hull, time_extreme
from inertiaproof.model.inertia import spatial_inertia, unit_body
from inertiaproof.model.positive_map import (
    exact_map,
    key_step_proof,
    kraus_factors,
    spatial_from_pseudo,
    verify_choi,
)
from inertiaproof.result import Verdict
from inertiaproof.scene import robots
from inertiaproof.suite.context import Context
from inertiaproof.suite.profiles import Profile
from inertiaproof.suite.registry import REPLAYERS

FAST = Profile("test", examples=8, samples=300, rounds=8, symbolic_max_n=2, derandomize=True)


def ctx():
    return Context(FAST, seed=0)


def test_key_step_proof_is_exact_and_sharp():
    cert = key_step_proof()
    assert cert["ok"] and cert["choi_psd"] and cert["choi_mismatch"] == 0 and cert["choi_rank"] == 3
    assert (cert["lower"], cert["upper"]) == (1.0, 2.0)
    assert cert["l_identity_diagonal"] == ["1", "1", "1", "2", "2", "2"]


def test_perturbed_map_is_not_certified():
    choi = [[Fraction(x) for x in row] for row in key_step_proof()["choi"]]

    def wrong(f):
        z = exact_map(f)
        z[3][3] += Fraction(1, 10**6) * f[3][3]
        return z

    check = verify_choi(np.array(choi, dtype=object), reference=wrong)
    assert check["mismatch"] != 0
    negative = np.array(choi, dtype=object)
    negative[0][0] -= 1
    assert not verify_choi(negative)["psd"]


def test_kraus_form():
    rng = np.random.default_rng(1)
    a = kraus_factors()
    for _ in range(20):
        p = rng.standard_normal(4)
        ap = np.tensordot(p, a, 1)
        assert np.allclose(ap.T @ ap, spatial_from_pseudo(np.outer(p, p)), atol=1e-13)


def test_qj_is_degree_one_per_coordinate():
    """The Bernstein step needs QJ = a + b cos q_j + c sin q_j in every revolute coordinate (prismatic: a + b q_j)."""
    rng = np.random.default_rng(2)
    for scene in (robots.panda(), robots.ur5(), robots.revolute_prismatic(1.0)):
        chain = scene.chain
        q = rng.uniform(-1, 1, chain.n)
        for j, joint in enumerate(chain.joints):
            x = np.linspace(-2, 2, 7)
            qs = np.tile(q, (7, 1))
            qs[:, j] = x
            y = chain.body_jacobian(qs).reshape(7, -1)
            basis = np.stack([np.ones(7), np.cos(x), np.sin(x)] if joint.revolute else [np.ones(7), x], -1)
            coef, *_ = np.linalg.lstsq(basis, y, rcond=None)
            assert np.abs(basis @ coef - y).max() < 1e-12 * max(1, np.abs(y).max())


def test_bracket_contains_dense_grid_extreme():
    chain = robots.planar_2r().chain
    b = jacobian_sup(chain, samples=50, rounds=12, rng=np.random.default_rng(0))
    q2 = np.linspace(-np.pi, np.pi, 20001)
    dense = np.linalg.svd(chain.body_jacobian(np.stack([0 * q2, q2], -1)), compute_uv=False)[:, 0].max()
    assert b.lower <= dense + 1e-12 and dense <= b.upper
    assert b.upper <= REPROVABLE * b.lower * (1 + 1e-12)  # as tight as reported brackets go (Bracket.widen)
    uppers = [u for _, _, u in b.convergence if u is not None]
    assert uppers and uppers[0] >= uppers[-1] and len(b.convergence) > 2


def test_a_priori_bound_is_valid():
    from inertiaproof.dynamics import composite

    rng = np.random.default_rng(3)
    for chain in (robots.panda().chain, robots.ur5().chain, robots.revolute_prismatic(1.0).chain):
        lo, hi = chain.coordinate_box()
        q = lo + (hi - lo) * rng.random((2000, chain.n))
        assert np.linalg.svd(chain.body_jacobian(q), compute_uv=False)[:, 0].max() <= apriori_bound(chain, None, "sup")
        thetas = rng.normal(size=(2, chain.n, 10))  # indefinite Z too: the bound is on sigma_max(M)
        sigma_m = np.abs(np.linalg.eigvalsh(composite.mass_matrix(chain, q[:, None], thetas[None]))).max()
        assert sigma_m <= apriori_bound(chain, thetas, "sup")


SCENE = robots.planar_2r(payload=1.0)


def test_thm2_paper_holds_and_overstated_constant_is_violated():
    assert thm2_result(ctx(), [SCENE]).verdict == Verdict.HOLDS
    _, _, evidence, _ = lower_bound_case(ctx(), SCENE)
    assert evidence["constants"]["paper"]["kind"] == "lower_bound"
    k = 2 * evidence["constants"]["observed"]["value"] / evidence["constants"]["paper"]["value"]
    result = thm2_result(ctx(), [SCENE], k=k)
    assert result.verdict == Verdict.VIOLATED
    replayed = REPLAYERS[result.counterexample["kind"]](result.counterexample["data"], ctx())
    assert replayed.verdict == Verdict.VIOLATED


def test_thm3_shrunk_constant_is_violated():
    assert thm3_result(ctx(), [SCENE]).verdict == Verdict.HOLDS
    _, _, evidence, _ = upper_bound_case(ctx(), SCENE)
    k = 0.5 * evidence["constants"]["observed"]["value"] / evidence["constant_range"]["upper"]["value"]
    result = thm3_result(ctx(), [SCENE], k=k)
    assert result.verdict == Verdict.VIOLATED
    assert REPLAYERS[result.counterexample["kind"]](result.counterexample["data"], ctx()).verdict == Verdict.VIOLATED


def test_thm4_shrunk_constant_is_violated():
    assert thm4_result(ctx(), [SCENE]).verdict == Verdict.HOLDS
    _, _, evidence, _ = rate_case(ctx(), SCENE)
    k = 0.5 * evidence["constants"]["observed"]["value"] / evidence["constant_range"]["upper"]["value"]
    assert thm4_result(ctx(), [SCENE], k=k, hunt_factor=2.0).verdict == Verdict.VIOLATED


def _shrunk(result_fn):
    good = result_fn(ctx())
    assert good.verdict == Verdict.HOLDS
    c = good.evidence
    k = 0.5 * c["constants"]["observed"]["value"] / c["constant_range"]["upper"]["value"]
    bad = result_fn(ctx(), k=k)
    assert bad.verdict == Verdict.VIOLATED
    assert REPLAYERS[bad.counterexample["kind"]](bad.counterexample["data"], ctx()).verdict == Verdict.VIOLATED


def test_eq_acc_shrunk_constant_is_violated():
    _shrunk(acc_result)


def test_thm5_shrunk_constant_is_violated():
    _shrunk(thm5_result)


def test_sharp_factor_two_of_thm4_is_attained_and_below_it_the_pointwise_bound_fails():
    """One revolute joint turning about z at its origin: QJ = e_6, and Phidot with f(Phidot) = I4 gives M = 2."""
    from inertiaproof.dynamics.chain import Chain, Joint
    from inertiaproof.model.inertia import pseudo_inertia_inverse

    chain = Chain((Joint("revolute", (0, 0, 1)),))
    phidot = pseudo_inertia_inverse(np.eye(4))[None]
    state = {"theta": unit_body()[None, None], "theta_dot": phidot[None], "psi": np.zeros((1, 6)),
             "psi_dot": np.zeros((1, 6))}
    q = np.zeros((1, 1))
    margin, resolution, lhs, rhs = margins("Thm4", chain, q, state, 1.0, ["chi (certified, factor 2)"])
    assert abs(lhs[0] - 2.0) < 1e-14 and abs(rhs[0] - 2.0) < 1e-14 and abs(margin[0]) <= resolution[0] < 1e-8
    margin, resolution, lhs, rhs = margins("Thm4", chain, q, state, 0.95)
    assert margin[0] < -resolution[0]
    cx = point_counterexample("Thm4", chain, q, state, 0.95, worst_point("Thm4", chain, q, state, 0.95))
    assert replay_point(cx["data"])[0] < 0
    assert REPLAYERS["bound-point"](cx["data"], ctx()).verdict == Verdict.VIOLATED


@pytest.mark.parametrize("check_id, factor, moving_mass", [
    ("Thm2", 3.0, False), ("Thm3", 0.05, False), ("Thm4", 0.2, False), ("EQ-acc", 0.1, True), ("Asm3/Thm5", 0.01, True)])
def test_hunts_find_a_replayable_chain_for_a_wrong_factor(check_id, factor, moving_mass):
    evidence, cx = run_hunt(check_id, ctx(), factor, moving_mass, examples=30)
    assert cx is not None and evidence["smallest_margin"]["value"] < 0
    assert REPLAYERS[cx["kind"]](cx["data"], ctx()).verdict == Verdict.VIOLATED


def test_margin_below_rounding_is_not_a_violation():
    """lambda_min(M) ~ 1e-17 ||M|| on a nearly singular QJ: its sign is rounding, so the margin is unresolved."""
    chain = robots.non_normal_2r().chain
    theta = robots.non_normal_2r().trajectory.base
    state = {"theta": theta[None], "theta_dot": theta[None] * 0, "psi": np.zeros((1, 12)), "psi_dot": np.zeros((1, 12))}
    q = np.array([[1e-6, 0.3]])
    margin, resolution, lhs, rhs = margins("Thm2", chain, q, state, 1.0)
    assert resolution[0] > 1e-6 and margin[0] > -resolution[0]


def test_def3_with_a_wrong_spatial_inertia_is_violated():
    traj = robots.panda(payload=2.0).trajectory
    assert def3_result({"panda": traj}).verdict == Verdict.HOLDS

    def wrong(theta):
        z = spatial_inertia(theta)
        z[..., 3:, 3:] *= 0.5
        return z

    assert def3_result({"panda": traj}, spatial=wrong).verdict == Verdict.VIOLATED


def test_def2_gram_identity_with_a_wrong_unit_body_is_violated():
    scene = robots.planar_2r()
    assert def2_result(ctx(), [scene]).verdict == Verdict.HOLDS
    wrong = np.tile(unit_body() * np.array([1.0] * 4 + [1.01] * 3 + [1.0] * 3), (2, 1))
    assert def2_result(ctx(), [scene], theta_for_identity=wrong).verdict == Verdict.VIOLATED


def test_cx_normal_on_a_normal_chain_is_violated():
    assert cx_normal_result(robots.non_normal_2r()).verdict == Verdict.HOLDS
    assert cx_normal_result(robots.planar_2r()).verdict == Verdict.VIOLATED


def test_moving_mass_bounds_are_valid():
    traj = robots.trolley_2r(loop=True, mass=2.0).trajectory
    lv = lumped_velocity_bounds(traj, samples=20001)
    for key in ("psi", "psi_dot"):
        assert lv[key]["observed"] <= lv[key]["certified"]
    for name in BODY_FUNCTIONS:
        d = time_extreme(traj, name, samples=4001)
        assert (d["certified"] <= d["observed"] + 1e-12) if d["sense"] == "min" else (d["observed"] <= d["certified"] + 1e-12)


def test_the_moving_mass_hull_bounds_the_mass_matrix_over_time_and_without_the_lift_it_does_not():
    """lambda_min of M along Theta(t) stays above its min over the hull's rows and lambda_max below its max, on random
    bodies carrying a payload ramp and a moving mass; the hull of the rest alone (no row above the moving mass) fails
    the upper side."""
    from hypothesis import given, settings, strategies as st
    from inertiaproof.counterexamples.trajectories import mixed_trajectories
    from inertiaproof.dynamics import composite

    chain = robots.planar_2r().chain
    q = np.random.default_rng(0).uniform(-np.pi, np.pi, (40, 2))
    spectra = lambda thetas: np.linalg.eigvalsh(composite.mass_matrix(chain, q[:, None], thetas[None]))  # noqa: E731
    escaped = []

    @settings(max_examples=20, deadline=None, derandomize=True)
    @given(st.data())
    def inside(data):
        mixed = data.draw(mixed_trajectories(2, 1.0))
        along = spectra(mixed.theta(mixed.times(200))[0])
        rest, above = (spectra(moving_mass_hull(mixed, kind)) for kind in ("lmin", "lmax"))
        assert rest[..., 0].min() <= along[..., 0].min() * (1 + 1e-9)
        assert along[..., -1].max() <= above[..., -1].max() * (1 + 1e-9)
        escaped.append(along[..., -1].max() > rest[..., -1].max() * (1 + 1e-9))

    inside()
    assert any(escaped)


def test_the_trolleys_mass_matrix_brackets_are_certified_over_its_hull_and_reproved():
    from inertiaproof.verify.cli import check

    scene = robots.trolley_2r()
    for case, side in ((lower_bound_case, "lower"), (upper_bound_case, "upper")):
        bracket = case(ctx(), scene)[2]["bracket"]
        certified, observed = bracket[side]["value"], bracket["upper" if side == "lower" else "lower"]["value"]
        assert np.isfinite(certified) and ((certified <= observed) if side == "lower" else (observed <= certified))
        assert "hull of the rest's vertices" in bracket[side]["note"]
        assert check(bracket[side]["certificate"].certificate)["status"] == "re-proved"


def test_triangular_normality_floor_is_valid_on_random_chains():
    from hypothesis import given, settings
    from inertiaproof.counterexamples.chains import chains

    @settings(max_examples=40)
    @given(chains())
    def floor_below_every_sample(drawn):
        chain, _ = drawn
        floor = triangular_normality_floor(chain)
        lo, hi = chain.coordinate_box()
        q = lo + (hi - lo) * np.random.default_rng(0).random((500, chain.n))
        smallest = np.linalg.svd(chain.body_jacobian(q), compute_uv=False)[:, -1].min() ** 2
        assert 0 <= floor <= smallest * (1 + 1e-12)

    floor_below_every_sample()


def test_triangular_normality_floor_certifies_the_arms_and_not_the_non_normal_chain():
    assert triangular_normality_floor(robots.panda().chain) > 1e-2
    assert triangular_normality_floor(robots.ur5().chain) > 1e-2
    assert triangular_normality_floor(robots.non_normal_2r().chain) == 0.0


def test_cor1_with_a_misstated_alpha2_is_violated():
    from inertiaproof.checks.mass_matrix_bounds import cor1_result

    assert cor1_result(ctx(), [SCENE]).verdict == Verdict.HOLDS
    bad = cor1_result(ctx(), [SCENE], k_upper=0.01)
    assert bad.verdict == Verdict.VIOLATED
    assert REPLAYERS[bad.counterexample["kind"]](bad.counterexample["data"], ctx()).verdict == Verdict.VIOLATED


def test_lem1_with_an_inconsistent_body_is_violated():
    """Lemma 1 needs consistent bodies: a negative mass on a normal chain gives lambda_min(M) < 0."""
    from dataclasses import replace

    from inertiaproof.checks.normality import lem1_result

    scene = robots.planar_2r()
    assert lem1_result(ctx(), [scene]).verdict == Verdict.HOLDS
    base = scene.trajectory.base.copy()
    base[1] *= -1
    bad = replace(scene, name="planar-2r-negative-mass", trajectory=replace(scene.trajectory, base=base))
    assert lem1_result(ctx(), [bad]).verdict == Verdict.VIOLATED


def test_asm2_lem2_with_a_wrong_growth_offset_is_violated():
    from inertiaproof.checks.normality import asm2_lem2_result

    assert asm2_lem2_result(ctx()).verdict == Verdict.HOLDS
    assert asm2_lem2_result(ctx(), claimed_offset=-1.0).verdict == Verdict.VIOLATED


def test_cor2_with_a_normal_chain_as_the_non_normal_one_is_violated():
    from inertiaproof.checks.normality import cor2_result

    assert cor2_result(ctx(), robots.non_normal_2r()).verdict == Verdict.HOLDS
    assert cor2_result(ctx(), robots.planar_2r()).verdict == Verdict.VIOLATED


def test_cx_sphere_with_a_wrong_radius_is_violated():
    from inertiaproof.checks.normality import cx_sphere_result

    assert cx_sphere_result(ctx()).verdict == Verdict.HOLDS
    assert cx_sphere_result(ctx(), claimed_radius=0.1 * (1 + 1e-6)).verdict == Verdict.VIOLATED


def test_a_sup_side_of_six_joints_comes_with_a_partition_the_checker_walks():
    """UR5's sup lambda_max(M): the Fourier side has no partition, and the root box alone does not prove it (the
    checker walks a tree once and cuts nothing beyond it); the ladder's side (as sharp here) comes with one, which
    the checker re-proves as the prover wrote it."""
    from inertiaproof.bounds.configuration import mass_sup
    from inertiaproof.bounds.constants import bracket_certificate
    from inertiaproof.verify.cli import check

    scene = robots.ur5()
    b = mass_sup(scene.chain, scene.trajectory.base[None], samples=300, rounds=20, rng=np.random.default_rng(0))
    cert = bracket_certificate(b)
    assert b.proof is not None and cert["tree"] != "." and b.upper <= 1.05 * b.lower
    assert check(cert)["status"] == "re-proved"
    assert check({**cert, "tree": "."})["status"] == "not re-proved"
