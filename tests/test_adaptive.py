"""Adaptive laws (inertiaproof.sim.adaptive), the closed loop on three plants (tracking), runs as data (recipe)."""

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from inertiaproof.counterexamples.inertias import consistent_phi
from inertiaproof.dynamics import motion
from inertiaproof.model.inertia import pseudo_inertia, pseudo_inertia_inverse
from inertiaproof.sim import adaptive, estimates, simulate, tracking
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


THIN_ROD = str(SCENES / "stiff_thin_rod.toml")


def _differences(batch, t, y):
    """d ydot / dy per run (B, size, size) by forward differences of the batched right-hand side (a test oracle)."""
    runs, size = len(batch.specs), batch.size
    h = 1e-7 * np.maximum(np.abs(y), batch.scale()).reshape(runs, size)
    probes = np.repeat(y.reshape(1, runs, size), size, 0)
    probes[np.arange(size), :, np.arange(size)] += h.T
    change = batch.rhs(t, probes.reshape(size, -1)).reshape(size, runs, size) - batch.rhs(t, y).reshape(runs, size)
    return np.transpose(change / h.T[:, :, None], (1, 2, 0))


def test_the_jacobian_has_the_stiff_terms_of_the_closed_loop():
    """On the thin rod (inertia 5e-9 kg m^2 about the spindle) Slotine-Li's adaptation loop gamma R^T M^-1 R is the
    stiff part (~3e5 /s; M^-1 K_D is only ~10 /s): the analytic blocks match differences of the right-hand side
    exactly where they are exact (dq/dqd, dqdd/dz, dzdot/dz) and the spectral radius within 15 %; the laws'
    linearizations match complex steps."""
    recipes = [Recipe(THIN_ROD, law, horizon=1.0, timing=(0.2, 0.1)) for law in ("slotine-li", "natural")]
    batch = tracking.Batch(recipes[0].chain(), [r.spec() for r in recipes])
    y = batch.initial_state() + 1e-3 * np.random.default_rng(0).normal(size=batch.size * 2) * batch.scale()
    exact, ours = _differences(batch, 0.3, y), batch.jacobian_blocks(0.3, y)
    n, z = batch.n, slice(2 * batch.n, -1)
    for rows, cols in ((slice(0, n), slice(n, 2 * n)), (slice(n, 2 * n), z), (z, z)):
        scale = np.abs(exact[:, rows, cols]).max() + 1e-300
        assert np.abs(exact[:, rows, cols] - ours[:, rows, cols]).max() <= 1e-4 * scale
    rho = np.abs(np.linalg.eigvals(exact)).max(-1)
    assert np.allclose(np.abs(np.linalg.eigvals(ours)).max(-1), rho, rtol=0.15) and rho[0] > 1e5
    assert batch.stiffness()[0] > 1e5 and batch.stiffness()[1] < 1e3
    sparse = batch.jacobian(0.3, y)
    assert sparse.shape == (2 * batch.size,) * 2 and sparse.nnz <= 2 * batch.size ** 2
    # velocity_columns' d qdd / dqd (C and R in qd too) against central differences, exact for qdd quadratic in qd
    # whatever the step: within the forward step's truncation (measured 8e-4 and 11 % of the block); the analytic
    # block alone is off by 100 % and 47 %
    dense, qd, size, h = sparse.toarray(), slice(n, 2 * n), batch.size, 1e-2
    probes = np.repeat(y.reshape(1, 2, size), 2 * n, 0)
    probes[np.arange(n), :, n + np.arange(n)] += h
    probes[n + np.arange(n), :, n + np.arange(n)] -= h
    f = batch.rhs(0.3, probes.reshape(2 * n, -1)).reshape(2 * n, 2, size)[:, :, qd]
    central = np.moveaxis((f[:n] - f[n:]) / (2 * h), 0, -1)  # (runs, qdd row, qd column)
    for k, analytic in enumerate(batch.jacobian_blocks(0.3, y)):
        scale = np.abs(central[k]).max()
        assert np.abs(dense[k * size + n:k * size + 2 * n, k * size + n:k * size + 2 * n] - central[k]).max() \
            <= 0.15 * scale
        assert np.abs(analytic[qd, qd] - central[k]).max() > 0.4 * scale
    class Leaky(adaptive.SlotineLi):  # the default linearization: differences
        linearization = adaptive.AdaptiveLaw.linearization

        def rate(self, z, g):
            return -self.gain * g - 5.0 * z

    for law in (adaptive.SlotineLi(2.0), adaptive.NaturalAdaptation(3.0), Leaky(2.0)):
        z0 = law.initial(recipes[0].spec().theta_hat0)
        d_estimate, d_rate_z, d_rate_g = law.linearization(z0, np.ones_like(z0))
        step = np.zeros(10)
        step[4] = 1e-30
        assert np.allclose(d_estimate[..., 4], law.estimate(z0 + 1j * step).imag / 1e-30, rtol=1e-5, atol=1e-12)
        g = np.broadcast_to(np.eye(10)[4], z0.shape)
        assert np.allclose(d_rate_g[..., 4], law.rate(z0, g) - law.rate(z0, 0 * g))
        assert np.allclose(d_rate_z, -5.0 * np.eye(10) if isinstance(law, Leaky) else 0.0)


