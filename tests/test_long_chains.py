"""Long chains within a counted budget: the comparison inverse in floats against exact rationals, branch and bound
that a budget cannot pay for, and the audit's quick and full budgets."""

from fractions import Fraction

import numpy as np
import pytest

from inertiaproof.bounds.apriori import comparison_inverse, triangular_normality_floor
from inertiaproof.bounds.extremes import bracket_extreme
from inertiaproof.dynamics.chain import Chain
from inertiaproof.suite.profiles import PROFILES


def _exact_inverse(diag, off):
    """C^-1 of C = diag - off in rationals (the oracle)."""
    n = len(diag)
    c = [[Fraction(float(diag[l])) if l == k else -Fraction(float(off[l, k])) for k in range(n)] for l in range(n)]
    inverse = [[Fraction(0)] * n for _ in range(n)]
    for col in range(n):
        for l in range(n):
            rhs = Fraction(int(l == col)) - sum((c[l][k] * inverse[k][col] for k in range(l)), Fraction(0))
            inverse[l][col] = rhs / c[l][l]
    return inverse


@pytest.mark.parametrize("seed", range(5))
def test_comparison_inverse_bounds_the_exact_inverse_from_above_and_closely(seed):
    rng = np.random.default_rng(seed)
    n = 12
    diag = rng.uniform(0.5, 1.5, n)
    off = np.tril(rng.uniform(0, 2, (n, n)), -1)
    upper = comparison_inverse(diag, off)
    exact = _exact_inverse(diag, off)
    for l in range(n):
        for k in range(n):
            assert Fraction(float(upper[l, k])) >= exact[l][k]
            assert float(upper[l, k]) <= float(exact[l][k]) * (1 + 1e-12) + 1e-300


def test_comparison_inverse_rounded_to_nearest_would_not_be_an_upper_bound():
    """The rounding allowance matters: the unrounded forward substitution falls below the exact inverse somewhere."""
    rng = np.random.default_rng(0)
    n = 30
    diag = rng.uniform(0.5, 1.5, n)
    off = np.tril(rng.uniform(0, 2, (n, n)), -1)
    plain = np.zeros((n, n))
    for l in range(n):
        row = off[l, :l] @ plain[:l]
        row[l] += 1.0
        plain[l] = row / diag[l]
    exact = _exact_inverse(diag, off)
    assert any(Fraction(float(plain[l, k])) < exact[l][k] for l in range(n) for k in range(l + 1))
    upper = comparison_inverse(diag, off)
    assert all(Fraction(float(upper[l, k])) >= exact[l][k] for l in range(n) for k in range(l + 1))


def _snake(n):
    """n revolute joints, 10 cm apart, each axis turned a quarter turn from the last."""
    return Chain.from_dh([(0.1, np.pi / 2, 0.0, 0.0)] * n, limits=[(-2.8, 2.8)] * n, name=f"snake {n}")


def test_triangular_floor_of_a_100_joint_chain_is_fast_and_below_samples():
    chain = _snake(100)
    floor = triangular_normality_floor(chain)
    lo, hi = chain.coordinate_box()
    q = lo + (hi - lo) * np.random.default_rng(1).random((20, chain.n))
    smallest = np.linalg.svd(chain.body_jacobian(q), compute_uv=False)[:, -1].min() ** 2
    assert 0 <= floor <= smallest


def test_a_budget_that_pays_for_no_box_gives_no_certified_side_and_says_so():
    calls = []

    def value(q):
        return (q**2).sum(1)

    def box_bound(c, r):
        calls.append(len(c))
        return np.zeros(len(c))

    kw = dict(sense="min", quantity_name="x", samples=16, rounds=2, rng=np.random.default_rng(0))
    cheap = bracket_extreme(value, box_bound, -np.ones(3), np.ones(3), **kw)
    assert cheap.certified is not None and cheap.boxes > 1 and calls
    calls.clear()
    costly = bracket_extreme(value, box_bound, -np.ones(3), np.ones(3), cost=1e6, **kw)
    assert costly.certified is None and costly.boxes == 0 and not calls
    assert "budget pays for" in costly.note
    calls.clear()
    few = bracket_extreme(value, box_bound, -np.ones(3), np.ones(3), cost=50.0, **kw)  # 5 boxes paid: one round of 2
    assert few.boxes == 3 and calls == [1, 2]


def test_audit_budgets_quick_by_default_full_with_bounds_all():
    ci, deep = PROFILES["ci"], PROFILES["deep"]
    assert ci.audit_budget("arms") == (512, 2) and ci.audit_budget("all") == (512, 20)
    from inertiaproof.bounds.pivots import PIVOT_MIN_ROUNDS
    assert ci.audit_budget("arms")[1] < PIVOT_MIN_ROUNDS <= ci.audit_budget("all")[1]
    assert deep.audit_budget("arms")[1] >= PIVOT_MIN_ROUNDS
