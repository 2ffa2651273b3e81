"""The polynomial box bounds of Section 4's extremes (inertiaproof.bounds.taylor), the spectral kinds and
Bracket.tighten: the facts the certified side rests on, checked against samples, and a mutant the check catches."""

from __future__ import annotations

import tracemalloc
from pathlib import Path

import numpy as np
import pytest

from inertiaproof.bounds.configuration import jacobian_normality, jacobian_sup, mass_inf, mass_sup
from inertiaproof.bounds.extremes import Bracket
from inertiaproof.bounds.spectral import CONVEX, Spectral, spectral
from inertiaproof.bounds.domain import free_coordinates
from inertiaproof.bounds.taylor import (
    MassFamily, box_bounds, certified_box_bound, entry_degrees, entry_sups, fourier_sups, perron_bound,
)
from inertiaproof.bounds.time import parameter_vertices
from inertiaproof.dynamics import composite
from inertiaproof.scene import robots
from inertiaproof.scene.format import load_scene

SCENES = Path(__file__).resolve().parents[1] / "scenes"


def _arms():
    return [robots.panda(payload=2.0), robots.ur5(), robots.spatial_3r(), robots.planar_2r(payload=1.0)]


def _stack(scene, rate=False):
    verts = parameter_vertices(scene.trajectory)
    return verts[1] if rate else verts[0]


@pytest.mark.parametrize("scene", _arms()[:3], ids=lambda s: s.name)
def test_entry_degrees_are_the_harmonics_along_each_coordinate(scene):
    """M_il along q_j (others fixed) has no harmonic beyond entry_degrees[i, l, j] (7 samples resolve degree 3)."""
    chain, thetas = scene.chain, _stack(scene)
    deg = entry_degrees(chain.n)
    rng = np.random.default_rng(3)
    angles = 2 * np.pi * np.arange(7) / 7
    for q in rng.uniform(-2, 2, (3, chain.n)):
        for j in range(chain.n):
            qs = np.repeat(q[None], 7, 0)
            qs[:, j] = q[j] + angles
            m = composite.mass_matrix(chain, qs[:, None], thetas[None])  # (7, V, n, n)
            harmonics = np.abs(np.fft.fft(m, axis=0)) / 7  # index h: harmonic h (and 7 - h)
            scale = np.abs(m).max() + 1e-300
            for h in (1, 2, 3):
                beyond = harmonics[h].max(0) > 1e-12 * scale  # (n, n)
                assert not np.any(beyond & (deg[:, :, j] < h)), (j, h)


@pytest.mark.parametrize("scene", _arms(), ids=lambda s: s.name)
def test_entry_sups_bound_every_sampled_entry(scene):
    chain = scene.chain
    rng = np.random.default_rng(4)
    q = rng.uniform(-np.pi, np.pi, (4000, chain.n))
    for thetas in (_stack(scene), _stack(scene, rate=True)):
        family = MassFamily(chain, thetas)  # the smaller of the length bounds and the Wiener norms
        m = composite.mass_matrix(chain, q[:, None], thetas[None])
        for s in (entry_sups(chain, thetas), family.sups):
            assert np.all(np.abs(m).max(0) <= s * (1 + 1e-12) + 1e-300)
        assert np.abs(np.linalg.eigvalsh(m)).max() <= perron_bound(family)


def test_wiener_norms_are_sharper_than_lengths_on_ur5():
    scene = robots.ur5()
    chain, thetas = scene.chain, _stack(scene)
    wiener = fourier_sups(chain, thetas, free_coordinates(chain))
    assert wiener.sum() < 0.5 * entry_sups(chain, thetas).sum()
    assert perron_bound(MassFamily(chain, thetas)) < 1.1 * 3.8146  # the sampled sup of lambda_max (bench)


def _boxes(chain, rng, count, scale):
    lo, hi = chain.coordinate_box()
    r = np.minimum(scale * rng.random((count, chain.n)), 0.5 * (hi - lo))
    c = lo + r + (hi - lo - 2 * r) * rng.random((count, chain.n))
    return c, r


@pytest.mark.parametrize("scene", _arms()[:3] + [load_scene(SCENES / "many_links_24.toml")], ids=lambda s: s.name)
@pytest.mark.parametrize("kind", ["lmin", "lmax", "absmax"])
def test_box_bounds_hold_on_samples_inside_each_box(scene, kind):
    """The certified bound on a box against 300 configurations drawn in it (Thetadot for absmax: indefinite)."""
    chain = scene.chain
    thetas = _stack(scene, rate=kind == "absmax")
    family = MassFamily(chain, thetas)
    rng = np.random.default_rng(5)
    for scale in (0.02, 0.3, 2.0):
        c, r = _boxes(chain, rng, 6, scale)
        bound = box_bounds(family, kind, c, r)
        for k in range(len(c)):
            q = c[k] + r[k] * (2 * rng.random((300, chain.n)) - 1)
            v = spectral(composite.mass_matrix(chain, q[:, None], thetas[None]), kind)
            if kind == "lmin":
                assert v.min() >= bound[k]
            else:
                assert v.max() <= bound[k]


