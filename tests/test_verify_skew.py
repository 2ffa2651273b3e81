"""The ``skew-partials`` claim (Theorem 5's sups of sigma_max(Y_p), inertiaproof.verify.skew): the trolley 2R's two
certificates, as the prover writes them from its branch and bound's partition, are re-proved; an oracle by finite
differences of QJ stays within their bounds; tampered certificates are refuted or rejected. The checker walks a tree
once: where a test relied on it cutting beyond the tree, the prover completes the tree first
(inertiaproof.bounds.completion.complete)."""

from __future__ import annotations

import copy
from fractions import Fraction

import numpy as np
import pytest

from inertiaproof.bounds.completion import complete
from inertiaproof.bounds.configuration import skew_partial_sup
from inertiaproof.bounds.extremes import _prefix_code
from inertiaproof.scene import robots
from inertiaproof.verify.cli import check
from inertiaproof.verify.tree import parse


@pytest.fixture(scope="module")
def trolley():
    """The chain and the two brackets of the Asm3/Thm5 check's scene, with the ci profile's budget."""
    chain = robots.trolley_2r(loop=True, mass=2.0).chain
    worst, rss = skew_partial_sup(chain, samples=2000, rounds=20, rng=np.random.default_rng(0))
    return chain, {"max_sigma": worst, "rss_sigma": rss}


def _certificate(brackets, quantity):
    return brackets[quantity].certificate()


@pytest.mark.parametrize("quantity", ["max_sigma", "rss_sigma"])
def test_the_trolleys_certificates_are_reproved(trolley, quantity):
    chain, brackets = trolley
    cert = _certificate(brackets, quantity)
    assert cert["claim"] == {**cert["claim"], "kind": "skew-partials", "quantity": quantity}
    assert Fraction(cert["claim"]["bound"]) == Fraction(brackets[quantity].certified)  # the certified side as it is
    parse(cert["tree"], [(Fraction(a), Fraction(b)) for a, b in cert["domain"]])  # a partition of the domain
    out = check(complete(cert, boxes=5000))
    assert out["status"] == "re-proved", out
    assert "sigma_max(Y_p(q))" in out["claim"], out


def _oracle(chain, q, h=1e-5):
    """sigma_max(Y_p(q)) for every row p, Y_p = dK_p/dq - (dK_p/dq)^T, K_p = (QJ)^T e_p, by central differences of
    QJ (chain.body_jacobian): (K, 6N)."""
    d = np.stack([(chain.body_jacobian(q + h * e) - chain.body_jacobian(q - h * e)) / (2 * h)
                  for e in np.eye(chain.n)], -1)  # (K, 6N, n, n): [p, k, j] = d QJ[p, k] / d q_j
    return np.linalg.svd(d - np.swapaxes(d, -1, -2), compute_uv=False)[..., 0]


def test_an_oracle_by_finite_differences_stays_within_the_certified_sides(trolley):
    chain, brackets = trolley
    q = np.random.default_rng(7).uniform(-np.pi, np.pi, (300, chain.n))
    q = np.concatenate([q, [brackets["max_sigma"].witness, brackets["rss_sigma"].witness, [0.0, 0.0]]])
    s = _oracle(chain, q)
    assert s.max() <= brackets["max_sigma"].certified
    assert np.sqrt((s**2).sum(1)).max() <= brackets["rss_sigma"].certified
    assert s.max() > 0.999 and np.sqrt((s**2).sum(1)).max() > 0.999  # the sides are near what is attained


@pytest.mark.parametrize("witness, quantity", [(True, "rss_sigma"), *(pytest.param(*case, marks=pytest.mark.slow)
                                                for case in ((True, "max_sigma"), (False, "max_sigma"),
                                                             (False, "rss_sigma")))])
def test_a_bound_below_an_attained_value_is_refuted(trolley, quantity, witness):
    chain, brackets = trolley
    cert = copy.deepcopy(_certificate(brackets, quantity))
    attained = float(_oracle(chain, np.array([[0.0, 0.0]]))[0].max())  # 1 at q = 0 (both quantities)
    cert["claim"]["bound"] = str(Fraction(0.999 * attained))
    if not witness:
        cert.pop("witness")
    out = check(complete(cert, boxes=2000))
    assert out["status"] == "refuted" and out["where"]["witness"]["q"], out
    assert "witness" in out["why"] if witness else "centre" in out["why"], out


def test_a_negative_bound_is_refuted_not_proved_by_its_square(trolley):
    chain, brackets = trolley
    for quantity in ("max_sigma", "rss_sigma"):
        cert = copy.deepcopy(_certificate(brackets, quantity))
        cert["claim"]["bound"] = "-2"  # (-2)^2 = 4 is above every sigma_max(Y_p)^2 of the trolley
        assert check(cert)["status"] == "refuted"


@pytest.mark.parametrize("tree", ["one leaf less", None, ". extra", "7 . ."])
def test_a_tree_that_is_no_partition_is_rejected(trolley, tree):
    chain, brackets = trolley
    cert = copy.deepcopy(_certificate(brackets, "max_sigma"))
    cert["tree"] = cert["tree"].rsplit(" .", 1)[0] if tree == "one leaf less" else tree
    out = check(cert)
    assert out["status"] == "bad certificate" and "tree" in out["why"], out


@pytest.mark.slow
def test_a_chain_with_another_joint_axis_is_not_reproved(trolley):
    chain, brackets = trolley
    for quantity in ("max_sigma", "rss_sigma"):
        cert = copy.deepcopy(_certificate(brackets, quantity))
        cert["chain"]["joints"][1]["axis"] = ["1", "0", "0"]
        assert check(cert)["status"] in ("refuted", "not re-proved")
        out = check(complete(cert, boxes=2000))
        assert out["status"] in ("refuted", "not re-proved"), out


def test_malformed_fields_are_rejected(trolley):
    chain, brackets = trolley
    cert = _certificate(brackets, "max_sigma")
    for field, value in (("quantity", "sigma"), ("coordinate", "cubic"), ("domain", [["0", "1"]]),
                         ("witness", ["9", "0"]), ("bodies", 3)):
        bad = copy.deepcopy(cert)
        if field == "quantity":
            bad["claim"]["quantity"] = value
        elif field == "coordinate":
            bad["chain"]["joints"][1]["coordinate"] = value
        else:
            bad[field] = value
        out = check(bad)
        assert out["status"] == "bad certificate", (field, out)


def test_the_prefix_code_of_the_halvings():
    """Box 0 halved along coordinate 1 into boxes 1 and 2, box 2 along coordinate 0 into 3 and 4."""
    splits = [(np.array([0]), np.array([1]), 1), (np.array([2]), np.array([0]), 3)]
    assert _prefix_code(splits) == "1 . 0 . ."
    assert _prefix_code([]) == "."
