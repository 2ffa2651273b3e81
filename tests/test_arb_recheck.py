"""The certified side of the configuration brackets re-checked in ball arithmetic (python-flint's arb; issue 12).

Families: lambda_min and lambda_max of M(q, Theta) (Theorems 2, 3) on the planar 2R, spatial 3R and Panda arms,
sigma_max(M(q, Thetadot)) (Theorem 4) on the 2R, sigma_max(QJ) (Lemma 2) on the 3R.

The branch and bound of inertiaproof.bounds.configuration bounds a spectral function of M(q, Theta) (or QJ(q))
over each box of configurations (``box_bound(centres, radii)``, handed to bracket_extreme). Here that very
function is captured during a real bracket computation and evaluated on sampled small boxes; arb evaluates
M(q) (tests/arb_oracle.py, written from the chain's definition, not from the package's kinematics) at points of
each box with rigorous enclosures of its eigenvalues (acb_mat.eig of the midpoint plus Weyl's inequality for
the radii). A certified lower bound of lambda_min over a box must lie below arb's upper end of lambda_min(M(q))
at every point q of the box (an upper bound above arb's lower end of lambda_max, sigma_max), else it is
provably wrong. The same holds for the bracket's final certified side over the whole domain. A box bound made
too optimistic (the vertex bound moved inwards) is caught, so the re-check can fail.
"""

import numpy as np
import pytest

flint = pytest.importorskip("flint")

from arb_oracle import arb_body_jacobian, arb_mass_matrix, ball, eigen_enclosures, mat  # noqa: E402

from inertiaproof.bounds import branch, configuration  # noqa: E402
from inertiaproof.bounds.domain import free_coordinates, search_box  # noqa: E402
from inertiaproof.model.inertia import spatial_inertia  # noqa: E402
from inertiaproof.scene import robots  # noqa: E402

BOXES = 6  # sampled boxes per family
POINTS = 3  # random points per box besides its centre
RADIUS = 0.002  # half-width of a sampled box, as a fraction of the domain's width: small, so the box bound is tight


def _capture(monkeypatch, compute):
    """Run ``compute()`` with bracket_extreme spied on: the result and every (quantity, box_bound, sense) it got."""
    calls = []
    real = branch.bracket_extreme

    def spy(value, box_bound, lo, hi, **kwargs):
        calls.append((kwargs.get("quantity_name"), box_bound, kwargs.get("sense")))
        return real(value, box_bound, lo, hi, **kwargs)

    monkeypatch.setattr(branch, "bracket_extreme", spy)
    result = compute()
    monkeypatch.setattr(branch, "bracket_extreme", real)
    final = [c for c in calls if c[0] == result.quantity and c[1] is not None]
    assert final, f"no certified box bound was used for {result.quantity}"
    return result, final[-1][1]


def _arb_spectra(chain, q, thetas, what):
    """Rigorous (low, high) of the quantity at the point q: lambda_min / lambda_max of M over the stack (worst),
    or sigma_max of QJ."""
    if what == "smax":
        qj = mat(arb_body_jacobian(chain, q))
        (_, _), (low, high) = eigen_enclosures(qj.transpose() * qj)
        return np.sqrt(max(low, 0.0)) * (1 - 1e-15), np.sqrt(high) * (1 + 1e-15)
    found = [eigen_enclosures(arb_mass_matrix(chain, q, spatial_inertia(theta))) for theta in thetas]
    if what == "lmin":
        return min(f[0][0] for f in found), min(f[0][1] for f in found)
    if what == "absmax":  # sigma_max of a symmetric matrix: max(|lambda_min|, lambda_max)
        return (max(max(f[1][0], -f[0][1]) for f in found),
                max(max(abs(f[1][0]), abs(f[1][1]), abs(f[0][0]), abs(f[0][1])) for f in found))
    return max(f[1][0] for f in found), max(f[1][1] for f in found)


def _boxes(chain, rng):
    lo, hi = search_box(chain)
    width = hi - lo
    centres = lo + width * (RADIUS + (1 - 2 * RADIUS) * rng.random((BOXES, chain.n)))
    return centres, np.broadcast_to(RADIUS * width, centres.shape).copy()