def test_cached_coefficients_are_keyed_by_the_whole_chain():
    """Two chains that differ only in one joint's axis share no cached Fourier coefficients (the cache key once left
    the axis out: the second chain got the first one's entry sups)."""
    from inertiaproof.dynamics.chain import Chain

    sc = robots.panda()
    theta = np.asarray(sc.trajectory.theta(np.array([0.0]))[0])
    data = sc.chain.to_data()
    data["joints"][2]["axis"] = [0.0, 1.0, 0.0]
    other = Chain.from_data(data)
    from inertiaproof.bounds import memo

    memo.clear()
    alone = perron_bound(MassFamily(other, theta))
    memo.clear()
    perron_bound(MassFamily(sc.chain, theta))
    assert perron_bound(MassFamily(other, theta)) == alone


def test_certified_box_bound_is_the_batched_bound_on_one_box():
    scene = robots.panda(payload=2.0)
    thetas = _stack(scene)
    lo, hi = np.full(7, -0.1), np.full(7, 0.2)
    one = certified_box_bound(scene.chain, thetas, "lmax", lo, hi)
    batched = box_bounds(MassFamily(scene.chain, thetas), "lmax", (0.5 * (lo + hi))[None], (0.5 * (hi - lo))[None])
    assert one == float(batched[0])
    assert certified_box_bound(scene.chain, thetas, "lmax", lo, hi) == one  # pure: same inputs, same answer


def test_a_bound_without_its_remainder_is_caught_by_the_samples():
    """The sampled check above can fail: the centre's value taken as the bound of a wide box is violated."""
    scene = robots.panda(payload=2.0)
    chain, thetas = scene.chain, _stack(scene)
    rng = np.random.default_rng(6)
    c, r = _boxes(chain, rng, 4, 1.5)
    caught = 0
    for k in range(len(c)):
        mutant = spectral(composite.mass_matrix(chain, c[k][None, None], thetas[None]), "lmax").max()
        q = c[k] + r[k] * (2 * rng.random((300, chain.n)) - 1)
        caught += spectral(composite.mass_matrix(chain, q[:, None], thetas[None]), "lmax").max() > mutant
    assert caught >= 3


def test_long_chain_brackets_are_polynomial_and_certified():
    """24 joints: every bracket finishes with a certified side, within a few hundred MiB (numpy allocations)."""
    scene = load_scene(SCENES / "many_links_24.toml")
    chain, thetas = scene.chain, _stack(scene)
    kw = dict(samples=200, rounds=8, rng=np.random.default_rng(0))
    tracemalloc.start()
    try:
        brackets = [mass_inf(chain, thetas, **kw), mass_sup(chain, thetas, **kw), jacobian_sup(chain, **kw),
                    jacobian_normality(chain, **kw)]
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 600 * 2**20
    for b in brackets:
        assert b.certified is not None and np.isfinite(b.certified)
        assert b.lower <= b.upper * (1 + 1e-12)


def test_spectral_kinds_know_their_convexity():
    assert {k.value for k in CONVEX} == {"lmax", "smax", "absmax"}
    assert Spectral("lmin").sense == "min" and Spectral.ABSMAX.sense == "max"
    a = np.diag([-3.0, 1.0, 2.0])
    assert Spectral.LMIN(a) == -3.0 and Spectral.ABSMAX(a) == 3.0 and spectral(a, "lmax") == 2.0


def test_tighten_adopts_only_a_sharper_certified_side():
    low = Bracket("inf", "min", 1.0, 0.2, np.zeros(2), [[0.0, 0.2, 1.0]])
    assert not low.tighten(0.1, "weaker") and low.certified == 0.2
    assert low.tighten(0.5, "sharper") and low.certified == 0.5 and low.convergence[0][1] == 0.5
    assert "sharper" in low.note and "weaker" not in low.note
    high = Bracket("sup", "max", 1.0, None, np.zeros(2), [[0.0, 1.0, None]])
    assert high.tighten(3.0, "a priori") and high.upper == 3.0 and high.convergence[0][2] == 3.0
    assert not high.tighten(4.0, "looser") and not high.tighten(np.nan, "nan")
