"""Terms of the generalized robotics equation (RoboticEquation), numerically.

    M(q, Theta) qdd + (C(q, qd, Theta) + M(q, Thetadot) + H(q, Psi)) qd + G(q, Theta)
        = tau + w - J^T Q^T Psidot

All functions are pure over arrays and batched over leading axes:
``qj`` is QJ (..., 6N, n), ``dqj`` is dQJ/dq (..., 6N, n, n) with the
derivative index last, ``theta`` (..., N, 10) stacks the bodies' Phi, and
``psi`` (..., 6N) is the lumped velocity Psi.
"""

from __future__ import annotations

import numpy as np

from inertiaproof.model.inertia import spatial_inertia

__all__ = [
    "christoffel", "coriolis", "coriolis_force", "generalized_forces", "gravity", "lumped_acceleration_force",
    "lumped_jacobian_derivative", "lumped_velocity_matrix", "mass_matrix", "mass_matrix_partials",
    "mass_matrix_time_derivative",
]


def _blocks(qj):
    """QJ (..., 6N, n) -> (..., N, 6, n)."""
    return qj.reshape(qj.shape[:-2] + (qj.shape[-2] // 6, 6, qj.shape[-1]))


def mass_matrix(qj, theta):
    """M = (QJ)^T blockdiag(Z(Phi_l)) QJ (MassMatrix). Linear in ``theta``, so M(q, Thetadot) is mass_matrix(qj, theta_dot)."""
    zb = spatial_inertia(theta) @ _blocks(qj)  # (..., N, 6, n)
    return np.swapaxes(qj, -1, -2) @ zb.reshape(zb.shape[:-3] + (-1, zb.shape[-1]))


def mass_matrix_partials(qj, dqj, theta):
    """dM/dq (..., n, n, n), entry [k, j, i] = d M_kj / d q_i."""
    b = _blocks(qj)
    zb = spatial_inertia(theta) @ b
    flat = dqj.reshape(dqj.shape[:-2] + (-1,))  # (..., 6N, n k * n i)
    z6 = zb.reshape(zb.shape[:-3] + (-1, zb.shape[-1]))  # (..., 6N, n j)
    n = qj.shape[-1]
    half = (np.swapaxes(flat, -1, -2) @ z6).reshape(flat.shape[:-2] + (n, n, n))  # [k, i, j], a BLAS product
    half = np.swapaxes(half, -1, -2)  # [k, j, i]
    return half + np.swapaxes(half, -3, -2)


def christoffel(dm):
    """Gamma[i, j, k] = 1/2 (dM_kj/dq_i + dM_ki/dq_j - dM_ij/dq_k) (Cristoffel), from dm[k, j, i] = dM_kj/dq_i."""
    d = np.moveaxis(dm, -1, -3)  # d[i, k, j] = dM_kj / dq_i
    return 0.5 * (np.swapaxes(d, -2, -1) + np.moveaxis(d, -1, -3) - np.moveaxis(d, -3, -1))


def coriolis(dm, qd):
    """C[k, j] = sum_i Gamma[i, j, k] qd_i (DefCoriolis)."""
    return np.swapaxes(np.einsum("...ijk,...i->...jk", christoffel(dm), qd), -1, -2)


def coriolis_force(qj, dqj, theta, q_dot):
    """C(q, qd) qd (..., n) without dM/dq: from (Cristoffel), C qd = Mdot_q qd - 1/2 d(qd^T M qd)/dq with
    Mdot_q = sum_i dM/dq_i qd_i; with M = sum_l B_l^T Z_l B_l (MassMatrix), v_l = B_l qd, Bd_l = sum_i dB_l/dq_i qd_i
    and D_l[:, k] = dB_l/dq_k qd,

        C qd = sum_l Bd_l^T Z_l v_l + B_l^T Z_l Bd_l qd - D_l^T Z_l v_l,

    O(N n^2) per sample where :func:`coriolis` of :func:`mass_matrix_partials` costs O(N n^3)."""
    b = _blocks(qj)
    db = dqj.reshape(b.shape + (dqj.shape[-1],))  # [l, r, k, i] = d B_l[r, k] / d q_i
    z = spatial_inertia(theta)  # (..., N, 6, 6)
    v = (b @ q_dot[..., None, :, None])[..., 0]  # (..., N, 6)
    bd = (db @ q_dot[..., None, None, :, None])[..., 0]  # (..., N, 6, n): sum_i dB/dq_i qd_i
    d = np.einsum("...lrjk,...j->...lrk", db, q_dot)  # column k: dB/dq_k qd
    w = (z @ v[..., None])[..., 0]  # Z_l v_l
    bd_qd = (bd @ q_dot[..., None, :, None])[..., 0]
    u = (z @ bd_qd[..., None])[..., 0]  # Z_l Bd_l qd
    return np.einsum("...lrk,...lr->...k", bd - d, w) + np.einsum("...lrk,...lr->...k", b, u)


def gravity(qj, rotations, theta, g):
    """G = dU/dq (DefGravitation) with U = -sum_l g^T (m_l z_l + R_l h_l) for gravitational acceleration g.

    As dz_l/dq = R_l (QJ linear rows) and dR_l/dq_i = R_l S(omega_li), one gets
    G = -(QJ)^T blockdiag(Z_l) stack(R_l^T g, 0).
    """
    b = _blocks(qj)
    local_g = np.swapaxes(rotations, -1, -2) @ np.asarray(g, dtype=float)  # (..., N, 3)
    wrench = np.concatenate([local_g, np.zeros_like(local_g)], -1)
    return -np.einsum("...lri,...lr->...i", b, (spatial_inertia(theta) @ wrench[..., None])[..., 0])


def lumped_jacobian_derivative(dqj, psi):
    """A = d(J^T Q^T Psi)/dq (..., n, n), entry [k, j] = sum_p dQJ[p, k, j] Psi_p."""
    return np.einsum("...pkj,...p->...kj", dqj, psi)


def lumped_velocity_matrix(dqj, psi):
    """H(q, Psi) = A - A^T with A = d(J^T Q^T Psi)/dq (DefH)."""
    a = lumped_jacobian_derivative(dqj, psi)
    return a - np.swapaxes(a, -1, -2)


def lumped_acceleration_force(qj, psi_dot):
    """J^T Q^T Psidot (RoboticEquation, right-hand side)."""
    return np.einsum("...pk,...p->...k", qj, psi_dot)


def generalized_forces(qj, dqj, rotations, g, q_ddot, q_dot, theta, theta_dot=None, psi=None, psi_dot=None):
    """tau + w demanded by (RoboticEquation) for a motion: the generalized equation's inverse dynamics (C qd by
    :func:`coriolis_force`, checked against :func:`coriolis` of the Christoffel symbols by Prop1/Prop2:numeric)."""
    m = mass_matrix(qj, theta)
    lhs_matrix = np.zeros_like(m)
    if theta_dot is not None:
        lhs_matrix = lhs_matrix + mass_matrix(qj, theta_dot)
    if psi is not None:
        lhs_matrix = lhs_matrix + lumped_velocity_matrix(dqj, psi)
    out = ((m @ q_ddot[..., None])[..., 0] + coriolis_force(qj, dqj, theta, q_dot)
           + (lhs_matrix @ q_dot[..., None])[..., 0] + gravity(qj, rotations, theta, g))
    if psi_dot is not None:
        out = out + lumped_acceleration_force(qj, psi_dot)
    return out


def mass_matrix_time_derivative(qj, dqj, theta, theta_dot, q_dot):
    """Total derivative Mdot = sum_i dM/dq_i qd_i + M(q, Thetadot) (Prop1)."""
    dm = mass_matrix_partials(qj, dqj, theta)
    return np.einsum("...kji,...i->...kj", dm, q_dot) + mass_matrix(qj, theta_dot)
