"""Uniform primitive solids and their exact moments (MassDistributionToInertialParam).

A solid of mass m has the density-weighted covariance
Sigma_c = int rho (x - c)(x - c)^T dx about its centre of mass c; in any pose
(R, p) the second moment about the frame origin is
Sigma = R Sigma_c R^T + m c' c'^T with c' = R c + p, and
Phi = (m, m c', I = tr(Sigma) I3 - Sigma) (Theorem 1, inverse map).
Moments are additive, so a union of disjoint solids or a nonnegative mixture
of densities has the sum of their Phi.

The moment formulas use integer constants only, so they evaluate on floats,
on ``fractions.Fraction`` (exact, for rational inputs) and on SymPy symbols
(EQ-moments compares them with SymPy's exact integration).
"""

from __future__ import annotations

import math

import numpy as np

from .inertia import inertia_from_sigma, pack

__all__ = [
    "contains", "covariance", "DIMS", "DIMS_MEANING", "moments", "phi_from_covariance", "SHAPES", "solid",
    "validate", "volume",
]

SHAPES = ("box", "ellipsoid", "sphere", "cylinder", "cone", "tetrahedron")
DIMS = {"box": 3, "ellipsoid": 3, "sphere": 1, "cylinder": 2, "cone": 2, "tetrahedron": 12}
DIMS_MEANING = {
    "box": "side lengths (a, b, c), centred",
    "ellipsoid": "semi-axes (a, b, c), centred",
    "sphere": "radius (r,), centred",
    "cylinder": "(radius, height) along z, centred",
    "cone": "(base radius, height) along z, base on z = 0, apex at z = height",
    "tetrahedron": "the four vertices, 12 numbers",
}


def _array(x):
    """Float array, or an object array when the entries are exact (Fraction, SymPy)."""
    a = np.asarray(x)
    return a if a.dtype == object else a.astype(float)


def validate(shape, dims):
    """The dimensions as an array, or ValueError naming what is wrong."""
    if shape not in DIMS:
        raise ValueError(f"unknown solid {shape!r}; one of {', '.join(SHAPES)}")
    dims = _array(dims).reshape(-1)
    if dims.size != DIMS[shape]:
        raise ValueError(f"{shape} needs {DIMS[shape]} dims ({DIMS_MEANING[shape]}), got {dims.size}")
    values = np.array([float(d) for d in dims])
    if not np.all(np.isfinite(values)):
        raise ValueError(f"{shape} dims must be finite, got {values.tolist()}")
    if shape != "tetrahedron" and not np.all(values > 0):
        raise ValueError(f"{shape} dims must be > 0, got {values.tolist()}")
    if shape == "tetrahedron" and not volume(shape, dims) > 0:
        raise ValueError("tetrahedron vertices are coplanar (volume 0): not a solid")
    return dims


def covariance(shape, mass, dims):
    """(Sigma_c, c) of a uniform solid in its own frame: covariance about the CoM and the CoM.

    dims as in :data:`DIMS_MEANING`. Exact for exact inputs.
    """
    dims = _array(dims).reshape(-1)
    zero = np.zeros(3, dtype=dims.dtype)
    if shape == "box":
        return mass * np.diag(dims**2) / 12, zero
    if shape == "ellipsoid":
        return mass * np.diag(dims**2) / 5, zero
    if shape == "sphere":
        r2 = dims[0] ** 2
        return mass * np.diag([r2, r2, r2]) / 5, zero
    if shape == "cylinder":
        r, h = dims
        return mass * np.diag([3 * r * r, 3 * r * r, h * h]) / 12, zero
    if shape == "cone":
        r, h = dims
        return mass * np.diag([12 * r * r, 12 * r * r, 3 * h * h]) / 80, np.array([0 * h, 0 * h, h / 4])
    if shape == "tetrahedron":
        v = dims.reshape(4, 3)
        total = v.sum(axis=0)
        second = (v.T @ v + np.outer(total, total)) / 20  # int x x^T dV / V
        c = total / 4
        return mass * (second - np.outer(c, c)), c
    raise ValueError(f"unknown solid {shape!r}; one of {', '.join(SHAPES)}")


