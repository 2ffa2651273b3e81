"""physical_consistency (the foundation's classifier) against eigvalsh and an independent exact decision."""

import numpy as np
import pytest
from exact_oracle import verdict_of_phi

from inertiaproof.model.consistency import (
    CONSISTENT,
    DEGENERATE,
    INCONSISTENT,
    INVALID,
    LABELS,
    decide_exactly,
    physical_consistency,
)
from inertiaproof.model.degenerate import point_masses
from inertiaproof.model.inertia import PHI_FIELDS, pseudo_inertia, pseudo_inertia_inverse, sigma_com
from inertiaproof.model.solids import solid

RNG_SEED = 20240601


def random_pd_f(rng, n, lowest=-6):
    q, _ = np.linalg.qr(rng.normal(size=(n, 4, 4)))
    lam = 10.0 ** rng.uniform(lowest, 0, size=(n, 4))
    return 10.0 ** rng.uniform(-3, 3, size=(n, 1, 1)) * (q * lam[:, None, :]) @ np.swapaxes(q, 1, 2)


def boundary_rows(rng, n):
    """Integer point masses on a point, line or plane (exactly singular f), times powers of two."""
    dims = rng.integers(0, 3, size=n)
    origin = rng.integers(-6, 7, size=(n, 1, 3))
    spans = rng.integers(-6, 7, size=(n, 2, 3)) * (np.arange(2)[None, :, None] < dims[:, None, None])
    coords = rng.integers(-4, 5, size=(n, 4, 2))
    points = origin + np.einsum("npk,nkj->npj", coords, spans)
    masses = rng.integers(0, 5, size=(n, 4)).astype(float)
    masses[:, 0] += 1
    x = np.concatenate([points, np.ones((n, 4, 1))], -1).astype(float)
    f = np.einsum("np,npi,npj->nij", masses, x, x)
    return pseudo_inertia_inverse(f) * 2.0 ** rng.integers(-30, 30, size=(n, 1)), dims


def test_agrees_with_eigvalsh_away_from_the_boundary():
    rng = np.random.default_rng(RNG_SEED)
    phi = np.concatenate([pseudo_inertia_inverse(random_pd_f(rng, 3000)),
                          rng.normal(size=(3000, 10)) * 10.0 ** rng.uniform(-3, 3, size=(3000, 1))])
    f = pseudo_inertia(phi)
    lam = np.linalg.eigvalsh(f)[:, 0] / np.linalg.norm(f, axis=(1, 2))
    keep = np.abs(lam) > 1e-8
    c = physical_consistency(phi[keep])
    assert np.array_equal(c.verdict == CONSISTENT, lam[keep] > 0)
    np.testing.assert_allclose(c.lambda_min_rel, lam[keep], rtol=1e-6, atol=1e-13)
    positive = phi[keep][:, 0] > 0
    s = np.linalg.eigvalsh(sigma_com(phi[keep][positive]))
    ratio = s[:, 0] / s.sum(axis=1)
    resolved = np.abs(ratio) > 1e-8
    np.testing.assert_allclose(c.triangle_slack[positive][resolved], ratio[resolved], rtol=1e-6, atol=1e-12)


def test_exact_band_on_and_next_to_the_boundary():
    """Singular rows and their 1-4 ulp moves: every verdict equals the independent exact decision."""
    rng = np.random.default_rng(RNG_SEED + 1)
    singular, _ = boundary_rows(rng, 600)
    moved = singular.copy()
    for row, field, steps in zip(moved, rng.integers(0, 10, size=600), rng.integers(1, 5, size=600)):
        for _ in range(steps):
            row[field] = np.nextafter(row[field], np.inf if rng.random() < 0.5 else -np.inf)
    phi = np.concatenate([singular, moved])
    c = physical_consistency(phi)
    expected = [verdict_of_phi(p) for p in phi]
    assert list(c.labels) == expected
    assert c.decided_exactly[:600].all(), "exactly singular rows must be decided in rational arithmetic"
    assert set(expected[600:]) >= {"consistent", "inconsistent"}


