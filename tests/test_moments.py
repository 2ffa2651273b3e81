"""EQ-moments and the density model: closed forms, quadrature, Monte Carlo, independent oracles, bad input."""

import json
import re
from fractions import Fraction

import numpy as np
import pinocchio as pin
import pytest
import sympy as sp
from inertiaproof.checks import moments
from scipy import integrate

from inertiaproof.cli import main
from inertiaproof.errors import InputError
from inertiaproof.model import degenerate, density, quadrature, solids
from inertiaproof.model.inertia import inertia_com, unpack
from inertiaproof.result import Verdict


def test_eq_moments_holds(ctx):
    result = moments.eq_moments(ctx)
    assert result.verdict == Verdict.HOLDS, result.summary
    assert result.evidence["quadrature"]["worst_ratio"]["value"] <= 1.0


def test_perturbed_closed_form_is_violated(ctx):
    def wrong(spec):
        m, h, sigma = density.moments(spec)
        return m, h, sigma * (1 + 1e-9)

    result = moments.eq_moments(ctx, closed_form=wrong)
    assert result.verdict == Verdict.VIOLATED
    assert result.evidence["quadrature"]["verdict"] == "VIOLATED"
    assert result.counterexample["kind"] == "moments"


def test_wrong_centre_of_mass_is_violated_by_monte_carlo():
    def wrong(spec):
        m, h, sigma = density.moments(spec)
        return m, h * 1.1, sigma

    pieces = {k: density.parse(v) for k, v in moments.union_and_mixture().items()}
    result = moments.monte_carlo_part(pieces, np.random.default_rng(0), 2**18, closed_form=wrong)
    assert result.verdict == Verdict.VIOLATED
    assert result.evidence["detectable_error"]["value"] < 0.1


def test_wrong_symbolic_formula_is_violated():
    def wrong(shape, mass, dims, rotation=None, position=(0, 0, 0)):
        m, h, sigma = solids.moments(shape, mass, dims, rotation, position)
        return m, h, sigma * (sp.Rational(81, 80) if shape == "cone" else 1)

    result = moments.symbolic_part(wrong, max_degree=1)
    assert result.verdict == Verdict.VIOLATED and "cone" in result.summary


def test_replay_of_a_moments_counterexample_runs_with_the_current_code(ctx, tmp_path, capsys):
    result = moments.quadrature_part({"bad": density.parse(moments.union_and_mixture()["union"])},
                                     closed_form=lambda s: (lambda m, h, g: (m * 2, h, g))(*density.moments(s)))
    assert result.verdict == Verdict.VIOLATED
    path = ctx.save_counterexample(result)
    assert main(["replay", str(path)]) == 0  # the current closed forms agree with quadrature again
    assert "HOLDS" in capsys.readouterr().out


@pytest.mark.parametrize("shape", solids.SHAPES)
def test_solids_against_scipy_cubature(shape):
    """An oracle outside the suite: scipy's adaptive cubature of the indicator-free parametrisation."""
    dims = {"box": [0.3, 0.5, 0.2], "ellipsoid": [0.3, 0.2, 0.4], "sphere": [0.25], "cylinder": [0.2, 0.6],
            "cone": [0.3, 0.5], "tetrahedron": [0, 0, 0, 0.4, 0.1, 0, 0.1, 0.5, 0, 0.1, 0.1, 0.3]}[shape]
    mass = 2.5
    ref = np.zeros(10)
    rho = mass / solids.volume(shape, dims)
    region = _scipy_region(shape, dims)
    for k, g in enumerate([lambda x: 1.0] + [lambda x, i=i: x[i] for i in range(3)]
                          + [lambda x, i=i, j=j: x[i] * x[j] for i in range(3) for j in range(i, 3)]):
        ref[k] = rho * region(g)
    m, h, sigma = solids.moments(shape, mass, dims)
    ours = np.array([m, *h, *sigma[np.triu_indices(3)]])
    np.testing.assert_allclose(ours, ref, rtol=1e-6, atol=1e-9)