def recheck(chain, box_bound, what, thetas, rng):
    """[(box bound, arb's rigorous end at the box's points)] for sampled boxes; the bound is wrong where it lies
    beyond that end (above it for lmin, below for lmax and smax)."""
    centres, radii = _boxes(chain, rng)
    bounds = box_bound(centres, radii)
    free = free_coordinates(chain)
    out = []
    for c, r, b in zip(centres, radii, bounds):
        points = [c] + [c + np.where(free, r, 0.0) * rng.uniform(-1, 1, chain.n) for _ in range(POINTS)]
        ends = [_arb_spectra(chain, [ball(x) for x in p], thetas, what) for p in points]
        out.append((float(b), min(e[1] for e in ends) if what == "lmin" else max(e[0] for e in ends)))
    return out


def wrong(pairs, what):
    return [(b, e) for b, e in pairs if (b > e if what == "lmin" else b < e)]


CASES = [  # (scene, what): lambda_min and lambda_max of M, sigma_max of QJ
    (robots.planar_2r(payload=1.0), "lmin"), (robots.planar_2r(payload=1.0), "lmax"),
    (robots.spatial_3r(), "lmin"), (robots.spatial_3r(), "lmax"), (robots.spatial_3r(), "smax"),
    (robots.panda(payload=2.0), "lmin"), (robots.panda(payload=2.0), "lmax"),
    (robots.planar_2r(payload=1.0), "absmax"),  # Theorem 4's sigma_max(M(q, Thetadot))
]


def _compute(scene, what, rng):
    chain = scene.chain
    thetas = scene.trajectory.base[None]
    kw = dict(samples=200, rounds=2, rng=rng)
    if what == "lmin":
        return lambda: configuration.mass_inf(chain, thetas, **kw), thetas
    if what == "lmax":
        return lambda: configuration.mass_sup(chain, thetas, **kw), thetas
    if what == "absmax":  # the rates of the payload ramp's segment ends (bounds.time.parameter_vertices)
        from inertiaproof.bounds.time import parameter_vertices

        rates = parameter_vertices(scene.trajectory)[1]
        return lambda: configuration.mass_sup(chain, rates, kind="absmax", name="sup sigma_max(M(q, Thetadot))",
                                              **kw), rates
    return lambda: configuration.jacobian_sup(chain, **kw), thetas


@pytest.mark.parametrize("scene, what", CASES, ids=[f"{s.name}-{w}" for s, w in CASES])
def test_certified_box_bounds_agree_with_arb(scene, what, monkeypatch):
    rng = np.random.default_rng(12)
    compute, thetas = _compute(scene, what, rng)
    result, box_bound = _capture(monkeypatch, compute)
    pairs = recheck(scene.chain, box_bound, what, thetas, rng)
    assert not wrong(pairs, what), wrong(pairs, what)
    assert not final_side_wrong(scene, result, thetas, what, rng)


def final_side_wrong(scene, result, thetas, what, rng, count=8):
    """Points where arb proves the bracket's certified side over the whole domain wrong: its witness and ``count``
    random configurations."""
    lo, hi = search_box(scene.chain)
    points = [np.asarray(result.witness, float)] + list(lo + (hi - lo) * rng.random((count, scene.chain.n)))
    bad = []
    for q in points:
        low, high = _arb_spectra(scene.chain, [ball(x) for x in q], thetas, what)
        if (result.certified > high) if what == "lmin" else (result.certified < low):
            bad.append((q.tolist(), result.certified, (low, high)))
    return bad


@pytest.mark.parametrize("scene, what", [CASES[0], CASES[1]], ids=["2r-lmin", "2r-lmax"])
def test_arb_recheck_catches_an_optimistic_certified_side(scene, what, monkeypatch):
    """The bracket's certified side claimed 1% beyond the value its witness attains: arb sees it."""
    rng = np.random.default_rng(12)
    compute, thetas = _compute(scene, what, rng)
    result = compute()
    result.certified = result.observed * (1.01 if what == "lmin" else 0.99)
    assert final_side_wrong(scene, result, thetas, what, rng)


