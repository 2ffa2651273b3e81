import numpy as np
import sympy as sp
from inertiaproof.checks import identities as checks
from inertiaproof.checks.identities import bijection_result, identity_result, numeric_agreement_result
from inertiaproof.symbolic import identities

from inertiaproof.result import Verdict
from inertiaproof.suite.context import Context
from inertiaproof.suite.profiles import PROFILES


def test_geometric_fact_holds():
    lhs, rhs, symbols = identities.geometric_fact()
    assert identity_result("EQ-geom", lhs, rhs, symbols, "Tjaja").verdict == Verdict.HOLDS


def test_geometric_fact_perturbed_is_violated():
    lhs, rhs, symbols = identities.geometric_fact()
    bad = rhs + sp.Rational(1, 10**9) * sp.eye(3)
    result = identity_result("EQ-geom", lhs, bad, symbols, "Tjaja")
    assert result.verdict == Verdict.VIOLATED
    assert result.counterexample["kind"] == "identity"


def test_eq_inverse_and_translation_hold():
    ctx = Context(PROFILES["ci"])
    for fn in (checks.eq_inverse, checks.eq_translation, checks.eq_geom):
        result = fn(ctx)
        assert result.verdict == Verdict.HOLDS, result.summary
    assert checks.eq_inverse(ctx).evidence["bijection"]["determinant"]["value"] != "0"


def test_wrong_inverse_is_violated():
    wrong = lambda s: s.trace() / 2 * sp.eye(3) - s  # noqa: E731
    assert identity_result("EQ-inverse", *identities.inverse_after_sigma(wrong), "inverse").verdict == Verdict.VIOLATED
    assert identity_result("EQ-inverse", *identities.sigma_after_inverse(wrong), "inverse").verdict == Verdict.VIOLATED


def test_non_bijective_f_is_violated():
    """Sigma = tr(I)/3 I3 - I is traceless: f misses half of sym(4), det A = 0, and the kernel is reported."""
    a, residual, symbols = identities.pseudo_inertia_coordinate_matrix(lambda i: i.trace() / 3 * sp.eye(3) - i)
    result = bijection_result("EQ-inverse", a, residual, symbols)
    assert result.verdict == Verdict.VIOLATED and "kernel_phi" in result.counterexample["data"]


def test_nonlinear_f_is_violated():
    a, residual, symbols = identities.pseudo_inertia_coordinate_matrix(lambda i: i * i)
    assert bijection_result("EQ-inverse", a, residual, symbols).verdict == Verdict.VIOLATED


def test_numeric_f_disagreeing_with_the_symbolic_f_is_violated():
    a, _, _ = identities.pseudo_inertia_coordinate_matrix()
    bad = a.copy()
    bad[0, 4] += sp.Rational(1, 10**6)
    assert numeric_agreement_result("EQ-inverse", bad, np.random.default_rng(0)).verdict == Verdict.VIOLATED


def test_wrong_translation_is_violated():
    wrong = lambda m, h, i: i + identities.skew(h).T * identities.skew(h) / m  # noqa: E731
    result = identity_result("EQ-translation", *identities.translation_invariance(wrong), "translation")
    assert result.verdict == Verdict.VIOLATED


def test_symbolic_f_matches_the_numeric_pseudo_inertia():
    from inertiaproof.model.inertia import pseudo_inertia

    m, h, inertia, symbols = identities.phi_symbols()
    f = identities.pseudo_inertia(m, h, inertia)
    phi = [sp.Rational(k + 2, 7) for k in range(10)]
    exact = np.array(f.subs(dict(zip(symbols, phi))).tolist(), dtype=float)
    np.testing.assert_allclose(pseudo_inertia(np.array(phi, dtype=float)), exact, rtol=1e-15)
