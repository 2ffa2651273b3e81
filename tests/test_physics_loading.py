"""GRE-physics, loading: plastic captures of pieces at rest converge to the equation's solution."""

import numpy as np
import pytest
from inertiaproof.checks import physics

from inertiaproof.result import Verdict
from inertiaproof.scene import robots
from inertiaproof.scene.format import load_scene
from inertiaproof.sim import capture, fixedstep
from inertiaproof.sim.control import controller
from inertiaproof.suite.context import Context
from inertiaproof.suite.profiles import PROFILES
from inertiaproof.suite.registry import REPLAYERS
from tests.test_physics_internal import SCENES, _perturbed


@pytest.fixture(scope="module")
def loading():
    return physics.loading_result([({"builtin": "planar-2r-payload"}, robots.planar_2r(2.0))], Context(PROFILES["ci"]))


def test_captures_at_rest_converge_with_order_two(loading):
    assert loading.verdict == Verdict.HOLDS, loading.summary
    entry = loading.evidence["scenes"]["planar-2r-payload"]
    assert abs(entry["order_at_rest_centred"]["value"] - 2.0) < 0.2
    assert abs(entry["order_at_rest_slice_start"]["value"] - 1.0) < 0.2
    assert entry["error_at_rest_centred"][-1]["value"] < 1e-3


def test_mass_arriving_with_the_body_velocity_misses_the_equation(loading):
    entry = loading.evidence["scenes"]["planar-2r-payload"]
    mismatch = entry["mismatch_if_carried"]["value"]
    assert mismatch > 0.05
    carried = [q["value"] for q in entry["carried_pieces_vs_equation"]]
    assert min(carried) > 0.5 * mismatch  # pieces that arrive moving do not approach the equation ...
    assert entry["carried_pieces_vs_their_limit"][-1]["value"] < 1e-3  # ... but the equation without M(q, Thetadot)
    assert "at rest" in loading.evidence["assumption"]
    assert set(loading.evidence["series"]["lines"]) >= {"at rest, centred -> (RoboticEquation)"}


@pytest.mark.parametrize("term, factor, replay", [("parameter_rate", 0.5, True), ("gravity", 1.01, False)])
def test_a_perturbed_equation_is_violated(term, factor, replay):
    scene = robots.planar_2r(2.0)
    result = physics.loading_result([({"builtin": "planar-2r-payload"}, scene)], Context(PROFILES["ci"]),
                                    forces=_perturbed(term, factor), steps=64, counts=(4, 8, 16, 32))
    assert result.verdict == Verdict.VIOLATED, result.summary
    assert result.counterexample["kind"] == "gre-physics-loading"
    if replay:
        replayed = REPLAYERS["gre-physics-loading"](result.counterexample["data"], Context(PROFILES["ci"]))
        assert replayed.verdict == Verdict.HOLDS


def test_convergence_verdict_decides_from_the_tail():
    counts = [4, 8, 16, 32, 64]
    second = [1e-2 / k**2 for k in counts]
    assert capture.convergence_verdict(counts, second, 1e-12)[0] == Verdict.HOLDS
    level = [1e-2 / k**2 + 3e-4 for k in counts]
    verdict, order, why, settled = capture.convergence_verdict(counts, level, 1e-12)
    assert verdict == Verdict.VIOLATED and settled and order < 0.3
    floor = capture.convergence_verdict(counts, [1e-3, 1e-6, 1e-9, 1e-9, 1e-9], 1e-9)
    assert floor[0] == Verdict.HOLDS
    crossing = capture.convergence_verdict(counts, [1e-3, 1e-5, 1e-8, 3e-8, 1e-8], 1e-12)
    assert crossing[0] == Verdict.INCONCLUSIVE and not crossing[3]
    assert capture.convergence_verdict(counts, [1e-3, np.nan, 1, 1, 1], 1e-12)[0] == Verdict.INCONCLUSIVE


def test_schedule_puts_captures_on_the_grid():
    index, mass_times = capture.Pieces(4, "middle").schedule(1.0, 2.0, 16)
    assert index.tolist() == [2, 6, 10, 14] and mass_times.tolist() == [1.25, 1.5, 1.75, 2.0]
    index, _ = capture.Pieces(4, "start").schedule(1.0, 2.0, 16)
    assert index.tolist() == [0, 4, 8, 12]
    with pytest.raises(ValueError):
        capture.Pieces(8).schedule(0.0, 1.0, 12)


def test_mass_window_and_stiff_scenes():
    scene = robots.planar_2r(2.0)
    assert capture.mass_window(scene.trajectory) == (1.0, 1.5)
    with pytest.raises(ValueError):
        capture.mass_window(robots.trolley_2r().trajectory)
    control = controller(scene.chain, scene.trajectory)
    assert capture.steps_for((1.0, 1.5), 1e3, (4, 64), 128) == 512
    too_stiff = capture.study(scene.chain, scene.trajectory, control, (4, 8), 16, max_steps=8)
    assert too_stiff.verdict == Verdict.INCONCLUSIVE and "too stiff" in too_stiff.why


