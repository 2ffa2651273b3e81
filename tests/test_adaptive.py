"""Adaptive laws (inertiaproof.sim.adaptive), the closed loop on three plants (tracking), runs as data (recipe)."""

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from inertiaproof.counterexamples.inertias import consistent_phi
from inertiaproof.dynamics import motion
from inertiaproof.model.inertia import pseudo_inertia, pseudo_inertia_inverse
from inertiaproof.sim import adaptive, estimates, tracking
from inertiaproof.sim.recipe import Recipe

SCENES = Path(__file__).resolve().parents[1] / "scenes"

LAWS = [adaptive.SlotineLi(0.7), adaptive.NaturalAdaptation(3.0)]


def _thetas(draw_count=2, thinness=6):
    return st.lists(consistent_phi(size=(0.05, 1.0), thinness=thinness), min_size=draw_count,
                    max_size=draw_count).map(np.stack)


@given(_thetas())
def test_f_as_a_matrix_is_the_pseudo_inertia(theta):
    assert np.allclose(adaptive.f_map(theta), pseudo_inertia(theta), rtol=0, atol=1e-14 * np.abs(theta).max())
    f = pseudo_inertia(theta)
    assert np.allclose(adaptive.f_inverse(f), pseudo_inertia_inverse(f), rtol=0, atol=1e-13 * np.abs(theta).max())
    a = np.random.default_rng(0).normal(size=f.shape)
    a = a + np.swapaxes(a, -1, -2)
    assert np.allclose(np.sum(adaptive.adjoint(a) * theta, -1), np.trace(a @ f, axis1=-2, axis2=-1))


@pytest.mark.parametrize("law", LAWS, ids=lambda law: law.name)
@settings(max_examples=25)
@given(truth=_thetas(1, thinness=1), estimate=_thetas(1, thinness=1), drive=st.integers(0, 2**31))
def test_each_law_keeps_its_divergence_promise(law, truth, estimate, drive):
    """dD/dt along the law = -g . (Theta_hat - Theta), and dD/dTheta as documented: central differences on a body
    of moderate condition (the identity is algebraic; the differences need a step below the smallest scale)."""
    z = law.initial(estimate)
    assert np.allclose(law.estimate(z), estimate, rtol=1e-9, atol=1e-9 * np.abs(estimate).max())
    g = np.random.default_rng(drive).normal(size=truth.shape)
    zdot = law.rate(z, g)
    change, error = _derivative(lambda h: law.divergence(z + h * zdot, truth), 1e-2 * np.abs(z).max() / np.abs(zdot).max())
    promised = -np.sum(g * (law.estimate(z) - truth))
    floor = 1e-6 * np.sum(np.abs(g * (law.estimate(z) - truth))) + 1e-9 * np.sum(np.abs(g)) * np.abs(truth).max()
    assert change == pytest.approx(promised, rel=1e-3, abs=max(floor, 10 * error))
    direction = np.random.default_rng(drive + 1).normal(size=truth.shape) * np.abs(truth).max()
    k = 1e-2
    if np.linalg.eigvalsh(pseudo_inertia(truth - k * direction))[..., 0].min() > 0:
        numeric, error = _derivative(lambda h: law.divergence(z, truth + h * direction), k)
        assert numeric == pytest.approx(np.sum(law.divergence_gradient(z, truth) * direction), rel=1e-3,
                                        abs=max(1e-9, 10 * error))


def _derivative(fn, h):
    """d/dh fn at 0: central differences with a Richardson step (error O(h^4)) at h, h/4, h/16, ...; the value
    where two neighbouring steps agree best (truncation falls, rounding grows as h shrinks), and that disagreement
    as its error estimate (an ill-conditioned body leaves rounding of 1e-9 at the best step)."""
    def richardson(h):
        return (4 * (fn(h / 2) - fn(-h / 2)) / h - (fn(h) - fn(-h)) / (2 * h)) / 3

    values = [richardson(h / 4**k) for k in range(14)]
    best = min(range(13), key=lambda k: abs(values[k] - values[k + 1]))
    return values[best + 1], abs(values[best] - values[best + 1])


def test_natural_estimate_is_positive_definite_exactly_while_its_mirror_is():
    theta = np.stack([pseudo_inertia_inverse(np.diag([0.01, 0.02, 0.03, 1.0]))])
    law = adaptive.NaturalAdaptation(1.0)
    z = law.initial(theta)
    push = -law.rate(z, np.ones_like(theta)) * 1e3  # a huge step the other way
    for scale in np.geomspace(1e-6, 1.0, 13):
        u = law.mirror(z + scale * push)
        mirror_pd = np.linalg.eigvalsh(u)[..., 0].min() > 0
        estimate_pd = np.linalg.eigvalsh(pseudo_inertia(law.estimate(z + scale * push)))[..., 0].min() > 0
        assert mirror_pd == estimate_pd


