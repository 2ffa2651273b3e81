"""Ordinary least squares: min |A theta - b|^2, and the noise's confidence of what it finds.

The data fix theta only up to the regressor's null space (:mod:`.excitation`); the fit is the solution nearest to
a reference theta_0 (the file's values) in the scaled coordinates, theta = theta_0 + D^-1 A_s^+ (b - A theta_0)
with the pseudo-inverse of the SVD truncated at the numerical rank, so directions the data do not see keep the
file's values. With r the residual and m rows, sigma^2 = r / (m - rank) estimates the torque noise's variance and
Cov = sigma^2 D^-1 V_r S_r^-2 V_r^T D^-1 the covariance on the identifiable part; base parameters beta = theta_P +
K theta_D (A theta = A_P beta) have Cov_beta = sigma^2 (A_P^T A_P)^-1. Each body's Phi_l of the fit is classified
by :func:`inertiaproof.model.consistency.physical_consistency` (Definition 1, Theorem 1).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from inertiaproof.model.consistency import physical_consistency

from .excitation import NULL_TOL, Excitation, column_scale, excitation

__all__ = ["LeastSquares", "body_verdicts", "least_squares"]


@dataclass(frozen=True)
class LeastSquares:
    theta: np.ndarray
    residual: float  # |A theta - b|^2
    sigma: float  # estimated torque noise (standard deviation per row)
    covariance: np.ndarray  # (p, p) on the identifiable part
    base: np.ndarray  # beta
    base_covariance: np.ndarray
    excitation: Excitation
    rows: int

    @property
    def standard_errors(self):
        return np.sqrt(np.clip(np.diag(self.covariance), 0, None))

    @property
    def base_errors(self):
        return np.sqrt(np.clip(np.diag(self.base_covariance), 0, None))


def least_squares(a, b, names, reference=None):
    """The :class:`LeastSquares` fit of rows ``a`` (m, p) to ``b`` (m,) nearest ``reference`` (default 0)."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    ref = np.zeros(a.shape[1]) if reference is None else np.asarray(reference, dtype=float)
    scale, zero = column_scale(a)
    scaled = a / scale
    scaled[:, zero] = 0.0
    q, r_factor = np.linalg.qr(scaled)  # the one factorisation of the rows; the rest works on R (p x p)
    ex = excitation(a, names, (scale, zero, scaled, r_factor))
    u, s, vt = np.linalg.svd(r_factor, full_matrices=False)
    r = ex.rank
    ur, sr, vr = u[:, :r], s[:r], vt[:r].T
    step = vr @ ((ur.T @ (q.T @ (b - a @ ref))) / sr)
    theta = ref + step / ex.scale
    res = b - a @ theta
    residual = float(res @ res)
    dof = max(a.shape[0] - r, 1)
    sigma2 = residual / dof
    cov = sigma2 * (vr / sr**2) @ vr.T / np.outer(ex.scale, ex.scale)
    rb = r_factor[:, ex.base]
    gram_inv = np.linalg.pinv(rb.T @ rb, rcond=NULL_TOL**2) / np.outer(ex.scale[ex.base], ex.scale[ex.base])
    return LeastSquares(theta, residual, float(np.sqrt(sigma2)), cov, ex.base_values(theta), sigma2 * gram_inv, ex,
                        a.shape[0])


def body_verdicts(theta, bodies):
    """[{body, verdict, reason}] of each body's Phi (10 entries each, in the order of ``bodies``)."""
    phi = np.asarray(theta, dtype=float)[:10 * len(bodies)].reshape(len(bodies), 10)
    c = physical_consistency(phi)
    return [{"body": name, **row} for name, row in zip(bodies, c.rows())]
