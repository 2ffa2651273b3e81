"""The articulated-body pivot bounds (inertiaproof.bounds.pivots) against samples inside boxes, exact at a point,
and a mutant (the turn's loss dropped) that the samples catch."""

from __future__ import annotations

import numpy as np
import pytest

from inertiaproof.bounds import pivots
from inertiaproof.bounds.configuration import pivot_normality
from inertiaproof.bounds.pivots import PivotFamily, pivot_bounds
from inertiaproof.bounds.spectral import spectral
from inertiaproof.bounds.time import parameter_vertices
from inertiaproof.dynamics import composite
from inertiaproof.scene import robots


def _unit(chain):
    return np.tile(np.array([1.0, 0, 0, 0, 1, 1, 1, 0, 0, 0]), (chain.bodies, 1))[None]


def _cases():
    out = []
    for scene in (robots.panda(payload=2.0), robots.ur5(), robots.spatial_3r()):
        out.append((scene.chain, _unit(scene.chain), "lmin", (0.05, 0.4, 1.5)))
        out.append((scene.chain, parameter_vertices(scene.trajectory)[0], "lmin", (0.005, 0.02)))
        out.append((scene.chain, parameter_vertices(scene.trajectory)[0], "lmax", (0.02, 0.2)))
    return out


@pytest.mark.parametrize("chain, thetas, kind, scales", _cases(),
                         ids=lambda x: x.name if hasattr(x, "name") else None)
def test_pivot_bounds_hold_on_samples_inside_each_box(chain, thetas, kind, scales):
    rng = np.random.default_rng(7)
    family = PivotFamily(chain, thetas)
    lo, hi = chain.coordinate_box()
    for scale in scales:
        r = np.minimum(scale * rng.random((5, chain.n)), 0.5 * (hi - lo))
        c = lo + r + (hi - lo - 2 * r) * rng.random((5, chain.n))
        start = spectral(composite.mass_matrix(chain, c[:, None], thetas[None]), kind)
        bound = pivot_bounds(family, kind, c, r, start)[0]
        for k in range(len(c)):
            q = c[k] + r[k] * (2 * rng.random((400, chain.n)) - 1)
            v = spectral(composite.mass_matrix(chain, q[:, None], thetas[None]), kind)
            assert (v.min() >= bound[k]) if kind == "lmin" else (v.max() <= bound[k])


def test_pivot_bound_is_exact_at_a_point():
    scene = robots.panda(payload=2.0)
    chain, thetas = scene.chain, parameter_vertices(scene.trajectory)[0]
    q = np.random.default_rng(8).uniform(-1, 1, (1, chain.n))
    exact = spectral(composite.mass_matrix(chain, q[:, None], thetas[None]), "lmin")
    bound = pivot_bounds(PivotFamily(chain, thetas), "lmin", q, np.zeros_like(q), exact)[0]
    assert exact.min() * (1 - 1e-9) <= bound[0] <= exact.min()


def test_a_turn_without_its_loss_is_caught(monkeypatch):
    """Dropping the loss of the turns makes the bound of a wide box exceed sampled values."""
    scene = robots.ur5()
    chain, thetas = scene.chain, _unit(scene.chain)
    real = PivotFamily.rotated_lower

    def lossless(self, b, p, c, r, relative=True):
        lower, loss = real(self, b, p, c, np.zeros_like(r), relative)
        return lower, loss

    monkeypatch.setattr(PivotFamily, "rotated_lower", lossless)
    rng = np.random.default_rng(9)
    lo, hi = chain.coordinate_box()
    r = np.tile(0.5 * (hi - lo), (4, 1))
    c = np.tile(0.5 * (hi + lo), (4, 1)) + rng.uniform(-0.5, 0.5, (4, chain.n))
    start = spectral(composite.mass_matrix(chain, c[:, None], thetas[None]), "lmin")
    bound = pivot_bounds(PivotFamily(chain, thetas), "lmin", c, r, start)[0]
    q = lo + (hi - lo) * rng.random((4000, chain.n))
    assert spectral(composite.mass_matrix(chain, q[:, None], thetas[None]), "lmin").min() < bound.max()


def test_pivot_normality_is_certified_and_cached():
    chain = robots.ur5().chain
    first = pivot_normality(chain, 10, 500)
    q = np.random.default_rng(10).uniform(-np.pi, np.pi, (20000, chain.n))
    sampled = spectral(composite.mass_matrix(chain, q[:, None], _unit(chain)[None]), "lmin").min()
    assert 0 < first <= sampled and pivot_normality(chain, 10, 500) == first
    assert pivots.PIVOT_MIN_ROUNDS <= 20  # the ci profile's budget runs it


@pytest.mark.parametrize("scene", [robots.ur5(), robots.spatial_3r()], ids=lambda s: s.name)
def test_weighted_pivot_floor_is_below_the_sampled_inf_of_lambda_min(scene):
    """M(q) >= sum_l mu_l QJ_l^T QJ_l for mu_l <= lambda_min(Z_l): the pivot bound of the right side is below
    every sampled lambda_min(M) (and positive on these chains)."""
    from inertiaproof.model.inertia import spatial_inertia

    chain, thetas = scene.chain, parameter_vertices(scene.trajectory)[0]
    mu = spectral(spatial_inertia(thetas), "lmin")
    bound = pivot_normality(chain, 10, 500, mu)
    q = np.random.default_rng(11).uniform(-np.pi, np.pi, (20000, chain.n))
    sampled = spectral(composite.mass_matrix(chain, q[:, None], thetas[None]), "lmin").min()
    assert 0 < bound <= sampled