def _scipy_region(shape, d):
    """int g over the canonical solid with scipy.integrate.tplquad, in Cartesian coordinates with curved bounds."""
    opts = dict(epsabs=1e-11, epsrel=1e-8)
    if shape == "box":
        a, b, c = d
        return lambda g: integrate.tplquad(lambda z, y, x: g((x, y, z)), -a / 2, a / 2, -b / 2, b / 2, -c / 2, c / 2, **opts)[0]
    if shape in ("ellipsoid", "sphere"):
        a, b, c = d if shape == "ellipsoid" else d * 3

        def run(g):
            yb = lambda x: b * np.sqrt(max(0.0, 1 - (x / a) ** 2))  # noqa: E731
            zb = lambda x, y: c * np.sqrt(max(0.0, 1 - (x / a) ** 2 - (y / b) ** 2))  # noqa: E731
            return integrate.tplquad(lambda z, y, x: g((x, y, z)), -a, a, lambda x: -yb(x), yb,
                                     lambda x, y: -zb(x, y), zb, **opts)[0]
        return run
    if shape in ("cylinder", "cone"):
        r, h = d

        def run(g):
            lo, hi = (-h / 2, h / 2) if shape == "cylinder" else (0.0, h)
            radius = (lambda z: r) if shape == "cylinder" else (lambda z: r * (1 - z / h))
            yb = lambda z, x: np.sqrt(max(0.0, radius(z) ** 2 - x * x))  # noqa: E731
            return integrate.tplquad(lambda y, x, z: g((x, y, z)), lo, hi, lambda z: -radius(z), radius,
                                     lambda z, x: -yb(z, x), yb, **opts)[0]
        return run
    v = np.asarray(d).reshape(4, 3)
    e = (v[1:] - v[0]).T
    det = abs(np.linalg.det(e))
    return lambda g: det * integrate.tplquad(lambda w, t, u: g(v[0] + e @ [u, t, w]), 0, 1, 0, lambda u: 1 - u,
                                             0, lambda u, t: 1 - u - t, **opts)[0]


def test_solids_against_pinocchio_inertia():
    """Pinocchio's own box/ellipsoid/cylinder inertias (an independent implementation) about the CoM."""
    for shape, ours, theirs in [
        ("box", [0.3, 0.5, 0.2], pin.Inertia.FromBox(2.0, 0.3, 0.5, 0.2)),
        ("ellipsoid", [0.3, 0.5, 0.2], pin.Inertia.FromEllipsoid(2.0, 0.3, 0.5, 0.2)),
        ("cylinder", [0.2, 0.7], pin.Inertia.FromCylinder(2.0, 0.2, 0.7)),
        ("sphere", [0.4], pin.Inertia.FromSphere(2.0, 0.4)),
    ]:
        phi = solids.solid(shape, 2.0, ours)
        np.testing.assert_allclose(inertia_com(phi), theirs.inertia, rtol=1e-12, atol=1e-15)


def test_exact_moments_are_exact():
    """Fractions in, Fractions out; they round to the float moments."""
    spec = density.parse(moments.union_and_mixture()["mixture"])
    m, h, sigma = density.moments(spec, exact=True)
    assert isinstance(m, Fraction) and all(isinstance(x, Fraction) for x in sigma.flat)
    mf, hf, sf = density.moments(spec)
    np.testing.assert_allclose(np.array(sigma, dtype=float), sf, rtol=1e-13)
    assert density.pseudo_inertia_exact(spec)[3, 3] == m


def test_mixture_is_additive_and_scales():
    mix = density.parse(moments.union_and_mixture()["mixture"])
    parts = [density.phi({"components": [c]}) for c in mix["components"]]
    np.testing.assert_allclose(density.phi(mix), np.sum(parts, axis=0), rtol=1e-14)


def test_evaluate_integrates_to_the_mass():
    spec = density.parse(moments.union_and_mixture()["union"])
    (m, _, _), (se, _, _) = quadrature.monte_carlo(spec, 2**17, np.random.default_rng(3))
    assert abs(m - 2.7) < 6 * se


