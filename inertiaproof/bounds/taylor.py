"""Certified bounds of the spectral extremes of M(q, Theta) on a box of configurations, in polynomial time.

The family is M(q) = M(c + d), |d_j| <= r_j (MassMatrix, Theorems 2-4). Three facts make a bound that
costs O(n) symmetric eigenproblems per box instead of 2^n vertices:

- Structure of the entries (composite rigid bodies): M_il = s_i^T X_{i<-l}(q) I^c_l(q) s_l for i <= l,
  where X_{i<-l} depends on q_{i+1}..q_l with degree 1 and the composite inertia I^c_l on q_{l+1}..q_n
  with degree 2 (trigonometric for turns, algebraic for slides). So dM_il/dq_j = 0 for j <= min(i, l),
  and M_il has degree <= 1 in q_j for min < j <= max, <= 2 beyond (:func:`entry_degrees`).
- Entry sizes: from lengths alone, M_il = sum_{b >= max(i,l)} (QJ_b e_i)^T Z(Phi_b) (QJ_b e_l) gives a bound
  S_il of |M_il| for every q (:func:`entry_sups`); for up to ``FOURIER_LIMIT`` free turning joints the Wiener
  norm of the exact Fourier coefficients is often much smaller (:func:`fourier_sups`), and the smaller is kept.
  The spectral radius of S bounds |lambda|_max(M(q)) for every q (:func:`perron_bound`).
- Bernstein's inequality (a full period) and Markov's (the limits of a slide) bound every partial
  derivative of M_il by c_il,j S_il, so on the box the second-order Taylor remainder of entry (i, l) is at
  most 1/2 (sum_j c_il,j r_j)^2 S_il and the first-order one (mean value) at most (sum_j c_il,j r_j) S_il.

With E = M(q) - M(c) - sum_j d_j dM/dq_j(c) bounded entrywise by B, and any u > 0,
x^T E x >= -sum_il B_il |x_i||x_l| >= -sum_i x_i^2 (B u)_i / u_i (AM-GM), so E >= -diag(Bu/u). The linear
part obeys d_j A_j >= -r_j |A_j| with |A_j| the matrix absolute value (U |Lambda| U^T). Hence

    lambda_min(M(q)) >= lambda_min(M(c) - sum_j r_j |A_j| - diag(B u / u))      for all q in the box,

and the mirror image for lambda_max; u is chosen from the eigenvector at the centre (the bound holds for
every u > 0, the choice only sharpens it). Alternatively the linear part is put into B entrywise; the
better of the two is kept.

Rounding (stated, a posteriori): the centre values and partials are computed in floating point; each
entry of M(c) and of r_j dM/dq_j(c) is allowed ``ENTRY_ROUNDING`` n eps times its bound S_il (resp.
c_il,j r_j S_il), added to B; the complex step of the partials (h = 1e-30) adds h^2/6 c^3 S, below
those; each final eigenvalue is moved outwards by ``ROUNDING`` eps ||X||_F (Weyl with the backward error
of a symmetric eigensolver). Every step is polynomial in n: O(n^4) per box.

Entry point for a single box: :func:`certified_box_bound` (also used by the tests' ball-arithmetic
re-check); batched over boxes: :func:`box_bounds`.
"""

from __future__ import annotations

import numpy as np

from inertiaproof.dynamics import composite
from inertiaproof.model.inertia import spatial_inertia

from .domain import bernstein_domain, certification_obstacle, free_coordinates
from .lengths import column_bounds
from .memo import memo
from .spectral import EPS, ROUNDING

__all__ = [
    "box_bounds", "certified_box_bound", "ENTRY_ROUNDING", "entry_degrees", "entry_factors", "entry_sups",
    "FOURIER_LIMIT", "FOURIER_TERMS", "fourier_coefficients", "fourier_terms", "fourier_sups", "perron_of",
    "MassFamily", "perron_bound",
]

ENTRY_ROUNDING = 64.0  # allowance of a computed entry of M(c) or dM/dq(c), in units of n eps * S_il


def entry_degrees(n):
    """deg[i, l, j]: degree of M_il in q_j (0 for j <= min(i, l), 1 up to max(i, l), 2 beyond)."""
    i, l, j = np.meshgrid(np.arange(n), np.arange(n), np.arange(n), indexing="ij")
    low, high = np.minimum(i, l), np.maximum(i, l)
    return np.where(j <= low, 0, np.where(j <= high, 1, 2)).astype(float)


def entry_factors(chain):
    """c[i, l, j] with sup |dM_il/dq_j| <= c S_il: Bernstein (degree) on a period, Markov (2 deg^2 / width) on a slide."""
    lo, hi = bernstein_domain(chain)
    deg = entry_degrees(chain.n)
    revolute = np.array([j.revolute for j in chain.joints])
    width = np.maximum(hi - lo, 1e-300)
    return np.where(revolute[None, None, :], deg, 2.0 * deg**2 / width[None, None, :])


