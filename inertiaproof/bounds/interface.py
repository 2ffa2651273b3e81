"""A certified lower bound of inf_q lambda_min(M(q, Theta)) (Theorem 2) from the chain split at a body: two branch
and bounds over half the coordinates each instead of one over all of them.

M(q) - gamma I > 0 exactly when every pivot of its tip-first factorisation is positive (:mod:`.pivots`). The pivots
of joints k+1..n-1, and the articulated inertia A_k(q) they hand to body k, depend on q_(k+1)..q_(n-1) only (the
tail); the pivots of joints k..0 are those of the head chain (joints 0..k) whose body k has the inertia A_k(q), and
that recursion is Loewner-monotone in it. So for any symmetric L (one per parameter set):

- tail: A_k(q) >= L on every box of a partition of the tail's coordinates (:func:`.pivots.interface_test`), and
- head: the head chain with body k's inertia L has positive pivots with armature -gamma on every box of a partition
  of the head's coordinates (:func:`.pivots.pivot_test`, top k)

prove lambda_min(M(q)) > gamma on the product of the two partitions, the whole domain. A box of either side has
half the coordinates, so the partitions add where the ladders of :mod:`.pivot_search` multiply. L is only numbers:
how it is found does not enter the proof. Two candidates come from SDPs over sampled configurations
(:func:`interface_inertia`, :func:`_interfaces`): the head's margin as large as possible while the tail keeps a
margin relative to |A_k|, and then the tail's margin as large as possible while the head keeps half of its own.
Both sides bound their turns in the |F| metric with ridge 1e-3 (L is indefinite: A_k with armature -gamma is
negative along the motions the tail can absorb).

Measured (deep budget, ``python bench/split_interface.py``): Panda 2 kg, split at body 4, Thm2 1.01x
proved on 9,870 tail and 15,794 head boxes (51,326 tested; the ladder over all six coordinates with the best
rotation-invariant body form: 1.14x, and an SDP caps every such form at 1.105x), Definition 2's unit bodies 1.01x
(the ladder: 1.03x); UR5, split at body 3, 1.01x for both; example-robot-data's UR5 (limits +-2 pi) 1.01x with
the second candidate. Upper sides are not split: on Panda's sup lambda_max the split proves 1.25x with the deep
budget, the ladder 1.08x. Their seconds: bench/results/bounds_timings.md.
"""

from __future__ import annotations

import time

import numpy as np

from inertiaproof.model.inertia import spatial_inertia

from .certificate import SplitProof, partition_tree
from .domain import free_coordinates, search_box
from .pivot_search import ladder_budget, partition
from .pivots import PivotFamily, articulated_lower, eigen_compose, interface_test, pivot_test

__all__ = ["EVIDENCE", "RUNGS", "SAMPLES", "SPLIT_MIN", "head_terms", "interface_inertia", "split_body", "split_ladder"]

EVIDENCE = ("from the chain split at a body: the tail's articulated inertia above an interface inertia L and the "
            "head's pivots with L, each proved by branch and bound over its own coordinates "
            "(inertiaproof.bounds.interface)")  # how a bracket cites the split's certified side
RUNGS = (1.01, 1.02, 1.05, 1.1, 1.25, 1.6, 1.95)  # observed / target, the most ambitious first (each its own L)
SAMPLES = 4000  # configurations each side of the SDP is checked on (the cutting planes come from them)
SPLIT_MIN = 4  # free coordinates from which a chain is split (3R's two: the ladders over both prove 1.01x, the split
# 1.25x)
SHARE = 2  # the split's share of a ladder's budget; each candidate L gets half of what is left (Panda's Thm2:
# 51,000 boxes of 180,000)
MARGIN = 0.05  # the tail's relative margin in the first candidate: 1 - 1/ratio up to this
CUTS = 30  # worst samples of each side added to the SDP per round
ROUNDS = 10
METRIC, RIDGE = "abs", 1e-3  # the turns' loss metric on both sides (measured, Panda 1.03x: 10-40x fewer boxes than
# 'shift' with ridge 1e-2)


