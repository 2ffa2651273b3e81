"""The checker's ``body-spectrum`` claims (inertiaproof.verify.bodies): spectral bounds of the bodies' matrices over
the hull of the parameter vertices, decided in exact rational arithmetic, and the prover's certificates of the time
extremes (inertiaproof.bounds.time.time_extreme), whose certified sides carry a rounding allowance."""

from __future__ import annotations

import copy
from fractions import Fraction

import numpy as np
import pytest
from flint import fmpq

from inertiaproof.bounds.certificate import body_spectrum_certificate
from inertiaproof.bounds.time import BODY_FUNCTIONS, parameter_vertices, time_extreme
from inertiaproof.model.inertia import pseudo_inertia, spatial_inertia
from inertiaproof.scene import robots
from inertiaproof.verify import bodies
from inertiaproof.verify.cli import check


def _random_rows(seed, count=20):
    """Physically consistent bodies (random point clouds) and arbitrary rows (rates)."""
    rng = np.random.default_rng(seed)
    rows = []
    for _ in range(count):
        points, masses = rng.normal(size=(5, 3)), rng.random(5) + 0.1
        m, h = masses.sum(), masses @ points
        inertia = sum(w * (p @ p * np.eye(3) - np.outer(p, p)) for w, p in zip(masses, points))
        rows.append([m, *h, inertia[0, 0], inertia[1, 1], inertia[2, 2], inertia[0, 1], inertia[1, 2], inertia[0, 2]])
    return np.array(rows)


def _stack(seed=0, vertices=3, bodies_=2):
    return _random_rows(seed, vertices * bodies_).reshape(vertices, bodies_, 10)


@pytest.mark.parametrize("formula, reference", [(bodies.pseudo_inertia, pseudo_inertia),
                                                (bodies.spatial_inertia, spatial_inertia)])
def test_the_checkers_formulas_agree_with_the_model(formula, reference):
    rows = np.concatenate([_random_rows(1), np.random.default_rng(2).normal(size=(20, 10))])
    for row in rows:
        exact = formula([fmpq(Fraction(x).numerator, Fraction(x).denominator) for x in row])
        expected = reference(row)
        got = np.array([[float(Fraction(int(x.p), int(x.q))) for x in r] for r in exact])
        assert got.shape == expected.shape
        assert np.allclose(got, expected, rtol=0, atol=1e-14 * np.abs(expected).max())


def _extreme(stack, name):
    build, kind, _ = BODY_FUNCTIONS[name]
    w = np.linalg.eigvalsh(build(stack))
    return {"lmin": w[..., 0].min(), "lmax": w[..., -1].max(), "absmax": np.abs(w).max()}[kind]


@pytest.mark.parametrize("name", sorted(BODY_FUNCTIONS))
def test_a_true_claim_is_reproved(name):
    stack = _stack()
    value = _extreme(stack, name)
    bound = value - 1e-6 * abs(value) if name.startswith("lmin") else value + 1e-6 * abs(value)
    out = check(body_spectrum_certificate(stack, name, bound))
    assert out["status"] == "re-proved", out


@pytest.mark.parametrize("name", ["lmin_f", "lmin_Z"])
def test_a_bound_just_above_lambda_min_is_refuted(name):
    stack = _stack()
    build = BODY_FUNCTIONS[name][0]
    w = np.linalg.eigvalsh(build(stack))[..., 0]  # (V, N)
    v, l = np.unravel_index(np.argmin(w), w.shape)
    cert = body_spectrum_certificate(stack, name, w[v, l] * (1 + 1e-9))
    out = check(cert)
    assert out["status"] == "refuted", out
    where = out["where"]["witness"]  # the (parameter set, body) at which the claim fails; the sides there
    assert where["body"] == l + 1 and "F - bound I" in out["where"]["sides"], out
    assert out["where"]["sides"]["bound"] == cert["claim"]["bound"], out
    assert [Fraction(x) for x in cert["parameters"][where["parameter_set"]][l]] == [Fraction(x) for x in stack[v, l]]
    assert f"body {l + 1}" in out["why"] and bodies_matrix(name) in out["why"]


