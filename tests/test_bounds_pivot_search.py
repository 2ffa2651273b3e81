"""The ladder of pivot-proved targets (inertiaproof.bounds.pivot_search) and the turn losses it rests on
(inertiaproof.bounds.pivots): never above sampled values, a partition that covers the domain, and broken
versions (a loss term dropped, failing boxes forgotten, a bound raised) caught."""

from __future__ import annotations

import numpy as np
import pytest

from inertiaproof.budget import available_cores
from inertiaproof.bounds import ladders, pivot_search, pivots
from inertiaproof.bounds.configuration import jacobian_normality, mass_inf, pivot_normality
from inertiaproof.bounds.domain import free_coordinates, search_box
from inertiaproof.bounds.pivots import PivotFamily, pivot_bounds, pivot_test
from inertiaproof.bounds.spectral import spectral
from inertiaproof.bounds.time import parameter_vertices
from inertiaproof.dynamics import composite
from inertiaproof.model.inertia import spatial_inertia
from inertiaproof.scene import robots

UNIT = np.array([1.0, 0, 0, 0, 1, 1, 1, 0, 0, 0])


def _forms(scene):
    """(name, thetas) of the forms the ladders prove: unit bodies, the weighted unit form, the real inertias."""
    thetas = parameter_vertices(scene.trajectory)[0]
    mu = spectral(spatial_inertia(thetas), "lmin").min(0, keepdims=True)
    return [("unit", np.tile(UNIT, (scene.chain.bodies, 1))[None]), ("weighted", mu[..., None] * UNIT),
            ("real", thetas)]


def _random_boxes(rng, scale, lo, hi, free, count=6):
    """``count`` boxes (centres, radii) inside [lo, hi], radii 0.5-1.5 ``scale`` in the free coordinates."""
    r = np.where(free, np.minimum(scale * (0.5 + rng.random((count, len(lo)))), 0.5 * (hi - lo)), 0.0)
    return lo + r + (hi - lo - 2 * r) * rng.random((count, len(lo))), r


def _inside(rng, centres, radii, count=1500):
    """Per box, ``count`` uniform configurations inside it."""
    return [c + r * (2 * rng.random((count, len(c))) - 1) for c, r in zip(centres, radii)]


def _lmin(chain, thetas, q):
    return spectral(composite.mass_matrix(chain, q[:, None], thetas[None]), "lmin")  # (K, V)


@pytest.mark.parametrize("scene", [robots.panda(payload=2.0), robots.ur5()], ids=lambda s: s.name)
@pytest.mark.parametrize("form", [0, 1, 2], ids=["unit", "weighted", "real"])
@pytest.mark.parametrize("metric", pivots.METRICS)
def test_a_passing_box_holds_on_dense_samples(scene, form, metric):
    """Where the pivot test passes gamma (the bisection bound of the box), every sampled lambda_min in the box is
    at least gamma: boxes of 0.01-0.6 rad (both sides of pivots.SWITCH) and whole periods, in either loss metric."""
    chain = scene.chain
    _, thetas = _forms(scene)[form]
    family = PivotFamily(chain, thetas)
    family.metric = metric
    rng = np.random.default_rng(20 + form + 10 * pivots.METRICS.index(metric))
    lo, hi = search_box(chain)
    free = free_coordinates(chain)
    scales = (0.01, 0.1, 0.3, 0.6) if form < 2 else (0.003, 0.01, 0.03)
    for scale in scales:
        c, r = _random_boxes(rng, scale, lo, hi, free)
        bound = pivot_bounds(family, "lmin", c, r, _lmin(chain, thetas, c), steps=30)[0]
        for k, q in enumerate(_inside(rng, c, r)):
            assert _lmin(chain, thetas, q).min() >= bound[k]
    whole = np.where(free, 0.5 * (hi - lo), 0.0)[None]
    gamma = pivot_bounds(family, "lmin", (0.5 * (lo + hi))[None], whole, _lmin(chain, thetas, (0.5 * (lo + hi))[None]))[0]
    q = lo + (hi - lo) * rng.random((4000, chain.n))
    assert _lmin(chain, thetas, q).min() >= gamma[0]