def test_the_three_plants_and_the_lyapunov_balance():
    """Payload (Psi = 0): Eq. (2) is the generalized equation, Eq. (1) is not; with a trolley all three differ.
    Every run closes its Lyapunov balance; a plant without M(q, Thetadot) qd in its forces does not."""
    payload = [Recipe("planar-2r-payload", law, plant, horizon=0.6, timing=(0.1, 0.2))
               for law in ("slotine-li", "natural") for plant in tracking.PLANTS]
    runs, _ = tracking.simulate(payload[0].chain(), [r.spec() for r in payload], 0.6, samples=13, rtol=1e-6)
    by = {(r.law, r.plant): run for r, run in zip(payload, runs)}
    for law in ("slotine-li", "natural"):
        assert np.array_equal(by[law, "gre"].y, by[law, "pagilla"].y)
        assert np.abs(by[law, "gre"].y[-1] - by[law, "classical"].y[-1]).max() > 1e-4
    assert max(run.balance_error for run in runs) < 1e-3
    trolley = [Recipe("trolley-2r", "slotine-li", plant, horizon=0.6, timing=(0.1, 0.3)) for plant in tracking.PLANTS]
    runs, _ = tracking.simulate(trolley[0].chain(), [r.spec() for r in trolley], 0.6, samples=13, rtol=1e-6)
    ends = [run.y[-1, :4] for run in runs]
    assert min(np.abs(ends[0] - ends[1]).max(), np.abs(ends[0] - ends[2]).max(), np.abs(ends[1] - ends[2]).max()) > 1e-6
    assert max(run.balance_error for run in runs) < 1e-3

    def no_rate(kin, g, p, qd, qdd):
        return motion.generalized_forces(kin, g, dataclasses.replace(p, theta_dot=0 * p.theta_dot), qd, qdd)

    (wrong,), _ = tracking.simulate(payload[0].chain(), [payload[0].spec()], 0.6, samples=13, rtol=1e-6, forces=no_rate)
    assert wrong.balance_error > 1e-2


def test_a_law_that_breaks_its_promise_breaks_the_balance():
    class Leaky(adaptive.SlotineLi):
        name = "leaky"

        def rate(self, z, g):
            return -self.gain * g - 5.0 * z

    recipe = Recipe("planar-2r-payload", "slotine-li", horizon=0.5, timing=(0.1, 0.2))
    spec = dataclasses.replace(recipe.spec(), law=Leaky(1.0))
    (run,), _ = tracking.simulate(recipe.chain(), [spec], 0.5, samples=11, rtol=1e-6)
    assert run.finished and run.balance_error > 1e-2


def test_a_batch_stopped_by_its_budget_keeps_what_it_reached():
    recipe = Recipe("planar-2r-payload", "natural", horizon=2.0)
    (run,), batch = tracking.simulate(recipe.chain(), [recipe.spec()], 2.0, samples=41, max_evaluations=60)
    assert run.status == "budget" and "stopped at t" in run.note
    assert 1 < len(run.t) < 41 and np.all(np.isfinite(run.y))
    series = estimates.series(recipe.chain(), run, batch)
    assert series["lambda_min_f_hat"].shape == (len(run.t), 2)


def test_recipes_are_plain_data_and_share_their_objects():
    recipe = Recipe("trolley-2r", "natural", "pagilla", horizon=1.0, gamma=3.0, estimate=(0.5, 2.0),
                    home=(0.1, 0.2), timing=(0.2, 0.4))
    again = Recipe.from_data(recipe.to_data())
    assert again == recipe
    a, b = recipe.spec(), again.spec()
    assert a.trajectory is b.trajectory and a.law is b.law and a.law.gain == 3.0
    assert np.allclose(a.theta_hat0[1], 2.0 * a.trajectory.theta(np.array(0.0))[0][1])
    assert a.trajectory.loads[0].path.profile.duration == 0.4


def test_a_batch_too_stiff_for_rk45_is_not_started():
    """The 24-link snake's K_D = kd diag(M) against its M: lambda_max(M^-1 K_D) ~ 1e5 /s, so RK45 would need ~2e5
    evaluations over 1 s, more than 10 x a budget of 2000; the batch says so at once instead of spending its budget; a 2R run
    with the same budget starts."""
    from scipy.linalg import eigh

    from inertiaproof.dynamics import terms

    snake = Recipe(str(SCENES / "many_links_24.toml"), "slotine-li", horizon=1.0)
    batch = tracking.Batch(snake.chain(), [snake.spec()])
    q0 = batch.split(batch.initial_state())[0][0]
    m = terms.mass_matrix(snake.chain().body_jacobian(q0), batch.parameters(0.0).theta[0])
    rho = batch.fastest_rate()[0]
    assert rho == pytest.approx(eigh(np.diag(batch.kd[0]), m, eigvals_only=True).max(), rel=1e-8) and rho > 1e4
    (run,), batch = tracking.simulate(snake.chain(), [snake.spec()], 1.0, samples=11, max_evaluations=2_000)
    assert run.status == "too stiff" and not run.finished and "stiff solver" in run.note
    assert batch.evaluations <= 2 and len(run.t) == 1
    small = Recipe("planar-2r-payload", "natural", horizon=0.2)
    (run,), _ = tracking.simulate(small.chain(), [small.spec()], 0.2, samples=5, max_evaluations=2_000)
    assert run.status == "ok"


def test_a_batch_with_a_numerically_singular_mass_matrix_is_not_started():
    """extreme_lengths.toml (links of 1 km, 1 m, 1 mm): cond(M(q0)) ~ 1e20, beyond simulate.MAX_CONDITION, the
    criterion of the stability and loading studies; the run says so instead of integrating digits that are lost."""
    recipe = Recipe(str(SCENES / "extreme_lengths.toml"), "natural", horizon=0.5)
    (run,), batch = tracking.simulate(recipe.chain(), [recipe.spec()], 0.5, samples=5)
    assert run.status == "ill-conditioned" and run.status in tracking.NOT_STARTED and "cond(M" in run.note
    assert batch.evaluations <= 2 and len(run.t) == 1