@pytest.mark.parametrize("scene, what", [CASES[0], CASES[3], CASES[4]], ids=["2r-lmin", "3r-lmax", "3r-smax"])
def test_arb_recheck_catches_an_optimistic_box_bound(scene, what, monkeypatch):
    """The vertex bound moved inwards by 30% of its size: box bounds claim more than M attains, and arb sees it."""
    real = branch.vertex_bound

    def optimistic(a, da, radii, free, kind):
        v = real(a, da, radii, free, kind)
        return v - 0.3 * np.abs(v) if kind in configuration.CONVEX else v + 0.3 * np.abs(v)

    monkeypatch.setattr(branch, "vertex_bound", optimistic)
    rng = np.random.default_rng(12)
    compute, thetas = _compute(scene, what, rng)
    _, box_bound = _capture(monkeypatch, compute)
    pairs = recheck(scene.chain, box_bound, what, thetas, rng)
    assert wrong(pairs, what), pairs


def _entry_points(chain, thetas, rng, count=2000, keep=24):
    """The configurations where sampled |M_il| peak (one per entry and parameter set, at most ``keep``) and a few
    random ones: where a too small entry sup would show."""
    lo, hi = search_box(chain)
    q = lo + (hi - lo) * rng.random((count, chain.n))
    from inertiaproof.dynamics import composite

    m = np.abs(composite.mass_matrix(chain, q[:, None], np.asarray(thetas)[None]))  # (K, V, n, n)
    peaks = np.unique(m.reshape(count, -1).argmax(0))
    order = np.argsort(-m.reshape(count, -1).max(1)[peaks])
    return list(q[peaks[order][:keep]]) + list(q[:4])


def fourier_entries_wrong(chain, thetas, s, points):
    """Entries (v, i, l, q) where arb proves |M_il(q, Theta_v)| > S_il: the entry sup is wrong there."""
    bad = []
    for q in points:
        for v, theta in enumerate(np.asarray(thetas)):
            m = arb_mass_matrix(chain, [ball(x) for x in q], spatial_inertia(theta))
            for i in range(chain.n):
                for l in range(chain.n):
                    low = max(float(m[i, l].lower()), -float(m[i, l].upper()))  # |x| >= this for all x in the ball
                    if low > s[v, i, l]:
                        bad.append((v, i, l, q.tolist(), low, s[v, i, l]))
    return bad


FOURIER_CASES = [robots.spatial_3r(), robots.panda(payload=2.0)]


@pytest.mark.parametrize("scene", FOURIER_CASES, ids=[s.name for s in FOURIER_CASES])
def test_fourier_entry_sups_agree_with_arb(scene):
    """The certified sups of |M_il(q)| over the search box (inertiaproof.bounds.fourier, singles and pairs of
    coordinates on grids) lie above arb's lower end of |M_il(q)| where sampled entries peak."""
    from inertiaproof.bounds.fourier import FourierFamily, certified_entry_sups

    thetas = scene.trajectory.base[None]
    s = certified_entry_sups(FourierFamily(scene.chain, thetas), 3, 48, 32)
    points = _entry_points(scene.chain, thetas, np.random.default_rng(12))
    assert not fourier_entries_wrong(scene.chain, thetas, s, points)


def test_arb_recheck_catches_shrunk_fourier_entry_sups():
    """The same entry sups shrunk 30%: arb proves some of them wrong."""
    from inertiaproof.bounds.fourier import FourierFamily, certified_entry_sups

    scene = robots.spatial_3r()
    thetas = scene.trajectory.base[None]
    s = 0.7 * certified_entry_sups(FourierFamily(scene.chain, thetas), 3, 48, 32)
    assert fourier_entries_wrong(scene.chain, thetas, s, _entry_points(scene.chain, thetas, np.random.default_rng(12)))


# -- the articulated-body pivot test and the ladder of targets (bounds.pivots, bounds.pivot_search) -----------

def _pivot_forms(scene):
    """The forms whose inf lambda_min the ladders prove: unit bodies (Definition 2), the weighted unit form of
    Theorem 2's floor (mu_l = lambda_min(Z_l), smallest over the stack) and the real inertias."""
    from inertiaproof.bounds.spectral import spectral
    from inertiaproof.bounds.time import parameter_vertices

    thetas = parameter_vertices(scene.trajectory)[0]
    unit = np.array([1.0, 0, 0, 0, 1, 1, 1, 0, 0, 0])
    mu = spectral(spatial_inertia(thetas), "lmin").min(0, keepdims=True)
    return {"unit": np.tile(unit, (scene.chain.bodies, 1))[None], "weighted": mu[..., None] * unit, "real": thetas}


