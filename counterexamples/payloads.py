"""Random payloads of a payload set (:class:`inertiaproof.bounds.payload.PayloadSet`): realisable mass distributions.

A payload is a sum of up to four parts whose masses add up to at most the set's: point masses anywhere in the
ellipsoid, uniform spheres and turned boxes lying wholly inside it (their Phi are moments of nonnegative densities
in the ellipsoid, Theorem 1).
"""

from __future__ import annotations

import numpy as np
from hypothesis import strategies as st

from inertiaproof.model import solids
from inertiaproof.model.inertia import point_mass

from .inertias import rotations

__all__ = ["payloads", "points_in"]

SHAPES = ("point", "sphere", "box")


def _unit(draw):
    v = np.array([draw(st.floats(-1, 1, allow_nan=False)) for _ in range(3)])
    n = np.linalg.norm(v)
    return v / n if n > 1e-6 else np.array([1.0, 0, 0])


@st.composite
def points_in(draw, centre, semi_axes):
    """A point of the ellipsoid (``semi_axes`` (3,) along the frame's axes), often on its boundary (where the
    extremes are)."""
    reach = draw(st.one_of(st.just(1.0), st.floats(0, 1, allow_nan=False)))
    return np.asarray(centre, float) + np.asarray(semi_axes, float) * reach * _unit(draw)


@st.composite
def _part(draw, mass, centre, semi_axes):
    shape = draw(st.sampled_from(SHAPES))
    smallest = float(np.min(semi_axes))
    if shape == "point" or smallest == 0:
        return point_mass(mass, draw(points_in(centre, semi_axes)))
    size = smallest * draw(st.floats(0.01, 1, allow_nan=False))  # the part's own radius (a box: half its diagonal)
    # |(x + s u - c) / a| <= |(x - c) / a| + s / min(a) <= 1 for x in the ellipsoid shrunk by 1 - s / min(a)
    where = draw(points_in(centre, np.asarray(semi_axes, float) * (1 - size / smallest)))
    if shape == "sphere":
        return solids.solid("sphere", mass, (size,), None, where)
    edges = np.array([draw(st.floats(0.05, 1, allow_nan=False)) for _ in range(3)])
    edges *= 2 * size / np.linalg.norm(edges)
    return solids.solid("box", mass, tuple(edges), draw(rotations()), where)


@st.composite
def payloads(draw, mass, centre, semi_axes):
    """Phi (10,) of a payload of mass at most ``mass`` in the ellipsoid (``centre`` (3,), ``semi_axes`` (3,))."""
    if mass == 0:
        return np.zeros(10)
    weights = np.array([draw(st.floats(0.05, 1, allow_nan=False)) for _ in range(draw(st.integers(1, 4)))])
    total = mass * draw(st.one_of(st.just(1.0), st.floats(0.01, 1, allow_nan=False)))
    return sum(draw(_part(total * w / weights.sum(), centre, semi_axes)) for w in weights)