def _turn_violations(chain, radii_range, rng, count=40, points=60, metric="shift"):
    """The largest violation of L <= Phi_b(x)^T P Phi_b(x) over sampled x of |x - c| <= r (lambda_min of the
    difference, relative to ||P||; < 0 is a violation), for random anisotropic P (eigenvalues 1e-4 .. 5; with
    ``metric`` 'abs' the heaviest negated: indefinite, as a pivot leaves it) and every turning joint b of the
    chain: :meth:`PivotFamily.rotated_lower` in that metric."""
    family = PivotFamily(chain, np.tile(UNIT, (chain.bodies, 1))[None])
    family.metric = metric
    spectrum = np.geomspace(1e-4, 5.0, 6) * (1, 1, 1, 1, 1, -1 if metric == "abs" else 1)
    worst = np.inf
    for b in range(1, chain.n):
        if not family.revolute[b]:
            continue
        basis = np.linalg.qr(rng.normal(size=(count, 6, 6)))[0]
        p = (basis * spectrum[None, None, :]) @ np.swapaxes(basis, -1, -2)
        p = p[:, None]
        c, r = rng.uniform(-3, 3, count), rng.uniform(*radii_range, count)
        lower, _ = family.rotated_lower(b, p, c, r)
        for k in range(points):
            x = c + r * rng.uniform(-1, 1, count)
            t = family.turn_maps(b, x)[:, None]
            exact = family.before[b].T @ (np.swapaxes(t, -1, -2) @ (family.after[b].T @ p @ family.after[b]) @ t) @ family.before[b]
            worst = min(worst, float((np.linalg.eigvalsh(exact - lower)[..., 0] / 5.0).min()))
    return worst


@pytest.mark.parametrize("radii", [(0.01, 0.1), (0.1, 0.4), (0.4, 1.2), (1.2, 3.2)])
@pytest.mark.parametrize("metric", pivots.METRICS)
def test_turn_lower_bound_holds_on_samples(radii, metric):
    assert _turn_violations(robots.panda().chain, radii, np.random.default_rng(31), metric=metric) >= -1e-12


@pytest.mark.parametrize("drop, radii", [("first-order", (0.05, 0.4)), ("second-order", (0.05, 0.4)),
                                         ("wide", (0.4, 1.5))])
@pytest.mark.parametrize("metric", pivots.METRICS)
def test_a_turn_loss_term_dropped_is_caught(drop, radii, metric, monkeypatch):
    """A loss term of pivots._turn_terms dropped (its weight set to 0): the turn's lower bound rises above sampled
    turned matrices (the samples of test_turn_lower_bound_holds_on_samples). The r^3 and r^4 terms near the
    centre are below what sampling resolves (measured: dropping 2 E^2 pos(-F2c) is not caught on 0.2-0.4 rad)."""
    real = pivots._turn_terms

    def broken(f1c, f1s, f2c, f2s, rr):
        terms, weights = real(f1c, f1s, f2c, f2s, rr)
        weights = list(weights)
        if drop == "wide":
            weights = [np.where(rr <= pivots.SWITCH, w, 0 * w) for w in weights]
        else:
            k = {"first-order": 0, "second-order": 1}[drop]
            weights[k] = 0 * weights[k]
        return terms, tuple(weights)

    monkeypatch.setattr(pivots, "_turn_terms", broken)
    assert _turn_violations(robots.panda().chain, radii, np.random.default_rng(31), metric=metric) < -1e-9


def _ladder(scene, form, boxes=6000):
    chain = scene.chain
    _, thetas = _forms(scene)[form]
    family = PivotFamily(chain, thetas)
    lo, hi = search_box(chain)
    free = free_coordinates(chain)
    q = np.where(free, lo + (hi - lo) * np.random.default_rng(40).random((3000, chain.n)), 0.5 * (lo + hi))
    v = _lmin(chain, thetas, q).min(1)
    k = int(np.argmin(v))
    found = pivot_search.pivot_ladder(family, lambda x: _lmin(chain, thetas, x), float(v[k]), q[k], lo, hi, free,
                                      max_boxes=boxes, guard_s=120)
    return chain, thetas, found


@pytest.mark.parametrize("scene, form", [(robots.ur5(), 0), (robots.ur5(), 1), (robots.panda(payload=2.0), 0)],
                         ids=["ur5-unit", "ur5-weighted", "panda-unit"])
