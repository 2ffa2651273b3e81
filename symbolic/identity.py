"""Deciding that a list of derived expressions vanishes identically, exactly or by randomised testing.

Exact: every entry's canonical form (:meth:`canonical` of its calculus) is the
zero polynomial; for the chains this is the normal form modulo
sin^2 + cos^2 = 1, for the abstract system ``expand`` over independent atoms.

Randomised (Schwartz-Zippel): an entry P not in the ideal gives a nonzero
polynomial Q(t, x) = prod_k (1 + t_k^2)^{d_k} P(c(t), s(t), x) with
c = (1 - t^2)/(1 + t^2), s = 2t/(1 + t^2) (rational points on the unit circle,
so sin and cos stay exact) of total degree at most D (:func:`degree_bound`). With
every coordinate drawn uniformly from a set S of integers, one point misses a
nonzero Q with probability at most D/|S|; K independent points at most
(D/|S|)^K. That bound is stated as the error probability.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass, field
from fractions import Fraction

__all__ = [
    "decide_exact", "decide_randomised", "Decision", "degree_bound", "EvaluatedDerivation", "fixed_point",
    "leaves", "point_from_json", "point_json", "PointCalculus", "random_point", "SAMPLE_BITS", "witness",
]

SAMPLE_BITS = 32  # coordinates drawn from [-2^31, 2^31): |S| = 2^32


@dataclass
class Decision:
    holds: bool
    method: str  # "exact" or "randomised"
    entries: int
    nonzero: list = field(default_factory=list)  # indices of entries that do not vanish
    terms: int = 0  # terms of the canonical forms (exact) or of the evaluated polynomials
    points: int = 0
    degree: int = 0
    error_probability: Fraction = Fraction(0)
    witness: dict | None = None  # {"entry", "point", "value"}: a rational point where an entry is not 0
    seconds: float = 0.0


def fixed_point(calc, salt):
    """A deterministic rational point (values derived from sha256, independent of PYTHONHASHSEED)."""
    from inertiaproof.symbolic.functions_of_time import point_value

    if hasattr(calc, "ring"):
        return {key: point_value({"salt": salt}, key) for key in calc.point_keys()}
    return {"salt": salt}


def witness(calc, entries, index, tries=12):
    """A rational point where entries[index] is not 0 (for a nonzero canonical form one exists; small points first)."""
    for salt in range(tries):
        point = fixed_point(calc, salt)
        value = calc.evaluate(entries[index], point)
        if value != 0:
            return {"entry": index, "point": point, "value": value}
    return None


def decide_exact(calc, entries):
    start = time.perf_counter()
    forms = [calc.canonical(e) for e in entries]
    nonzero = [i for i, f in enumerate(forms) if f != 0]
    terms = sum(calc.size(f) for f in forms)
    found = witness(calc, forms, nonzero[0]) if nonzero else None
    return Decision(not nonzero, "exact", len(entries), nonzero, terms, witness=found,
                    seconds=time.perf_counter() - start)


class PointCalculus:
    """The calculus attributes a claim's formula reads, as exact numbers at one point."""

    def __init__(self, calc, value):
        self.n, self.zero, self.one = calc.n, Fraction(0), Fraction(1)
        for name in ("q_dot", "q_ddot", "theta", "theta_dot", "psi", "psi_dot"):
            setattr(self, name, tuple(value(x) for x in getattr(calc, name)))

    def free_roles(self, x):
        return set()


class EvaluatedDerivation:
    """A derivation whose objects are evaluated at a point on first use; ``read`` keeps what was evaluated."""

    def __init__(self, d, point):
        self._d, self._point, self.read, self._memo = d, point, [], {}
        self.calc = PointCalculus(d.calc, self._value)
        self.system = _Namespace(v=tuple(map(self._value, d.system.v)), a=tuple(map(self._value, d.system.a)),
                                 block=d.system.block)

    def _value(self, leaf):
        self.read.append(leaf)
        return self._d.calc.evaluate(leaf, self._point, self._memo)

    def _map(self, obj):
        if dataclasses.is_dataclass(obj):
            return type(obj)(**{f.name: self._map(getattr(obj, f.name)) for f in dataclasses.fields(obj)})
        if isinstance(obj, (tuple, list)):
            return tuple(self._map(x) for x in obj)
        return self._value(obj)

    def __getattr__(self, name):
        if name.startswith("_"):
            raise AttributeError(name)
        value = self._map(getattr(self._d, name))
        setattr(self, name, value)
        return value


