"""Section 2 identities as SymPy objects: each function returns (lhs, rhs, symbols).

The checks in ``inertiaproof.checks.identities`` decide lhs == rhs exactly
(expand to a canonical polynomial form); tests feed them perturbed
right-hand sides to see VIOLATED.
"""

from __future__ import annotations

import sympy as sp


def skew(x):
    """S(x) (paper, Notation)."""
    return sp.Matrix([[0, -x[2], x[1]], [x[2], 0, -x[0]], [-x[1], x[0], 0]])


def geometric_fact():
    """(Tjaja): S(x)^T S(x) = tr(x x^T) I3 - x x^T."""
    x = sp.Matrix(sp.symbols("x1:4", real=True))
    lhs = skew(x).T * skew(x)
    rhs = (x * x.T).trace() * sp.eye(3) - x * x.T
    return lhs, rhs, tuple(x)
