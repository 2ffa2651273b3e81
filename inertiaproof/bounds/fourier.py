"""Certified sups of |M_il(q, Theta)| over the search box from M's exact Fourier series, and their spectral radius:
the sup sides of Theorems 3 and 4 (sup lambda_max(M(q, Theta)), sup sigma_max(M(q, Thetadot))) for chains with at
most ``FOURIER_LIMIT`` free turning coordinates (issue 12, "Certified brackets that close").

M is a finite Fourier series in the m free coordinates (MassMatrix: degree <= 2 per turning coordinate),
M_il(q) = sum_k F_k,il e^(i k.q), k in {-2..2}^m, with F exact up to a stated allowance delta
(:func:`inertiaproof.bounds.taylor.fourier_coefficients`). Split the coordinates into a few B and the rest A:

    M_il(q) = sum_(k_A) e^(i k_A.q_A) g_(k_A),il(q_B),   g_(k_A)(q_B) = sum_(k_B) F_(k_A, k_B) e^(i k_B.q_B),

so |M_il(q)| <= h_il(q_B) := sum_(k_A) |g_(k_A),il(q_B)| for every q_A (the Wiener norm in A only), and the sup
over the box is at most the sup of h over the box's B-face. h is evaluated at the centres p of a grid of cells of
half-widths eta_j over the joint limits of B; inside a cell |e^(i k_B.(q-p)) - 1| <= sum_(j in B) |k_j| eta_j, so

    sup_box |M_il| <= max_grid h_il(p) + sum_(j in B) eta_j W_il,j,      W_il,j = sum_k |k_j| |F_k,il|

(:func:`partial_wiener_sups`). Every B gives a valid bound; the least over the subsets tried is kept per entry.
With B empty this is the Wiener norm over a whole period (taylor.fourier_sups); one or two coordinates see the
joint limits and the phases between the harmonics of B. The spectral radius of S >= |M(q)| entrywise bounds
lambda_max and sigma_max = |lambda|_max of M(q) for every q in the box (Perron-Frobenius, :func:`perron_of`).

Rounding (stated): |F_k| carries delta (5^m delta added to every h); evaluating h adds at most (5^m + 64) eps
times the Wiener norm sum_k |F_k,il| (exponentials to 2 eps, the sums over k_B and k_A of nonnegative terms); the
grid's half-widths are widened by a relative 1e-12; every eigenvalue is moved outwards by ``ROUNDING`` eps ||.||_F.
Polynomial: (cells) 5^m (V n^2) operations per subset.
"""

from __future__ import annotations

import itertools

import numpy as np

from .domain import free_coordinates, search_box
from .spectral import EPS
from .taylor import fourier_coefficients, perron_of

__all__ = ["certified_entry_sups", "FourierFamily", "PAIR_CELLS", "partial_wiener_sups", "perron_of", "SINGLE_CELLS"]

SINGLE_CELLS = 96  # grid cells along one coordinate B (the ci profile's; more with a larger budget)
PAIR_CELLS = 96  # grid cells along each of two coordinates B


class FourierFamily:
    """M(q, Theta_v) of a stack (V, N, 10) as its Fourier series in the free coordinates: coefficients (5,)*m + (V,
    n, n), their allowance delta and Wiener norms of the partials W (V, n, n, m); ``usable`` False (and nothing
    else set) where no series is available (a free slide, more than FOURIER_LIMIT free coordinates)."""

    def __init__(self, chain, thetas):
        self.chain = chain
        self.thetas = np.asarray(thetas, float)
        self.free = free_coordinates(chain)
        found = fourier_coefficients(chain, self.thetas, self.free)
        self.usable = found is not None
        if not self.usable:
            return
        f, k, self.delta = found
        self.idx = np.flatnonzero(self.free)
        m = len(self.idx)
        self.count = len(f)  # 5^m
        self.shape = f.shape[1:]  # (V, n, n)
        self.tensor = f.reshape((5,) * m + (-1,))  # (5,)*m + (V n n,): axis j is frequency 0, 1, 2, -2, -1
        size = np.abs(f).reshape(len(f), -1)
        ak = np.abs(k).astype(float)  # (5^m, m)
        self.wiener = (size.sum(0).reshape(self.shape) + self.count * self.delta) * (1 + (self.count + 4) * EPS)
        w = ak.T @ size + ak.sum(0)[:, None] * self.delta.reshape(1, -1)  # (m, V n n): Wiener norms of dM/dq_j
        self.slopes = np.moveaxis(w.reshape((m,) + self.shape), 0, -1) * (1 + (self.count + 8) * EPS)

    def head(self, fraction=0.2):
        """The joints whose Perron-vector component of the Wiener norms is at least ``fraction`` of the largest:
        the entries among them decide rho(S)."""
        _, u = np.linalg.eigh(self.wiener)
        u = np.abs(u[..., -1]).max(0)
        return np.flatnonzero(u >= fraction * u.max())