class _Namespace:
    def __init__(self, **kw):
        self.__dict__.update(kw)


def random_point(calc, rng, keys):
    """Every coordinate uniform in [-2^31, 2^31)."""
    half = 2 ** (SAMPLE_BITS - 1)
    return {key: int(rng.integers(-half, half)) for key in keys}


def degree_bound(calc, leaves, extra=1):
    """D for the residual of a claim: its entries are sums of derived objects times at most ``extra`` coordinates.

    With d_k the largest degree in (c_k, s_k) and r the largest degree in the
    other coordinates over the objects read, Q(t, x) has total degree at most
    2 sum_k d_k + r + extra.
    """
    trig, rest = {}, 0
    for leaf in leaves:
        t, r = calc.degree_profile(leaf)
        rest = max(rest, r)
        for k, e in t.items():
            trig[k] = max(trig.get(k, 0), e)
    return 2 * sum(trig.values()) + rest + extra


def decide_randomised(formula, d, rng, points=2):
    """Evaluate the derived objects at random points and the claim's formula on those numbers.

    ``formula(derivation)`` returns the entries that must vanish; run on an
    :class:`EvaluatedDerivation` it combines exact values, so no polynomial is
    expanded or reduced. The bound (D/2^32)^points is the error probability.
    """
    start = time.perf_counter()
    calc = d.calc
    keys = _point_keys(d)
    nonzero, found, read, count = [], None, [], 0
    for _ in range(points):
        point = random_point(calc, rng, keys)
        at = EvaluatedDerivation(d, point)
        values = formula(at)
        count = len(values)
        read = at.read
        for i, value in enumerate(values):
            if value != 0 and i not in nonzero:
                nonzero.append(i)
                found = found or {"entry": i, "point": point, "value": value}
    degree = degree_bound(calc, read)
    per_point = min(Fraction(degree, 2**SAMPLE_BITS), Fraction(1))
    return Decision(not nonzero, "randomised", count, sorted(nonzero), 0, points, degree,
                    per_point**points if not nonzero else Fraction(0), found, time.perf_counter() - start)


def leaves(obj):
    if dataclasses.is_dataclass(obj):
        return [x for f in dataclasses.fields(obj) for x in leaves(getattr(obj, f.name))]
    if isinstance(obj, (tuple, list)):
        return [x for item in obj for x in leaves(item)]
    return [obj]


def _point_keys(d):
    """The coordinates of a derivation's objects (once per derivation)."""
    if hasattr(d.calc, "ring"):
        return d.calc.point_keys()  # a jet ring's points give every coordinate
    cached = _KEYS.get(id(d))
    if cached is None or cached[0] is not d:
        cached = _KEYS[id(d)] = (d, d.calc.point_keys(leaves((d.euler_lagrange, d.equation, d.F, d.N, d.regressors.R, d.regressors.R_M_velocity, d.system.v,
                   d.system.a, d.calc.q_dot, d.calc.q_ddot, d.calc.theta, d.calc.theta_dot, d.calc.psi_dot))))
    return cached[1]


_KEYS: dict = {}


def point_json(point):
    """A point as JSON-ready rows [key..., "p/q"] (keys are tuples of roles and indices)."""
    return [[_plain_key(k), str(v)] for k, v in point.items()]


def point_from_json(rows):
    return {_tuple_key(k): (Fraction(v) if not isinstance(k, str) else int(v)) for k, v in rows}


def _plain_key(k):
    return [_plain_key(x) for x in k] if isinstance(k, tuple) else k


def _tuple_key(k):
    return tuple(_tuple_key(x) for x in k) if isinstance(k, list) else k