def test_float_path_never_disagrees_with_exact_outside_the_band():
    """Thin bodies far from the origin (Sigma - h h^T/m cancels) and their mirror images just across the boundary,
    at relative distances 1e-16..1e-8 that straddle the resolution band."""
    rng = np.random.default_rng(RNG_SEED + 2)
    n = 1500
    q, _ = np.linalg.qr(rng.normal(size=(n, 3, 3)))
    size = 10.0 ** rng.uniform(-3, 1, size=(n, 1))
    delta = 10.0 ** rng.uniform(-16, -6, size=n) * np.where(rng.random(n) < 0.5, -1, 1)
    m = 10.0 ** rng.uniform(-2, 2, size=n)
    eigenvalues = m[:, None] * size**2 * np.stack([np.ones(n), 10.0 ** rng.uniform(-8, 0, size=n), delta], -1)
    sigma_c = np.einsum("nij,nj,nkj->nik", q, eigenvalues, q)
    com = size * 10.0 ** rng.uniform(0, 3, size=(n, 1)) * rng.normal(size=(n, 3))
    f = np.zeros((n, 4, 4))
    f[:, :3, :3] = sigma_c + m[:, None, None] * com[:, :, None] * com[:, None, :]
    f[:, :3, 3] = f[:, 3, :3] = m[:, None] * com
    f[:, 3, 3] = m
    phi = pseudo_inertia_inverse(f)
    c = physical_consistency(phi, margins=False)
    expected = np.array([verdict_of_phi(p) for p in phi])
    float_path = ~c.decided_exactly
    assert float_path.sum() > 100 and (~float_path).sum() > 100
    wrong = np.flatnonzero(c.labels != expected)
    assert wrong.size == 0, f"{wrong.size} disagreements, e.g. row {phi[wrong[0]].tolist()}"


@pytest.mark.parametrize("dimension,kind", [(0, "point mass"), (1, "line mass"), (2, "planar mass")])
def test_degenerate_rank_and_kind(dimension, kind):
    a, u, v = np.array([1.0, -2.0, 3.0]), np.array([2.0, 1.0, -1.0]), np.array([-1.0, 1.0, 3.0])
    points = {0: [a, a], 1: [a, a + u, a - 2 * u], 2: [a, a + u, a + v, a + u + v]}[dimension]
    m, h, sig = point_masses(np.arange(1.0, len(points) + 1), points)
    phi = pseudo_inertia_inverse(np.block([[sig, h[:, None]], [h[None, :], np.array([[m]])]]))
    c = physical_consistency(phi[None])
    assert c.verdict[0] == DEGENERATE and c.degenerate_rank[0] == dimension
    assert kind in c.reason(0)
    assert c.lambda_min_rel[0] == pytest.approx(0.0, abs=1e-14)


@pytest.mark.parametrize("field", range(10))
@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_invalid_rows_name_their_field(field, bad):
    phi = np.tile(solid("box", 1.0, [0.1, 0.2, 0.3]), (3, 1))
    phi[1, field] = bad
    c = physical_consistency(phi)
    assert list(c.verdict) == [CONSISTENT, INVALID, CONSISTENT]
    assert c.invalid_field[1] == field and PHI_FIELDS[field] in c.reason(1)
    assert [r["verdict"] for r in c.rows()] == ["consistent", "invalid", "consistent"]


@pytest.mark.parametrize("mass", [0.0, -1.0, -1e-300])
def test_nonpositive_mass_is_inconsistent(mass):
    phi = solid("sphere", 1.0, [0.2])
    phi[0] = mass
    c = physical_consistency(phi[None])
    assert c.verdict[0] == INCONSISTENT and "mass <= 0" in c.reason(0)
    assert decide_exactly(phi)[0] == INCONSISTENT


def test_zero_row_is_inconsistent():
    assert physical_consistency(np.zeros((1, 10))).verdict[0] == INCONSISTENT


def test_batch_shapes_and_bad_width():
    phi = np.tile(solid("cone", 2.0, [0.1, 0.4]), (2, 3, 1))
    c = physical_consistency(phi)
    assert c.verdict.shape == (2, 3) and c.sigma_com_eigenvalues.shape == (2, 3, 3)
    with pytest.raises(ValueError, match="10 entries"):
        physical_consistency(np.zeros((4, 9)))


def test_verdicts_do_not_depend_on_margins():
    rng = np.random.default_rng(RNG_SEED + 3)
    phi = np.concatenate([rng.normal(size=(500, 10)), boundary_rows(rng, 200)[0]])
    assert np.array_equal(physical_consistency(phi).verdict, physical_consistency(phi, margins=False).verdict)