def volume(shape, dims):
    """Volume (float) of the solid."""
    d = np.array([float(x) for x in np.asarray(dims).reshape(-1)])
    if shape == "box":
        return float(np.prod(d))
    if shape == "ellipsoid":
        return 4.0 / 3.0 * math.pi * float(np.prod(d))
    if shape == "sphere":
        return 4.0 / 3.0 * math.pi * d[0] ** 3
    if shape == "cylinder":
        return math.pi * d[0] ** 2 * d[1]
    if shape == "cone":
        return math.pi * d[0] ** 2 * d[1] / 3.0
    if shape == "tetrahedron":
        v = d.reshape(4, 3)
        return abs(float(np.linalg.det(v[1:] - v[0]))) / 6.0
    raise ValueError(f"unknown solid {shape!r}; one of {', '.join(SHAPES)}")


def contains(shape, dims, y):
    """Whether points y (..., 3), in the solid's own frame, lie in the closed solid."""
    d = np.array([float(x) for x in np.asarray(dims).reshape(-1)])
    y = np.asarray(y, dtype=float)
    x1, x2, x3 = y[..., 0], y[..., 1], y[..., 2]
    if shape == "box":
        return np.all(np.abs(y) <= d / 2, axis=-1)
    if shape in ("ellipsoid", "sphere"):
        axes = d if shape == "ellipsoid" else np.repeat(d, 3)
        return np.sum((y / axes) ** 2, axis=-1) <= 1.0
    if shape == "cylinder":
        return (x1 * x1 + x2 * x2 <= d[0] ** 2) & (np.abs(x3) <= d[1] / 2)
    if shape == "cone":
        radius = d[0] * (1.0 - x3 / d[1])
        return (x3 >= 0) & (x3 <= d[1]) & (x1 * x1 + x2 * x2 <= radius**2)
    if shape == "tetrahedron":
        v = d.reshape(4, 3)
        bary = np.linalg.solve((v[1:] - v[0]).T, (y - v[0]).reshape(-1, 3).T).T.reshape(y.shape)
        return np.all(bary >= 0, axis=-1) & (bary.sum(axis=-1) <= 1.0)
    raise ValueError(f"unknown solid {shape!r}; one of {', '.join(SHAPES)}")


def moments(shape, mass, dims, rotation=None, position=(0, 0, 0)):
    """(m, h, Sigma) about the frame origin, Sigma = int rho x x^T dx (MassDistributionToInertialParam).

    Exact when mass, dims, rotation and position are exact (Fraction or SymPy).
    """
    sigma_c, c = covariance(shape, mass, dims)
    r = np.eye(3, dtype=sigma_c.dtype) if rotation is None else _array(rotation)
    com = r @ c + _array(position)
    return mass, mass * com, r @ sigma_c @ r.T + mass * np.outer(com, com)


def phi_from_covariance(mass, sigma_c, com):
    """Phi of a body with mass, covariance about its CoM and CoM position."""
    com = np.asarray(com, dtype=float)
    sigma = np.asarray(sigma_c, dtype=float) + mass * np.outer(com, com)
    return pack(mass, mass * com, inertia_from_sigma(sigma))


def solid(shape, mass, dims, rotation=None, position=(0.0, 0.0, 0.0)):
    """Phi of a uniform solid of the given mass, turned by ``rotation`` and moved to ``position``."""
    if not mass > 0:
        raise ValueError(f"a solid needs a positive mass, got {mass}")
    dims = validate(shape, dims)
    m, h, sigma = moments(shape, float(mass), dims.astype(float), rotation, np.asarray(position, dtype=float))
    return pack(m, h, inertia_from_sigma(sigma))