def partial_wiener_sups(family: FourierFamily, subset, cells, columns=None):
    """S (V, n, n) >= sup over the search box of |M_il(q, Theta_v)| from the Fourier series, with the free
    coordinates ``subset`` (indices into the free ones) on a grid of ``cells`` cells each over their joint limits
    and the others by their Wiener norm (module docstring). ``columns`` (a mask (V, n, n)) restricts the work; the
    other entries get the whole-period Wiener norm. M is real and symmetric, so only i <= l is computed and
    g_(-k_A) = conj(g_(k_A)) (F_(-k) = conj(F_k)): half of the k_A, counted twice."""
    lo, hi = search_box(family.chain)
    m = len(family.idx)
    upper = np.broadcast_to(np.triu(np.ones(family.shape[-2:], bool)), family.shape)
    cols = (upper if columns is None else upper & np.asarray(columns, bool)).reshape(-1)
    x = family.tensor[..., cols]
    freq = np.array([0.0, 1.0, 2.0, -2.0, -1.0])
    etas, factors = [], []
    for b in subset:
        j = family.idx[b]
        width = (hi[j] - lo[j]) / cells
        centres = lo[j] + (np.arange(cells) + 0.5) * width
        etas.append(0.5 * width * (1 + 1e-12) + 1e-300)
        factors.append(np.exp(1j * np.outer(centres, freq)))  # (cells, 5)
    rest = [a for a in range(m) if a not in subset]
    x = np.moveaxis(x, list(subset), list(range(len(subset))))  # (5,)*|B| + (5,)*|A| + (C,)
    x = x.reshape((5 ** len(subset), -1, x.shape[-1]))  # 5^|B|, 5^|A|, C
    half, weight = _half(len(rest))
    x = np.ascontiguousarray(np.swapaxes(x[:, half, :], 1, 2)).reshape(len(x), -1)  # 5^|B|, C * 5^|A| / 2
    slopes = family.slopes.reshape(-1, m)[cols]  # (C, m)
    ncols = x.shape[-1] // len(weight)
    if len(subset) == 0:
        covered = np.abs(x[0]).reshape(ncols, -1) @ weight
    elif len(subset) == 1:
        h = _h(x, factors[0], ncols, weight)  # (cells, C)
        covered = h.max(0) + etas[0] * slopes[:, subset[0]]
    else:
        covered = _pair_grid(x, factors, etas, [lo[family.idx[b]] for b in subset], cells,
                             [slopes[:, b] for b in subset], ncols, weight)
    wiener = family.wiener.reshape(-1)[cols]
    bound = (covered + family.count * family.delta.reshape(-1)[cols] + (family.count + 64) * EPS * wiener)
    out = family.wiener.reshape(-1).copy()
    out[cols] = np.minimum(bound * (1 + 8 * EPS), wiener)
    out = out.reshape(family.shape)
    low = np.tril(np.ones(family.shape[-2:], bool), -1)
    return np.where(low, np.swapaxes(out, -1, -2), out)


