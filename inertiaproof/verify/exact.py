"""Numbers of a certificate, read strictly: exact rationals written as "p/q" or decimals ("0.1" is 1/10), JSON
without duplicate keys, NaN, Infinity or floats, and balls that are finite before they are compared."""

import json
import re
from fractions import Fraction

from flint import arb, fmpq

DIGITS = 2000  # the longest number a certificate may write (characters): exact arithmetic on it stays bounded
NUMBER = re.compile(r"[-+]?(\d+(\.\d*)?|\.\d+)([eE][-+]?\d{1,4})?(/\d+)?")


class BadCertificate(ValueError):
    """The certificate is malformed: its message names the field."""


def need(holds, why):
    """Nothing where ``holds``, else :class:`BadCertificate` ``why``."""
    if not holds:
        raise BadCertificate(why)


def known(cert, keys):
    """Nothing, or :class:`BadCertificate` for a field of ``cert`` beyond ``keys``."""
    need(set(cert) <= set(keys), f"unknown field(s) {sorted(set(cert) - set(keys))}")


def fields(obj, keys, where, optional=()):
    """``obj``, an object with every field of ``keys`` and none beyond them and ``optional``."""
    need(isinstance(obj, dict) and set(keys) <= set(obj) <= set(keys) | set(optional),
         f"{where}: the fields {sorted(keys)}" + (f" (and {sorted(optional)})" if optional else ""))
    return obj


def _pairs(pairs):
    seen = {}
    for key, value in pairs:
        need(key not in seen, f"duplicate key {key!r}: a certificate says one thing once")
        seen[key] = value
    return seen


def read_json(text, floats=False):
    """The JSON document ``text``, read strictly: a duplicate key, NaN or Infinity, or (unless ``floats``) a JSON
    float is a :class:`BadCertificate`; so is trailing data (``json.loads``)."""
    try:
        return json.loads(text, object_pairs_hook=_pairs, parse_constant=lambda t: need(
            False, f"{t} is not a number a certificate may hold"), **({} if floats else {"parse_float": lambda t: need(
                False, f"the JSON number {t}: exact numbers are written as strings (\"p/q\" or a decimal)")}))
    except json.JSONDecodeError as exc:
        raise BadCertificate(f"not JSON: {exc}") from None


def rational(text, where):
    """The exact rational a certificate writes as ``text`` (a string: "p/q", an integer or a decimal)."""
    need(isinstance(text, str) and len(text) <= DIGITS and NUMBER.fullmatch(text), f"{where}: numbers are written "
         f"as strings (\"p/q\" or a decimal) of at most {DIGITS} characters, not {str(text)[:40]!r}")
    try:
        value = Fraction(text)
    except (ValueError, ZeroDivisionError):
        raise BadCertificate(f"{where}: {text!r} is not a rational number") from None
    return fmpq(value.numerator, value.denominator)


def rational_matrix(rows, shape, where):
    """The exact rationals of a certificate's ``shape`` matrix ``rows`` (lists of numbers)."""
    need(isinstance(rows, list) and len(rows) == shape[0] and all(isinstance(r, list) and len(r) == shape[1]
                                                                  for r in rows),
         f"{where}: expected a {shape[0]}x{shape[1]} list of numbers")
    return [[rational(x, f"{where}[{i}][{j}]") for j, x in enumerate(r)] for i, r in enumerate(rows)]


def vector(xs, n, where):
    """The ``n`` exact rationals of the list ``xs``."""
    return rational_matrix([xs], (1, n), where)[0]


def symmetric(rows, n, where):
    """The exact rationals of the symmetric ``n`` x ``n`` matrix ``rows``."""
    m = rational_matrix(rows, (n, n), where)
    need(all(m[i][j] == m[j][i] for i in range(n) for j in range(i)), f"{where}: not symmetric")
    return m


def dyadic(x):
    """The exact rational of a float or of an exact ball (a ball's end)."""
    man, exp = (x if isinstance(x, arb) else arb(x)).mid().man_exp()
    return fmpq(int(man)) * fmpq(2) ** int(exp)


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


def unproved_pivot(rows):
    """The first pivot of the LDL^T of the symmetric matrix of balls ``rows`` (its lower triangle read) that is not
    a positive finite ball, or None: then every symmetric matrix in the balls is positive definite."""
    a = [list(r) for r in rows]
    for k in range(len(a)):
        if not (a[k][k].is_finite() and a[k][k] > 0):
            return k
        for i in range(k + 1, len(a)):
            f = a[i][k] / a[k][k]
            for j in range(k + 1, i + 1):
                a[i][j] -= f * a[j][k]
    return None


def above(rows, sign, shift):
    """Whether sign F + shift I >= 0 for the symmetric matrix of exact rationals F (``rows``), decided exactly."""
    return semidefinite([[sign * x + (shift if i == j else 0) for j, x in enumerate(r)] for i, r in enumerate(rows)])


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
