"""The checker's ``product`` claims (inertiaproof.verify.product): a constant of the paper built by a named formula
(inertiaproof.verify.product.FORMULAS, which fixes its factor and powers) from certified ingredients, factor *
prod x_i^p_i >= (<=) bound, decided exactly on the ingredients' bounds, each ingredient re-proved; and the product
certificates of the paper's constants the checks report (Thm2, Thm3, Thm4)."""

from __future__ import annotations

import copy
from fractions import Fraction

import numpy as np
import pytest

from inertiaproof.bounds.certificate import body_spectrum_certificate, product_certificate, spectrum_certificate
from inertiaproof.bounds.completion import complete
from inertiaproof.bounds.lengths import unit_bodies
from inertiaproof.bounds.time import BODY_FUNCTIONS
from inertiaproof.checks.mass_matrix_bounds import thm2_result, thm3_result
from inertiaproof.checks.other_components import thm4_result
from inertiaproof.dynamics import composite
from inertiaproof.scene import robots
from inertiaproof.suite.context import Context
from inertiaproof.suite.outputs import Outputs
from inertiaproof.suite.profiles import Profile
from inertiaproof.verify.cli import check

CHAIN = robots.planar_2r().chain
STACK = np.array([[[2.0, 0.1, -0.2, 0.05, 0.3, 0.25, 0.2, 0.01, 0.0, -0.02],
                   [1.2, 0.05, 0.0, 0.02, 0.2, 0.18, 0.1, 0.0, 0.0, 0.01]],
                  [[2.5, 0.0, 0.1, 0.0, 0.35, 0.3, 0.22, 0.0, 0.01, 0.0],
                   [1.0, 0.0, 0.03, 0.0, 0.15, 0.12, 0.08, 0.0, 0.0, 0.0]]])  # 2 vertices, the 2R arm's 2 bodies


def _ingredient(name, slack=1e-6, stack=STACK):
    build, kind, _ = BODY_FUNCTIONS[name]
    w = np.linalg.eigvalsh(build(stack))
    value = {"lmin": w[..., 0].min(), "lmax": w[..., -1].max(), "absmax": np.abs(w).max()}[kind]
    bound = value * (1 - slack) if kind == "lmin" else value * (1 + slack)
    return body_spectrum_certificate(stack, name, bound), Fraction(float(bound))


def _qj(quantity):
    """A certificate of inf lambda_min (0.9 of the sampled inf) or sup lambda_max (1.1 of the sampled sup) of
    (QJ)^T QJ of the 2R arm (unit bodies), completed by the prover, and its bound."""
    unit = unit_bodies(CHAIN)
    lo, hi = CHAIN.coordinate_box()
    q = lo + (hi - lo) * np.random.default_rng(0).random((2000, CHAIN.n))
    w = np.linalg.eigvalsh(composite.mass_matrix(CHAIN, q[:, None], unit[None]))
    bound = 0.9 * w[..., 0].min() if quantity == "lambda_min" else 1.1 * w[..., -1].max()
    cert = complete(spectrum_certificate(CHAIN, unit, quantity, bound), boxes=2000)
    return cert, Fraction(cert["claim"]["bound"])


def _lower(bound_factor=1.0):
    (xi, b1), (gamma, b2) = _ingredient("lmin_f"), _qj("lambda_min")
    exact = b1 * b2  # alpha1: factor 1, powers 1 and 1
    return product_certificate(">=", float(exact) * (1 - 1e-12) * bound_factor, "alpha1", [xi, gamma])


def test_a_true_product_is_reproved():
    out = check(_lower())
    assert out["status"] == "re-proved", out
    assert out["claim"].startswith("Theorem 2's alpha1"), out
    zeta, b1 = _ingredient("lmax_f")
    sigma, b2 = _qj("lambda_max")
    upper = product_certificate("<=", float(2 * b1 * b2) * (1 + 1e-12), "alpha2", [zeta, sigma])  # factor 2
    assert check(upper)["status"] == "re-proved"
    rate = product_certificate("<=", float(2 * 3 * b2) * (1 + 1e-12), "chi_sharp", [_ingredient("smax_fdot")[0], sigma])
    rate["ingredients"][0]["claim"]["bound"] = "3"  # sigma_max(f(Phidot)) <= 3: true, and nonnegative by kind
    assert check(rate)["status"] == "re-proved"


def test_a_bound_above_what_the_ingredients_give_is_not_reproved():
    """The arithmetic fails, and no witness says the constant is wrong: a proof step that does not go through."""
    out = check(_lower(bound_factor=1 + 1e-9))
    assert out["status"] == "not re-proved" and "ingredients' bounds give" in out["why"], out


