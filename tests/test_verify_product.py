"""The checker's ``product`` claims (inertiaproof.verify.product): a constant built by formula from certified
ingredients, factor * prod x_i^p_i >= (<=) bound, decided exactly on the ingredients' bounds, each ingredient
re-proved; and the product certificates of the paper's constants the checks report (Thm2, Thm3, Thm4)."""

from __future__ import annotations

import copy
from fractions import Fraction

import numpy as np
import pytest

from inertiaproof.bounds.certificate import body_spectrum_certificate, product_certificate
from inertiaproof.bounds.time import BODY_FUNCTIONS
from inertiaproof.checks.mass_matrix_bounds import thm2_result, thm3_result
from inertiaproof.checks.other_components import thm4_result
from inertiaproof.scene import robots
from inertiaproof.suite.context import Context
from inertiaproof.suite.outputs import Outputs
from inertiaproof.suite.profiles import Profile
from inertiaproof.verify.cli import check

STACK = np.array([[[2.0, 0.1, -0.2, 0.05, 0.3, 0.25, 0.2, 0.01, 0.0, -0.02]],
                  [[2.5, 0.0, 0.1, 0.0, 0.35, 0.3, 0.22, 0.0, 0.01, 0.0]]])  # 2 vertices, 1 consistent body


def _ingredient(name, slack=1e-6):
    build, kind, _ = BODY_FUNCTIONS[name]
    w = np.linalg.eigvalsh(build(STACK))
    value = {"lmin": w[..., 0].min(), "lmax": w[..., -1].max(), "absmax": np.abs(w).max()}[kind]
    bound = value * (1 - slack) if kind == "lmin" else value * (1 + slack)
    return body_spectrum_certificate(STACK, name, bound), Fraction(float(bound))


def _lower(bound_factor=1.0):
    (xi, b1), (zmin, b2) = _ingredient("lmin_f"), _ingredient("lmin_Z")
    exact = 3 * b1 * b2**2  # factor sqrt(9) = 3
    return product_certificate(">=", float(exact) * (1 - 1e-12) * bound_factor, ("sqrt", 9), [(xi, 1), (zmin, 2)],
                               "3 xi z^2 >= {bound}")


def test_a_true_product_is_reproved():
    out = check(_lower())
    assert out["status"] == "re-proved", out
    zeta, b1 = _ingredient("lmax_f")
    upper = product_certificate("<=", float(2 * b1 * 3) * (1 + 1e-12), 2, [(zeta, 1), (_ingredient("smax_fdot")[0], 1)],
                                "2 zeta mu <= {bound}")
    upper["ingredients"][1]["of"]["claim"]["bound"] = "3"  # sigma_max(f(Phi)) <= 3: true, and nonnegative by kind
    assert check(upper)["status"] == "re-proved"


def test_a_bound_above_what_the_ingredients_give_is_refuted():
    out = check(_lower(bound_factor=1 + 1e-9))
    assert out["status"] == "refuted" and "ingredients' bounds give" in out["why"], out


def test_an_ingredient_whose_own_claim_fails_refutes_the_product():
    cert = _lower()
    inner = cert["ingredients"][0]["of"]["claim"]
    inner["bound"] = str(Fraction(inner["bound"]) * 2)  # lambda_min(f) >= twice its value: false
    out = check(cert)
    assert out["status"] == "refuted" and out["where"]["ingredient"] == 0 and "not positive semidefinite" in out["why"]


def test_a_negative_lower_bound_is_a_bad_certificate():
    cert = _lower()
    cert["ingredients"][1]["of"]["claim"]["bound"] = "-1/2"  # x >= -1/2 bounds nothing of x^2 from below
    out = check(cert)
    assert out["status"] == "bad certificate" and "ingredients[1]" in out["why"] and "< 0" in out["why"], out


@pytest.mark.parametrize("powers", [(2,), (1, 1)])
def test_a_possibly_negative_factor_only_once_and_of_odd_power(powers):
    zeta, _ = _ingredient("lmax_f")
    cert = product_certificate("<=", 1e6, 1, [(copy.deepcopy(zeta), p) for p in powers], "zeta^p <= {bound}")
    out = check(cert)
    assert out["status"] == "bad certificate" and "may be negative" in out["why"], out


def test_nesting_is_bounded():
    cert = _lower()
    for _ in range(6):
        cert = product_certificate(">=", 0.0, 1, [(cert, 1)], "nested >= {bound}")
    out = check(cert)
    assert out["status"] == "bad certificate" and "nested deeper" in out["why"], out


def test_the_paper_constants_of_the_checks_carry_reproved_product_certificates():
    profile = Profile("test", examples=30, samples=300, refine_s=0.1, symbolic_max_n=2, derandomize=True)
    for fn, relation in ((thm2_result, ">="), (thm3_result, "<="), (thm4_result, "<=")):
        result = fn(Context(profile, seed=0, outputs=Outputs()), [robots.planar_2r(payload=1.0)])
        paper = result.evidence["scenes"]["planar-2r"]["constants"]["paper"]
        cert = paper["certificate"]
        assert cert["claim"]["kind"] == "product" and cert["claim"]["relation"] == relation
        assert Fraction(cert["claim"]["bound"]) == Fraction(paper["value"])  # the reported number itself
        out = check(cert)
        assert out["status"] == "re-proved", (result.id, out)
