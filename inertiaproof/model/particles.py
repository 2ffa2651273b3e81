"""A body's density as weighted particles, and the integrals Section 3 takes of it.

A uniform body is replaced by quadrature points x_i with weights w_i (masses)
that integrate polynomials of degree <= 3 over it exactly, so every integral
below equals the paper's integral of the density:

- Phi (Defml, DefIl): m = sum w, h = sum w x, I = sum w S(x)^T S(x);
- psi (the lumped velocity after DefMatrixZ): psi = sum w [v; S(x) v] for
  particles moving with velocity v relative to the body frame (sigma = 1);
- their time derivatives along the particles' motion (mass is conserved:
  the particles move, none appear).

Arrays are batched over leading axes: points (..., P, 3), weights (P,).
"""

from __future__ import annotations

import numpy as np

from .inertia import pack, skew

__all__ = ["box_particles", "lumped_velocity", "lumped_velocity_rate", "moments", "moments_rate", "particles_like"]


def box_particles(sides, rotation=None, points_per_axis=2):
    """Gauss-Legendre points of a uniform box of unit mass centred at 0: (points (P, 3), weights (P,)).

    Two points per axis integrate every polynomial of degree <= 3 exactly; a side of 0 gives a flat (degenerate) body.
    """
    nodes, w = np.polynomial.legendre.leggauss(points_per_axis)
    grid = np.stack(np.meshgrid(nodes, nodes, nodes, indexing="ij"), -1).reshape(-1, 3)
    weights = np.einsum("i,j,k->ijk", w, w, w).reshape(-1) / 8.0
    points = grid * (0.5 * np.asarray(sides, dtype=float))
    if rotation is not None:
        points = points @ np.asarray(rotation, dtype=float).T
    return points, weights


def particles_like(mass, inertia_com):
    """Particles of the uniform box with this mass and inertia about its centre (Theorem 1, necessity).

    The box's covariance Sigma_c = tr(I_c)/2 I3 - I_c = R diag(m s^2 / 12) R^T fixes its sides s and axes R;
    it exists when Sigma_c >= 0, i.e. when (mass, I_c) is a physical body.
    """
    inertia_com = np.asarray(inertia_com, dtype=float)
    sigma = 0.5 * np.trace(inertia_com) * np.eye(3) - inertia_com
    eigenvalues, axes = np.linalg.eigh(sigma)
    if eigenvalues.min() < -1e-12 * max(1.0, np.abs(eigenvalues).max()):
        raise ValueError(f"no body has mass {mass:g} and inertia {inertia_com.tolist()}: Sigma_c is not >= 0")
    sides = np.sqrt(12.0 * np.clip(eigenvalues, 0.0, None) / mass)
    points, weights = box_particles(sides, axes)
    return points, mass * weights


def moments(points, weights):
    """Phi = (m, h, I) of the particles (Defml, DefIl), shape (..., 10)."""
    s = skew(points)
    m = np.broadcast_to(weights.sum(), points.shape[:-2])
    h = np.einsum("p,...pi->...i", weights, points)
    inertia = np.einsum("p,...pji,...pjk->...ik", weights, s, s)
    return pack(m, h, inertia)


def moments_rate(points, velocities, weights):
    """dPhi/dt for particles at ``points`` moving with ``velocities`` in the body frame (no mass created)."""
    s, sv = skew(points), skew(velocities)
    m_dot = np.zeros(points.shape[:-2])
    h_dot = np.einsum("p,...pi->...i", weights, velocities)
    inertia_dot = np.einsum("p,...pji,...pjk->...ik", weights, sv, s)
    return pack(m_dot, h_dot, inertia_dot + np.swapaxes(inertia_dot, -1, -2))


def lumped_velocity(points, velocities, weights):
    """psi = int sigma rho [I3; S(x)] v dx = sum_i w_i [v_i; x_i x v_i], shape (..., 6)."""
    linear = np.einsum("p,...pi->...i", weights, velocities)
    angular = np.einsum("p,...pi->...i", weights, np.cross(points, velocities))
    return np.concatenate([linear, angular], -1)


def lumped_velocity_rate(points, accelerations, weights):
    """dpsi/dt = sum_i w_i [a_i; v_i x v_i + x_i x a_i], and v_i x v_i = 0."""
    return lumped_velocity(points, accelerations, weights)
