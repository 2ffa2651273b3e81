"""Certified sups of |M_il(q)| over the search box from M's exact Fourier series (inertiaproof.bounds.fourier) and
their Perron bound in mass_sup / jacobian_sup (issue 12): every bound lies above dense samples, and deliberately
broken versions (the grid remainder dropped, the bound shrunk 30%) are caught by the same samples."""

from __future__ import annotations

import numpy as np
import pytest

from inertiaproof.bounds import fourier
from inertiaproof.bounds.configuration import fourier_perron_bound, jacobian_sup, mass_sup
from inertiaproof.bounds.domain import search_box
from inertiaproof.bounds.fourier import FourierFamily, certified_entry_sups, partial_wiener_sups, perron_of
from inertiaproof.bounds.spectral import spectral
from inertiaproof.bounds.time import parameter_vertices
from inertiaproof.dynamics import composite
from inertiaproof.scene import robots

UNIT = np.array([1.0, 0, 0, 0, 1, 1, 1, 0, 0, 0])


def _cases():
    panda, ur5, r3 = robots.panda(payload=2.0), robots.ur5(), robots.spatial_3r()
    return [(panda, parameter_vertices(panda.trajectory)[0]), (panda, parameter_vertices(panda.trajectory)[1][:1]),
            (ur5, parameter_vertices(ur5.trajectory)[0]), (r3, parameter_vertices(r3.trajectory)[0]),
            (panda, np.tile(UNIT, (panda.chain.bodies, 1))[None])]


CASES = _cases()
IDS = ["panda-theta", "panda-rate", "ur5-theta", "3r-theta", "panda-unit"]


def _sampled(chain, thetas, count=20000, seed=3):
    """|M_il| at dense random configurations of the search box (K, V, n, n), and the configurations."""
    lo, hi = search_box(chain)
    q = lo + (hi - lo) * np.random.default_rng(seed).random((count, chain.n))
    return np.abs(composite.mass_matrix(chain, q[:, None], np.asarray(thetas)[None])), q


@pytest.mark.parametrize("scene, thetas", CASES, ids=IDS)
def test_entry_sups_lie_above_dense_samples(scene, thetas):
    family = FourierFamily(scene.chain, thetas)
    samples = _sampled(scene.chain, thetas)[0].max(0)
    m = len(family.idx)
    for subset in [(), (0,), (m - 1,), (0, m - 1)]:
        s = partial_wiener_sups(family, subset, 24)
        assert np.all(s >= samples), (subset, (samples - s).max())
    s = certified_entry_sups(family, 3, 48, 32)
    assert np.all(s >= samples)
    assert np.all(s <= family.wiener)


@pytest.mark.parametrize("scene, thetas", CASES[:3], ids=IDS[:3])
def test_perron_bound_lies_above_sampled_spectra(scene, thetas):
    bound = fourier_perron_bound(scene.chain, thetas, 20)
    m = composite.mass_matrix(scene.chain, _sampled(scene.chain, thetas, 5000)[1][:, None], thetas[None])
    assert bound >= spectral(m, "absmax").max()


def test_grids_see_the_joint_limits_and_phases():
    """On Panda with 2 kg the gridded sups are well below the Wiener norms over a whole period (the lead of issue 12:
    rho(S) 19.07 -> about 12 with pairs; the sampled sup of lambda_max is 6.61)."""
    scene, thetas = CASES[0]
    family = FourierFamily(scene.chain, thetas)
    assert perron_of(certified_entry_sups(family)).max() < 0.7 * perron_of(family.wiener).max()


def _broken_is_caught(monkeypatch, scene, thetas, how):
    family = FourierFamily(scene.chain, thetas)
    if how == "no-remainder":
        monkeypatch.setattr(family, "slopes", np.zeros_like(family.slopes))
        s = partial_wiener_sups(family, (0, 1), 2)
    else:
        s = 0.7 * certified_entry_sups(family, 3, 48, 32)
    samples = _sampled(scene.chain, thetas)[0].max(0)
    return np.any(s < samples)


@pytest.mark.parametrize("how", ["no-remainder", "shrunk"])
@pytest.mark.parametrize("scene, thetas", [CASES[0], CASES[3]], ids=[IDS[0], IDS[3]])
def test_a_broken_entry_sup_is_caught_by_the_samples(monkeypatch, scene, thetas, how):
    """The sampled check above can fail: a coarse grid without its remainder, or the bound shrunk 30%, lies below
    a sampled |M_il|."""
    assert _broken_is_caught(monkeypatch, scene, thetas, how)


def test_brackets_adopt_the_fourier_perron_bound():
    """Panda with 2 kg, ci budget: the sup sides close to within 2 (issue 12) through the Perron bound."""
    scene = robots.panda(payload=2.0)
    thetas, rates = parameter_vertices(scene.trajectory)[:2]
    kw = dict(samples=2000, rounds=20)
    for b in (mass_sup(scene.chain, thetas, rng=np.random.default_rng(0), **kw),
              mass_sup(scene.chain, rates, kind="absmax", rng=np.random.default_rng(0), **kw),
              jacobian_sup(scene.chain, rng=np.random.default_rng(0), **kw)):
        assert "inertiaproof.bounds.fourier" in b.note
        assert b.upper <= 2.0 * b.lower


def test_cells_widen_the_remainder_not_the_answer():
    """Finer grids give smaller (never larger than the Wiener norm) and still valid sups."""
    scene, thetas = CASES[3]
    family = FourierFamily(scene.chain, thetas)
    coarse, fine = partial_wiener_sups(family, (0,), 8), partial_wiener_sups(family, (0,), 64)
    assert np.all(fine <= coarse + 1e-12) and np.all(coarse <= family.wiener)
    assert fourier.SINGLE_CELLS >= 8
