import sympy as sp

from inertiaproof.checks.identities import identity_result
from inertiaproof.result import Verdict
from inertiaproof.symbolic import identities


def test_geometric_fact_holds():
    lhs, rhs, symbols = identities.geometric_fact()
    assert identity_result("EQ-geom", lhs, rhs, symbols, "Tjaja").verdict == Verdict.HOLDS


def test_geometric_fact_perturbed_is_violated():
    lhs, rhs, symbols = identities.geometric_fact()
    bad = rhs + sp.Rational(1, 10**9) * sp.eye(3)
    result = identity_result("EQ-geom", lhs, bad, symbols, "Tjaja")
    assert result.verdict == Verdict.VIOLATED
    assert result.counterexample["kind"] == "identity"