def test_a_stiff_batch_is_integrated_implicitly():
    """Slotine-Li on the thin rod: RK45 would need ~1e5 evaluations over 0.3 s, so "auto" takes BDF (Radau on
    request) with the block-diagonal Jacobian; the run finishes and closes its Lyapunov balance, while RK45 forced
    with the same counted budget stops at it."""
    recipe = Recipe(THIN_ROD, "slotine-li", horizon=0.3, timing=(0.1, 0.1))
    kw = dict(samples=7, rtol=3e-5, max_evaluations=1_500)
    (run,), batch = tracking.simulate(recipe.chain(), [recipe.spec()], 0.3, **kw)
    assert run.method == tracking.IMPLICIT_DEFAULT == "BDF" and run.finished and batch.jacobians > 0
    assert run.balance_error < 1000 * 3e-5 and len(run.t) == 7
    (radau,), _ = tracking.simulate(recipe.chain(), [recipe.spec()], 0.3, implicit="Radau", **kw)
    assert radau.method == "Radau" and radau.finished and np.abs(radau.y[-1, :3] - run.y[-1, :3]).max() < 1e-3
    (explicit,), batch = tracking.simulate(recipe.chain(), [recipe.spec()], 0.3, method="RK45", **kw)
    assert explicit.status == "budget" and explicit.t[-1] < 0.3 and tracking.spent(None, batch) > 1_500
    small = Recipe("planar-2r-payload", "natural", horizon=0.2)
    (run,), _ = tracking.simulate(small.chain(), [small.spec()], 0.2, samples=5, max_evaluations=2_000)
    assert run.status == "ok" and run.method == "RK45"


def test_a_batch_stopped_by_the_clock_says_so():
    """The wall clock is a safety net: a batch past max_seconds ends as ``clock`` (no evidence), not ``budget``."""
    recipe = Recipe("planar-2r-payload", "natural", horizon=1.0)
    (run,), _ = tracking.simulate(recipe.chain(), [recipe.spec()], 1.0, samples=11, max_seconds=0.0)
    assert run.status == tracking.CLOCK and "wall-clock" in run.note and not run.finished


def test_a_batch_with_a_numerically_singular_mass_matrix_is_not_started():
    """The cubic shoulder at q_1 = 0: M(q0) singular, its scaled condition (dynamics.forward) beyond
    simulate.MAX_CONDITION; the run says so instead of integrating digits that are lost. extreme_lengths.toml
    (links of 1 km, 1 m, 1 mm, cond(M(q0)) ~ 1e20 from its units alone) scales to a condition near 1 and starts."""
    cubic = Recipe(str(SCENES / "near_singular_cubic.toml"), "natural", horizon=0.5, home=(0.0, 0.5))
    (run,), batch = tracking.simulate(cubic.chain(), [cubic.spec()], 0.5, samples=5)
    assert run.status == "ill-conditioned" and run.status in tracking.NOT_STARTED and "scaled cond(M" in run.note
    assert batch.evaluations <= 2 and len(run.t) == 1
    extreme = Recipe(str(SCENES / "extreme_lengths.toml"), "natural", horizon=0.002)
    (run,), _ = tracking.simulate(extreme.chain(), [extreme.spec()], 0.002, samples=2, max_evaluations=2_000)
    assert run.status not in tracking.NOT_STARTED and len(run.t) > 1


def test_a_run_stopped_by_its_budget_names_the_mode_it_could_not_follow():
    """extreme_lengths.toml's natural-law runs (gain 10 on a 1e5 kg, 1 km link) stop within 4 ms of ci's count:
    their adaptation loop rings at 1.1e5 rad/s by then, where the closed loop's spectral radius was 2.6e3 /s at the
    start. A run the count stopped says what it could not follow."""
    extreme = Recipe(str(SCENES / "extreme_lengths.toml"), "natural", horizon=0.05)
    (run,), _ = tracking.simulate(extreme.chain(), [extreme.spec()], 0.05, samples=3, max_evaluations=2_000)
    assert run.status == "budget" and "the closed loop's fastest mode was then an oscillation of " in run.note
    frequency = float(run.note.split("an oscillation of ")[1].split(" rad/s")[0])
    start = float(run.note.split("spectral radius ")[1].split(" /s")[0])
    assert frequency > 1e4 > start


