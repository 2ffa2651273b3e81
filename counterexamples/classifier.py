"""Rows of Phi on both sides of the boundary of Theorem 1 and on it, over magnitudes 1e-150 to 1e150.

Families (each row is 10 floats in the paper's order, times 2^k for k in +-MAGNITUDE_BITS):

- ``by_delta``: Sigma_CoM = R diag(s1, s2, s3) R^T with s1 = side * delta * max(s2, s3), delta from
  1e-15 to 1e-3, a random rotation R and a centre of mass within two radii: relatively inconsistent
  (side -1) or consistent (side +1) by delta before rounding;
- ``degenerate``: point masses at dyadic points of a point, a line or a plane in a random direction
  (small numerators, so every entry of Phi is exact in floats): exactly on the boundary;
- ``off_degenerate``: such a row with one entry moved by 1 to 4 ulps;
- ``nonpositive_mass``: a consistent row with its mass set to 0 or made negative.

The side a row was built for is a label only: rounding can move a row by about eps, so only an exact
decision on its float values says where it lies. ``sweep`` draws every family, every decade of delta and
magnitudes across the whole range from a NumPy generator (a batched, systematic attack);
``boundary_rows`` draws them with Hypothesis (a hunt).
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
from hypothesis import strategies as st

__all__ = [
    "boundary_rows", "by_delta", "DELTAS", "degenerate", "KINDS", "MAGNITUDE_BITS", "nonpositive_mass",
    "off_degenerate", "sweep",
]

MAGNITUDE_BITS = 498  # 2^498 is about 1e150
DELTAS = tuple(10.0 ** -e for e in range(15, 2, -1))  # 1e-15 .. 1e-3
KINDS = {"point": 0, "line": 1, "plane": 2}


def _rotation(quaternion):
    """The rotation of a quaternion (the identity for one of length below 1e-6)."""
    norm = np.linalg.norm(quaternion)
    w, x, y, z = np.asarray(quaternion, float) / norm if norm > 1e-6 else (1.0, 0.0, 0.0, 0.0)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def _pack(m, h, sigma):
    inertia = np.trace(sigma) * np.eye(3) - sigma
    return np.array([m, *h, inertia[0, 0], inertia[1, 1], inertia[2, 2], inertia[0, 1], inertia[1, 2], inertia[0, 2]])


def by_delta(delta, side, mass, radius, spread, quaternion, com, magnitude):
    """Phi with Sigma_CoM's smallest principal value side * delta of its largest, before rounding.

    ``spread`` (two numbers in [0, 1]) sets s2, s3 = m radius^2 10^(-3 spread); ``com`` (3 numbers in [-1, 1])
    the centre of mass in units of 2 radius; the row is scaled by 2^magnitude."""
    s = mass * radius**2 * 10.0 ** (-3 * np.asarray(spread, float))
    rot = _rotation(quaternion)
    sigma_com = rot @ np.diag([side * delta * s.max(), *s]) @ rot.T
    c = 2 * radius * np.asarray(com, float)
    return np.ldexp(_pack(mass, mass * c, sigma_com + mass * np.outer(c, c)), magnitude)


def degenerate(kind, origin, directions, weights, masses, magnitude):
    """Phi of point masses at origin + a d1 + b d2 (dyadic), on a point, line or plane: exact in floats.

    ``origin`` and ``directions`` (two vectors) hold integers in [-2^10, 2^10] (units of 2^-10), ``weights``
    rows of two integers in [-8, 8] (units of 1/4), ``masses`` integers in [1, 8]."""
    spans = [np.array([Fraction(int(x), 2**10) for x in d], dtype=object) for d in directions][:KINDS[kind]]
    o = np.array([Fraction(int(x), 2**10) for x in origin], dtype=object)
    points = [o + sum((Fraction(int(w), 4) * d for w, d in zip(ws, spans)), np.zeros(3, dtype=object))
              for ws in weights]
    m = sum(Fraction(int(x)) for x in masses)
    h = sum((Fraction(int(x)) * p for x, p in zip(masses, points)), np.zeros(3, dtype=object))
    sigma = sum((Fraction(int(x)) * np.outer(p, p) for x, p in zip(masses, points)), np.zeros((3, 3), dtype=object))
    exact = _pack(m, h, sigma)
    row = np.array([float(x) for x in exact])
    if any(Fraction(float(x)) != x for x in exact):
        raise ValueError("a degenerate row is not exact in floats")  # cannot happen at these sizes
    return np.ldexp(row, magnitude)


def off_degenerate(row, entry, ulps):
    """``row`` with ``entry`` moved by ``ulps`` (nonzero, up to +-4) units in the last place."""
    out = np.array(row, float)
    for _ in range(abs(ulps)):
        out[entry] = np.nextafter(out[entry], np.inf if ulps > 0 else -np.inf)
    return out


def nonpositive_mass(row, mass):
    """A row with its mass replaced by ``mass`` <= 0."""
    out = np.array(row, float)
    out[0] = mass
    return out


# -- Hypothesis ---------------------------------------------------------------------------------------

_unit = st.floats(-1.0, 1.0, allow_nan=False)
_magnitude = st.integers(-MAGNITUDE_BITS, MAGNITUDE_BITS)


@st.composite
def _by_delta(draw):
    delta = 10.0 ** draw(st.floats(-15.0, -3.0))
    side = draw(st.sampled_from([-1, 1]))
    row = by_delta(delta, side, np.ldexp(1.0 + draw(st.floats(0, 1)), draw(st.integers(-20, 20))),
                   np.ldexp(1.0, draw(st.integers(-20, 20))), [draw(st.floats(0, 1)) for _ in range(2)],
                   [draw(_unit) for _ in range(4)] if draw(st.booleans()) else [1, 0, 0, 0],
                   [draw(_unit) for _ in range(3)], draw(_magnitude))
    return row, {"family": "by_delta", "side": side, "delta": delta}


@st.composite
def _degenerate(draw):
    kind = draw(st.sampled_from(sorted(KINDS)))
    coordinate = st.integers(-2**10, 2**10)
    count = draw(st.integers(1, 4))
    row = degenerate(kind, [draw(coordinate) for _ in range(3)], [[draw(coordinate) for _ in range(3)]
                                                                  for _ in range(2)],
                     [[draw(st.integers(-8, 8)) for _ in range(2)] for _ in range(count)],
                     [draw(st.integers(1, 8)) for _ in range(count)], draw(_magnitude))
    return row, {"family": "degenerate", "kind": kind}


@st.composite
def boundary_rows(draw):
    """(row, description): one of the families, drawn with Hypothesis."""
    family = draw(st.sampled_from(["by_delta", "degenerate", "off_degenerate", "nonpositive_mass"]))
    if family == "by_delta":
        return draw(_by_delta())
    row, about = draw(_degenerate())
    if family == "degenerate":
        return row, about
    if family == "off_degenerate":
        entry, ulps = draw(st.integers(0, 9)), draw(st.sampled_from([-4, -3, -2, -1, 1, 2, 3, 4]))
        return off_degenerate(row, entry, ulps), {**about, "family": family, "entry": entry, "ulps": ulps}
    mass = -abs(row[0]) * draw(st.sampled_from([0.0, 1e-300, 1e-16, 1.0]))
    return nonpositive_mass(row, mass), {**about, "family": family}


# -- a systematic sweep -------------------------------------------------------------------------------

def sweep(rng, repeats=2, magnitudes=(-MAGNITUDE_BITS, -332, -166, 0, 166, 332, MAGNITUDE_BITS)):
    """(rows (K, 10), descriptions): every decade of delta on both sides, every degenerate kind and its ulp
    moves, at each magnitude 2^k (1e-150, 1e-100, 1e-50, 1, 1e50, 1e100, 1e150), ``repeats`` times each."""
    rows, about = [], []
    for k in magnitudes:
        for _ in range(repeats):
            for delta in DELTAS:
                for side in (-1, 1):
                    rows.append(by_delta(delta, side, np.ldexp(1.0 + rng.random(), int(rng.integers(-20, 21))),
                                         np.ldexp(1.0, int(rng.integers(-20, 21))), rng.random(2),
                                         rng.normal(size=4), rng.uniform(-1, 1, 3), k))
                    about.append({"family": "by_delta", "side": side, "delta": delta, "magnitude": k})
            for kind in KINDS:
                count = int(rng.integers(1, 5))
                row = degenerate(kind, rng.integers(-2**10, 2**10 + 1, 3), rng.integers(-2**10, 2**10 + 1, (2, 3)),
                                 rng.integers(-8, 9, (count, 2)), rng.integers(1, 9, count), k)
                rows.append(row)
                about.append({"family": "degenerate", "kind": kind, "magnitude": k})
                entry, ulps = int(rng.integers(0, 10)), int(rng.choice([-2, -1, 1, 2]))
                rows.append(off_degenerate(row, entry, ulps))
                about.append({"family": "off_degenerate", "kind": kind, "entry": entry, "ulps": ulps, "magnitude": k})
            rows.append(nonpositive_mass(rows[-2], -abs(rows[-2][0]) * float(rng.choice([0.0, 1e-16]))))
            about.append({"family": "nonpositive_mass", "magnitude": k})
    return np.array(rows), about