def test_ladder_is_below_every_sampled_value(scene, form):
    chain, thetas, (gamma, tested, size, ratio, rungs, _) = _ladder(scene, form)
    assert gamma > 0 and ratio is not None and tested <= 6000 + pivot_search.CHUNK
    assert sum(r[1] for r in rungs) == tested and [r[0] for r in rungs if r[2] is not None][-1] == ratio
    spent = np.cumsum([0] + [t for _, t, _ in rungs])
    assert all((pivot_search.rung_cost(rungs[:k], r[0]) or 0) <= pivot_search.SLACK * (6000 - spent[k])
               for k, r in enumerate(rungs))
    lo, hi = search_box(chain)
    q = lo + (hi - lo) * np.random.default_rng(41).random((30000, chain.n))
    assert _lmin(chain, thetas, q).min() >= gamma


def test_rung_forecast():
    rungs = [(1.2, 9000, 5000), (1.1, 10_000, 6000)]
    assert pivot_search.rung_cost(rungs, 1.1) == pytest.approx(6000)  # the same rung again: each box once
    assert pivot_search.rung_cost(rungs, 1.05, -1) == pytest.approx(6000 * (2 * 2**pivot_search.GROWTH - 1))
    assert pivot_search.rung_cost(rungs, 1.05) == pytest.approx(6000 * (2 * (2.1 / 1.1)**pivot_search.GROWTH - 1))
    assert pivot_search.rung_cost([(1.2, 10_000, None)], 1.1) is pivot_search.rung_cost([(1.1, 100, 60)], 1.05) is None


def test_ladder_partition_covers_the_domain_and_forgetting_failed_boxes_is_caught(monkeypatch):
    """Every box of a proved partition passes gamma, and the boxes tile the domain (their volumes add up to
    the domain's, none sticks out). A _prove that drops failing boxes instead of halving them leaves a gap."""
    scene = robots.panda()
    chain = scene.chain
    _, thetas = _forms(scene)[0]
    family = PivotFamily(chain, thetas)
    lo, hi = search_box(chain)
    free = free_coordinates(chain)
    centre, radius = (0.5 * (lo + hi))[None], np.where(free, 0.5 * (hi - lo), 0.0)[None]
    rho = np.ones(chain.n)
    gamma = 0.33

    def covers(partition):
        c, r = partition
        ok, _ = pivot_test(family, 1.0, np.full((len(c), 1), -gamma), c, r)
        inside = np.all(c - r >= lo - 1e-12) and np.all(c + r <= hi + 1e-12)
        volume = np.prod(np.where(free, 2 * r, 1.0), axis=1).sum()
        return ok.all() and inside and np.isclose(volume, np.prod(np.where(free, hi - lo, 1.0)), rtol=1e-9)

    partition, _ = pivot_search._prove(family, 1.0, gamma, centre, radius, rho, 20000, np.inf)
    assert partition is not None and len(partition[0]) > 1 and covers(partition)

    real_test = pivot_search.pivot_test

    def forgetful(family, sign, armature, c, r):  # failing boxes reported as passing: nothing left to halve
        ok, losses = real_test(family, sign, armature, c, r)
        return np.ones_like(ok), losses

    monkeypatch.setattr(pivot_search, "pivot_test", forgetful)
    partition, _ = pivot_search._prove(family, 1.0, gamma, centre, radius, rho, 20000, np.inf)
    monkeypatch.setattr(pivot_search, "pivot_test", real_test)
    assert not covers(partition)


def test_a_ladder_bound_raised_50_percent_is_caught():
    """The ladder's certified side raised by 50% (UR5's unit form: within 1.45x of the sampled inf) lies above a
    sampled value: the sample check of test_ladder_is_below_every_sampled_value can fail."""
    chain, thetas, (gamma, *_) = _ladder(robots.ur5(), 0, boxes=20000)
    lo, hi = search_box(chain)
    q = lo + (hi - lo) * np.random.default_rng(41).random((30000, chain.n))
    sampled = _lmin(chain, thetas, q).min()
    assert gamma <= sampled < 1.5 * gamma