def test_repeated_eigenvalues():
    """Spheres (three equal eigenvalues of Sigma_CoM) and cylinders (two) anywhere: the closed form's weak spot."""
    rng = np.random.default_rng(RNG_SEED + 4)
    spheres = np.array([solid("sphere", 1.0 + k, [0.1 * (k + 1)], position=rng.normal(size=3)) for k in range(20)])
    cylinders = np.array([solid("cylinder", 2.0, [0.1, 0.3 + 0.1 * k], position=rng.normal(size=3)) for k in range(20)])
    c = physical_consistency(np.concatenate([spheres, cylinders]))
    assert (c.verdict == CONSISTENT).all()
    np.testing.assert_allclose(c.triangle_slack[:20], 1 / 3, rtol=1e-9)
    s = np.linalg.eigvalsh(sigma_com(cylinders))
    np.testing.assert_allclose(c.triangle_slack[20:], s[:, 0] / s.sum(axis=1), rtol=1e-9)


@pytest.mark.parametrize("exponent", [-1000, -600, -300, 0, 300, 600, 1000])
def test_extreme_scales(exponent):
    """f(2^k Phi) = 2^k f(Phi): verdicts and relative margins do not change, even where squares would over/underflow."""
    rows = np.array([solid("box", 2.0, [1, 0.5, 0.2], position=(0.3, 0.1, 0.2)),
                     solid("ellipsoid", 0.5, [0.3, 0.2, 0.1], position=(-1, 2, 0.5))])
    bad = rows[0].copy()
    bad[6] *= 3  # I33 too large: a triangle inequality fails
    rows = np.vstack([rows, bad])
    ref = physical_consistency(rows)
    c = physical_consistency(rows * 2.0**exponent)
    assert list(c.labels) == ["consistent", "consistent", "inconsistent"]
    np.testing.assert_allclose(c.triangle_slack, ref.triangle_slack, rtol=1e-12)
    np.testing.assert_allclose(c.lambda_min_rel, ref.lambda_min_rel, rtol=1e-9)


def test_decide_exactly_matches_the_oracle():
    rng = np.random.default_rng(RNG_SEED + 5)
    phi = np.concatenate([boundary_rows(rng, 100)[0], rng.integers(-3, 4, size=(100, 10)).astype(float)])
    for row in phi:
        assert LABELS[decide_exactly(row)[0]] == verdict_of_phi(row)


@pytest.mark.slow
def test_lambda_min_is_accurate_on_graded_clustered_and_singular_f():
    """lambda_min(f) (Laguerre with an a-posteriori bound, else LAPACK) within max(1e-6 |lambda|, 64 eps ||f||) of
    eigvalsh: robot-like graded f in SI units, two nearly equal smallest eigenvalues, and exactly singular f."""
    rng = np.random.default_rng(RNG_SEED + 6)
    n = 20000
    q, _ = np.linalg.qr(rng.normal(size=(n, 4, 4)))
    d = 10.0 ** rng.uniform(-14, -1, size=n)
    lam = np.stack([d, d * (1 + 10.0 ** rng.uniform(-16, 0, size=n)), 10.0 ** rng.uniform(-3, 0, size=n),
                    np.ones(n)], -1) * np.where(rng.random((n, 1)) < 0.3, -1, 1)
    clustered = pseudo_inertia_inverse((q * lam[:, None, :]) @ np.swapaxes(q, 1, 2))
    m = 10.0 ** rng.uniform(-2, 1, size=n)
    size = 10.0 ** rng.uniform(-2, -0.3, size=n)
    graded = np.array([solid("box", mi, si * 10.0 ** rng.uniform(-1.2, 0, size=3), position=si * rng.normal(size=3))
                       for mi, si in zip(m[:2000], size[:2000])])
    phi = np.concatenate([clustered, graded, boundary_rows(rng, 4000)[0]])
    f = pseudo_inertia(phi)
    norm = np.linalg.norm(f, axis=(1, 2))
    exact = np.linalg.eigvalsh(f)[:, 0]
    ours = physical_consistency(phi).lambda_min_rel * norm
    assert np.all(np.abs(ours - exact) <= np.maximum(1e-6 * np.abs(exact), 64 * np.finfo(float).eps * norm))