def test_a_natural_law_that_cannot_start_is_not_started_with_the_reason():
    """A body whose estimated mass lies on a line (here: none at all) has a singular f(Phi_hat(0)): the natural law's
    mirror f(Phi_hat)^-1 does not exist. The batch says so (status "no start") instead of raising LinAlgError."""
    recipe = Recipe("planar-2r-payload", "natural", horizon=0.2)
    spec = recipe.spec()
    spec = dataclasses.replace(spec, theta_hat0=np.concatenate([spec.theta_hat0[:1], 0 * spec.theta_hat0[1:]]))
    (run,), _ = tracking.simulate(recipe.chain(), [spec], 0.2, samples=5)
    assert run.status == "no start" and run.status in tracking.NOT_STARTED and "Theorem 1" in run.note
    assert len(run.t) == 1 and not run.finished


def test_a_natural_run_that_steps_over_its_barrier_is_no_evidence():
    """The hunt's micro 2R arm under a 1.26 kg payload ramp (400,000 times its mass) with the natural law at gain
    1.9e9: RK45 steps U_l = f(Phi_hat_l)^-1 across singular near t = 0.42 s. Along the exact solution D <= V stays
    finite (V grows with Thetadot but not in finite time to infinity), so U_l cannot get there: the run ends
    ``barrier``, not finished, and its negative lambda_min(f(Phi_hat)) counts against nothing."""
    recipe = Recipe(str(SCENES / "micro_2r.toml"), "natural", horizon=0.45, lam=1.0, kd=10.0, gamma=1.911261604766e9,
                    estimate=(0.33123872811590027, 1.331969887534906), amplitude=0.10020079435972962,
                    frequency=0.53656203763729, home=(-1.5158949178379812, -2.128690499988834),
                    payload=(1.2559913068121233, 0.10443550188062459, 1.0))
    (run,), _ = tracking.simulate(recipe.chain(), [recipe.spec()], 0.45, samples=46, rtol=1e-6)
    assert run.status == tracking.BARRIER and not run.finished and "stepped over" in run.note
    assert np.linalg.eigvalsh(pseudo_inertia(estimates.estimates(run)))[..., 0].min() < 0  # what it would have shown
    assert not adaptive.SlotineLi(1.0).outside(np.zeros((3, 2, 10))).any()  # a Euclidean law has no barrier


def test_a_run_stopped_at_its_barrier_says_float64_cannot_follow():
    """The passenger platform's natural law under a 0.25 s traverse at rtol 3e-6: the integrators stop (in the APP
    study at t = 0.2299 s, RK45, BDF and Radau alike, README: stiff runs; here, the traverse starting at 0.02 s, near
    0.05 s) with U_l = f(Phi_hat_l)^-1 singular to 1e-15 of its size: the note names the margin and that the exact
    solution stays off the barrier."""
    recipe = Recipe(str(SCENES / "passenger_platform.toml"), "natural", horizon=0.4, timing=(0.02, 0.25))
    (run,), _ = tracking.simulate(recipe.chain(), [recipe.spec()], 0.4, samples=21, rtol=3e-6,
                                  max_evaluations=20_000, method="RK45")
    assert run.status == "step collapse" and run.t[-1] < 0.1
    assert "from its barrier" in run.note and "lets it come as near as" in run.note and "cannot follow" in run.note
    assert not adaptive.SlotineLi(1.0).barrier_margin(np.zeros((2, 10))).min() < np.inf


