"""Random payloads of a payload set (:class:`inertiaproof.bounds.payload.Ball`): realisable mass distributions.

A payload is a sum of up to four parts whose masses add up to at most the set's: point masses anywhere in the
ball, uniform spheres and turned boxes lying wholly inside it (their Phi are moments of nonnegative densities in
the ball, Theorem 1). ``beyond`` draws from a larger set: heavier, or reaching out of the ball, so the attacks can
show that the set matters.
"""

from __future__ import annotations

import numpy as np
from hypothesis import strategies as st

from inertiaproof.model import solids
from inertiaproof.model.inertia import point_mass

from .inertias import rotations

__all__ = ["payloads", "points_in_ball"]

SHAPES = ("point", "sphere", "box")


def _unit(draw):
    v = np.array([draw(st.floats(-1, 1, allow_nan=False)) for _ in range(3)])
    n = np.linalg.norm(v)
    return v / n if n > 1e-6 else np.array([1.0, 0, 0])


@st.composite
def points_in_ball(draw, centre, radius):
    """A point of the ball, often on its sphere (where the extremes are)."""
    reach = draw(st.one_of(st.just(1.0), st.floats(0, 1, allow_nan=False)))
    return np.asarray(centre, float) + radius * reach * _unit(draw)


@st.composite
def _part(draw, mass, centre, radius):
    shape = draw(st.sampled_from(SHAPES))
    if shape == "point" or radius == 0:
        return point_mass(mass, draw(points_in_ball(centre, radius)))
    size = radius * draw(st.floats(0.01, 1, allow_nan=False))  # the part's own radius (a box: half its diagonal)
    where = draw(points_in_ball(centre, radius - size))
    if shape == "sphere":
        return solids.solid("sphere", mass, (size,), None, where)
    edges = np.array([draw(st.floats(0.05, 1, allow_nan=False)) for _ in range(3)])
    edges *= 2 * size / np.linalg.norm(edges)
    return solids.solid("box", mass, tuple(edges), draw(rotations()), where)


@st.composite
def payloads(draw, mass, centre, radius):
    """Phi (10,) of a payload of mass at most ``mass`` in the ball (``centre`` (3,), ``radius``), and its parts' count."""
    if mass == 0:
        return np.zeros(10)
    weights = np.array([draw(st.floats(0.05, 1, allow_nan=False)) for _ in range(draw(st.integers(1, 4)))])
    total = mass * draw(st.one_of(st.just(1.0), st.floats(0.01, 1, allow_nan=False)))
    return sum(draw(_part(total * w / weights.sum(), centre, radius)) for w in weights)
