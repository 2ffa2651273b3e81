"""Deciding that a list of derived expressions vanishes identically, exactly or by randomised testing.

Exact: every entry's canonical form (:meth:`canonical` of its calculus) is the
zero polynomial; for the chains this is the normal form modulo
sin^2 + cos^2 = 1, for the abstract system ``expand`` over independent atoms.

Randomised (Schwartz-Zippel): an entry P not in the ideal gives a nonzero
polynomial Q(t, x) = prod_k (1 + t_k^2)^{d_k} P(c(t), s(t), x) with
c = (1 - t^2)/(1 + t^2), s = 2t/(1 + t^2) (rational points on the unit circle,
so sin and cos stay exact) of total degree at most D (``degree_bound``). With
every coordinate drawn uniformly from a set S of integers, one point misses a
nonzero Q with probability at most D/|S|; K independent points at most
(D/|S|)^K. That bound is stated as the error probability.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from fractions import Fraction

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

    if hasattr(calc, "point_roles"):
        return {key: point_value({"salt": salt}, key) for key in calc.point_roles()}
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


def random_point(calc, rng, entries):
    """Every coordinate uniform in [-2^31, 2^31)."""
    half = 2 ** (SAMPLE_BITS - 1)
    if hasattr(calc, "point_roles"):
        keys = calc.point_roles()
    else:
        keys = sorted({calc.atom_key(a) for e in entries for a in _atoms(calc, e)}, key=repr)
    return {key: int(rng.integers(-half, half)) for key in keys}


def _atoms(calc, e):
    import sympy as sp

    e = sp.sympify(e)
    return (e.atoms(sp.Derivative) | e.atoms(sp.core.function.AppliedUndef)
            | {x for x in e.free_symbols if x in calc.symbol_roles})


def decide_randomised(calc, entries, rng, points=2):
    """Evaluate every entry at ``points`` random integer points; the bound (D/2^32)^points is the error probability."""
    start = time.perf_counter()
    degree = max((calc.degree_bound(e) for e in entries), default=0)
    nonzero, found = [], None
    for _ in range(points):
        point = random_point(calc, rng, entries)
        for i, e in enumerate(entries):
            value = calc.evaluate(e, point)
            if value != 0 and i not in nonzero:
                nonzero.append(i)
                found = found or {"entry": i, "point": point, "value": value}
    per_point = min(Fraction(degree, 2**SAMPLE_BITS), Fraction(1))
    return Decision(not nonzero, "randomised", len(entries), sorted(nonzero), 0, points, degree,
                    per_point**points if not nonzero else Fraction(0), found, time.perf_counter() - start)


def point_json(point):
    """A point as JSON-ready rows [key..., "p/q"] (keys are tuples of roles and indices)."""
    return [[_plain_key(k), str(v)] for k, v in point.items()]


def point_from_json(rows):
    return {_tuple_key(k): (Fraction(v) if not isinstance(k, str) else int(v)) for k, v in rows}


def _plain_key(k):
    return [_plain_key(x) for x in k] if isinstance(k, tuple) else k


def _tuple_key(k):
    return tuple(_tuple_key(x) for x in k) if isinstance(k, list) else k