def test_an_ingredient_whose_own_claim_fails_refutes_the_product():
    cert = _lower()
    inner = cert["ingredients"][0]["claim"]
    inner["bound"] = str(Fraction(inner["bound"]) * 2)  # lambda_min(f) >= twice its value: false
    out = check(cert)
    assert out["status"] == "refuted" and "ingredient 0" in out["why"] and "not positive semidefinite" in out["why"]
    assert out["where"]["witness"]["body"] in (1, 2) and out["where"]["sides"], out


def test_a_negative_lower_bound_is_a_bad_certificate():
    cert = _lower()
    cert["ingredients"][1]["claim"]["bound"] = "-1/2"  # x >= -1/2 bounds nothing of a product from below
    out = check(cert)
    assert out["status"] == "bad certificate" and "ingredients[1]" in out["why"] and "< 0" in out["why"], out


@pytest.mark.parametrize("formula, slot", [("chi_sharp", 0), ("alpha2", 1)])
def test_a_possibly_negative_quantity_only_where_the_formula_clamps_it(formula, slot):
    """lambda_max(f(Phi)) may be negative: it may stand only in a slot of power 1 that the formula clamps at 0
    (alpha2's f_max), not in one that must be nonnegative by its kind (a sigma_max, (QJ)^T QJ)."""
    zeta, _ = _ingredient("lmax_f")
    parts = [copy.deepcopy(zeta), _qj("lambda_max")[0]]  # alpha2's own ingredients, zeta where it may stand
    parts[slot] = copy.deepcopy(zeta)
    out = check(product_certificate("<=", 1e6, formula, parts))
    assert out["status"] == "bad certificate" and f"ingredients[{slot}]" in out["why"], out


@pytest.mark.parametrize("tamper, why", [
    (lambda c: c["claim"].update(formula="alpha7"), "claim.formula"),
    (lambda c: c["claim"].update(relation="<="), "claim.relation"),
    (lambda c: c["claim"].update(factor="9"), "claim"),  # the formula fixes the factor
    (lambda c: c["ingredients"].append(copy.deepcopy(c["ingredients"][0])), "ingredients"),  # no powers by repetition
    (lambda c: c["ingredients"].reverse(), "ingredients[0]"),  # the formula's order
    (lambda c: c["ingredients"][1].update(parameters=c["ingredients"][0]["parameters"]), "ingredients[1]"),  # not unit
])
def test_a_product_that_departs_from_its_formula_is_a_bad_certificate(tamper, why):
    cert = _lower()
    tamper(cert)
    out = check(cert)
    assert out["status"] == "bad certificate" and out["why"].startswith(why), out


def test_the_checker_names_the_ingredient_it_does_not_reprove_and_the_prover_completes_only_it():
    (xi, b1), chain = _ingredient("lmin_f", stack=STACK[:, [0, 1, 1]]), robots.spatial_3r().chain
    unit, (lo, hi) = unit_bodies(chain), chain.coordinate_box()
    q = lo + (hi - lo) * np.random.default_rng(0).random((2000, chain.n))
    inf = np.linalg.eigvalsh(composite.mass_matrix(chain, q[:, None], unit[None]))[..., 0].min()
    bare = spectrum_certificate(chain, unit, "lambda_min", 0.99 * inf)  # one box: the checker's pivots fall short
    cert = product_certificate(">=", float(b1 * Fraction(bare["claim"]["bound"])) * (1 - 1e-12), "alpha1",
                               [xi, bare])
    out = check(cert)
    assert out["status"] == "not re-proved" and set(out["where"]["ingredients"]) == {"1"}, out
    grown = complete(cert, 2000, out["where"])
    assert grown["ingredients"][0] is xi and grown["ingredients"][1]["tree"] != "."
    assert check(grown)["status"] == "re-proved"


def test_a_product_is_no_ingredient_of_a_product():
    """Products do not nest: every slot of a formula takes a claim of the kind it names."""
    cert = product_certificate(">=", 0.0, "alpha1", [_lower(), _qj("lambda_min")[0]])
    out = check(cert)
    assert out["status"] == "bad certificate" and "ingredients[0]" in out["why"] and "product" in out["why"], out


def test_the_paper_constants_of_the_checks_carry_reproved_product_certificates():
    profile = Profile("test", examples=30, samples=300, rounds=4, symbolic_max_n=2, derandomize=True)
    for fn, relation in ((thm2_result, ">="), (thm3_result, "<="), (thm4_result, "<=")):
        result = fn(Context(profile, seed=0, outputs=Outputs()), [robots.planar_2r(payload=1.0)])
        paper = result.evidence["scenes"]["planar-2r"]["constants"]["paper"]
        cert = paper["certificate"].certificate
        assert cert["claim"]["kind"] == "product" and cert["claim"]["relation"] == relation
        assert Fraction(cert["claim"]["bound"]) == Fraction(paper["value"])  # the reported number itself
        out = check(complete(cert, boxes=profile.tree_boxes))
        assert out["status"] == "re-proved", (result.id, out)