def entry_sups(chain, thetas):
    """S[v, i, l] >= sup_q |M_il(q, Theta_v)| over the Bernstein domain, for every q.

    M_il = sum_{b >= max(i,l)} x_i^T Z_b x_l with x_k = QJ_b e_k (MassMatrix). Column l of body l's block is
    the constant unit twist s_l, so the b = l term is |x_i^T (Z_l s_l)| <= lin_li |(Z s)_v| + ang_li |(Z s)_w|
    (exact s^T Z s when i = l too); for b > l, |x^T Z y| <= ||x||_W ||y||_W with W = |Z| and
    ||x||_W^2 <= lambda_max(W_vv) lin^2 + 2 ||W_vw|| lin ang + lambda_max(W_ww) ang^2 (column bounds of QJ from
    lengths).
    """
    linear, angular = column_bounds(chain)  # (bodies, joints)
    n = chain.n
    z = spatial_inertia(np.asarray(thetas, float))  # (V, N, 6, 6)
    za = _psd_abs(z)  # |Z|, with its rounding allowance
    l_v = np.linalg.eigvalsh(za[..., :3, :3])[..., -1]  # (V, N)
    l_w = np.linalg.eigvalsh(za[..., 3:, 3:])[..., -1]
    n_vw = np.linalg.norm(za[..., :3, 3:], 2, axis=(-2, -1))
    wn = np.sqrt(l_v[..., None] * linear[None] ** 2 + 2 * n_vw[..., None] * linear[None] * angular[None]
                 + l_w[..., None] * angular[None] ** 2) * (1 + 8 * EPS)  # (V, b, k) >= ||x_k||_W
    twists = np.array([j.unit_twist for j in chain.z_joints])  # (n, 6)
    zs = np.einsum("vlij,lj->vli", z, twists)  # (V, l, 6): Z_l s_l
    own = np.einsum("li,vli->vl", twists, zs)  # s_l^T Z_l s_l
    zs_v, zs_w = np.linalg.norm(zs[..., :3], axis=-1), np.linalg.norm(zs[..., 3:], axis=-1)  # (V, l)
    out = np.zeros(z.shape[:1] + (n, n))
    for l in range(n):
        for i in range(l + 1):
            at_l = np.abs(own[:, l]) if i == l else linear[l, i] * zs_v[:, l] + angular[l, i] * zs_w[:, l]
            beyond = (wn[:, l + 1:, i] * wn[:, l + 1:, l]).sum(-1)
            out[:, i, l] = out[:, l, i] = at_l + beyond
    return out * (1 + 16 * (n + 6) * EPS)  # the sums and products above, rounded up


FOURIER_LIMIT = 7  # free turning coordinates up to which the 5^m Fourier coefficients of M are computed
FOURIER_TERMS = 4_000_000  # terms 5^m n^2 of M's Fourier series (coefficients times entries, from 5^m samples of M)
# computed at most: a 7-joint chain with every coordinate free (5^7 49 = 3.8e6), not an 8-joint one (5^7 64 = 5.0e6)


def fourier_sups(chain, thetas, free):
    """W[v, i, l] = sum_k |F_k| >= sup_q |M_il(q, Theta_v)| over all q, or None (a free slide, more than
    ``FOURIER_LIMIT`` free coordinates, or more than ``FOURIER_TERMS`` terms 5^m n^2).

    M is a trigonometric polynomial of degree <= 2 in every turning coordinate, so its values on the grid of 5
    angles per free coordinate give its Fourier coefficients F_k (k in {-2..2}^m) exactly, and
    |M_il(q)| = |sum_k F_k,il e^(i k.q)| <= sum_k |F_k,il| (the Wiener norm). Rounding (stated): each sample
    carries ``ENTRY_ROUNDING`` n eps S_il (S from lengths), the FFT 5 m eps max |sample|; both are added for
    every one of the 5^m coefficients (:func:`fourier_coefficients`).
    """
    found = fourier_coefficients(chain, thetas, free)
    if found is None:
        return None
    coefficients, _, delta = found
    m = coefficients.shape[0]
    return (np.abs(coefficients).sum(0) + m * delta) * (1 + 2 * m * EPS)


def fourier_terms(chain, free=None):
    """5^m n^2: the terms of M's Fourier series in the m free coordinates (``free``, default the chain's)."""
    return 5 ** int(np.sum(free_coordinates(chain) if free is None else free)) * chain.n**2