def bodies_matrix(name):
    return "pseudo_inertia" if name.endswith("f") else "spatial_inertia"


def test_sigma_max_needs_both_sides():
    """sigma_max <= b means -b I <= F <= b I: a rate whose most negative eigenvalue is largest in size is refuted
    at b just above lambda_max(F) but below |lambda_min(F)|."""
    phi = -_random_rows(3, 1)  # -f(Phi) of a consistent body: every eigenvalue negative
    stack = phi.reshape(1, 1, 10)
    w = np.linalg.eigvalsh(pseudo_inertia(phi[0]))
    assert w[-1] < 0
    out = check(body_spectrum_certificate(stack, "smax_fdot", abs(w[0]) * 0.999))
    assert out["status"] == "refuted" and "bound I + F" in out["why"], out
    assert check(body_spectrum_certificate(stack, "smax_fdot", abs(w[0]) * 1.001))["status"] == "re-proved"


def _allowance_cases():
    """Stacks where lambda_min computed in floating point lies above the exact one (found over random seeds)."""
    for seed in range(200):
        stack = _stack(seed, vertices=1, bodies_=4)
        for name in ("lmin_f", "lmin_Z"):
            bare = float(_extreme(stack, name))
            if check(body_spectrum_certificate(stack, name, bare))["status"] == "refuted":
                yield stack, name, bare


def test_the_rounding_allowance_is_needed_and_enough():
    """A bound equal to eigvalsh's lambda_min, with no allowance, is refuted on some stack (the float eigenvalue
    lies a few ulps above the exact one); lowered by ROUNDING eps |lambda|_max it is re-proved."""
    from inertiaproof.bounds.spectral import EPS, ROUNDING

    found = next(_allowance_cases(), None)
    assert found is not None, "no stack where the bare float lambda_min is above the exact one"
    stack, name, bare = found
    build = BODY_FUNCTIONS[name][0]
    allowance = ROUNDING * EPS * np.abs(np.linalg.eigvalsh(build(stack))).max()
    assert check(body_spectrum_certificate(stack, name, bare - allowance))["status"] == "re-proved"


@pytest.mark.parametrize("scene", [robots.planar_2r(payload=1.0), robots.spatial_3r()])
def test_time_extremes_carry_certificates_the_checker_reproves(scene):
    traj = scene.trajectory
    verts = parameter_vertices(traj)
    assert verts is not None
    for name in BODY_FUNCTIONS:
        found = time_extreme(traj, name)
        cert = found.get("certificate")
        assert cert is not None and cert["claim"]["kind"] == "body-spectrum", name
        assert Fraction(cert["claim"]["bound"]) == Fraction(found["certified"])
        assert "rounding allowance" in found["how"]
        assert check(cert)["status"] == "re-proved", (name, check(cert))


def test_no_certificate_for_unbounded_rows():
    stack = _stack()
    stack[0, 1, 0] = np.inf
    assert body_spectrum_certificate(stack, "lmin_f", 0.0) is None
    assert body_spectrum_certificate(_stack(), "lmax_f", np.inf) is None


@pytest.mark.parametrize("tamper, field", [
    (lambda c: c["claim"].update(matrix="mass_matrix"), "claim.matrix"),
    (lambda c: c["claim"].update(quantity="sigma_min"), "claim.quantity"),
    (lambda c: c["parameters"][1][0].append("0"), "parameters[1][0]"),  # 11 numbers in a row
    (lambda c: c["parameters"][1][0].pop(), "parameters[1][0]"),  # 9 numbers
    (lambda c: c["parameters"][0][1].__setitem__(4, 0.25), "parameters[0][1][4]"),  # a float
    (lambda c: c["claim"].update(bound=0.5), "claim.bound"),
    (lambda c: c["parameters"][2].pop(), "parameters[2]"),  # a body missing
    (lambda c: c.update(parameters=[]), "parameters"),
])
def test_malformed_certificates_are_rejected_with_the_field(tamper, field):
    cert = copy.deepcopy(body_spectrum_certificate(_stack(), "lmin_f", 0.0))
    tamper(cert)
    out = check(cert)
    assert out["status"] == "bad certificate" and out["why"].startswith(field) and "\n" not in out["why"], out