@settings(max_examples=100)
@given(st.integers(0, 2**32 - 1))
def test_the_divergence_bounds_the_natural_laws_margin(seed):
    """NaturalAdaptation.margin_floor: every U_l whose divergence from Phi_l is D has barrier_margin at least
    margin_floor(D) (random f(Phi_l) and U_l over six decades of scale; U_l = f(Phi_l)^-1, whose margin is
    1 / cond(f(Phi_l)) at D = 0), and the floor is tight to the roots: with f(Phi_l) = 1 and U_l = diag(mu, 1, 1,
    1) it is mu / mu_hi."""
    rng = np.random.default_rng(seed)
    law = adaptive.NaturalAdaptation(rng.uniform(0.1, 10.0))
    a, b = rng.normal(size=(2, 4, 4))
    theta = adaptive.f_inverse(a @ a.T + 0.1 * np.eye(4))[None]
    z = adaptive.f_inverse(b @ b.T * 10.0 ** rng.uniform(-3, 3) + 1e-6 * np.eye(4))[None]
    assert law.barrier_margin(z)[0] >= law.margin_floor(law.divergence(z, theta), theta)[0] >= 0
    exact = adaptive.f_inverse(np.linalg.inv(a @ a.T + 0.1 * np.eye(4)))[None]  # U_l = f(Phi_l)^-1: D = 0
    assert law.barrier_margin(exact)[0] >= law.margin_floor(law.divergence(exact, theta), theta)[0] * (1 - 1e-9)
    mu = 10.0 ** rng.uniform(-8, 0)
    unit, z = adaptive.f_inverse(np.eye(4))[None], adaptive.f_inverse(np.diag([mu, 1.0, 1.0, 1.0]))[None]
    g = mu - np.log(mu) - 1.0
    grid = np.geomspace(1.0, 4 * g + 4, 200_001)
    mu_hi = grid[np.argmax(grid - np.log(grid) - 1.0 >= g)]  # the larger root on a grid of relative spacing 2e-5
    assert law.margin_floor(law.divergence(z, unit), unit)[0] == pytest.approx(mu / mu_hi, rel=1e-4)


def test_a_run_near_its_barrier_is_named_drifted_where_the_divergence_keeps_it_off():
    """The stop note of a run nearer its barrier than float64 resolves: where D <= V(0) + W keeps the exact solution
    farther off than UNRESOLVED_MARGIN, the integration drifted there; where not, float64 cannot follow."""
    law = adaptive.NaturalAdaptation(10.0)
    run = type("Run", (), {"spec": type("Spec", (), {"law": law})()})()
    theta = adaptive.f_inverse(np.eye(4))[None]
    drifted = tracking._near_barrier(run, 1e-15, 0.1, theta)
    assert "drifted" in drifted and "float64" not in drifted
    beyond = tracking._near_barrier(run, 1e-15, 35.0, theta)
    assert "cannot follow" in beyond and "drifted" not in beyond
    assert "cannot follow" in tracking._near_barrier(run, 1e-15, np.inf, theta)


def test_rk45_is_taken_only_well_inside_its_budget():
    """choose_method keeps RK45 only where its stability bound needs at most 1 / RK45_MARGIN of the budget: a batch
    predicted at 0.94 of its budget (Panda's 12 runs in ci) goes implicit."""
    recipes = [Recipe("panda-payload-3kg", law, horizon=1.7, timing=(0.2, 0.01)) for law in ("slotine-li", "natural")]
    batch = tracking.Batch(recipes[0].chain(), [r.spec() for r in recipes])
    need = simulate.least_evaluations("RK45", float(batch.stiffness(1.7).max()), 1.7)
    assert tracking.choose_method(batch, 1.7, int(need / 0.94)) == "BDF"
    assert tracking.choose_method(batch, 1.7, int(need * tracking.RK45_MARGIN) + 1) == "RK45"


def test_an_explicit_batch_a_run_stiffens_in_stops_where_it_does():
    """trolley_2r: the natural run of the 0.25 s traverse stiffens near t = 0.43 (a mode of 1e4-1e6 rad/s). A batch
    of it and a Slotine-Li run, RK45 by its stiffness at the start (63 /s), stops there at its first look
    (tracking._stiffened), with most of its count left for the runs alone. The natural run alone starts again with
    BDF within what its count has left; the batch with RK45 forced by the caller goes on to its count. Without the
    look the batch spends its 20,000, and the run alone its 3,000 with RK45."""
    runs = [Recipe(str(SCENES / "trolley_2r.toml"), law, horizon=1.7, timing=(0.2, d))
            for law, d in (("slotine-li", 1.0), ("natural", 0.25))]
    kw = dict(samples=86, rtol=3e-5, max_evaluations=20_000)
    batch_runs, batch = tracking.simulate(runs[0].chain(), [r.spec() for r in runs], 1.7, **kw)
    assert all(r.status == "budget" for r in batch_runs) and "run 1 of the batch stiffened" in batch_runs[0].note
    assert tracking.spent(None, batch) < 2 * tracking.STIFFENING_CHECK and batch_runs[0].t[-1] < 0.5
    forced = dict(kw, max_evaluations=1_500, method="RK45")
    batch_runs, batch = tracking.simulate(runs[0].chain(), [r.spec() for r in runs], 1.7, **forced)
    assert "stiffened" not in batch_runs[0].note and tracking.spent(None, batch) > 1_500
    (alone,), _ = tracking.simulate(runs[1].chain(), [runs[1].spec()], 0.5, **dict(kw, max_evaluations=3_000))
    assert alone.method == "BDF" and "the run stiffened" in alone.note and "BDF from the start" in alone.note
    assert 3_000 < alone.work < 3_100