def test_every_finite_magnitude_against_the_oracle():
    """Rows whose mass, first moment and inertia lie up to 600 decades apart: the verdict is the exact one."""
    rng = np.random.default_rng(RNG_SEED + 7)
    rows = []
    for _ in range(150):
        m = 10.0 ** rng.uniform(-300, 300)
        length = 10.0 ** rng.uniform(-150, 150)
        shape = rng.uniform(0.1, 1.0, size=3)
        principal = np.array([shape[1] + shape[2], shape[0] + shape[2], shape[0] + shape[1]]) * rng.choice([1, 1, 1.3])
        with np.errstate(all="ignore"):  # rows that leave the floats are dropped below
            h = m * length * rng.normal(size=3) * rng.choice([0.0, 1e-3, 1.0])
            inertia = m * length**2 * principal + (h * h).sum() / m * rng.choice([0.0, 1.0])
        rows.append([m, *h, *inertia, 0.0, 0.0, 0.0])
    phi = np.array(rows)
    phi = phi[np.isfinite(phi).all(axis=1)]
    c = physical_consistency(phi)
    expected = [verdict_of_phi(row) for row in phi]
    assert len(phi) > 100 and list(c.labels) == expected


@pytest.mark.parametrize("phi,label", [
    ([1e-308, 0, 0, 0, 1e308, 1e308, 1e308, 0, 0, 0], "consistent"),
    ([1.1e183, 0, 0, 0, 1e-200, 1e-200, 3e-200, 0, 0, 0], "inconsistent"),
    ([1e-300, 1e-160, 0, 0, 1e-300, 1e-300, 1e-300, 0, 0, 0], "inconsistent"),
    ([5e-324, 0, 0, 0, 1.7e308, 1.7e308, 1.7e308, 0, 0, 0], "consistent"),
])
def test_extreme_rows_of_the_issue(phi, label):
    c = physical_consistency(np.array([phi]))
    assert c.labels[0] == label == verdict_of_phi(phi)
    if label == "consistent":
        assert c.lambda_min_rel[0] > 0 and c.triangle_slack[0] > 0
    else:
        assert " by -" not in c.reason(0) and c.lambda_min_rel[0] < 0


PLATE_TEXT = ["1", "0", "0", "0", "0.1", "0.2", "0.3", "0", "0", "0"]


@pytest.mark.parametrize("inertia,float_label", [(("0.1", "0.2", "0.3"), "consistent"),
                                                 (("0.1", "0.7", "0.8"), "inconsistent")])
def test_decimals_are_decided_as_written_and_float64_is_named(inertia, float_label):
    text = ["1", "0", "0", "0", *inertia, "0", "0", "0"]
    phi = np.array([float(x) for x in text])
    assert physical_consistency(phi[None]).labels[0] == float_label == verdict_of_phi(phi)
    c = physical_consistency(phi[None], written=[text])
    assert c.labels[0] == "degenerate" and c.degenerate_rank[0] == 2 and c.float_verdict[0] == LABELS.index(float_label)
    reason = c.reason(0)
    assert reason.startswith("as written: degenerate") and "planar mass" in reason
    assert f"as float64: {float_label}" in reason and "engines that read doubles" in reason
    assert " by -" not in reason
    assert next(c.rows())["float64_verdict"] == float_label


def test_a_rotated_rod_as_written_is_a_line_mass():
    """A rod along (3, 4, 0)/5: I_CoM = I3 - u u^T, exactly representable as decimals, not as floats."""
    text = ["2", "0", "0", "0", "1.28", "0.72", "2", "-0.96", "0", "0"]
    c = physical_consistency(np.array([[float(x) for x in text]]), written=[text])
    assert c.labels[0] == "degenerate" and c.degenerate_rank[0] == 1 and "line mass" in c.reason(0)


def test_written_numbers_never_change_a_certain_float_verdict():
    rng = np.random.default_rng(RNG_SEED + 8)
    phi = np.round(rng.normal(size=(300, 10)), 3)
    text = [[repr(float(x)) for x in row] for row in phi]
    a, b = physical_consistency(phi), physical_consistency(phi, written=text)
    assert np.array_equal(a.verdict, b.verdict) and np.array_equal(a.verdict, b.float_verdict)