def _h(x, e, ncols, weight):
    """h (P, C) = sum over the half of the k_A of weight |g_(k_A)| at P points, e (P, 5^|B|) = e^(i k_B.p)."""
    step = max(1, int(2e6 // x.shape[1]))
    return np.concatenate([np.abs(e[a:a + step] @ x).reshape(-1, ncols, len(weight)) @ weight
                           for a in range(0, len(e), step)])


def _pair_grid(x, factors, etas, lows, cells, slopes, ncols, weight):
    """max over the cells x cells grid of two coordinates of h(p) + eta . W (the module's bound), in two levels:
    h at the centres of a grid three times coarser bounds each coarse cell by h + eta_coarse . W; a coarse cell is
    split into its 3 x 3 fine cells only where, for some entry, that exceeds the largest coarse h plus the fine
    remainder (else its coarse bound is kept: every point lies in a kept coarse cell or a fine cell).
    Without a coarse grid (cells not a multiple of 3 of at least 24) every fine cell is evaluated."""
    fine = [eta * s for eta, s in zip(etas, slopes)]
    rem_f = fine[0] + fine[1]
    if cells % 3 or cells < 24:
        e = (factors[0][:, None, :, None] * factors[1][None, :, None, :]).reshape(-1, 25)
        return _h(x, e, ncols, weight).max(0) + rem_f
    freq = np.array([0.0, 1.0, 2.0, -2.0, -1.0])
    coarse = cells // 3
    width = [6 * eta / (1 + 1e-12) for eta in etas]  # coarse widths: three fine cells
    centres = [lo + (np.arange(coarse) + 0.5) * w for lo, w in zip(lows, width)]
    ca, cb = np.meshgrid(centres[0], centres[1], indexing="ij")
    ca, cb = ca.reshape(-1), cb.reshape(-1)

    def expo(a, b):
        return (np.exp(1j * np.outer(a, freq))[:, :, None] * np.exp(1j * np.outer(b, freq))[:, None, :]).reshape(-1, 25)

    hc = _h(x, expo(ca, cb), ncols, weight)  # (coarse^2, C)
    bc = hc + 3 * rem_f  # coarse half-widths are three fine ones
    split = (bc > hc.max(0) + rem_f).any(1)
    covered = bc[~split].max(0) if (~split).any() else np.zeros(hc.shape[1])
    if split.any():
        offsets = np.array([-1.0, 0.0, 1.0])
        fa = (ca[split][:, None, None] + offsets[None, :, None] * width[0] / 3).repeat(3, 2).reshape(-1)
        fb = (cb[split][:, None, None] + offsets[None, None, :] * width[1] / 3).repeat(3, 1).reshape(-1)
        covered = np.maximum(covered, _h(x, expo(fa, fb), ncols, weight).max(0) + rem_f)
    return covered


def _half(d):
    """Indices of the k in {0, 1, 2, -2, -1}^d (FFT order, flattened) with k >= -k lexicographically, and their
    weights: 1 for k = 0, 2 for the others (each stands for k and -k)."""
    if d == 0:
        return np.array([0]), np.array([1.0])
    grid = np.stack(np.meshgrid(*([np.arange(5)] * d), indexing="ij"), -1).reshape(-1, d)
    mirror = np.ravel_multi_index(((5 - grid) % 5).T, (5,) * d)
    flat = np.arange(len(grid))
    keep = flat <= mirror
    return flat[keep], np.where(flat[keep] == mirror[keep], 1.0, 2.0)


def certified_entry_sups(family: FourierFamily, pairs=3, single_cells=None, pair_cells=None):
    """S (V, n, n): the least over the subsets tried of :func:`partial_wiener_sups`: every single free coordinate
    (all entries); then, parameter set by parameter set from the one of largest rho(S_v) while it can still raise
    max_v rho(S_v), the pairs among the ``pairs`` coordinates whose single grids lowered rho(S) most (head entries
    only, :meth:`FourierFamily.head`). Grids of ``single_cells`` and ``pair_cells`` cells (default
    ``SINGLE_CELLS``, ``PAIR_CELLS``)."""
    single_cells = SINGLE_CELLS if single_cells is None else single_cells
    pair_cells = PAIR_CELLS if pair_cells is None else pair_cells
    m = len(family.idx)
    s = family.wiener.copy()
    gains = []
    for b in range(m):
        single = partial_wiener_sups(family, (b,), single_cells)
        gains.append(perron_of(single).max())
        s = np.minimum(s, single)
    if pairs < 2 or m < 2:
        return s
    head = family.head()
    top = sorted(np.argsort(gains, kind="stable")[:pairs])
    rho = perron_of(s)
    done = np.zeros(len(rho), bool)
    while not done.all():
        v = int(np.argmax(np.where(done, -np.inf, rho)))
        if done.any() and rho[v] <= rho[done].max():
            break  # the parameter sets left cannot raise the max
        mask = np.zeros(family.shape, bool)
        mask[v, head[:, None], head[None, :]] = True
        for subset in itertools.combinations(top, 2):
            s = np.minimum(s, partial_wiener_sups(family, subset, pair_cells, mask))
        rho[v] = perron_of(s[v])
        done[v] = True
    return s