def fourier_coefficients(chain, thetas, free):
    """(F, k, delta): the exact Fourier coefficients F (5^m, V, n, n) of M(q, Theta_v) in the m free coordinates,
    their integer frequencies k (5^m, m) in {-2..2}, and the allowance delta (V, n, n) of every computed
    coefficient (|fl(F_k) - F_k| <= delta: ``ENTRY_ROUNDING`` n eps S_il per sample, 5 m eps max |sample| for the
    FFT, times 1.01); None where :func:`fourier_sups` is None. Cached by content; read only."""
    idx = np.flatnonzero(free)
    m = len(idx)
    if m > FOURIER_LIMIT or fourier_terms(chain, free) > FOURIER_TERMS or not all(chain.joints[j].revolute
                                                                                 for j in idx):
        return None
    thetas = np.asarray(thetas, float)
    return memo("fourier", chain, (thetas, np.asarray(free, bool)), lambda: _coefficients(chain, thetas, idx))




def _coefficients(chain, thetas, idx):
    m, n = len(idx), chain.n
    grid = (np.stack(np.meshgrid(*([2 * np.pi * np.arange(5) / 5] * m), indexing="ij"), -1).reshape(-1, m) if m
            else np.zeros((1, 0)))  # no free coordinate: M is constant
    q = np.zeros((len(grid), n))
    q[:, idx] = grid
    samples = composite.mass_matrix(chain, q[:, None], thetas[None])  # (5^m, V, n, n)
    coefficients = np.fft.fftn(samples.reshape((5,) * m + samples.shape[1:]), axes=tuple(range(m))) / 5**m
    freq = np.rint(np.fft.fftfreq(5) * 5).astype(int)  # 0, 1, 2, -2, -1: the FFT's order
    k = (np.stack(np.meshgrid(*([freq] * m), indexing="ij"), -1).reshape(-1, m) if m else np.zeros((1, 0), int))
    error = ENTRY_ROUNDING * n * EPS * entry_sups(chain, thetas) + 5 * max(m, 1) * EPS * np.abs(samples).max(0)
    out = (coefficients.reshape((-1,) + samples.shape[1:]), k, 1.01 * error)
    for a in out:
        a.flags.writeable = False
    return out


class MassFamily:
    """M(q, Theta_v) for a stack of parameter sets, with what its box bounds need (computed once)."""

    def __init__(self, chain, thetas):
        obstacle = certification_obstacle(chain)
        if obstacle is not None:
            raise ValueError(obstacle)
        self.chain = chain
        self.thetas = np.asarray(thetas, float)
        self.factors = entry_factors(chain)  # (n, n, n)
        self.sups = entry_sups(chain, self.thetas)  # (V, n, n)
        wiener = fourier_sups(chain, self.thetas, free_coordinates(chain))
        if wiener is not None:
            self.sups = np.minimum(self.sups, wiener)
        self.psd = bool(np.all(np.linalg.eigvalsh(spatial_inertia(self.thetas)) >= 0))

    def centre(self, c):
        """M(c) (K, V, n, n) and dM/dq(c) (K, V, n, n, n)."""
        m = composite.mass_matrix(self.chain, c[:, None], self.thetas[None])
        return m, composite.mass_matrix_partials(self.chain, c[:, None], self.thetas[None])


def _psd_abs(a):
    """|A| = U |Lambda| U^T of symmetric matrices (..., n, n), plus its rounding allowance on the diagonal."""
    w, u = np.linalg.eigh(a)
    out = np.einsum("...ij,...j,...kj->...ik", u, np.abs(w), u)
    slack = ROUNDING * EPS * np.linalg.norm(a, axis=(-2, -1))
    return out + slack[..., None, None] * np.eye(a.shape[-1])


def _product_error(t, m):
    """Entrywise bound of |fl(T M T^T) - T M T^T|: gamma_{2n+2} |T| |M| |T|^T (Higham, Thm 3.5), rounded up."""
    n = m.shape[-1]
    k = (2 * n + 2) * EPS
    at = np.abs(t)
    return k / (1 - k) * 1.01 * np.einsum("...ij,...jk,...lk->...il", at, np.abs(m), at)


def _lambda(x, lowest):
    """lambda_min (lowest) or lambda_max of symmetric x, moved outwards by ROUNDING eps ||x||_F."""
    ev = np.linalg.eigvalsh(x)
    allowance = ROUNDING * EPS * np.linalg.norm(x, axis=(-2, -1))
    return ev[..., 0] - allowance if lowest else ev[..., -1] + allowance


