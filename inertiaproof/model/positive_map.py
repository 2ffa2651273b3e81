"""The linear map L: sym(4) -> sym(6), f(Phi) -> Z(Phi), and certificates of its positivity.

Z(Phi) (DefMatrixZ) and f(Phi) (DefTrafoInertialParameters) are both linear in
Phi and f is a bijection (Theorem 1), so Z = L(f) with L = Z o f^{-1} linear.
The key steps of Theorems 2-4 are statements about L:

- Thm2 (LowerBoundedness): f >= xi I4 implies Z >= xi I6;
- Thm3 (UpperBoundedness): f <= zeta I4 implies Z <= 2 zeta I6;
- Thm4 (BoundedEffectofVaryingParam): sigma_max(Z(Phidot)) <= c sigma_max(f(Phidot))
  with the paper's c = sqrt(69) per body.

All three follow once L is positive (F >= 0 implies L(F) >= 0): then
F >= xi I4 gives L(F) >= xi L(I4), F <= zeta I4 gives L(F) <= zeta L(I4), and
-s I4 <= F <= s I4 gives -s L(I4) <= L(F) <= s L(I4); the sharpest universal
constants are lambda_min(L(I4)) and lambda_max(L(I4)), attained at F = I4.

The certificate of positivity is a positive semidefinite Choi matrix of an
extension of L to all 4x4 matrices, found by an SDP (CVXPY + Clarabel),
rounded to rationals and verified in exact arithmetic: the rounded matrix is
PSD (exact LDL^T) and reproduces L on a basis of sym(4) exactly.
"""

from __future__ import annotations

import time
import warnings
from fractions import Fraction
from functools import lru_cache

import numpy as np

from .inertia import pseudo_inertia_inverse, skew, spatial_inertia

__all__ = [
    "choi_sdp", "exact_map", "exact_psd", "extreme_eigenvalue_sdp", "key_step_proof", "kraus_choi",
    "kraus_factors", "map_of_choi", "rational", "spatial_from_pseudo", "SYM4_BASIS", "unit_symmetric",
    "verify_choi",
]

SYM4_BASIS = tuple(
    (i, j) for i in range(4) for j in range(i, 4)
)  # E_ij + E_ji (i < j) and E_ii: a basis of sym(4)


def unit_symmetric(i, j, n=4):
    """The basis element of sym(n): E_ii, or (E_ij + E_ji) / 2."""
    e = np.zeros((n, n))
    e[i, j] += 0.5
    e[j, i] += 0.5
    return e


def spatial_from_pseudo(f):
    """L(f) = Z(f^{-1}(f)) for f (..., 4, 4) symmetric."""
    return spatial_inertia(pseudo_inertia_inverse(f))


def kraus_factors():
    """A_k (3x6) with L(p p^T) = A(p)^T A(p), A(p) = sum_k p_k A_k = [s I3, -S(y)] for p = (y, s)."""
    a = np.zeros((4, 3, 6))
    a[:3, :, 3:] = -skew(np.eye(3))
    a[3, :, :3] = np.eye(3)
    return a


def kraus_choi():
    """The Choi matrix of X -> sum_kl X_kl A_k^T A_l: the Gram matrix [A_1 .. A_4]^T [A_1 .. A_4] (24x24)."""
    a = kraus_factors()
    g = np.concatenate(list(a), 1)  # 3 x 24
    return g.T @ g


# -- exact rational arithmetic -----------------------------------------------

def rational(a, max_denominator=None):
    """Fractions of an array; with ``max_denominator`` the nearest such rationals (rounding)."""
    a = np.asarray(a, dtype=float)
    if max_denominator is None:
        return np.vectorize(Fraction, otypes=[object])(a)
    return np.vectorize(lambda x: Fraction(x).limit_denominator(max_denominator), otypes=[object])(a)


