"""EQ-schur and EQ-triangle: they hold, and each checker catches a wrong side of its equivalence."""

from fractions import Fraction

import numpy as np
import sympy as sp
from hypothesis import strategies as st
from inertiaproof.checks import equivalences as eq
from inertiaproof.checks.identities import identity_result
from inertiaproof.symbolic import identities

from inertiaproof.cli import main
from inertiaproof.model.inertia import pseudo_inertia_inverse, sigma_from_inertia, unpack
from inertiaproof.result import Verdict


def test_eq_schur_holds(ctx):
    result = eq.eq_schur(ctx)
    assert result.verdict == Verdict.HOLDS, result.summary
    numeric = result.evidence["numeric"]
    assert numeric["sweep"]["disagreements"]["value"] == 0
    assert numeric["sweep"]["exact_decisions"]["value"] > 0 and numeric["hunt_exact_decisions"]["value"] > 0


def test_wrong_schur_complement_is_violated(ctx, capsys):
    def plus(phi):
        m, h, inertia = unpack(phi)
        return sigma_from_inertia(inertia) + np.outer(h, h) / m

    # f = [[Sigma, h], [h^T, 1]] with Sigma <= I3 and |h_1| >= 2: f is not positive definite, Sigma + h h^T / m is
    strongly_indefinite = st.tuples(*(st.floats(0.1, 1.0),) * 3, st.floats(2.0, 3.0)).map(
        lambda t: pseudo_inertia_inverse(np.block([[np.diag(t[:3]), np.array([[t[3]], [0.0], [0.0]])],
                                                   [np.array([[t[3], 0.0, 0.0, 1.0]])]])))
    result = eq.schur_numeric(ctx, rhs=lambda phi: eq.schur_side(phi, plus), strategy=strongly_indefinite)
    assert result.verdict == Verdict.VIOLATED
    path = ctx.save_counterexample(result)
    assert main(["replay", str(path)]) == 0  # the example decided with the right Schur complement: both sides agree
    assert "HOLDS" in capsys.readouterr().out


def test_wrong_symbolic_schur_factorisation_is_violated():
    wrong = lambda m, h, inertia: identities.sigma_of(inertia)  # noqa: E731
    assert identity_result("EQ-schur", *identities.schur_factorisation(wrong), "schur").verdict == Verdict.VIOLATED


def test_schur_on_exact_boundary_rows_is_decided_exactly():
    point = np.array([2.0, 2, -4, 6, 26, 20, 10, 4, 12, -6])  # m = 2 at (1, -2, 3)
    lhs, lhs_exact, _ = eq.pseudo_inertia_side(point)
    rhs, rhs_exact = eq.schur_side(point)
    assert (lhs, rhs) == (False, False) and lhs_exact and rhs_exact


def test_eq_triangle_holds(ctx):
    result = eq.eq_triangle(ctx)
    assert result.verdict == Verdict.HOLDS, result.summary
    assert result.evidence["numeric"]["equality_cases"]["value"] > 0


def test_non_strict_triangle_inequalities_are_violated(ctx):
    """The non-strict version (Traversaro's) is not equivalent to Sigma_CoM > 0: it admits rods and plates."""
    weak = lambda lam: lam[0] <= lam[1] + lam[2] and lam[1] <= lam[0] + lam[2] and lam[2] <= lam[0] + lam[1]  # noqa: E731
    result = eq.triangle_numeric(ctx, triangle=weak)
    assert result.verdict == Verdict.VIOLATED
    lam = [Fraction(x) for x in result.counterexample["data"]["lambda"]]
    assert min(lam[1] + lam[2] - lam[0], lam[0] + lam[2] - lam[1], lam[0] + lam[1] - lam[2]) == 0


def test_wrong_sigma_map_is_violated(ctx):
    result = eq.triangle_numeric(ctx, sigma_map=lambda i: np.trace(i) / 3 * np.eye(3, dtype=int) - i)
    assert result.verdict == Verdict.VIOLATED


def test_wrong_spectral_identity_is_violated():
    wrong = lambda j: j.trace() / 3 * sp.eye(3) - j  # noqa: E731
    assert identity_result("EQ-triangle", *identities.spectrum_of_sigma(wrong), "spec").verdict == Verdict.VIOLATED


def test_footnote_rod_is_not_positive_definite():
    """A rod: lambda = (0, a, a) fails strictness and I_CoM > 0 together; the footnote's implication is not vacuous."""
    rot = np.eye(3, dtype=int).astype(object)
    sigma_pd, strict, i_pd, _ = eq.triangle_decisions([Fraction(0), Fraction(3), Fraction(3)], rot)
    assert (sigma_pd, strict, i_pd) == (False, False, False)
    sigma_pd, strict, i_pd, _ = eq.triangle_decisions([Fraction(1), Fraction(2), Fraction(2)], rot)
    assert (sigma_pd, strict, i_pd) == (True, True, True)


def test_custom_strategy_reaches_the_hunt(ctx):
    only_points = st.just(np.array([1.0, 0, 0, 0, 0, 0, 0, 0, 0, 0]))
    result = eq.schur_numeric(ctx, rhs=lambda phi: (True, False), strategy=only_points)
    assert result.verdict == Verdict.VIOLATED
