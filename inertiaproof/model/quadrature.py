"""Moments of densities by numerical integration, independent of the closed forms (EQ-moments).

Each solid is the image of a cube under its own parametrisation (polar,
spherical or collapsed coordinates); a tensor Gauss-Legendre rule on the cube
(trapezoidal in the angle) integrates the pulled-back integrand
rho(x) [1, x, x x^T] |Jacobian|, a polynomial (trigonometric in the angle) of
low degree, so the rule is exact up to rounding. Nothing here uses the
covariance formulas of :mod:`inertiaproof.model.solids` or the Bernstein moment
formulas of :mod:`inertiaproof.model.density`; the only shared pieces are the
definitions of the shapes, the pose R(q) x + p and the volume (which the
zeroth moment checks).
"""

from __future__ import annotations

import numpy as np

from . import solids
from .density import bernstein_values, bounding_box, evaluate, rotation

__all__ = ["component_rule", "EPS", "gauss_legendre", "moments", "monte_carlo", "solid_rule"]

EPS = np.finfo(float).eps


def gauss_legendre(n, a, b):
    """Nodes and weights of the n-point Gauss-Legendre rule on [a, b]."""
    x, w = np.polynomial.legendre.leggauss(n)
    return a + (b - a) * (x + 1.0) / 2.0, w * (b - a) / 2.0


def _tensor(*rules):
    """Tensor product of 1-D rules: (points (N, k), weights (N,))."""
    grids = np.meshgrid(*[r[0] for r in rules], indexing="ij")
    weights = np.meshgrid(*[r[1] for r in rules], indexing="ij")
    return np.stack([g.ravel() for g in grids], -1), np.prod([w.ravel() for w in weights], axis=0)


def _angle(n):
    """Trapezoidal rule on [0, 2 pi): exact for trigonometric polynomials of degree < n."""
    return 2.0 * np.pi * np.arange(n) / n, np.full(n, 2.0 * np.pi / n)


def solid_rule(shape, dims, n=4):
    """Points y (N, 3) in the solid's own frame and weights w with sum w g(y) = int_solid g dy."""
    d = np.asarray(dims, dtype=float)
    if shape == "box":
        return _tensor(*[gauss_legendre(n, -s / 2, s / 2) for s in d])
    if shape in ("ellipsoid", "sphere"):
        axes = d if shape == "ellipsoid" else np.repeat(d, 3)
        pts, w = _tensor(gauss_legendre(n, 0, 1), gauss_legendre(n, -1, 1), _angle(2 * n))
        r, u, phi = pts.T
        s = np.sqrt(1.0 - u * u)
        y = np.stack([r * s * np.cos(phi), r * s * np.sin(phi), r * u], -1) * axes
        return y, w * r * r * np.prod(axes)
    if shape == "cylinder":
        radius, height = d
        pts, w = _tensor(gauss_legendre(n, 0, radius), _angle(2 * n), gauss_legendre(n, -height / 2, height / 2))
        rho, phi, z = pts.T
        return np.stack([rho * np.cos(phi), rho * np.sin(phi), z], -1), w * rho
    if shape == "cone":
        radius, height = d
        pts, w = _tensor(gauss_legendre(n, 0, 1), gauss_legendre(n, 0, 1), _angle(2 * n))
        s, t, phi = pts.T
        rho = radius * (1.0 - s) * t
        y = np.stack([rho * np.cos(phi), rho * np.sin(phi), height * s], -1)
        return y, w * radius**2 * height * (1.0 - s) ** 2 * t
    if shape == "tetrahedron":
        v = d.reshape(4, 3)
        edges = (v[1:] - v[0]).T
        pts, w = _tensor(*[gauss_legendre(n, 0, 1)] * 3)
        a, b, c = pts.T
        uvw = np.stack([a, (1 - a) * b, (1 - a) * (1 - b) * c], -1)
        return v[0] + uvw @ edges.T, w * abs(np.linalg.det(edges)) * (1 - a) ** 2 * (1 - b)
    raise ValueError(f"unknown solid {shape!r}; one of {', '.join(solids.SHAPES)}")


def component_rule(c, n=4):
    """Points x (N, 3) about the frame origin and masses w rho(x) (N,) of one density component."""
    r = rotation(np.asarray(c["quaternion"], dtype=float))
    if c["type"] == "solid":
        y, w = solid_rule(c["shape"], c["dims"], n)
        masses = w * (c["mass"] / solids.volume(c["shape"], c["dims"]))
    else:
        coef = np.asarray(c["coefficients"], dtype=float)
        sides = np.asarray(c["sides"], dtype=float)
        y, w = _tensor(*[gauss_legendre(max(n, (k + 4) // 2), -s / 2, s / 2) for s, k in zip(sides, coef.shape)])
        t = y / sides + 0.5
        b = [bernstein_values(t[:, i], coef.shape[i] - 1) for i in range(3)]
        masses = w * np.einsum("abc,na,nb,nc->n", coef, *b)
    return y @ r.T + np.asarray(c["position"], dtype=float), masses


def moments(spec, n=4):
    """(m, h, Sigma) of a density by quadrature, and the sums of |terms| (m, h, Sigma) that bound its rounding."""
    rules = [component_rule(c, n) for c in spec["components"]]
    x = np.concatenate([r[0] for r in rules])
    w = np.concatenate([r[1] for r in rules])
    outer = x[:, :, None] * x[:, None, :]
    value = (w.sum(), w @ x, np.einsum("n,nij->ij", w, outer))
    size = (np.abs(w).sum(), np.abs(w) @ np.abs(x), np.einsum("n,nij->ij", np.abs(w), np.abs(outer)))
    return value, size, w.size


def monte_carlo(spec, samples, rng):
    """(estimate, standard error) of (m, h, Sigma) from uniform samples in a box around the carrier.

    The estimate is unbiased; its error is asymptotically normal with the
    returned standard deviation (computed from the same samples).
    """
    lower, upper = bounding_box(spec)
    volume = float(np.prod(upper - lower))
    x = lower + (upper - lower) * rng.random((samples, 3))
    rho = evaluate(spec, x)
    carrier = rho != 0
    r, y = rho[carrier], x[carrier]
    terms = np.concatenate([r[:, None], r[:, None] * y, (r[:, None, None] * y[:, :, None] * y[:, None, :]).reshape(-1, 9)], 1)
    mean = terms.sum(axis=0) / samples
    variance = np.maximum((terms * terms).sum(axis=0) - samples * mean * mean, 0.0) / (samples - 1)
    split = lambda a: (a[0], a[1:4], a[4:].reshape(3, 3))  # noqa: E731
    return split(volume * mean), split(volume * np.sqrt(variance / samples))