PIVOT_CASES = [(robots.panda(payload=2.0), "unit", 0.02, "lmin", "shift"),
               (robots.panda(payload=2.0), "weighted", 0.02, "lmin", "shift"),
               (robots.panda(payload=2.0), "real", 0.002, "lmin", "shift"),
               (robots.ur5(), "unit", 0.05, "lmin", "shift"),
               (robots.panda(payload=2.0), "real", 0.002, "lmin", "abs"),
               (robots.ur5(), "unit", 0.05, "lmin", "abs"),
               (robots.panda(payload=2.0), "real", 0.01, "lmax", "shift"),
               (robots.panda(payload=2.0), "unit", 0.02, "lmax", "shift")]


@pytest.mark.parametrize("scene, form, radius, what, metric", PIVOT_CASES,
                         ids=[f"{s.name}-{f}-{w}-{m}" for s, f, _, w, m in PIVOT_CASES])
def test_pivot_box_bounds_agree_with_arb(scene, form, radius, what, metric):
    """The pivot bound of lambda_min (lambda_max: the upper ladders' test of gamma I - M) on sampled boxes (the
    bisection over pivot_test that the ladders' boxes pass; the turns' loss in either metric of pivots.METRICS) lies
    below arb's upper end of lambda_min(M(q)) (above arb's lower end of lambda_max) at the box's centre and random
    points."""
    from inertiaproof.bounds.pivots import PivotFamily, pivot_bounds
    from inertiaproof.bounds.spectral import spectral
    from inertiaproof.dynamics import composite

    chain = scene.chain
    thetas = _pivot_forms(scene)[form]
    rng = np.random.default_rng(13)
    lo, hi = search_box(chain)
    free = free_coordinates(chain)
    radii = np.where(free, radius * (hi - lo), 0.0)
    centres = lo + radii + (hi - lo - 2 * radii) * rng.random((BOXES, chain.n))
    radii = np.broadcast_to(radii, centres.shape).copy()
    start = spectral(composite.mass_matrix(chain, centres[:, None], thetas[None]), what)
    family = PivotFamily(chain, thetas)
    family.metric = metric
    bounds = pivot_bounds(family, what, centres, radii, start, steps=30)[0]
    assert np.all(np.isfinite(bounds))
    pairs = []
    for c, r, b in zip(centres, radii, bounds):
        points = [c] + [c + r * rng.uniform(-1, 1, chain.n) for _ in range(POINTS)]
        ends = [_arb_spectra(chain, [ball(x) for x in p], thetas, what) for p in points]
        pairs.append((float(b), min(e[1] for e in ends) if what == "lmin" else max(e[0] for e in ends)))
    assert not wrong(pairs, what), wrong(pairs, what)


@pytest.mark.parametrize("scene, form", [(robots.panda(payload=2.0), "unit"), (robots.panda(payload=2.0), "weighted"),
                                         (robots.ur5(), "unit")], ids=["panda-unit", "panda-weighted", "ur5-unit"])
def test_ladder_certified_side_agrees_with_arb(scene, form):
    """The ladder's certified inf (pivot_normality at the ci budget) lies below arb's upper end of lambda_min at
    the form's sampled minimiser and at random configurations."""
    from inertiaproof.bounds.configuration import pivot_normality
    from inertiaproof.bounds.spectral import spectral
    from inertiaproof.dynamics import composite

    chain = scene.chain
    thetas = _pivot_forms(scene)[form]
    gamma = pivot_normality(chain, 20, 500, None if form == "unit" else thetas[..., 0])
    assert gamma > 0
    lo, hi = search_box(chain)
    rng = np.random.default_rng(14)
    q = lo + (hi - lo) * rng.random((4000, chain.n))
    values = spectral(composite.mass_matrix(chain, q[:, None], thetas[None]), "lmin").min(1)
    points = [q[np.argmin(values)]] + list(q[:6])
    for p in points:
        low, high = _arb_spectra(chain, [ball(x) for x in p], thetas, "lmin")
        assert gamma <= high, (p.tolist(), gamma, (low, high))
    # a side claimed 1% beyond the sampled minimum is refuted by arb at that point
    low, high = _arb_spectra(chain, [ball(x) for x in points[0]], thetas, "lmin")
    assert 1.01 * values.min() > high


