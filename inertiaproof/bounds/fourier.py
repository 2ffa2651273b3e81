"""Fourier-Taylor bounds of M(q, Theta) over boxes of configurations: the sup sides of Theorems 3 and 4 (and of
sup sigma_max(QJ)^2 = sup lambda_max((QJ)^T QJ), unit bodies) for chains with at most ``FOURIER_LIMIT`` free
turning coordinates (issue 12, "Certified brackets that close").

M is a finite Fourier series in the m free coordinates (MassMatrix: degree <= 2 per turning coordinate),
M_il(q) = sum_k F_k,il e^(i k.q), k in {-2..2}^m, with F known exactly up to a stated allowance
(:func:`inertiaproof.bounds.taylor.fourier_coefficients`). On a box c + d, |d_j| <= r_j:

    M(c + d) = M(c) + sum_j d_j dM/dq_j(c) + E(d),
    E_il(d) = sum_k F_k,il e^(i k.c) (e^(i k.d) - 1 - i k.d),   |E_il(d)| <= 1/2 r^T H_il r =: B_il,
    H_il,jp = sum_k |k_j| |k_p| |F_k,il|                        (|e^(ix) - 1 - ix| <= x^2 / 2),

so on the box

- per entry: |M_il(q)| <= |M_il(c)| + sum_j r_j |dM_il/dq_j(c)| + B_il (:func:`entry_box_bounds`);
- spectrally: lambda_max(M(q)) <= max over the box's vertices of lambda_max of the linear part + rho(B), and the
  same for sigma_max = |lambda|_max (lambda_max and sigma_max are convex in the linear part; Weyl; ||E||_2 <=
  rho(|E|) <= rho(B), Perron-Frobenius): :func:`remainder_radius`, added to the vertex bound by
  :func:`inertiaproof.bounds.configuration.mass_sup`.

:func:`entry_sup_bounds` runs a branch and bound shared by all entries over the search box (joint limits) for
S_il >= sup_box |M_il(q)|; its spectral radius bounds sup lambda_max and sup sigma_max (Perron-Frobenius,
:func:`perron_of`), much closer than the Wiener norms sum_k |F_k,il| over a whole period.

Rounding (stated): |F_k| carries the coefficient allowance delta in H; M(c) and r_j dM/dq_j(c) (complex step)
carry ``ENTRY_ROUNDING`` n eps S_il (1 + rho_il) as in :func:`inertiaproof.bounds.taylor.box_bounds`; the sums
of nonnegative terms are rounded up by a relative (5^m + 2 m + 8) eps; every eigenvalue is moved outwards by
``ROUNDING`` eps ||.||_F.
"""

from __future__ import annotations

import numpy as np

from inertiaproof.dynamics import composite

from .domain import free_coordinates, search_box
from .spectral import EPS, ROUNDING
from .taylor import ENTRY_ROUNDING, MassFamily, fourier_coefficients

__all__ = ["entry_box_bounds", "entry_sup_bounds", "FourierFamily", "perron_of", "remainder_radius"]


class FourierFamily:
    """M(q, Theta_v) of a stack (V, N, 10) with its Fourier curvature H (V, n, n, m, m) in the free coordinates;
    ``usable`` False (and nothing else set) where no Fourier series is available."""

    def __init__(self, chain, thetas):
        self.chain = chain
        self.thetas = np.asarray(thetas, float)
        self.free = free_coordinates(chain)
        found = fourier_coefficients(chain, self.thetas, self.free)
        self.usable = found is not None
        if not self.usable:
            return
        f, k, delta = found
        self.idx = np.flatnonzero(self.free)
        m = len(self.idx)
        ak = np.abs(k).astype(float)  # (5^m, m)
        kk = (ak[:, :, None] * ak[:, None, :]).reshape(len(ak), -1)  # (5^m, m*m)
        size = np.abs(f).reshape(len(f), -1)  # (5^m, V*n*n)
        h = (kk.T @ size).reshape((m, m) + f.shape[1:]) + kk.sum(0).reshape(m, m)[..., None, None, None] * delta
        self.curvature = np.moveaxis(h, (0, 1), (-2, -1)) * (1 + (len(f) + 8) * EPS)  # (V, n, n, m, m)
        w = ak.T @ size + ak.sum(0)[:, None] * delta.reshape(1, -1)  # (m, V*n*n): Wiener norms of dM/dq_j
        self.slopes = np.moveaxis(w.reshape((m,) + f.shape[1:]), 0, -1) * (1 + (len(f) + 8) * EPS)  # (V, n, n, m)
        mass = MassFamily(chain, self.thetas)
        self.sups, self.factors = mass.sups, mass.factors  # (V, n, n), (n, n, n)
        self.weights = np.ones(chain.n)  # split where the curvature is largest (a coordinate's own second derivative)
        diag = np.diagonal(self.curvature, axis1=-2, axis2=-1)  # (V, n, n, m)
        self.weights[self.idx] = np.sqrt(np.max(np.linalg.eigvalsh(np.moveaxis(diag, -1, 1))[..., -1], 0)) + 1e-12

    def centre(self, c):
        """M(c) (K, V, n, n) and dM/dq(c) (K, V, n, n, n)."""
        m = composite.mass_matrix(self.chain, c[:, None], self.thetas[None])
        return m, composite.mass_matrix_partials(self.chain, c[:, None], self.thetas[None])

    def entry_remainder(self, radii):
        """B (K, V, n, n) >= |E_il| on boxes of radii (K, n), plus the rounding allowance of M(c) and r.dM/dq(c)."""
        r = np.asarray(radii, float)[:, self.idx]  # (K, m)
        m = r.shape[1]
        rr = (r[:, :, None] * r[:, None, :]).reshape(len(r), -1)  # (K, m*m)
        h = self.curvature.reshape(self.curvature.shape[:3] + (m * m,))  # (V, n, n, m*m)
        b = 0.5 * np.einsum("kp,vilp->kvil", rr, h) * (1 + (m * m + 4) * EPS)
        rho = np.einsum("ilj,kj->kil", self.factors, np.asarray(radii, float))[:, None]  # (K, 1, n, n)
        n = self.chain.n
        return b + ENTRY_ROUNDING * n * EPS * self.sups[None] * (1 + rho)


    def first_order(self, radii):
        """B1 (K, V, n, n) >= |M_il(q) - M_il(c)| on boxes of radii (K, n) (mean value theorem with the Wiener norms
        of dM_il/dq_j, valid for every q), plus the rounding allowance of M(c)."""
        r = np.asarray(radii, float)[:, self.idx]
        b = np.einsum("kj,vilj->kvil", r, self.slopes) * (1 + (r.shape[1] + 4) * EPS)
        return b + ENTRY_ROUNDING * self.chain.n * EPS * self.sups[None]