def test_degenerate_distributions_against_sympy():
    s, t = sp.symbols("s t", real=True)
    a, b, c = [sp.Matrix(v) for v in ([1, -2, 3], [2, 0, 1], [0, 1, 1])]
    x = a + s * (b - a)
    m, h, sigma = degenerate.rod(sp.Integer(6), np.array(list(a), dtype=object), np.array(list(b), dtype=object))
    assert sp.Matrix(sigma) == 6 * (x * x.T).applyfunc(lambda e: sp.integrate(e, (s, 0, 1)))
    y = a + s * (b - a) + t * (c - a)
    m, h, sigma = degenerate.triangle_lamina(sp.Integer(12), *[np.array(list(v), dtype=object) for v in (a, b, c)])
    integral = (y * y.T).applyfunc(lambda e: sp.integrate(e, (t, 0, 1 - s), (s, 0, 1)))
    assert sp.Matrix(sigma) == 12 * 2 * integral  # area of the unit triangle in (s, t) is 1/2


@pytest.mark.parametrize("spec,where", [
    ({"components": []}, "at least one component"),
    ({"components": [{"type": "blob"}]}, "component 0: 'type'"),
    ({"components": [{"type": "solid", "shape": "box", "mass": 1, "dims": [1, 2]}]}, "box needs 3 dims"),
    ({"components": [{"type": "solid", "shape": "box", "mass": 1, "dims": [1, -2, 1]}]}, "dims must be > 0"),
    ({"components": [{"type": "solid", "shape": "box", "mass": "x", "dims": [1, 1, 1]}]}, "field 'mass'"),
    ({"components": [{"type": "solid", "shape": "tetrahedron", "mass": 1, "dims": [0] * 12}]}, "coplanar"),
    ({"components": [{"type": "solid", "shape": "box", "mass": 1, "dims": [1, 1, 1], "quaternion": [0, 0, 0, 0]}]},
     "quaternion' is zero"),
    ({"components": [{"type": "bernstein_box", "sides": [1, 1, 1], "coefficients": [1, 2]}]}, "coefficients"),
    ({"components": [{"type": "solid", "shape": "box", "mass": 1, "dims": [1, 1, float("nan")]}]}, "not finite"),
])
def test_bad_densities_name_the_field(spec, where):
    with pytest.raises(InputError, match=re.escape(where)):
        density.parse(spec)


def test_replay_rejects_a_bad_density_in_one_line(tmp_path, capsys):
    path = tmp_path / "bad.json"
    path.write_text(json.dumps({"schema": "inertiaproof.counterexample/1", "kind": "density",
                                "data": {"density": {"components": [{"type": "solid", "shape": "box", "mass": 1,
                                                                     "dims": [1, 1]}]}}}))
    assert main(["replay", str(path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "component 0" in err[0] and "box needs 3 dims" in err[0]


def test_solid_rejects_nonpositive_mass_and_unknown_shapes():
    with pytest.raises(ValueError, match="positive mass"):
        solids.solid("box", 0.0, [1, 1, 1])
    with pytest.raises(ValueError, match="unknown solid"):
        solids.solid("torus", 1.0, [1, 1])


def test_moments_about_the_frame_origin_match_the_parallel_axis_theorem():
    rot = density.rotation(np.array([0.3, -0.2, 0.8, 0.1]))
    phi = solids.solid("cone", 1.3, [0.2, 0.5], rot, [0.4, -0.1, 0.2])
    m, h, _ = unpack(phi)
    sigma_c, c = solids.covariance("cone", 1.3, [0.2, 0.5])
    np.testing.assert_allclose(h / m, rot @ c + [0.4, -0.1, 0.2], rtol=1e-14)
    np.testing.assert_allclose(np.linalg.eigvalsh(inertia_com(phi)),
                               np.linalg.eigvalsh(np.trace(sigma_c) * np.eye(3) - sigma_c), rtol=1e-12)
