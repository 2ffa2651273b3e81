"""Phi on and next to the boundary of Theorem 1, with exactly representable values.

Point masses at integer points of a line or of a plane in general position
have integer Phi, exact in floats: f >= 0 singular (a point, line or planar
mass). ``near_boundary_phi`` moves one entry of such a Phi by a few ulps, so
only exact arithmetic can tell on which side it lies. ``shifted_com_phi``
moves the centre of mass of a consistent body without moving its mass.
``principal_inertia`` draws I_CoM = R diag(lambda) R^T with dyadic lambda (including triangle
equalities lambda_3 = lambda_1 + lambda_2) and a rational rotation R.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
from hypothesis import strategies as st
from inertiaproof.counterexamples.inertias import consistent_phi

from inertiaproof.model.degenerate import point_masses
from inertiaproof.model.density import rotation

__all__ = ["boundary_phi", "near_boundary_phi", "principal_inertia", "rational_rotation", "shifted_com_phi", "SMALL"]

SMALL = st.integers(-6, 6)


@st.composite
def boundary_phi(draw, dimension=None):
    """Integer Phi of 1-4 point masses on a point, line or plane (dimension 0, 1, 2), times a power of two."""
    dim = draw(st.integers(0, 2)) if dimension is None else dimension
    origin = np.array([draw(SMALL) for _ in range(3)])
    spans = [np.array([draw(SMALL) for _ in range(3)]) for _ in range(dim)]
    count = draw(st.integers(1, 4))
    points = np.array([origin + sum(draw(SMALL) * s for s in spans) for _ in range(count)] if spans else
                      [origin] * count)
    masses = np.array([draw(st.integers(1, 5)) for _ in range(count)])
    m, h, sigma = point_masses(masses, points)
    inertia = np.trace(sigma) * np.eye(3) - sigma
    phi = np.array([m, *h, inertia[0, 0], inertia[1, 1], inertia[2, 2], inertia[0, 1], inertia[1, 2], inertia[0, 2]],
                   dtype=float)
    return phi * 2.0 ** draw(st.integers(-20, 20))


@st.composite
def near_boundary_phi(draw):
    """A boundary Phi with one entry moved by 1-4 ulps up or down."""
    phi = draw(boundary_phi())
    k = draw(st.integers(0, 9))
    direction = draw(st.sampled_from([-np.inf, np.inf]))
    for _ in range(draw(st.integers(1, 4))):
        phi[k] = np.nextafter(phi[k], direction)
    return phi


@st.composite
def shifted_com_phi(draw):
    """A consistent Phi with h scaled by a factor in [0, 3] and I kept: the centre of mass moved without the mass.

    Sigma_CoM = Sigma - k^2 h h^T / m crosses the boundary as k grows: consistent for small k, inconsistent beyond.
    """
    phi = draw(consistent_phi(thinness=3)).copy()
    phi[1:4] *= draw(st.floats(0.0, 3.0))
    return phi


@st.composite
def rational_rotation(draw):
    """R(q) for a small integer quaternion q: rational and exactly orthogonal (as Fractions)."""
    q = [draw(st.integers(-4, 4)) for _ in range(4)]
    if not any(q):
        q = [1, 0, 0, 0]
    return rotation(np.array([Fraction(x) for x in q], dtype=object))


@st.composite
def principal_inertia(draw):
    """(lambda as Fractions, R): principal moments that are ordinary, on a triangle equality, or an ulp from one."""
    a = draw(st.integers(0, 2**20)) * Fraction(1, 2**10)
    b = draw(st.integers(0, 2**20)) * Fraction(1, 2**10)
    kind = draw(st.sampled_from(["equality", "near", "ordinary", "rod", "point"]))
    if kind == "equality":
        c = a + b
    elif kind == "near":
        c = a + b + draw(st.sampled_from([-1, 1])) * Fraction(1, 2**40)
    elif kind == "rod":
        a, c = Fraction(0), b
    elif kind == "point":
        a = b = c = Fraction(0)
    else:
        c = draw(st.integers(0, 2**21)) * Fraction(1, 2**10)
    lam = [a, b, c]
    order = draw(st.permutations([0, 1, 2]))
    return [lam[i] for i in order], draw(rational_rotation())