def test_upper_ladder_certified_side_agrees_with_arb():
    """The upper ladder's certified sup lambda_max of Panda's (2 kg) mass matrix (ladders.pivot_sup at the
    ci budget, goal 1.3) lies above arb's lower end of lambda_max at the sampled maximiser and at random
    configurations; a side claimed 1% below the sampled max is refuted by arb there."""
    from inertiaproof.bounds.ladders import pivot_sup
    from inertiaproof.bounds.spectral import spectral
    from inertiaproof.dynamics import composite

    scene = robots.panda(payload=2.0)
    chain, thetas = scene.chain, _pivot_forms(scene)["real"]
    lo, hi = search_box(chain)
    q = lo + (hi - lo) * np.random.default_rng(15).random((4000, chain.n))
    values = spectral(composite.mass_matrix(chain, q[:, None], thetas[None]), "lmax").max(1)
    k = int(np.argmax(values))
    gamma, note, _ = pivot_sup(chain, thetas, 20, float(values[k]), q[k], 1.3)
    assert np.isfinite(gamma), note
    for p in [q[k]] + list(q[:6]):
        low, high = _arb_spectra(chain, [ball(x) for x in p], thetas, "lmax")
        assert gamma >= low, (p.tolist(), gamma, (low, high))
    low, high = _arb_spectra(chain, [ball(x) for x in q[k]], thetas, "lmax")
    assert 0.99 * values[k] < low


# -- the axial lower forms (bounds.axial_form) and their ladder's certified side ----------------------------------

def test_axial_form_and_its_ladder_agree_with_arb():
    """UR5: every adopted axial Y_l lies below Z_l in arb (Z_l - Y_l positive definite: its leading minors' arb
    enclosures > 0, Z_l and Y_l exact as doubles) and Y_l raised 20% does not (x^T (Z_l - 1.2 Y_l) x < 0 in arb for
    a computed eigenvector x); the form ladder's certified side (probe
    budget at ci) lies below arb's upper end of lambda_min(M(q)) at M's sampled minimiser and random points."""
    from inertiaproof.bounds.axial_form import axial_lower_form
    from inertiaproof.bounds.configuration import form_ladder
    from inertiaproof.bounds.spectral import spectral
    from inertiaproof.bounds.time import parameter_vertices
    from inertiaproof.dynamics import composite

    scene = robots.ur5()
    chain, thetas = scene.chain, parameter_vertices(scene.trajectory)[0]
    lo, hi = search_box(chain)
    rng = np.random.default_rng(15)
    q = lo + (hi - lo) * rng.random((4000, chain.n))
    forms, axial = axial_lower_form(chain, thetas, q)
    assert axial.any()
    z = spatial_inertia(thetas)
    for l in np.flatnonzero(axial):
        for v in range(len(z)):
            d = mat([[ball(x) for x in row] for row in z[v, l]]) - mat([[ball(x) for x in row] for row in forms[0, l]])
            minors = [flint.arb_mat([[d[i, j] for j in range(k)] for i in range(k)]).det() for k in range(1, 7)]
            assert all(m > 0 for m in minors), (l, v)  # Sylvester: Z_l - Y_l is positive definite
            raised = 1.2 * forms[0, l]
            x = np.linalg.eigh(z[v, l] - raised)[1][:, 0]  # a direction where Z_l - 1.2 Y_l is negative
            xs = [ball(t) for t in x]
            form = sum((xs[i] * (ball(z[v, l, i, j]) - ball(raised[i, j])) * xs[j] for i in range(6) for j in range(6)),
                       flint.arb(0))
            assert form < 0, (l, v)
    gamma, inf, *_ = form_ladder(chain, forms, 20, 500, np.inf, probe=True)
    assert gamma > 0
    values = spectral(composite.mass_matrix(chain, q[:, None], thetas[None]), "lmin").min(1)
    for p in [q[np.argmin(values)]] + list(q[:6]):
        low, high = _arb_spectra(chain, [ball(x) for x in p], thetas, "lmin")
        assert gamma <= high, (p.tolist(), gamma, (low, high))
