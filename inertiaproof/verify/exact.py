"""Numbers of a certificate, read strictly: exact rationals written as "p/q" or decimals ("0.1" is 1/10), JSON
without duplicate keys, NaN, Infinity or floats, and balls that are finite before they are compared."""

from __future__ import annotations

import json
import re
from fractions import Fraction

from flint import arb, fmpq

__all__ = ["BadCertificate", "DIGITS", "ball_max", "finite", "rational", "rational_matrix", "read_json",
           "semidefinite"]

DIGITS = 2000  # the longest number a certificate may write (characters): exact arithmetic on it stays bounded
NUMBER = re.compile(r"[-+]?(\d+(\.\d*)?|\.\d+)([eE][-+]?\d{1,4})?(/\d+)?")


class BadCertificate(ValueError):
    """The certificate is malformed: its message names the field."""


def _pairs(pairs):
    seen = {}
    for key, value in pairs:
        if key in seen:
            raise BadCertificate(f"duplicate key {key!r}: a certificate says one thing once")
        seen[key] = value
    return seen


def _no_float(text):
    raise BadCertificate(f"the JSON number {text}: exact numbers are written as strings (\"p/q\" or a decimal)")


def _no_constant(text):
    raise BadCertificate(f"{text} is not a number a certificate may hold")


def read_json(text, floats=False):
    """The JSON document ``text``, read strictly: a duplicate key, NaN or Infinity, or (unless ``floats``) a JSON
    float is a :class:`BadCertificate`; so is trailing data (``json.loads``)."""
    try:
        return json.loads(text, object_pairs_hook=_pairs, parse_constant=_no_constant,
                          **({} if floats else {"parse_float": _no_float}))
    except json.JSONDecodeError as exc:
        raise BadCertificate(f"not JSON: {exc}") from None


def rational(text, where):
    """The exact rational a certificate writes as ``text`` (a string: "p/q", an integer or a decimal)."""
    if not isinstance(text, str) or len(text) > DIGITS or not NUMBER.fullmatch(text):
        raise BadCertificate(f"{where}: numbers are written as strings (\"p/q\" or a decimal) of at most {DIGITS} "
                             f"characters, not {str(text)[:40]!r}")
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


class NotFinite(ArithmeticError):
    """A ball the checker would compare is not finite: nothing is decided from it."""


def finite(x, what):
    """The ball ``x``, or :class:`NotFinite` naming ``what`` when it is NaN or unbounded."""
    if not x.is_finite():
        raise NotFinite(f"{what} is not a finite ball ({x})")
    return x


def ball_max(balls, what):
    """A ball whose upper end is the largest upper end of the finite ``balls`` (every one checked finite)."""
    return arb(max(finite(x, what).upper() for x in balls))


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
