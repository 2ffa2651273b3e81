"""Numbers of a certificate, read strictly: exact rationals written as "p/q" or decimals ("0.1" is 1/10), JSON
without duplicate keys, NaN, Infinity or floats, and balls that are finite before they are compared."""

import json
import re
from fractions import Fraction

from flint import arb, fmpq, fmpq_mat

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


def _refuse(why):
    return lambda text: need(False, why.format(text))


def read_json(text, floats=False):
    """The JSON document ``text``, read strictly: a duplicate key, NaN or Infinity, or (unless ``floats``) a JSON
    float is a :class:`BadCertificate`; so is trailing data (``json.loads``)."""
    strict = {} if floats else {"parse_float": _refuse("the JSON number {}: exact numbers are written as strings")}
    try:
        return json.loads(text, object_pairs_hook=_pairs, parse_constant=_refuse("{} is not a number"), **strict)
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


def rationals(xs, shape, where):
    """The exact rationals of the nested lists ``xs`` of ``shape`` (lengths, outermost first)."""
    if not shape:
        return rational(xs, where)
    what = f"{shape[0]} numbers" if len(shape) == 1 else f"a {'x'.join(map(str, shape))} array of numbers"
    need(isinstance(xs, list) and len(xs) == shape[0], f"{where}: {what}")
    return [rationals(x, shape[1:], f"{where}[{i}]") for i, x in enumerate(xs)]


def vector(xs, n, where):
    """The ``n`` exact rationals of the list ``xs``."""
    return rationals(xs, (n,), where)


def symmetric(rows, n, where):
    """The exact rationals of the symmetric ``n`` x ``n`` matrix ``rows``."""
    m = rationals(rows, (n, n), where)
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


def semidefinite(rows, sign=1, shift=0):
    """Whether sign F + shift I >= 0 for the symmetric n x n matrix F of exact rationals (``rows``), decided exactly:
    its eigenvalues t_i are real, and all are >= 0 iff q(s) = (-1)^n p(-s) = prod_i (s + t_i), p its characteristic
    polynomial, has no negative coefficient (if all t_i >= 0, the product has none; if none, q(s) >= s^n > 0 for
    s > 0, so no -t_i > 0 is a root)."""
    n = len(rows)
    a = fmpq_mat(n, n, [sign * fmpq(x.numerator, x.denominator) + (shift if i == j else 0)
                        for i, row in enumerate(rows) for j, x in enumerate(row)])
    return all((-1) ** (n - k) * c >= 0 for k, c in enumerate(a.charpoly().coeffs()))