def exact_psd(a):
    """(is PSD, rank, smallest nonzero pivot) of a symmetric rational matrix by LDL^T with symmetric pivoting.

    A zero pivot is allowed only when its whole remaining row is zero; a negative
    pivot, or a zero pivot with a nonzero row, proves the matrix is not PSD.
    """
    a = [[Fraction(x) for x in row] for row in np.asarray(a, dtype=object)]
    n = len(a)
    rank, smallest = 0, None
    remaining = list(range(n))
    while remaining:
        k = max(remaining, key=lambda i: a[i][i])
        pivot = a[k][k]
        if pivot < 0:
            return False, rank, pivot
        if pivot == 0:
            if any(a[i][j] != 0 for i in remaining for j in remaining):
                return False, rank, Fraction(0)
            break
        remaining.remove(k)
        rank += 1
        smallest = pivot if smallest is None else min(smallest, pivot)
        for i in remaining:
            if a[i][k] == 0:
                continue
            factor = a[i][k] / pivot
            for j in remaining:
                a[i][j] -= factor * a[k][j]
    return True, rank, smallest


def exact_map(f_exact):
    """L(F) in exact arithmetic for a rational symmetric 4x4 F (nested Fractions)."""
    f = [[Fraction(x) for x in row] for row in f_exact]
    sigma = [row[:3] for row in f[:3]]
    h = [f[i][3] for i in range(3)]
    m = f[3][3]
    tr = sigma[0][0] + sigma[1][1] + sigma[2][2]
    inertia = [[(tr if i == j else 0) - sigma[i][j] for j in range(3)] for i in range(3)]
    s = [[0, -h[2], h[1]], [h[2], 0, -h[0]], [-h[1], h[0], 0]]
    z = [[Fraction(0)] * 6 for _ in range(6)]
    for i in range(3):
        z[i][i] = m
        for j in range(3):
            z[i][3 + j] = -s[i][j]
            z[3 + i][j] = -s[j][i]
            z[3 + i][3 + j] = inertia[i][j]
    return z


def map_of_choi(choi, x):
    """The map a Choi matrix C defines, applied to X: sum_ij X_ij C_ij (exact if inputs are Fractions)."""
    out = [[Fraction(0)] * 6 for _ in range(6)]
    for i in range(4):
        for j in range(4):
            if x[i][j] == 0:
                continue
            for a in range(6):
                for b in range(6):
                    out[a][b] += x[i][j] * choi[6 * i + a][6 * j + b]
    return out


def verify_choi(choi, reference=exact_map):
    """Exact checks that a rational Choi matrix certifies positivity of L.

    Returns a dict: symmetric, psd, rank, and the largest exact mismatch between
    the map it defines and L on the basis of sym(4) (0 means it extends L).
    """
    c = [[Fraction(x) for x in row] for row in np.asarray(choi, dtype=object)]
    symmetric = all(c[i][j] == c[j][i] for i in range(24) for j in range(i))
    psd, rank, pivot = exact_psd(c) if symmetric else (False, None, None)
    mismatch = Fraction(0)
    for i, j in SYM4_BASIS:
        e = [[Fraction(0)] * 4 for _ in range(4)]
        e[i][j] += Fraction(1, 2)
        e[j][i] += Fraction(1, 2)
        got, want = map_of_choi(c, e), reference(e)
        mismatch = max(mismatch, max(abs(got[a][b] - want[a][b]) for a in range(6) for b in range(6)))
    return {"symmetric": symmetric, "psd": psd, "rank": rank, "smallest_pivot": pivot, "mismatch": mismatch}


# -- the SDP -------------------------------------------------------------------