def test_feedforward_in_chunks_is_the_whole_grid(monkeypatch):
    """FeedforwardPD.feedforward in chunks of FEEDFORWARD_CHUNK times (the loading study's memory) is the same as
    at once, for any shape of times."""
    from inertiaproof.sim import control as control_module

    scene = robots.planar_2r(2.0)
    pd = control_module.FeedforwardPD(scene.chain, controller(scene.chain, scene.trajectory, scene.control))
    times = np.linspace(0.0, 1.0, 21).reshape(7, 3)
    whole = pd.feedforward(times)
    monkeypatch.setattr(control_module, "FEEDFORWARD_CHUNK", 4)
    tol = 1e-12 * np.abs(whole).max()
    assert whole.shape == (7, 3, scene.chain.n) and np.allclose(pd.feedforward(times), whole, rtol=0, atol=tol)
    single = pd.feedforward(np.array(times[2, 1]))
    assert single.shape == (scene.chain.n,) and np.allclose(single, whole[2, 1], rtol=0, atol=tol)


@pytest.fixture(scope="module")
def implicit_loading():
    """The loading study on planar 2R with the implicit scheme the stiff scenes get (chosen there by stiffness)."""
    return physics.loading_result([({"builtin": "planar-2r-payload"}, robots.planar_2r(2.0))], Context(PROFILES["ci"]),
                                  steps=64, counts=(4, 8, 16, 32), scheme=fixedstep.RADAU_IIA)


def test_the_implicit_scheme_decides_the_loading_study(implicit_loading):
    """Radau IIA's captures at rest converge with the same order 2 as RK4's; its observed order is its own, 3."""
    assert implicit_loading.verdict == Verdict.HOLDS, implicit_loading.summary
    entry = implicit_loading.evidence["scenes"]["planar-2r-payload"]
    assert entry["scheme"] == fixedstep.RADAU_IIA.name and entry["scheme_order"]["value"] == 3
    assert abs(entry["order_at_rest_centred"]["value"] - 2.0) < 0.2
    assert abs(entry["observed_integration_order"]["value"] - 3.0) < 0.3
    assert entry["work"]["newton_iterations"]["value"] >= entry["work"]["steps"]["value"] > 0


@pytest.mark.slow
def test_the_implicit_scheme_sees_a_perturbed_equation():
    scene = robots.planar_2r(2.0)
    result = physics.loading_result([({"builtin": "planar-2r-payload"}, scene)], Context(PROFILES["ci"]),
                                    forces=_perturbed("parameter_rate", 0.5), steps=64, counts=(4, 8, 16, 32),
                                    scheme=fixedstep.RADAU_IIA)
    assert result.verdict == Verdict.VIOLATED, result.summary
    assert result.counterexample["data"]["scheme"] == fixedstep.RADAU_IIA.name
    replayed = REPLAYERS["gre-physics-loading"](result.counterexample["data"], Context(PROFILES["ci"]))
    assert replayed.verdict == Verdict.HOLDS
    assert replayed.evidence["scenes"]["planar-2r-payload"]["scheme"] == fixedstep.RADAU_IIA.name


def test_stiffness_chooses_the_implicit_scheme():
    """The thin rod's fastest mode (3.7e9 rad/s over a 0.3 s window) would need 2^31 RK4 steps: Radau IIA instead,
    its steps set by the slow motion; the planar 2R (122 rad/s) keeps RK4."""
    counts = (4, 8, 16, 32, 64)
    assert capture.scheme_for((0.2, 0.5), 3.7e9, counts, 128, 2048) == (fixedstep.RADAU_IIA, 0.0)
    assert capture.scheme_for((1.0, 1.5), 122.0, counts, 128, 2048) == (fixedstep.RK4, 122.0)
    assert capture.refined_steps(128, 12.0, 2.99, 3, 2048) == 512  # 12x lower floor at order 3: two doublings
    assert capture.refined_steps(128, 1e6, 3.0, 3, 2048) == 2048  # never beyond max_steps
    assert capture.refined_steps(128, 1.5, np.nan, 3, 2048) == 256


def test_a_floor_left_high_at_the_step_cap_ends_the_study_and_names_the_mode():
    """extreme_lengths' millimetre link moves at 2.6-2.7e3 /s, which 256 RK4 steps over the 0.4 s window do not
    resolve: the floor stays above MAX_FLOOR at the cap, so more pieces cannot help and K is not refined (in ci
    three K refinements of 2,048 steps took 50 s, all INCONCLUSIVE); the reason names the unresolved mode."""
    scene = load_scene(SCENES / "extreme_lengths.toml")
    control = controller(scene.chain, scene.trajectory, scene.control)
    cs = capture.study(scene.chain, scene.trajectory, control, (4, 8, 16), 64, horizon=scene.horizon(), max_steps=256)
    assert cs.verdict == Verdict.INCONCLUSIVE and cs.floor > capture.MAX_FLOOR
    assert [counts for _, counts in cs.history] == [(4, 8, 16)] * len(cs.history) and cs.history[-1][0] == 256
    assert "nothing can be compared" in cs.why and "fastest mode" in cs.why and "|lambda| h" in cs.why