def test_ci_brackets_of_panda_and_ur5_within_2x():
    """The ci budget (20 rounds, 2000 samples) brackets Panda's (2 kg) inf lambda_min(M) and inf
    sigma_min(QJ)^2 and UR5's inf sigma_min(QJ)^2 within 2x (issue 12)."""
    for scene, inf in ((robots.panda(payload=2.0), True), (robots.ur5(), False)):
        chain = scene.chain
        kw = dict(samples=2000, rounds=20, rng=np.random.default_rng(0))
        brackets = [jacobian_normality(chain, **kw)]
        if inf:
            brackets.append(mass_inf(chain, parameter_vertices(scene.trajectory)[0], **dict(kw, rng=np.random.default_rng(0))))
        for b in brackets:
            assert 0 < b.lower and b.upper / b.lower <= 2.0, (b.quantity, b.lower, b.upper)


def test_pivot_normality_stops_at_its_goal_and_caches():
    chain = robots.ur5().chain
    first = pivot_normality(chain, 20, 500)
    assert first > 0 and pivot_normality(chain, 20, 500) == first
    assert pivot_search.ladder_goal(20) == 2.0 and pivot_search.ladder_goal(800) < 1.1


def _block_form(scene):
    from inertiaproof.bounds.configuration import block_lower_form

    chain, thetas = scene.chain, parameter_vertices(scene.trajectory)[0]
    lo, hi = search_box(chain)
    q = lo + (hi - lo) * np.random.default_rng(50).random((300, chain.n))
    return chain, thetas, block_lower_form(thetas, q, chain, grid=8)


@pytest.mark.parametrize("scene", [robots.panda(payload=2.0), robots.ur5()], ids=lambda s: s.name)
def test_block_lower_form_is_below_every_body_and_m(scene):
    """diag(mu_l I3, nu_l I3) <= Z(Theta_v)_l for every body and parameter set, so sum_l QJ_l^T Y_l QJ_l <= M(q)
    at sampled q; the ladder's bound of the form lies below sampled lambda_min(M); nu raised 30% breaks the first."""
    from inertiaproof.bounds.lengths import block_rows

    chain, thetas, (mu, nu) = _block_form(scene)
    z = spatial_inertia(thetas)
    y = spatial_inertia(block_rows(mu, nu)[None])  # (1, N, 6, 6)
    assert np.all(np.linalg.eigvalsh(z - y)[..., 0] >= 0)
    y_bad = spatial_inertia(block_rows(mu, 1.3 * nu)[None])
    assert np.any(np.linalg.eigvalsh(z - y_bad)[..., 0] < 0)
    lo, hi = search_box(chain)
    q = lo + (hi - lo) * np.random.default_rng(51).random((3000, chain.n))
    m = composite.mass_matrix(chain, q[:, None], thetas[None])
    form = composite.mass_matrix(chain, q[:, None], block_rows(mu, nu)[None][None])
    assert np.linalg.eigvalsh(m - form)[..., 0].min() >= -1e-12
    if scene.name == "panda":  # UR5's block form proves nothing in this budget (-inf, sound): Panda only
        gamma = pivot_normality(chain, 20, 500, mu[None], angular=nu)
        assert 0 < gamma <= _lmin(chain, thetas, q).min()


# -- the upper side: gamma I - M > 0 (sup lambda_max; Theorems 3 and 4, sup sigma_max(QJ)) ----------------------

def _upper_forms(scene):
    """(name, thetas) of the stacks whose sup lambda_max the upper ladders prove: unit bodies, the real inertias, and
    Theorem 4's parameter rates with their negatives (indefinite: sup lambda_max = sup sigma_max)."""
    rates = parameter_vertices(scene.trajectory)[1]
    return [("unit", np.tile(UNIT, (scene.chain.bodies, 1))[None]), ("real", parameter_vertices(scene.trajectory)[0]),
            ("rates", np.concatenate([rates, -rates]))]


def _lmax(chain, thetas, q):
    return spectral(composite.mass_matrix(chain, q[:, None], thetas[None]), "lmax")  # (K, V)


