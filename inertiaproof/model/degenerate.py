"""Point, line and planar mass distributions: the bodies Definition 1 leaves out (Thm1-boundary).

Each returns (m, h, Sigma) with Sigma = int x x^T dmu for a measure mu
carried by a point, a segment or a plane; exact for exact (Fraction) inputs.
Since f(Phi) = int [x; 1] [x; 1]^T dmu, the rank of f is at most one more
than the dimension of the carrier: f >= 0 is singular.
"""

from __future__ import annotations

import numpy as np

__all__ = ["DIMENSION", "parallelogram_lamina", "point_masses", "rod", "triangle_lamina"]

DIMENSION = {"point": 0, "line": 1, "plane": 2}


def _vectors(*xs):
    return [np.asarray(x) if np.asarray(x).dtype == object else np.asarray(x, dtype=float) for x in xs]


def point_masses(masses, points):
    """Masses m_i at points p_i: (sum m_i, sum m_i p_i, sum m_i p_i p_i^T)."""
    masses, points = _vectors(masses, points)
    return masses.sum(), masses @ points, np.einsum("i,ij,ik->jk", masses, points, points)


def rod(mass, start, end):
    """A uniform segment from ``start`` to ``end``: int_0^1 x(s) x(s)^T ds with x = a + s d."""
    a, end = _vectors(start, end)
    d = end - a
    cross = np.outer(a, d)
    return mass, mass * (a + d / 2), mass * (np.outer(a, a) + (cross + cross.T) / 2 + np.outer(d, d) / 3)


def triangle_lamina(mass, v0, v1, v2):
    """A uniform triangle: int x x^T dA / A = (sum v_i v_i^T + (sum v_i)(sum v_i)^T) / 12."""
    v = np.stack(_vectors(v0, v1, v2))
    total = v.sum(axis=0)
    return mass, mass * total / 3, mass * (v.T @ v + np.outer(total, total)) / 12


def parallelogram_lamina(mass, centre, u, v):
    """A uniform parallelogram c + s u + t v, s, t in [-1/2, 1/2]: Sigma = m (c c^T + (u u^T + v v^T) / 12)."""
    c, u, v = _vectors(centre, u, v)
    return mass, mass * c, mass * (np.outer(c, c) + (np.outer(u, u) + np.outer(v, v)) / 12)