def _side(a, da, r, b_rem, t, sign):
    """Bound of sign * lambda_(max|min) of T M(q) T^T over the box, in the congruence T (..., n, n).

    a (K, V, n, n) the centre, da (K, V, n, n, n) its partials, b_rem (K, V, n, n) an entrywise bound of the
    Taylor remainder and of the centre's rounding. Returns mu with sign * lambda(T M(q) T^T) <= sign * mu.
    """
    n = a.shape[-1]
    tt = np.swapaxes(t, -1, -2)
    nc = t @ a @ tt
    nj = np.einsum("...ij,...jkp,...lk->...pil", t, da, t)  # (K, V, n_p, n, n)
    lin = (_psd_abs(nj) * r[:, None, :, None, None]).sum(2)
    col = np.linalg.norm(t, axis=-2)
    weights = [1.0 / np.maximum(col, 1e-300), np.ones_like(col)]
    best = None
    err = _product_error(t, a) + np.einsum("...pil,...p->...il", np.abs(nj), r[:, None, :]) * (2 * n + 2) * EPS * 1.01
    for u in weights:
        d = np.einsum("...il,...l->...i", b_rem, u) / u  # E >= -diag(d)
        rem = np.einsum("...ij,...j,...kj->...ik", t, d, t)  # T diag(d) T^T
        shift = lin + rem + np.linalg.norm(err, axis=(-2, -1))[..., None, None] * np.eye(n)
        val = _lambda(nc - shift if sign < 0 else nc + shift, sign < 0)
        best = val if best is None else (np.maximum(best, val) if sign < 0 else np.minimum(best, val))
    return best


def box_bounds(family: MassFamily, kind, centres, radii):
    """Certified bound on each box (centres, radii: (K, n)) of the spectral kind over the box and the stack.

    kind 'lmin': a lower bound of min_v inf_box lambda_min(M); 'lmax': an upper bound of max_v sup lambda_max;
    'absmax': an upper bound of max_v sup sigma_max (symmetric: max(lambda_max, -lambda_min)). Returns (K,).

    lambda_min of a positive definite centre uses the congruence T = L^-1 (L L^T ~ M(c), Cholesky):
    T M(q) T^T >= mu I gives M(q) >= mu T^-1 T^-T >= mu / ||T||_2^2 I (mu > 0), a relative bound that sees
    the small eigenvalues in their own scale. Otherwise (and for lambda_max) T = I: Weyl with the linear
    part bounded by sum_j r_j |dM/dq_j| and the remainder by diag(B u / u).
    """
    c, r = np.asarray(centres, float), np.asarray(radii, float)
    n = c.shape[1]
    a, da = family.centre(c)  # (K, V, n, n), (K, V, n, n, n)
    s = family.sups[None]  # (1, V, n, n)
    rho = np.einsum("ilj,kj->kil", family.factors, r)[:, None]  # (K, 1, n, n)
    b_rem = 0.5 * rho**2 * s + ENTRY_ROUNDING * n * EPS * s * (1 + rho)  # Taylor remainder + rounding of a, da
    eye = np.broadcast_to(np.eye(n), a.shape)
    out = []
    for sign in ((-1.0,) if kind == "lmin" else (1.0,) if kind == "lmax" else (1.0, -1.0)):
        plain = _side(a, da, r, b_rem, eye, sign)
        if sign < 0:
            low = plain
            try_scaled = np.all(np.linalg.eigvalsh(a)[..., 0] > 0, axis=-1)
            if try_scaled.any():
                k = np.flatnonzero(try_scaled)
                lch = np.linalg.cholesky(a[k])
                t = np.linalg.inv(lch)
                mu = _side(a[k], da[k], r[k], b_rem[k], t, -1.0)
                norm_t = np.linalg.norm(t, 2, axis=(-2, -1)) * (1 + ROUNDING * EPS * n)
                scaled = np.where(mu > 0, mu / norm_t**2, -np.inf)
                low = low.copy()
                low[k] = np.maximum(low[k], scaled)
            out.append(low.min(1))
        else:
            out.append(plain.max(1))
    if kind in ("lmin", "lmax"):
        return out[0]
    return np.maximum(out[0], -out[1])


def perron_bound(family: MassFamily):
    """max_v rho(S_v) >= sup_q |lambda|_max(M(q, Theta_v)) for every q: |M(q)| <= S entrywise, so the spectral radius
    of M(q) is at most that of |M(q)|, at most that of S (Perron-Frobenius), rounded up."""
    return float(perron_of(family.sups).max())


def perron_of(s):
    """rho(S) of symmetric nonnegative S (..., n, n), rounded up: at least |lambda|_max of every symmetric matrix
    bounded by S entrywise (Perron-Frobenius)."""
    return np.linalg.eigvalsh(s)[..., -1] + ROUNDING * EPS * np.linalg.norm(s, axis=(-2, -1))


def certified_box_bound(chain, thetas, kind, lo, hi):
    """The certified bound of ``kind`` ('lmin': lower; 'lmax', 'absmax': upper) of M(q, Theta_v) over q in the box
    [lo, hi] and every parameter set v of ``thetas`` (V, N, 10); a float. Pure: same inputs, same answer."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    family = MassFamily(chain, thetas)
    return float(box_bounds(family, kind, (0.5 * (lo + hi))[None], (0.5 * (hi - lo))[None])[0])