@pytest.mark.parametrize("scene", [robots.panda(payload=2.0), robots.ur5()], ids=lambda s: s.name)
@pytest.mark.parametrize("form", [0, 1, 2], ids=["unit", "real", "rates"])
def test_a_passing_upper_box_holds_on_dense_samples(scene, form):
    """Where the pivot test of gamma I - M passes (the bisection bound of lambda_max on the box), every sampled
    lambda_max in the box is at most gamma: boxes of 0.01-0.6 rad."""
    chain = scene.chain
    _, thetas = _upper_forms(scene)[form]
    family = PivotFamily(chain, thetas)
    rng = np.random.default_rng(60 + form)
    lo, hi = search_box(chain)
    free = free_coordinates(chain)
    for scale in (0.01, 0.1, 0.3, 0.6):
        c, r = _random_boxes(rng, scale, lo, hi, free)
        start = np.broadcast_to(_lmax(chain, thetas, c).max(1, keepdims=True), (len(c), len(thetas)))  # rates: >= 0
        bound = pivot_bounds(family, "lmax", c, r, start, steps=30)[0]
        assert scale > 0.1 or np.all(np.isfinite(bound))  # the bisection looks up to twice the centre's value
        for k, q in enumerate(_inside(rng, c, r)):
            assert _lmax(chain, thetas, q).max() <= bound[k]


def _upper_ladder(scene, form, boxes=6000):
    chain = scene.chain
    _, thetas = _upper_forms(scene)[form]
    lo, hi = search_box(chain)
    free = free_coordinates(chain)
    q = np.where(free, lo + (hi - lo) * np.random.default_rng(42).random((3000, chain.n)), 0.5 * (lo + hi))
    v = _lmax(chain, thetas, q).max(1)
    k = int(np.argmax(v))
    found = pivot_search.pivot_ladder(PivotFamily(chain, thetas), lambda x: _lmax(chain, thetas, x), float(v[k]),
                                      q[k], lo, hi, free, max_boxes=boxes, guard_s=120, sign=-1.0)
    return chain, thetas, found


@pytest.mark.parametrize("scene, form, boxes", [(robots.ur5(), 1, 6000), (robots.panda(payload=2.0), 0, 6000),
                                                pytest.param(robots.panda(payload=2.0), 2, 1500,
                                                             marks=pytest.mark.slow)],
                         ids=["ur5-real", "panda-unit", "panda-rates"])
def test_upper_ladder_is_above_every_sampled_value(scene, form, boxes):
    chain, thetas, (gamma, tested, size, ratio, rungs, _) = _upper_ladder(scene, form, boxes)
    assert np.isfinite(gamma) and ratio is not None and ratio < 2 and tested <= boxes + pivot_search.CHUNK
    lo, hi = search_box(chain)
    q = lo + (hi - lo) * np.random.default_rng(43).random((30000, chain.n))
    assert _lmax(chain, thetas, q).max() <= gamma


def test_an_upper_ladder_bound_lowered_is_caught():
    """The upper ladder's certified side lowered to 1/1.5 of it lies below a sampled value (UR5's real inertias:
    proved within 1.5x), so the sample check above can fail; so does a ladder whose pivot test ignores the boxes'
    widths (each box judged at its centre), started from a sampled max of 20 configurations."""
    chain, thetas, (gamma, *_) = _upper_ladder(robots.ur5(), 1, boxes=20000)
    lo, hi = search_box(chain)
    free = free_coordinates(chain)
    q = lo + (hi - lo) * np.random.default_rng(43).random((30000, chain.n))
    sampled = _lmax(chain, thetas, q).max()
    assert gamma / 1.5 < sampled <= gamma
    real_test = pivot_search.pivot_test
    few = q[:20]
    k = int(np.argmax(_lmax(chain, thetas, few).max(1)))
    try:
        pivot_search.pivot_test = lambda family, sign, armature, c, r: real_test(family, sign, armature, c, 0 * r)
        wrong = pivot_search.pivot_ladder(PivotFamily(chain, thetas), lambda x: _lmax(chain, thetas, x),
                                          float(_lmax(chain, thetas, few[k:k + 1]).max()), few[k], lo, hi, free,
                                          max_boxes=4000, guard_s=60, sign=-1.0)[0]
    finally:
        pivot_search.pivot_test = real_test
    assert wrong < sampled


