"""Certified bounds over every q from the chain's lengths alone (no branch and bound): sup_q sigma_max(QJ) and
sup_q ||M(q, Theta)|| (:func:`apriori_bound`), ||QJ_l||_F per body, and the block-triangular floor of
inf_q sigma_min(QJ)^2 (Definition 2, :func:`triangular_normality_floor`)."""

from __future__ import annotations

import numpy as np

from inertiaproof.model.inertia import spatial_inertia

from .domain import certification_obstacle
from .lengths import column_bounds
from .spectral import EPS, ROUNDING, spectral

__all__ = ["apriori_bound", "apriori_jacobian_blocks", "comparison_inverse", "triangular_normality_floor"]


def apriori_jacobian_blocks(chain):
    """Certified ||QJ_l||_F per body l for all q, from lengths alone (identity coordinate maps, bounded slides)."""
    linear, angular = column_bounds(chain)
    return np.sqrt((linear**2 + angular**2).sum(1))


def triangular_normality_floor(chain):
    """A certified lower bound of inf_q sigma_min(QJ)^2 over all q (0 when none is available).

    Column l of body l's block is the joint's constant unit twist s_l (identity
    coordinate maps), and the block has no columns right of l. With the projector
    P_l onto s_l, (QJ)^T QJ = sum_l QJ_l^T QJ_l >= sum_l QJ_l^T P_l QJ_l = W^T W,
    W lower triangular with rows s_l^T QJ_l / |s_l|: W_ll = |s_l| and
    |W_lk| <= (|s_l,v| lin_lk + |s_l,w| ang_lk) / |s_l| (column_bounds). The
    neighbour entry W_l,l-1 depends on joint l alone, a + b cos x_l + c sin x_l
    (a slide: affine in x_l), and is bounded exactly. The comparison matrix C
    (|W_ll| on, minus those bounds off the diagonal) has C^-1 >= |W^-1| entrywise,
    so sigma_min(QJ)^2 >= 1 / ||C^-1||_2^2 with ||C^-1||_2 <= min(||C^-1||_F,
    (||C^-1||_1 ||C^-1||_inf)^(1/2)). C is an M-matrix, so C^-1 >= 0 is built by forward
    substitution from nonnegative terms only, each step rounded up (:func:`comparison_inverse`),
    and the norms from nonnegative sums inflated by their rounding bound (O(n^3) floats, where exact rationals grew
    without bound).
    """
    if certification_obstacle(chain) is not None:
        return 0.0
    linear, angular = column_bounds(chain)
    twists = [j.unit_twist for j in chain.z_joints]
    n = chain.n
    diag, off = np.empty(n), np.zeros((n, n))  # C_ll from below, |C_lk| from above
    for l, s in enumerate(twists):
        size = np.linalg.norm(s)
        diag[l] = size * (1 - 8 * EPS)  # ||s|| of 6 numbers: relative rounding under 4 eps
        for k in range(l):
            bound = (np.linalg.norm(s[:3]) * linear[l, k] + np.linalg.norm(s[3:]) * angular[l, k]) / size
            if k == l - 1:
                bound = min(bound, _neighbour_bound(chain.z_joints[l], s, twists[k], chain.joints[l].limits) / size)
            off[l, k] = np.nextafter(bound * (1 + 1e-12) + 1e-300, np.inf)
    with np.errstate(over="ignore", invalid="ignore"):
        inverse = comparison_inverse(diag, off)
        square = _up(np.sum(inverse**2), n * n + 1)
        ones = _up(inverse.sum(0).max(), n)
        infinity = _up(inverse.sum(1).max(), n)
        norm_sq = min(square, _up(ones * infinity, 1))
    if not np.isfinite(norm_sq) or norm_sq <= 0:
        return 0.0
    return float(np.nextafter(1.0 / norm_sq, 0))


def _up(x, terms):
    """An upper bound of the exact value of a float computation ``x`` of ``terms`` roundings on nonnegative numbers:
    each rounding is off by a relative u = eps/2 at most, so the exact value is at most x / (1 - terms u) <=
    x (1 + 2 terms eps), the product itself rounded up by one ulp."""
    return np.nextafter(x * (1 + 2 * (terms + 1) * EPS), np.inf)


def comparison_inverse(diag, off):
    """X >= C^-1 entrywise for the lower triangular M-matrix C = diag(``diag``) - ``off`` (``off`` >= 0 strictly
    lower): X_l = (e_l + off_l,:l X_:l) / diag_l, row by row; nonnegative terms only, so every step's value rounded
    up (:func:`_up`; l products, l sums, one division) bounds the exact one, and the rows it builds on are upper
    bounds already (monotonicity)."""
    n = len(diag)
    inverse = np.zeros((n, n))
    for l in range(n):
        row = off[l, :l] @ inverse[:l]
        row[l] += 1.0
        inverse[l] = _up(row / diag[l], 2 * l + 2)
    return inverse


def _neighbour_bound(joint, s, previous, limits):
    """max over x of |s . X_after J(x) X_before s_prev|: a + b cos x + c sin x for a turn (|a| + (b^2 + c^2)^(1/2)),
    affine in x for a slide (its ends over the limits)."""
    y = previous if joint.before_twist is None else joint.before_twist @ previous
    v = s if joint.after_twist is None else joint.after_twist.T @ s
    if joint.revolute:
        a = v[2] * y[2] + v[5] * y[5]
        b = v[0] * y[0] + v[1] * y[1] + v[3] * y[3] + v[4] * y[4]
        c = v[0] * y[1] - v[1] * y[0] + v[3] * y[4] - v[4] * y[3]
        return abs(a) + np.hypot(b, c)
    if limits is None:
        return np.inf
    base, slope = v @ y, v[0] * y[4] - v[1] * y[3]
    return max(abs(base + slope * x) for x in limits)


def apriori_bound(chain, thetas, kind):
    """A certified bound of sup_q sigma_max(QJ) (thetas None) or of sup_q ||M(q, Theta_v)|| over all q, from lengths.

    With G[l, k] >= ||QJ_l[:, k]|| (column_bounds), ||QJ x||^2 = sum_l ||QJ_l x||^2 <=
    ||G |x| ||^2, so sigma_max(QJ) <= ||G||_2; and |x^T M x| <= sum_l max|lambda(Z_l)|
    ||QJ_l x||^2 <= ||D G||_2^2 with D = diag(max|lambda(Z_l)|^(1/2)). The computed
    spectral norm is inflated by its rounding allowance.
    """
    if certification_obstacle(chain) is not None:
        return np.inf
    linear, angular = column_bounds(chain)
    g = np.sqrt(linear**2 + angular**2)
    inflate = 1 + ROUNDING * EPS * chain.n
    if thetas is None:
        return float(np.linalg.norm(g, 2) * inflate)
    z = spectral(spatial_inertia(np.asarray(thetas, float)), "absmax")  # (V, N)
    return float(max(np.linalg.norm(np.sqrt(zv)[:, None] * g, 2) ** 2 for zv in z) * inflate**2)
