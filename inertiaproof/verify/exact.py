"""Numbers of a certificate: exact rationals written as "p/q" or as decimals ("0.1" is 1/10)."""

from __future__ import annotations

from fractions import Fraction

from flint import fmpq

__all__ = ["BadCertificate", "rational", "rational_matrix", "semidefinite"]


class BadCertificate(ValueError):
    """The certificate is malformed: its message names the field."""


def rational(text, where):
    """The exact rational a certificate writes as ``text`` (a string: "p/q", an integer or a decimal)."""
    if not isinstance(text, str):
        raise BadCertificate(f"{where}: numbers are written as strings (\"p/q\" or a decimal), not {text!r}")
    try:
        value = Fraction(text)
    except (ValueError, ZeroDivisionError):
        raise BadCertificate(f"{where}: {text!r} is not a rational number") from None
    return fmpq(value.numerator, value.denominator)


def rational_matrix(rows, shape, where):
    """The exact rationals of a certificate's ``shape`` matrix ``rows`` (lists of numbers)."""
    if not (isinstance(rows, list) and len(rows) == shape[0] and all(isinstance(r, list) and len(r) == shape[1]
                                                                     for r in rows)):
        raise BadCertificate(f"{where}: expected a {shape[0]}x{shape[1]} list of numbers")
    return [[rational(x, f"{where}[{i}][{j}]") for j, x in enumerate(r)] for i, r in enumerate(rows)]


def semidefinite(rows):
    """Whether the symmetric matrix of exact rationals ``rows`` is positive semidefinite, decided exactly: LDL^T
    with the largest remaining diagonal entry as pivot; once every remaining diagonal entry is zero, the rest
    must vanish (a zero diagonal entry of a semidefinite matrix has a zero row)."""
    a = [list(r) for r in rows]
    left = list(range(len(a)))
    while left:
        k = max(left, key=lambda i: a[i][i])
        d = a[k][k]
        if d < 0:
            return False
        if d == 0:
            return all(a[i][j] == 0 for i in left for j in left)
        left.remove(k)
        for i in left:
            f = a[i][k] / d
            for j in left:
                a[i][j] -= f * a[k][j]
    return True
