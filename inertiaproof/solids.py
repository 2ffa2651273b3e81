"""Uniform primitive solids and their exact moments (MassDistributionToInertialParam).

A solid of mass m has the density-weighted covariance
Sigma_c = int rho (x - c)(x - c)^T dx about its centre of mass c; in any pose
(R, p) the second moment about the frame origin is
Sigma = R Sigma_c R^T + m c' c'^T with c' = R c + p, and
Phi = (m, m c', I = tr(Sigma) I3 - Sigma) (Theorem 1, inverse map).
Moments are additive, so a union of disjoint solids or a nonnegative mixture
of densities has the sum of their Phi.
"""

from __future__ import annotations

import numpy as np

from .inertia import inertia_from_sigma, pack

SHAPES = ("box", "ellipsoid", "sphere", "cylinder", "cone", "tetrahedron")


def covariance(shape, mass, dims):
    """(Sigma_c, c) of a uniform solid in its own frame.

    box: side lengths (a, b, c), centred; ellipsoid: semi-axes (a, b, c);
    sphere: (r,); cylinder: (r, h) along z, centred; cone: (r, h), base on
    z = 0, apex at z = h; tetrahedron: the four vertices (4, 3).
    """
    dims = np.asarray(dims, dtype=float)
    if shape == "box":
        return mass / 12.0 * np.diag(dims**2), np.zeros(3)
    if shape == "ellipsoid":
        return mass / 5.0 * np.diag(dims**2), np.zeros(3)
    if shape == "sphere":
        return mass / 5.0 * dims[0] ** 2 * np.eye(3), np.zeros(3)
    if shape == "cylinder":
        r, h = dims
        return mass * np.diag([r * r / 4, r * r / 4, h * h / 12]), np.zeros(3)
    if shape == "cone":
        r, h = dims
        return mass * np.diag([3 * r * r / 20, 3 * r * r / 20, 3 * h * h / 80]), np.array([0.0, 0.0, h / 4])
    if shape == "tetrahedron":
        v = dims.reshape(4, 3)
        total = v.sum(axis=0)
        second = (v.T @ v + np.outer(total, total)) / 20.0  # int x x^T dV / V
        c = total / 4.0
        return mass * (second - np.outer(c, c)), c
    raise ValueError(f"unknown solid {shape!r}; one of {SHAPES}")


def volume(shape, dims):
    dims = np.asarray(dims, dtype=float)
    if shape == "box":
        return float(np.prod(dims))
    if shape == "ellipsoid":
        return 4.0 / 3.0 * np.pi * float(np.prod(dims))
    if shape == "sphere":
        return 4.0 / 3.0 * np.pi * dims[0] ** 3
    if shape == "cylinder":
        return np.pi * dims[0] ** 2 * dims[1]
    if shape == "cone":
        return np.pi * dims[0] ** 2 * dims[1] / 3.0
    if shape == "tetrahedron":
        v = dims.reshape(4, 3)
        return abs(np.linalg.det(v[1:] - v[0])) / 6.0
    raise ValueError(f"unknown solid {shape!r}; one of {SHAPES}")


def phi_from_covariance(mass, sigma_c, com):
    """Phi of a body with mass, covariance about its CoM and CoM position."""
    com = np.asarray(com, dtype=float)
    sigma = np.asarray(sigma_c, dtype=float) + mass * np.outer(com, com)
    return pack(mass, mass * com, inertia_from_sigma(sigma))


def solid(shape, mass, dims, rotation=None, position=(0.0, 0.0, 0.0)):
    """Phi of a uniform solid of the given mass, turned by ``rotation`` and moved to ``position``."""
    if not mass > 0:
        raise ValueError(f"a solid needs a positive mass, got {mass}")
    sigma_c, c = covariance(shape, mass, dims)
    r = np.eye(3) if rotation is None else np.asarray(rotation, dtype=float)
    return phi_from_covariance(mass, r @ sigma_c @ r.T, r @ c + np.asarray(position, dtype=float))
