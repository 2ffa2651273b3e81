"""The matrix families of Section 4's configuration extremes, q -> (A(q), dA/dq), and what is computed from them
at a point or on a box's vertices: QJ (degree 1 in every coordinate), M(q, Theta) (degree 2), the skew partials
Y_p = dK_p/dq - dK_p/dq^T (DefK), and the extreme of a spectral function over the linear part of A on a box."""

from __future__ import annotations

import itertools

import numpy as np

from inertiaproof.dynamics import composite

from .spectral import CONVEX, EPS, ROUNDING, spectral

__all__ = ["jacobian_family", "mass_family", "mass_spectra", "root_up", "skew_partials", "value_for_norm",
           "vertex_bound"]


def jacobian_family(chain):
    """q -> (QJ, dQJ/dq) with QJ (K, 1, 6N, n): polynomial degree 1."""
    def evaluate(q, derivatives=True):
        qj = chain.body_jacobian(q)[:, None]
        return (qj, chain.body_jacobian_derivative(q)[:, None]) if derivatives else qj
    return evaluate, 1


def mass_family(chain, thetas):
    """q -> (M(q, Theta_v), dM/dq) for a stack of parameter sets thetas (V, N, 10): polynomial degree 2."""
    thetas = np.asarray(thetas, float)

    def evaluate(q, derivatives=True):
        m = composite.mass_matrix(chain, q[:, None], thetas[None])
        if not derivatives:
            return m
        return m, composite.mass_matrix_partials(chain, q[:, None], thetas[None])
    return evaluate, 2


def mass_spectra(chain, thetas, q, kind):
    """kind (e.g. 'lmin', 'lmax') of M(q_k, Theta_v) for configurations q (K, n) and a stack thetas (V, N, 10):
    (K, V)."""
    return spectral(composite.mass_matrix(chain, q[:, None], np.asarray(thetas, float)[None]), kind)


def vertex_bound(a, da, radii, free, kind):
    """Extreme of the spectral function over the linear part a + sum_j d_j da_j, |d_j| <= r_j, at the box's vertices.

    ``a`` (K, V, r, s), ``da`` (K, V, r, s, n). Convex kinds give the max over
    vertices (an upper bound), lmin the min (a lower bound); a rounding
    allowance of the eigen/singular value computation is added outwards.
    """
    idx = np.flatnonzero(free)
    signs = np.array(list(itertools.product((-1.0, 1.0), repeat=len(idx)))) if len(idx) else np.zeros((1, 0))
    steps = signs[None] * radii[:, idx][:, None, :]  # (K, 2^d, d)
    lin = np.einsum("kvrsj,kej->kevrs", da[..., idx], steps) + a[:, None]
    vals = spectral(lin, kind)  # (K, 2^d, V)
    size = np.linalg.norm(a, axis=(-2, -1)) + np.einsum("kvj,kj->kv", np.linalg.norm(da, axis=(-3, -2)), radii)
    allowance = ROUNDING * EPS * size  # (K, V)
    if kind in CONVEX:
        return (vals.max(1) + allowance).max(1)
    return (vals.min(1) - allowance).min(1)


def value_for_norm(evaluate, kind):
    def value(q):
        return spectral(evaluate(q, derivatives=False), kind).max(-1)
    return value


def root_up(x):
    """sqrt(x) rounded up (a certified bound of sigma_max(QJ) from one of sigma_max(QJ)^2)."""
    return float(np.sqrt(x) * (1 + 2 * EPS))


def skew_partials(dqj):
    """Y_p = dK_p/dq - (dK_p/dq)^T for every row p of QJ (DefK, proof of Theorem 5): (..., 6N, n, n)."""
    return dqj - np.swapaxes(dqj, -1, -2)