def perron_of(b):
    """rho(B) of symmetric nonnegative B (..., n, n), rounded up: a bound of ||E||_2 for every |E| <= B entrywise."""
    return np.linalg.eigvalsh(b)[..., -1] + ROUNDING * EPS * np.linalg.norm(b, axis=(-2, -1))


def remainder_radius(family: FourierFamily, radii):
    """max_v rho(B_v) on each box (K,): the spectral norm of the Taylor remainder E is at most this."""
    return perron_of(family.entry_remainder(radii)).max(1) * (1 + 4 * EPS)


def entry_box_bounds(family: FourierFamily, centres, radii):
    """U (K, V, n, n) >= sup over the box of |M_il(q, Theta_v)|: the least of |M(c)| + sum_j r_j |dM/dq_j(c)| + B,
    |M(c)| + B1 (:meth:`FourierFamily.first_order`) and the family's entry sups over a whole period (Wiener norm,
    lengths)."""
    c, r = np.asarray(centres, float), np.asarray(radii, float)
    a, da = family.centre(c)
    lin = np.einsum("kvilj,kj->kvil", np.abs(da), r)
    taylor = (np.abs(a) + lin + family.entry_remainder(r)) * (1 + (2 * c.shape[1] + 8) * EPS)
    first = (np.abs(a) + family.first_order(r)) * (1 + 4 * EPS)
    return np.minimum(np.minimum(taylor, first), family.sups[None])  # the Wiener norm (or the lengths) bound every q


def entry_sup_bounds(family: FourierFamily, rng, *, rounds, samples=2000, batch=64):
    """(S, observed): S (V, n, n) >= sup over the search box of |M_il(q, Theta_v)|, certified, and the largest
    sampled |M_il| (a true value, S >= observed). One branch and bound for all entries: a box stays while some
    entry's bound on it exceeds that entry's best sampled value; the boxes that raise rho(S) most (Perron vector
    weights) are split first, along the coordinate of largest curvature-weighted radius; ``rounds`` rounds."""
    chain = family.chain
    lo, hi = search_box(chain)
    free = family.free
    mid = 0.5 * (lo + hi)
    q = np.where(free, lo + (hi - lo) * rng.random((samples, chain.n)), mid)
    best = np.abs(composite.mass_matrix(chain, q[:, None], family.thetas[None])).max(0)  # (V, n, n)
    centres, radii = mid[None].copy(), np.where(free, 0.5 * (hi - lo), 0.0)[None]
    bounds = entry_box_bounds(family, centres, radii)
    for _ in range(rounds):
        s = np.maximum(best, bounds.max(0))
        _, u = np.linalg.eigh(s)
        u = np.abs(u[..., -1])  # (V, n): Perron vectors; d rho / d S_il = u_i u_l
        gain = (np.maximum(bounds - best, 0) * (u[:, :, None] * u[:, None, :])).sum((2, 3)).max(1)  # (K,)
        keep = (bounds > best).any((1, 2, 3))  # a box whose every bound is at most the entry's attained value is done
        centres, radii, bounds, gain = centres[keep], radii[keep], bounds[keep], gain[keep]
        if not len(gain):
            break
        take = np.argsort(-gain, kind="stable")[:batch]
        rest = np.ones(len(gain), bool)
        rest[take] = False
        c, r = centres[take], radii[take]
        axis = np.argmax(r * family.weights, 1)
        half = r.copy()
        half[np.arange(len(r)), axis] *= 0.5
        shift = np.zeros_like(r)
        shift[np.arange(len(r)), axis] = half[np.arange(len(r)), axis]
        child_c, child_r = np.concatenate([c - shift, c + shift]), np.concatenate([half, half])
        child_b = np.minimum(entry_box_bounds(family, child_c, child_r), np.concatenate([bounds[take]] * 2))
        best = np.maximum(best, np.abs(composite.mass_matrix(chain, child_c[:, None], family.thetas[None])).max(0))
        centres = np.concatenate([centres[rest], child_c])
        radii = np.concatenate([radii[rest], child_r])
        bounds = np.concatenate([bounds[rest], child_b])
    s = best if not len(bounds) else np.maximum(best, bounds.max(0))
    return s, best