def split_body(chain):
    """The body k the chain is split at: the head (joints 0..k) takes the smaller half of the free coordinates, the
    tail the larger (UR5's Thm2: 1.01x proved with the tail q4..q6; with q5, q6 none in 120,000 boxes);
    None with fewer than ``SPLIT_MIN`` free coordinates."""
    idx = np.flatnonzero(free_coordinates(chain))
    if len(idx) < SPLIT_MIN:
        return None
    return int(idx[len(idx) // 2 - 1])


def head_terms(chain, z, k, q):
    """The head's mass matrix less body k's part, sum_(b<k) QJ_b^T Z_b QJ_b (P, V, k+1, k+1), and QJ_k (P, 6, k+1), at
    configurations q (P, n): the head's M with body k's inertia L is the first plus QJ_k^T L QJ_k."""
    qj = chain.body_jacobian(q).reshape(len(q), chain.bodies, 6, chain.n)[..., :k + 1]
    fixed = sum(np.einsum("pin,vij,pjm->pvnm", qj[:, b], z[:, b], qj[:, b]) for b in range(k))
    return fixed + np.zeros((len(q), z.shape[0], k + 1, k + 1)), qj[:, k]


def _svec_index(d):
    """Rows, columns and scales of Clarabel's PSD triangle: the upper triangle by columns, off-diagonals times sqrt 2."""
    rows, cols = np.triu_indices(d)
    order = np.lexsort((rows, cols))
    rows, cols = rows[order], cols[order]
    return rows, cols, np.where(rows == cols, 1.0, np.sqrt(2.0))


def _svec(m):
    rows, cols, scale = _svec_index(m.shape[-1])
    return m[..., rows, cols] * scale


def interface_inertia(tail, metric, fixed, jac, tail_margin, head_floor):
    """The SDP max tau over symmetric L: tail_i - L >= (``tail_margin`` + a tau) metric_i for every i and
    fixed_j + jac_j^T L jac_j >= (``head_floor`` + b tau) I for every j (tail, metric (A, 6, 6), fixed (B, h, h),
    jac (B, 6, h)), where (a, b) is (0, 1) with ``head_floor`` None (taken 0: the head's margin as large as the
    tail's fixed margin allows) and (1, 0) otherwise (the tail's extra margin as large as the head's floor allows);
    solved by Clarabel: (L, tau), or (None, -inf) where it is not solved."""
    import clarabel
    import scipy.sparse as sparse

    rows, cols, _ = _svec_index(6)
    basis = np.zeros((len(rows), 6, 6))  # L = sum_m x_m basis_m
    basis[np.arange(len(rows)), rows, cols] = basis[np.arange(len(rows)), cols, rows] = 1.0
    m, h = len(rows), fixed.shape[-1]
    a_tail, b_head = (0.0, 1.0) if head_floor is None else (1.0, 0.0)
    # s = b - A x in the PSD cone, x = (L's coordinates, tau): the tail's svec(tail - margin metric - L - a tau
    # metric), the head's svec(fixed - floor I + jac^T L jac - b tau I)
    tail_a = np.concatenate([np.broadcast_to(_svec(basis).T, (len(tail), m, m)), a_tail * _svec(metric)[..., None]],
                            -1)
    head_l = _svec(np.einsum("bin,mij,bjk->bmnk", jac, basis, jac)).transpose(0, 2, 1)  # (B, h(h+1)/2, m)
    eye = np.broadcast_to(b_head * _svec(np.eye(h))[None, :, None], head_l.shape[:2] + (1,))
    a = np.vstack([tail_a.reshape(-1, m + 1), np.concatenate([-head_l, eye], -1).reshape(-1, m + 1)])
    b = np.concatenate([_svec(tail - tail_margin * metric).ravel(),
                        _svec(fixed - (head_floor or 0.0) * np.eye(h)).ravel()])
    cones = [clarabel.PSDTriangleConeT(6)] * len(tail) + [clarabel.PSDTriangleConeT(h)] * len(fixed)
    cost = np.zeros(m + 1)
    cost[-1] = -1.0
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    solution = clarabel.DefaultSolver(sparse.csc_matrix((m + 1, m + 1)), cost, sparse.csc_matrix(a), b, cones,
                                      settings).solve()
    if str(solution.status) not in ("Solved", "AlmostSolved"):
        return None, -np.inf
    x = np.asarray(solution.x)
    return np.einsum("m,mij->ij", x[:m], basis), float(x[-1])


def _abs_metric(a):
    """|A| plus 1e-2 of its largest |eigenvalue|: the tail's margin is relative in every direction."""
    w, u = np.linalg.eigh(a)
    return eigen_compose(u, np.abs(w) + 1e-2 * np.abs(w).max(-1, keepdims=True))


def _interfaces(chain, family, z, k, gamma, margin, q_tail, q_head):
    """Candidates for L (one per parameter set), each from an SDP by cutting planes over the sampled configurations
    (the worst ``CUTS`` of each side added per round): the head's margin t as large as the tail's relative ``margin``
    allows (with no tail margin where that leaves t <= gamma: not itself a candidate); then the tail's margin as large
    as the head's floor (gamma + t) / 2 allows (Panda's head needs its margin, the tail of example-robot-data's UR5
    more than 1%). Returns [(L (V, 6, 6), the head's sampled floor (V,))] with every floor above gamma; [] where a
    pivot of the tail is not positive at a sample or an SDP is not solved."""
    stack = z.shape[0]
    zero = np.zeros((len(q_tail), chain.n))
    ok, tail, _ = articulated_lower(family, np.full((len(q_tail), stack), -gamma), k, q_tail, zero)
    if not ok.all():
        return []
    metric = _abs_metric(tail)
    fixed, jac = head_terms(chain, z, k, q_head)
    found = np.zeros((2, stack, 6, 6)), np.full((2, stack), -np.inf)
    cuts = [list(np.argsort(np.linalg.eigvalsh(tail[:, v])[:, 0])[:2 * CUTS]) for v in range(stack)], \
        [list(range(2 * CUTS)) for _ in range(stack)]  # q_head starts with its corners

    def solve(v, tail_margin, floor):  # (L, the head's sampled floor), cutting planes added to cuts
        ti, hi = cuts[0][v], cuts[1][v]
        for _ in range(ROUNDS):
            lower, tau = interface_inertia(tail[ti, v], metric[ti, v], fixed[hi, v], jac[hi], tail_margin, floor)
            if lower is None:
                return None, -np.inf
            extra = tau if floor is not None else 0.0
            tail_gap = np.linalg.eigvalsh(tail[:, v] - lower - (tail_margin + extra) * metric[:, v])[:, 0]
            head_gap = np.linalg.eigvalsh(fixed[:, v] + np.swapaxes(jac, -1, -2) @ lower @ jac)[:, 0]
            if (tail_gap.min() > -1e-9 * np.abs(tail[:, v]).max()
                    and head_gap.min() >= (tau if floor is None else floor) * (1 - 1e-6)):
                break
            ti += list(np.argsort(tail_gap)[:CUTS])
            hi += list(np.argsort(head_gap)[:CUTS])
        return lower, head_gap.min()

    for v in range(stack):
        tail_margin = margin
        lower, top = solve(v, margin, None)
        if lower is not None and top <= gamma:  # that margin leaves the head none: the second from no margin
            tail_margin = 0.0
            lower, top = solve(v, 0.0, None)
        elif lower is not None:
            found[0][0, v], found[1][0, v] = lower, top
        if lower is None:
            return []
        if top > gamma:
            found[0][1, v], found[1][1, v] = solve(v, tail_margin, 0.5 * (gamma + top))
    return [(lower, floors) for lower, floors in zip(*found) if np.all(floors > gamma)]


def _score(r, losses):
    """Halve where the turn loses most times the radius (a coordinate whose turn loses nothing: the widest)."""
    return np.where(r > 0, losses * r + 1e-6 * r, -1.0)


def split_ladder(chain, thetas, observed, rounds, floor=-np.inf):
    """The largest gamma = observed / ratio (``RUNGS``, only targets above ``floor``) proved by the split at
    :func:`split_body`, within 1/``SHARE`` of the boxes and seconds of :func:`ladder_budget` (``rounds``), each of a
    rung's candidates for L (:func:`_interfaces`) within half of what is left: (gamma, a note, its
    :class:`~inertiaproof.bounds.certificate.SplitProof` or None), gamma -inf when none was proved. ``observed``
    must be attained (gamma <= observed)."""
    k = split_body(chain)
    if k is None or not observed > 0:
        return -np.inf, f"no split (fewer than {SPLIT_MIN} free coordinates)", None
    z = spatial_inertia(np.asarray(thetas, float))
    boxes, guard_s = ladder_budget(rounds, chain.n)
    boxes, deadline = boxes // SHARE, time.perf_counter() + guard_s / SHARE
    lo, hi = search_box(chain)
    free = free_coordinates(chain)
    rng = np.random.default_rng(0)
    q = np.where(free, lo + (hi - lo) * rng.random((2 * SAMPLES, chain.n)), 0.5 * (lo + hi))
    head = free & (np.arange(chain.n) <= k)
    corners = np.array(np.meshgrid(*[(lo[j], hi[j]) if head[j] else (0.5 * (lo[j] + hi[j]),) for j in range(chain.n)],
                                   indexing="ij")).reshape(chain.n, -1).T
    q_head = np.vstack([corners, q[SAMPLES:]])  # the corners among the SDP's first head constraints
    tail_family = PivotFamily(chain, inertias=z, ridge=RIDGE, metrics=(METRIC,))
    used, notes = 0, []
    for ratio in RUNGS:
        gamma = observed / ratio
        if gamma <= floor:
            continue
        candidates = _interfaces(chain, tail_family, z, k, gamma, min(1 - 1 / ratio, MARGIN), q[:SAMPLES], q_head)
        if not candidates:
            notes.append(f"{ratio:g}: no interface inertia (a pivot of the tail not positive at a sample, or the "
                         "head's sampled margin not above the target)")
            continue
        for lower, _ in candidates:
            parts, tested = _prove_split(chain, tail_family, z, k, gamma, lower, head, free, lo, hi,
                                         (boxes - used) // 2, deadline)
            used += tested
            if len(parts) == 2:
                proof = SplitProof(k, lower, *(partition_tree(*part, lo, hi) for part in parts), (METRIC, RIDGE))
                return gamma, (f"target {observed:.6g}/{ratio:g} proved split at body {k + 1}: the tail's A_{k + 1} >= "
                               f"L on {len(parts[0][0])} boxes of joints {k + 2}..{chain.n}, the head with body "
                               f"{k + 1}'s inertia L on {len(parts[1][0])} boxes of joints 1..{k + 1} ({used} boxes "
                               "tested)"), proof
        notes.append(f"{ratio:g}: not proved within the budget")
        if used >= boxes or time.perf_counter() > deadline:
            break
    return -np.inf, "split at body {}: {}".format(k + 1, "; ".join(notes) or "no target above the floor"), None


def _prove_split(chain, tail_family, z, k, gamma, lower, head, free, lo, hi, budget, deadline):
    """Branch and bound of the tail's and the head's tests with the interface inertia ``lower``, up to ``budget``
    boxes tested in all: ([the tail's partition (centres, radii), the head's] (fewer where one ran out), boxes
    tested)."""
    stack = z.shape[0]
    heads = z.copy()
    heads[:, k] = lower
    head_family = PivotFamily(chain, inertias=heads, ridge=RIDGE, metrics=(METRIC,))
    armature = (lambda c: np.full((len(c), stack), -gamma))
    sides = ((lambda c, r: _all(interface_test(tail_family, armature(c), lower, k, c, r)), free & ~head),
             (lambda c, r: _all(pivot_test(head_family, 1.0, armature(c), c, r, top=k)), head))
    parts, used = [], 0
    for test, side in sides:
        found, tested = partition(test, _score, (0.5 * (lo + hi))[None], np.where(side, 0.5 * (hi - lo), 0.0)[None],
                                  budget - used, deadline)
        used += tested
        if found is None:
            break
        parts.append(found)
    return parts, used


def _all(found):
    ok, losses = found
    return ok.all(1), losses