def choi_sdp(lmap=spatial_from_pseudo):
    """Find a PSD Choi matrix of an extension of ``lmap`` (sym(4) -> sym(6)) with CVXPY + Clarabel.

    The symmetric inputs fix the symmetric part of every block; the free
    variables are the images K_ij (antisymmetric 6x6) of the antisymmetric
    inputs E_ij - E_ji. Maximises t with C >= t P on the support P of the
    diagonal blocks, rows off the support pinned to zero (a PSD matrix with a
    zero diagonal entry has a zero row). Returns (C as floats, t, status, seconds).
    """
    import cvxpy as cp

    blocks = [[None] * 4 for _ in range(4)]
    constraints = []
    free = {}
    for i in range(4):
        for j in range(4):
            base = lmap(unit_symmetric(i, j))
            if i < j:
                k = cp.Variable((6, 6))
                constraints.append(k == -k.T)
                free[i, j] = k
                blocks[i][j] = base + k
            elif i > j:
                blocks[i][j] = base - free[j, i]
            else:
                blocks[i][j] = base
    c = cp.bmat(blocks)
    diagonal = np.concatenate([np.diag(lmap(unit_symmetric(i, i))) for i in range(4)])
    support = np.flatnonzero(diagonal > 0)
    off = np.flatnonzero(diagonal <= 0)
    t = cp.Variable()
    p = np.eye(24)[support]
    reduced = p @ c @ p.T
    constraints.append(0.5 * (reduced + reduced.T) - t * np.eye(len(support)) >> 0)
    if off.size:
        constraints.append(np.eye(24)[off] @ c == 0)
    constraints.append(t <= 1)
    problem = cp.Problem(cp.Maximize(t), constraints)
    start = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the feasible set has no interior: Clarabel reports optimal_inaccurate
        problem.solve(solver="CLARABEL")
    seconds = time.perf_counter() - start
    value = None if c.value is None else 0.5 * (c.value + c.value.T)
    return value, (None if t.value is None else float(t.value)), problem.status, seconds


def extreme_eigenvalue_sdp(matrix, sense):
    """max c with matrix >= c I (sense 'min') or min c with matrix <= c I ('max'), by CVXPY + Clarabel.

    Returns (c, dual W, seconds); W >= 0 with tr W = 1 and <matrix, W> = c
    certifies that no better c exists.
    """
    import cvxpy as cp

    n = matrix.shape[0]
    c = cp.Variable()
    lmi = (matrix - c * np.eye(n) >> 0) if sense == "min" else (c * np.eye(n) - matrix >> 0)
    problem = cp.Problem(cp.Maximize(c) if sense == "min" else cp.Minimize(c), [lmi])
    start = time.perf_counter()
    problem.solve(solver="CLARABEL")
    seconds = time.perf_counter() - start
    return float(c.value), np.asarray(lmi.dual_value), seconds


@lru_cache(maxsize=4)
def key_step_proof(max_denominator=1000):
    """The certificate behind Theorems 2-4, computed once per process.

    Returns plain data: the SDP's Choi matrix rounded to rationals and its exact
    verification, L(I4) exactly, the sharp constants lambda_min(L(I4)) and
    lambda_max(L(I4)) (with their SDP values and dual certificates) and the
    solve times.
    """
    choi, t, status, choi_seconds = choi_sdp()
    if choi is None:
        return {"ok": False, "reason": f"Choi SDP returned status {status}", "sdp_status": status}
    rounded = rational(choi, max_denominator)
    check = verify_choi(rounded)
    identity = [[Fraction(int(i == j)) for j in range(4)] for i in range(4)]
    l_identity = exact_map(identity)
    diag = [l_identity[i][i] for i in range(6)]
    offdiag_zero = all(l_identity[i][j] == 0 for i in range(6) for j in range(6) if i != j)
    lower, w_low, s_low = extreme_eigenvalue_sdp(np.array(l_identity, dtype=float), "min")
    upper, w_up, s_up = extreme_eigenvalue_sdp(np.array(l_identity, dtype=float), "max")
    lower_exact, upper_exact = min(diag), max(diag)
    lower_ok = exact_psd([[l_identity[i][j] - (lower_exact if i == j else 0) for j in range(6)] for i in range(6)])[0]
    upper_ok = exact_psd([[(upper_exact if i == j else 0) - l_identity[i][j] for j in range(6)] for i in range(6)])[0]
    ok = check["symmetric"] and check["psd"] and check["mismatch"] == 0 and offdiag_zero and lower_ok and upper_ok
    return {
        "ok": bool(ok),
        "choi_rank": check["rank"],
        "choi_psd": check["psd"],
        "choi_mismatch": float(check["mismatch"]),
        "choi_max_denominator": max(x.denominator for x in rounded.flat),
        "choi_interior_margin": t,
        "sdp_status": status,
        "choi_seconds": choi_seconds,
        "l_identity_diagonal": [str(x) for x in diag],
        "lower": float(lower_exact),
        "upper": float(upper_exact),
        "lower_sdp": lower,
        "upper_sdp": upper,
        "eigen_seconds": s_low + s_up,
        "choi": [[str(x) for x in row] for row in rounded],
    }
