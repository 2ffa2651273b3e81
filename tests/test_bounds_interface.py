"""The chain split at a body (inertiaproof.bounds.interface): its certified side below sampled values and arb's
enclosure and tight enough that a side raised 5% is caught; the tail's test rejecting an interface inertia above
the tail and its bound below the tail on sampled points of a box; the head's test the pivots of the head's M; the
SDP's interface inertia meeting its constraints."""

from __future__ import annotations

import numpy as np
import pytest

from inertiaproof.bounds import interface
from inertiaproof.bounds.domain import free_coordinates, search_box
from inertiaproof.bounds.interface import head_terms, interface_inertia, split_body, split_ladder
from inertiaproof.bounds.pivots import PivotFamily, articulated_lower, interface_test, pivot_test
from inertiaproof.bounds.spectral import spectral
from inertiaproof.bounds.time import parameter_vertices
from inertiaproof.dynamics import composite
from inertiaproof.model.inertia import spatial_inertia
from inertiaproof.scene import robots

PANDA = robots.panda(payload=2.0)


def _panda():
    chain, thetas = PANDA.chain, parameter_vertices(PANDA.trajectory)[0]
    lo, hi = search_box(chain)
    q = np.where(free_coordinates(chain), lo + (hi - lo) * np.random.default_rng(21).random((20000, chain.n)),
                 0.5 * (lo + hi))
    values = spectral(composite.mass_matrix(chain, q[:, None], thetas[None]), "lmin").min(1)
    return chain, thetas, q, values


@pytest.fixture(scope="module")
def panda_split():
    """Panda's (2 kg) split proved at the 1.03x rung with the deep profile's smallest budget."""
    chain, thetas, q, values = _panda()
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(interface, "RUNGS", (1.03,))
        gamma, note, _ = split_ladder(chain, thetas, float(values.min()), 200)
    return chain, thetas, q, values, gamma, note


def test_split_body_halves_the_free_coordinates():
    assert split_body(PANDA.chain) == 3  # head q2..q4, tail q5..q7
    assert split_body(robots.ur5().chain) == 2  # head q2, q3, tail q4..q6
    assert split_body(robots.spatial_3r().chain) is None  # two free coordinates: not split


def test_split_is_below_every_sampled_value_and_a_side_raised_5_percent_is_caught(panda_split):
    chain, thetas, q, values, gamma, note = panda_split
    assert gamma == pytest.approx(values.min() / 1.03), note
    assert "split at body 4" in note
    assert gamma <= values.min()
    assert 1.05 * gamma > values.min()  # the sample check can fail: the side is within 3% of the samples


def test_split_side_agrees_with_arb(panda_split):
    """The split's certified side lies below arb's upper end of lambda_min(M(q)) at the sampled minimiser and random
    configurations (tests/arb_oracle.py: M from the chain's definition)."""
    pytest.importorskip("flint")
    from arb_oracle import arb_mass_matrix, ball, eigen_enclosures

    chain, thetas, q, values, gamma, _ = panda_split
    for p in [q[np.argmin(values)]] + list(q[:4]):
        high = min(eigen_enclosures(arb_mass_matrix(chain, [ball(x) for x in p], spatial_inertia(t)))[0][1]
                   for t in thetas)
        assert gamma <= high, (p.tolist(), gamma, high)


def _tail_at(chain, thetas, gamma, k, q):
    family = PivotFamily(chain, thetas)
    ok, a, _ = articulated_lower(family, np.full((len(q), len(thetas)), -gamma), k, q, np.zeros_like(q))
    assert ok.all()
    return family, a


def test_interface_test_rejects_an_inertia_above_the_tail_and_its_bound_holds_in_a_box():
    """At a point (radius 0) A_k less 1e-9 of its size passes and A_k plus that fails; on a box of radius 0.05 rad in
    the tail's coordinates the Loewner bound lies below A_k(q) at 300 sampled q (A_k from the same recursion at
    the point, whose turns are exact there)."""
    chain, thetas, q, values = _panda()
    k, gamma = split_body(chain), 0.9 * values.min()
    family, a = _tail_at(chain, thetas, gamma, k, q[:1])
    size = np.linalg.norm(a[0], axis=(-2, -1))[:, None, None] * np.eye(6)
    for shift, expected in ((-1e-9, True), (1e-9, False)):
        ok, _ = interface_test(family, np.full((1, len(thetas)), -gamma), a[0] + shift * size, k, q[:1],
                               np.zeros((1, chain.n)))
        assert ok.all() == expected
    radii = np.where(np.arange(chain.n) > k, 0.05, 0.0)[None]
    _, bound, _ = articulated_lower(family, np.full((1, len(thetas)), -gamma), k, q[:1], radii)
    inside = q[:1] + radii * np.random.default_rng(22).uniform(-1, 1, (300, chain.n))
    _, exact = _tail_at(chain, thetas, gamma, k, inside)
    assert np.linalg.eigvalsh(exact - bound).min() > -1e-12 * np.abs(exact).max()


