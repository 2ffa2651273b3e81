"""Exact decisions in rational arithmetic, on float inputs or on decimals as written.

A float is a dyadic rational, so a matrix of floats scales to an integer
matrix by a power of two; signs of minors are then decided exactly with
Python integers (Bareiss fraction-free elimination). A decimal as written in
a file (``0.1``) is the rational it denotes (1/10), not its nearest float:
:func:`written_fraction` reads it.
"""

from __future__ import annotations

import math
import re
from fractions import Fraction
from itertools import combinations

import numpy as np

__all__ = [
    "definiteness", "determinant", "integer_matrix", "principal_minors", "to_fractions", "written_fraction",
    "WRITTEN_DIGITS", "WRITTEN_EXPONENT",
]

DECIMAL = re.compile(r"\s*([+-]?(?:\d+\.?\d*|\.\d+))(?:[eE]([+-]?\d+))?\s*")
WRITTEN_DIGITS = 1000  # longer decimals (and exponents beyond) are taken as their float: no number of a
WRITTEN_EXPONENT = 1000  # file needs more, and 10^(10^9) would not fit in memory


def written_fraction(text):
    """The rational a decimal denotes (``"0.1"`` -> 1/10), or None for text that is no plain decimal of moderate
    size (then the float is all there is)."""
    if not isinstance(text, str) or len(text) > WRITTEN_DIGITS + 10:
        return None
    match = DECIMAL.fullmatch(text)
    if not match or (match.group(2) and abs(int(match.group(2))) > WRITTEN_EXPONENT):
        return None
    return Fraction(text.strip())


def to_fractions(a):
    """Exact rationals of a float array (nested lists of Fraction)."""
    a = np.asarray(a, dtype=float)
    if not np.all(np.isfinite(a)):
        raise ValueError("exact arithmetic needs finite values")
    return np.vectorize(Fraction, otypes=[object])(a)


def integer_matrix(q):
    """Scale a matrix of Fractions with a common denominator to integers (same signs of minors up to a positive factor)."""
    q = np.asarray(q, dtype=object)
    den = math.lcm(*(x.denominator for x in q.flat))
    return [[int(x * den) for x in row] for row in q]


def determinant(a):
    """Exact determinant of a square integer matrix by Bareiss elimination (every division is exact)."""
    a = [list(row) for row in a]
    n = len(a)
    if n == 0:
        return 1
    sign, prev = 1, 1
    for k in range(n - 1):
        if a[k][k] == 0:
            swap = next((i for i in range(k + 1, n) if a[i][k] != 0), None)
            if swap is None:
                return 0
            a[k], a[swap] = a[swap], a[k]
            sign = -sign
        for i in range(k + 1, n):
            for j in range(k + 1, n):
                a[i][j] = (a[i][j] * a[k][k] - a[i][k] * a[k][j]) // prev
        prev = a[k][k]
    return sign * a[n - 1][n - 1]


def principal_minors(a):
    """All principal minors of a symmetric matrix, keyed by index tuple."""
    n = len(a)
    return {
        idx: determinant([[a[i][j] for j in idx] for i in idx])
        for r in range(1, n + 1)
        for idx in combinations(range(n), r)
    }


def definiteness(a):
    """'pd', 'psd' (singular) or 'indefinite' for a symmetric exact matrix, and its rank.

    Positive definite iff all leading principal minors are > 0 (Sylvester);
    positive semidefinite iff all principal minors are >= 0.
    """
    n = len(a)
    minors = principal_minors(a)
    if all(minors[tuple(range(k))] > 0 for k in range(1, n + 1)):
        return "pd", n
    if all(v >= 0 for v in minors.values()):
        rank = max((len(idx) for idx, v in minors.items() if v != 0), default=0)
        return "psd", rank
    return "indefinite", None
