"""Regressors of the generalized robotics equation (RoboticRegressor, RoboticRegressorVel), built from QJ.

Z is linear in Phi, so Z(Phi) w = Y(w) Phi for a twist w with Y(w) (6 x 10)
free of parameters. With the body blocks B_l = QJ_l (6 x n) and their
partials dB_l/dq_i, every Theta-linear term of (RoboticEquation) splits over
the bodies (all arrays batched over leading axes; per body n x 10):

- M(q, Theta) a = sum_l R_M,l(q, a) Phi_l with R_M,l = B_l^T Y(B_l a);
- C(q, qd, Theta) v = sum_l R_C,l Phi_l with, from (Cristoffel) and
  M = sum_l B_l^T Z(Phi_l) B_l, R_C,l = (T1 + T2 - T3) / 2, where
  T1 = Bd^T Y(B v) + B^T Y(Bd v) (Bd = sum_i dB/dq_i qd_i: the dM/dq_i qd_i v part),
  T2 = Bv^T Y(B qd) + B^T Y(Bv qd) (Bv = sum_j dB/dq_j v_j: the dM/dq_j v_j qd part),
  T3[k] = (dB/dq_k qd)^T Y(B v) + (B qd)^T Y(dB/dq_k v) (the qd^T dM/dq_k v part);
- G(q, Theta) = sum_l R_G,l Phi_l with R_G,l = -B_l^T Y((R_l^T g, 0)) (DefGravitation).

R_l(q, qd, v, a) = R_M,l(q, a) + R_C,l + R_G,l, and M(q, Thetadot) v = sum_l R_M,l(q, v) Phidot_l.
"""

from __future__ import annotations

import numpy as np

from inertiaproof.model.inertia import spatial_inertia

__all__ = [
    "apply_regressor", "christoffel_terms", "coriolis_regressor", "gravity_regressor", "mass_regressor",
    "regressor", "twist_regressor", "UNIT_Z",
]

UNIT_Z = spatial_inertia(np.eye(10))  # Z(e_h) for the ten unit parameter vectors: (10, 6, 6)


def twist_regressor(w):
    """Y(w) (..., 6, 10) with Z(Phi) w = Y(w) Phi, for twists w (..., 6): one product w @ [UNIT_Z as 6 x 60]."""
    unit = np.moveaxis(UNIT_Z, 0, -1).reshape(6, 60)  # [r, s, h] -> [r, s * 10 + h]; UNIT_Z[h] is symmetric
    w = np.asarray(w)
    return (w.reshape(-1, 6) @ unit).reshape(w.shape[:-1] + (6, 10))


def _blocks(qj):
    return qj.reshape(qj.shape[:-2] + (qj.shape[-2] // 6, 6, qj.shape[-1]))


def _apply(b, x):
    """B_l x for blocks b (..., N, 6, n) and vectors x (..., n): (..., N, 6)."""
    return (b @ x[..., None, :, None])[..., 0]


def _project(b, w):
    """B_l^T Y(w_l) for blocks (..., N, 6, n) and twists (..., N, 6): (..., N, n, 10)."""
    return np.swapaxes(b, -1, -2) @ twist_regressor(w)


def mass_regressor(qj, a):
    """R_M,l(q, a) (..., N, n, 10): M(q, Theta) a = sum_l R_M,l Phi_l (RoboticRegressorVel with a = v)."""
    b = _blocks(qj)
    return _project(b, _apply(b, a))


def christoffel_terms(qj, dqj, q_dot, v):
    """(T1, T2, T3), each (..., N, n, 10), of the Coriolis regressor; R_C,l = (T1 + T2 - T3) / 2.

    The four contractions of dB/dq (with qd and v over the derivative index and over the column index) are two
    matrix products with the pair (qd, v); each T is one product of stacked blocks with stacked Y's."""
    b = _blocks(qj)
    db = dqj.reshape(b.shape + (dqj.shape[-1],))  # [l, r, k, i] = d B_l[r, k] / d q_i
    pair = np.stack(np.broadcast_arrays(q_dot, v), -1)[..., None, None, :, :]  # (..., 1, 1, n, 2)
    by_rate = db @ pair  # [..., k, 0] = (sum_i dB/dq_i qd_i)[:, k] = Bd, [..., 1] = Bv
    by_column = np.swapaxes(db, -1, -2) @ pair  # [..., k, 0] = dB/dq_k qd, [..., 1] = dB/dq_k v
    bd, bv = by_rate[..., 0], by_rate[..., 1]
    dk_qd, dk_v = by_column[..., 0], by_column[..., 1]
    b_qd, b_v = _apply(b, q_dot), _apply(b, v)
    y_qd, y_v = twist_regressor(b_qd), twist_regressor(b_v)
    stack = lambda *xs: np.concatenate(xs, -2)  # noqa: E731  (..., N, 6 m, .): one product per T
    t1 = np.swapaxes(stack(bd, b), -1, -2) @ stack(y_v, twist_regressor(_apply(bd, v)))
    t2 = np.swapaxes(stack(bv, b), -1, -2) @ stack(y_qd, twist_regressor(_apply(bv, q_dot)))
    t3 = np.swapaxes(stack(dk_qd, dk_v), -1, -2) @ stack(y_v, y_qd)
    return t1, t2, t3


def coriolis_regressor(qj, dqj, q_dot, v):
    """R_C,l (..., N, n, 10): C(q, qd, Theta) v = sum_l R_C,l Phi_l."""
    t1, t2, t3 = christoffel_terms(qj, dqj, q_dot, v)
    return 0.5 * (t1 + t2 - t3)


def gravity_regressor(qj, rotations, g):
    """R_G,l (..., N, n, 10): G(q, Theta) = sum_l R_G,l Phi_l for gravitational acceleration g."""
    local_g = np.swapaxes(rotations, -1, -2) @ np.asarray(g, dtype=float)  # (..., N, 3)
    return -_project(_blocks(qj), np.concatenate([local_g, np.zeros_like(local_g)], -1))


def regressor(qj, dqj, rotations, g, q_dot, v, a):
    """R_l(q, qd, v, a) (..., N, n, 10): M a + C(q, qd) v + G = sum_l R_l Phi_l (RoboticRegressor)."""
    return mass_regressor(qj, a) + coriolis_regressor(qj, dqj, q_dot, v) + gravity_regressor(qj, rotations, g)


def apply_regressor(r, theta):
    """sum_l R_l Phi_l for regressors (..., N, n, 10) and parameters (..., N, 10)."""
    return np.einsum("...lkh,...lh->...k", r, theta)