def test_mass_sup_adopts_the_upper_ladder_where_the_fourier_bound_is_short(monkeypatch):
    """Where the bracket is wider than the ladder's goal (here: the Fourier bound left out, the ci budget's vertex
    bracket 2.5x) mass_sup's certified side of Panda's (2 kg) sup lambda_max comes from the upper ladder, within
    1.5x and above dense samples."""
    from inertiaproof.bounds import configuration, perron

    monkeypatch.setattr(perron, "fourier_perron_bound", lambda *a, **k: None)
    scene = robots.panda(payload=2.0)
    chain, thetas = scene.chain, parameter_vertices(scene.trajectory)[0]
    b = configuration.mass_sup(chain, thetas, samples=500, rounds=20, rng=np.random.default_rng(0))
    assert "gamma I - M" in b.note and b.upper / b.lower < 1.5, (b.lower, b.upper, b.note)
    lo, hi = search_box(chain)
    q = lo + (hi - lo) * np.random.default_rng(44).random((20000, chain.n))
    assert _lmax(chain, thetas, q).max() <= b.upper


def test_pivot_test_over_threads_answers_as_one():
    """pivot_test split over threads (from pivots.SPLIT boxes per thread) gives the single call's answer."""
    scene = robots.panda(payload=2.0)
    chain, thetas = scene.chain, parameter_vertices(scene.trajectory)[0]
    lo, hi = search_box(chain)
    c, r = _random_boxes(np.random.default_rng(70), 0.05, lo, hi, free_coordinates(chain), count=3 * pivots.SPLIT + 7)
    family = PivotFamily(chain, thetas)
    armature = np.full((len(c), len(thetas)), -1.2e-3)
    split, whole = pivots.pivot_test(family, 1.0, armature, c, r), pivots._pivot_test(family, 1.0, armature, c, r)
    assert available_cores() < 2 or len(c) // pivots.SPLIT >= 2
    assert np.array_equal(split[0], whole[0]) and np.array_equal(split[1], whole[1]) and 0 < split[0].mean() < 1


def test_upper_ladder_leaves_out_only_sets_with_every_body_negative(monkeypatch):
    """Theorem 4's stack is the rates and their negatives; a set whose every Z_l <= 0 (Weyl) has M <= 0, below
    any positive target, and is left out of the upper ladder; a set with one body indefinite is kept."""
    scene = robots.panda(payload=2.0)
    rate = parameter_vertices(scene.trajectory)[1]
    rate = rate[np.argmax(spectral(spatial_inertia(rate), "lmin").min(1))]  # the growing payload: every Z_l >= 0
    mixed = -rate.copy()
    mixed[-1, 0] = 1.0  # the payload's mass up, its rotational inertia down: indefinite
    assert spectral(spatial_inertia(mixed[-1]), "lmin") < 0 < spectral(spatial_inertia(mixed[-1]), "lmax")
    seen = []
    monkeypatch.setattr(ladders, "_ladder", lambda chain, family, *a, **k: (seen.append(family.z.shape[0]), (1.0, ""))[1])
    for stack, kept in (([rate, -rate], 1), ([-rate, mixed], 1), ([rate, -rate, mixed], 2)):
        ladders.pivot_sup(scene.chain, np.array(stack), 800, 1.0, np.zeros(scene.chain.n), 1.01)
        assert seen.pop() == kept


@pytest.mark.slow
def test_real_inertias_close_so101s_bracket_in_ci():
    """SO-101's jaw (its inertia mostly m rho^2 of an off-axis com) defeats every lower form (2.87x in ci); the
    ladder on the bodies themselves, in the |F| metric, brings the ci bracket within 2x, above dense samples."""
    from importlib import metadata

    from inertiaproof.audit.document import read_robot
    from inertiaproof.audit.kinematic_tree import kinematic_tree

    try:
        dist = metadata.distribution("example-robot-data")
    except metadata.PackageNotFoundError:
        pytest.skip("example-robot-data is not installed (test extra)")
    robots_dir = dist.locate_file("cmeel.prefix/share/example-robot-data/robots")
    sc = kinematic_tree(read_robot(robots_dir / "so_arm_description/urdf/so101.urdf")).chains[0]
    chain, thetas = sc.chain, np.asarray(sc.theta)[None]
    b = mass_inf(chain, thetas, samples=512, rounds=20, rng=np.random.default_rng(0))
    assert "pivots of M(q) - gamma I" in b.note and b.upper / b.lower < 2, (b.lower, b.upper, b.note)
    lo, hi = search_box(chain)
    q = np.where(free_coordinates(chain), lo + (hi - lo) * np.random.default_rng(45).random((20000, chain.n)),
                 0.5 * (lo + hi))
    assert _lmin(chain, thetas, q).min() >= b.lower