def test_head_test_is_the_head_mass_matrix():
    """The head's pivot test (top k, body k's inertia L) at a point passes gamma just below lambda_min of
    sum_(b<k) QJ_b^T Z_b QJ_b + QJ_k^T L QJ_k over joints 0..k and fails just above it."""
    chain, thetas, q, _ = _panda()
    k = split_body(chain)
    z = spatial_inertia(thetas)
    lower = z[:, k] - 0.01 * np.eye(6)  # an indefinite body: the test is of any symmetric inertia
    fixed, jac = head_terms(chain, z, k, q[:1])
    value = np.linalg.eigvalsh(fixed[0] + jac[0].T @ lower @ jac[0])[:, 0].min()
    heads = z.copy()
    heads[:, k] = lower
    family = PivotFamily(chain, inertias=heads)
    for factor, expected in ((1 - 1e-9, True), (1 + 1e-9, False)):
        ok, _ = pivot_test(family, 1.0, np.full((1, len(thetas)), -factor * value), q[:1], np.zeros((1, chain.n)), top=k)
        assert ok.all() == expected


def test_interface_inertia_meets_its_constraints():
    """Either SDP: the head's margin with the tail's fixed, or the tail's extra margin with the head's floor fixed."""
    rng = np.random.default_rng(23)
    tail = np.array([x @ x.T - 0.5 * np.eye(6) for x in rng.normal(size=(20, 6, 6))])
    metric = np.broadcast_to(np.eye(6), tail.shape)
    fixed = np.array([x @ x.T for x in rng.normal(size=(20, 3, 3))])
    jac = rng.normal(size=(20, 6, 3))
    head = (lambda lower: np.linalg.eigvalsh(fixed + np.swapaxes(jac, -1, -2) @ lower @ jac).min())
    lower, t = interface_inertia(tail, metric, fixed, jac, 0.1, None)
    assert np.isfinite(t)
    assert np.linalg.eigvalsh(tail - lower - 0.1 * metric).min() > -1e-6
    assert head(lower) > t - 1e-6
    lower, extra = interface_inertia(tail, metric, fixed, jac, 0.1, t - 1.0)  # a floor below t: room for the tail
    assert extra > 0
    assert np.linalg.eigvalsh(tail - lower - (0.1 + extra) * metric).min() > -1e-6
    assert head(lower) > t - 1.0 - 1e-6


def test_an_interface_inertia_raised_is_refused_by_the_tail_and_caught_without_it(monkeypatch):
    """An interface inertia raised by 0.05 I lets the head prove a target 10% above the sampled inf; the tail's test
    refuses it (nothing proved). With a tail test that passes every box the split claims that target, and the
    sample check catches it."""
    chain, thetas, q, values = _panda()
    real, found = interface._interfaces, []

    def raised(chain, family, z, k, gamma, margin, q_tail, q_head):  # both runs: the same rung, one SDP
        if not found:
            found.append(real(chain, family, z, k, gamma / 1.2, margin, q_tail, q_head)[0][0])
        return [(found[0] + 0.05 * np.eye(6), np.full(len(found[0]), np.inf))]

    monkeypatch.setattr(interface, "_interfaces", raised)
    monkeypatch.setattr(interface, "RUNGS", (1 / 1.1,))
    gamma, note, _ = split_ladder(chain, thetas, float(values.min()), 20)
    assert gamma == -np.inf, note

    def forgetful(family, armature, lower, k, c, r):
        return np.ones((len(c), len(thetas)), bool), np.zeros((len(c), chain.n))

    monkeypatch.setattr(interface, "interface_test", forgetful)
    gamma, note, _ = split_ladder(chain, thetas, float(values.min()), 20)
    assert gamma > values.min(), note
