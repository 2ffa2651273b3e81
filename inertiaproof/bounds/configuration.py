"""Ingredients and constants of the Section 4 bounds for a chain and a parameter trajectory, as plain data.

Configuration extremes (inf/sup over q of eigenvalues of M, singular values of
QJ, of Y_p = dK_p/dq - dK_p/dq^T (DefK)) are bracketed with
:func:`inertiaproof.bounds.extremes.bracket_extreme`. The certified side rests on
two facts:

- QJ is a trigonometric polynomial of degree <= 1 in every revolute
  coordinate and an algebraic polynomial of degree <= 1 in every prismatic one
  (joint rotations enter once per product; cross products of vectors turned by
  the same rotation are turned by it), so M = (QJ)^T Z QJ has degree <= 2.
  Bernstein's inequality (a full period) and Markov's (a finite interval)
  bound every partial derivative of x^T A(q) y by c_j sup |x^T A y|, hence
  the Taylor remainder of A on a box of radii r by 1/2 S (sum_j c_j r_j)^2,
  S = sup ||A|| over the Bernstein domain.
- lambda_max and sigma_max are convex, lambda_min concave, in the linear part
  A(c) + sum_j d_j dA/dq_j(c): their extremes over a box lie at its vertices.

Up to ``VERTEX_LIMIT`` free coordinates the 2^d vertices are enumerated (the linear part exactly). Beyond, a
box costs O(n) symmetric eigenproblems (:mod:`inertiaproof.bounds.taylor`: per-entry degrees and sizes, a
second-order remainder, the linear part by matrix absolute values), so time and memory grow polynomially with
the joints; the budget is a count of rounds scaled by the cost of a box, with a wall-clock guard, and where it
runs out the bracket is wider, never missing. Every sup of lambda_max or |lambda|_max is also bounded by the
spectral radius of entrywise bounds of |M_il(q)| (Perron-Frobenius; lengths, or the Wiener norm of M's exact
Fourier coefficients); with a Fourier series (at most FOURIER_LIMIT free turning joints) :func:`mass_sup` and
:func:`jacobian_sup` also adopt the spectral radius of certified sups of |M_il| over the search box, one or two
coordinates on a grid over their joint limits (:mod:`inertiaproof.bounds.fourier`, :func:`fourier_perron_bound`).
With a budget of PIVOT_MIN_S or more per bracket and at most PIVOT_LIMIT free coordinates, the infima adopt a
ladder of targets proved with the articulated-body pivots of M - gamma I (:mod:`inertiaproof.bounds.pivot_search`;
with a deep budget first the chain split at a body, :mod:`inertiaproof.bounds.interface`), and the suprema, where
still wider than the ladder's goal, the same ladder on gamma I - M (:func:`_tighten_by_ladder`).
Every bracket adopts a sharper certified side only through :meth:`inertiaproof.bounds.extremes.Bracket.tighten`.

Over time, Theta(t) of payloads and scalings lies on segments
Theta_base + s Phi_load with s in the profile's range; spectral extremes that
are concave or convex in Theta are then attained at the segment's ends (exact
for one load per body). Moving masses are bounded by positivity (Z(Phi_load) >= 0)
and by the profile's rate and acceleration bounds.

The entry point for audits is :func:`mass_matrix_bounds`.
"""

from __future__ import annotations

import functools
import itertools

import numpy as np

from inertiaproof.dynamics import composite
from inertiaproof.model.inertia import spatial_inertia

from .domain import (
    bernstein_domain, certification_obstacle, chain_key, content_memo, derivative_factors, free_coordinates, search_box,
)
from .extremes import bracket_extreme
from .fourier import PAIR_CELLS, SINGLE_CELLS, FourierFamily, certified_entry_sups, perron_of
from .axial_form import axial_lower_form, form_lmin
from .certificate import PivotProof, SkewClaim, SpectrumClaim, distinct, partition_tree
from .interface import EVIDENCE, split_ladder
from .lengths import _block_rows, _unit_bodies, column_bounds, lever_bounds
from .pivot_search import DEEP_S, EXTRA, ladder_budget, ladder_goal, pivot_ladder
from .pivots import METRICS, PIVOT_LIMIT, PIVOT_MIN_S, PivotFamily
from .taylor import MassFamily, box_bounds, perron_bound
from .spectral import CONVEX, EPS, ROUNDING, Spectral, spectral

__all__ = [
    "apriori_bound", "apriori_jacobian_blocks", "block_lower_form", "column_bounds", "configuration_bracket", "EPS",
    "FOURIER_DEEP_S", "FOURIER_PAIRS_S", "form_ladder", "fourier_perron_bound", "jacobian_family",
    "jacobian_normality", "jacobian_sup", "lever_bounds", "mass_family", "mass_inf", "mass_spectra", "mass_sup", "ROUNDING",
    "box_cost", "pivot_normality", "skew_partial_sup", "VERTEX_LIMIT", "skew_partials", "triangular_normality_floor", "value_for_norm", "vertex_bound",
]


REAL_PROBE = 3  # the real inertias' probe: 1/3 of the ci budget (SO-101: 64x proved after 9,000 boxes, 1.45x at 45,000)
AXIAL_FIRST = 1.1  # in ci another form runs before the isotropic one where its sampled inf is this much higher
REPROVABLE = 1 + 2**-10  # the narrowest bracket reported: a certified side within 1e-6 of an extreme attained along a
# curve (spatial 3R's sup lambda_max((QJ)^T QJ)) is beyond the independent checker's boxes (not within 50,000 cuts;
# 1e-4 away: 49,000 boxes; 1e-3: 1,400), so a narrower bracket is widened to this ratio (Bracket.widen)
VERTEX_LIMIT = 6  # free coordinates up to which the 2^d vertices of the linear part are enumerated (exact linear part)

# -- matrix families A(q) with derivatives --------------------------------------

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


VERTEX_SHARE = (0.25, 0.05)  # of a bracket's budget (under DEEP_S, from it) for branch and bound with vertex bounds
# where the pivot ladders run after it


def configuration_bracket(chain, family, kind, *, quantity_name, samples, refine_s, rng, value_kind=None,
                          square=False, progress=None, thetas=None):
    """Bracket of sup (convex kinds) or inf (lmin) over the chain's configurations of kind(M(q, Theta_v)).

    ``family`` is (evaluate, degree) from :func:`mass_family` (degree 2, with its ``thetas``); the value over a
    stack of parameter sets is the worst over the stack. ``value_kind`` overrides how the observed side is
    computed (e.g. 'smin' of QJ by SVD while the certified side bounds lmin of (QJ)^T QJ); ``square`` squares
    observed singular values to match. The certified side is branch and bound with
    :func:`inertiaproof.bounds.taylor.box_bounds` (polynomial in the number of joints per box). Where the pivot
    ladders run after it (:func:`_ladders_run`), it gets ``VERTEX_SHARE`` of the budget (Panda, 2 kg, deep: its
    certified side of Theorem 2's inf is 0, the ladders' 1.5e-3; Panda's five deep brackets 723 s -> 403 s with the
    threads of the pivot test at a share of 0.25, 418 s -> 365 s from 0.25 to 0.05, the same ratios).
    """
    evaluate, degree = family
    sense = Spectral(kind).sense
    pick = np.max if sense == "max" else np.min
    obs_kind = value_kind or kind

    source = evaluate if value_kind is None else jacobian_family(chain)[0]

    def value(q):
        v = spectral(source(q, derivatives=False), obs_kind)
        return pick(v**2 if square else v, axis=-1)

    lo, hi = search_box(chain)
    free = free_coordinates(chain)
    obstacle = certification_obstacle(chain)
    if _ladders_run(chain, refine_s):  # the ladders' certified sides are sharper there
        refine_s *= VERTEX_SHARE[refine_s >= DEEP_S]
    if obstacle is None and (degree != 2 or thetas is None) and free.sum() > VERTEX_LIMIT:
        obstacle = "no polynomial box bound for this family"
    if obstacle is not None:
        return bracket_extreme(value, None, lo, hi, sense=sense, quantity_name=quantity_name, samples=samples,
                               refine_s=refine_s, rng=rng, free=free, note=obstacle)
    if free.sum() <= VERTEX_LIMIT:
        return _vertex_bracket(chain, family, kind, value, lo, hi, free, quantity_name=quantity_name, samples=samples,
                               refine_s=refine_s, rng=rng, progress=progress, thetas=thetas)
    apriori = apriori_bound(chain, thetas, "sup")
    fam = MassFamily(chain, thetas)
    weights = fam.factors.max(axis=(0, 1))  # split where the entries can move most

    def box_bound(c, r):
        return box_bounds(fam, kind, c, r)

    note = ("second-order Taylor bound per box: entry sizes from lengths, Bernstein/Markov remainder, "
            "congruence by the centre's Cholesky factor for lambda_min; rounding allowances stated in "
            "inertiaproof.bounds.taylor")
    result = bracket_extreme(value, box_bound, lo, hi, sense=sense, quantity_name=quantity_name, samples=samples,
                             refine_s=refine_s, rng=rng, free=free, weights=weights, progress=progress, note=note,
                             cost=box_cost(chain.n, len(fam.thetas)))
    psd = bool(np.all(spectral(spatial_inertia(np.asarray(thetas, float)), "lmin") >= 0))
    return _with_fallback(result, kind, apriori, psd, chain, thetas)


def _vertex_bracket(chain, family, kind, value, lo, hi, free, *, quantity_name, samples, refine_s, rng, progress=None,
                    thetas=None):
    """The certified side of :func:`configuration_bracket` for at most VERTEX_LIMIT free coordinates (no
    certification obstacle): the extreme of the linear part at a box's vertices plus a Taylor remainder.

    ``family`` is (evaluate, degree) from :func:`jacobian_family` or :func:`mass_family`; ``value`` the observed
    side over configurations (K, n) -> (K,) on the search box [lo, hi].
    """
    evaluate, degree = family
    sense = Spectral(kind).sense
    dlo, dhi = bernstein_domain(chain)
    factors = derivative_factors(chain, dlo, dhi, degree)
    apriori = apriori_bound(chain, thetas if degree == 2 else None, "sup")
    same = np.allclose(dlo[free], lo[free]) and np.allclose(dhi[free], hi[free])

    def bound_with(scale, kind_here):
        def box_bound(c, r):
            a, da = evaluate(c)
            v = vertex_bound(a, da, r, free, kind_here)
            rho = (r[:, free] * factors[free]).sum(1)
            rem = 0.5 * rho**2
            if scale is None:  # self-referential: the sup itself bounds the remainder (box holding the maximiser)
                with np.errstate(over="ignore"):  # rem just below 1: the quotient overflows to inf, a valid bound
                    return np.where(rem < 1, np.maximum(v, 0) / np.maximum(1 - rem, 1e-300), np.inf)
            return v + scale * rem if kind_here in CONVEX else v - scale * rem
        return box_bound

    stage = refine_s / 2 if (sense == "min" or not same) else refine_s
    scale, note = None, ""
    norm_kind = "smax" if degree == 1 else "absmax"
    if sense == "min" or not same:
        sup = bracket_extreme(value_for_norm(evaluate, norm_kind), bound_with(None, norm_kind), dlo, dhi, sense="max",
                              quantity_name=f"sup ||A|| for {quantity_name}", samples=samples, refine_s=stage,
                              rng=rng, free=free, weights=factors, cost=_legacy_cost(free))
        scale = min(np.inf if sup.certified is None else sup.certified, apriori)
        note = f"Taylor remainder scaled by sup ||A|| <= {scale:.6g} over a full period (certified)"
        if not np.isfinite(scale):
            return _with_fallback(bracket_extreme(value, None, lo, hi, sense=sense, quantity_name=quantity_name,
                                                  samples=samples, refine_s=stage, rng=rng, free=free,
                                                  note="sup ||A|| over a period not certified in the time budget"),
                                  kind, apriori, thetas is not None)
    result = bracket_extreme(value, bound_with(scale, kind), lo, hi, sense=sense, quantity_name=quantity_name,
                             samples=samples, refine_s=stage if scale is not None else refine_s, rng=rng, free=free,
                             weights=factors, progress=progress, note=note, cost=_legacy_cost(free))
    if scale is not None and sense == "max":
        result.tighten(scale, "the sup over a period is sharper")
    psd = thetas is not None and bool(np.all(spectral(spatial_inertia(np.asarray(thetas, float)), "lmin") >= 0))
    return _with_fallback(result, kind, apriori, psd, chain, thetas)


def _legacy_cost(free):
    """The vertex path's cost: 2^d vertices per box, 45 per round and second of budget (calibrated: refine_s is about
    the seconds a bracket takes on 2 loaded cores)."""
    d = int(np.sum(free))
    return 2.0**d / 45.0 if d <= VERTEX_LIMIT else box_cost(len(free))


def box_cost(n, stack=1):
    """Relative cost of one box bound against a 7-joint chain with one parameter set (O(n^4) per box)."""
    return max(1.0, stack * (n / 7.0) ** 4)


def _with_fallback(result, kind, apriori, psd, chain=None, thetas=None):
    """Where branch and bound certified less: the Perron bound of the entry sizes or the a priori length bound
    (sup), or 0 (inf of a PSD form)."""
    if kind in CONVEX:
        result.tighten(apriori, "the a priori bound from link lengths (Frobenius norm) is sharper")
        if thetas is not None and kind in ("lmax", "absmax") and certification_obstacle(chain) is None:
            result.tighten(perron_bound(MassFamily(chain, thetas)),
                           "spectral radius of the entrywise bounds |M_il(q)| <= S_il from lengths (Perron-Frobenius)")
    elif kind == "lmin" and psd:
        result.tighten(0.0, "0, as M = (QJ)^T Z QJ with Z >= 0 (key step, positivity of L)")
    return result


def value_for_norm(evaluate, kind):
    def value(q):
        return spectral(evaluate(q, derivatives=False), kind).max(-1)
    return value


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
    substitution from nonnegative terms only, each step rounded up (:func:`_comparison_inverse`),
    and the norms from nonnegative sums inflated by their rounding bound (O(n^3) floats: a 100-joint
    chain in milliseconds, where exact rationals grew without bound).
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
        inverse = _comparison_inverse(diag, off)
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


def _comparison_inverse(diag, off):
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


# -- the ingredients over configurations ----------------------------------------------

def jacobian_sup(chain, **kw):
    """sup_q sigma_max(QJ) (SVD). Beyond ``VERTEX_LIMIT`` free coordinates: the square root of the bracket of
    sup_q lambda_max((QJ)^T QJ), the mass matrix of unit bodies (Z = I), whose box bounds are polynomial."""
    if free_coordinates(chain).sum() <= VERTEX_LIMIT or certification_obstacle(chain) is not None:
        b = configuration_bracket(chain, jacobian_family(chain), "smax", quantity_name="sup_q sigma_max(QJ)", **kw)
        if certification_obstacle(chain) is None:
            unit = _unit_bodies(chain)
            _tighten_by_fourier(b, chain, unit, kw.get("refine_s", 0.0), square=False)
            _tighten_by_ladder(b, chain, unit, kw.get("refine_s", 0.0), square=False)
            b.certify = SpectrumClaim(chain, unit, "lambda_max", square=True)
        return b.widen(REPROVABLE)
    unit = _unit_bodies(chain)
    b = configuration_bracket(chain, mass_family(chain, unit), "lmax", value_kind="smax", square=True,
                              quantity_name="sup_q sigma_max(QJ)", thetas=unit, **kw)
    _tighten_by_fourier(b, chain, unit, kw.get("refine_s", 0.0), square=True)
    _tighten_by_ladder(b, chain, unit, kw.get("refine_s", 0.0), square=True)
    root = (lambda x: None if x is None else float(np.sqrt(max(x, 0.0))))
    b.observed, b.certified = root(b.observed), None if b.certified is None else _root_up(max(b.certified, 0.0))
    b.convergence = [[t, root(lo), root(hi)] for t, lo, hi in b.convergence]
    b.note += "; square roots of the bracket of sup_q lambda_max((QJ)^T QJ) (unit bodies)"
    b.certify = SpectrumClaim(chain, unit, "lambda_max", square=True)
    return b.widen(REPROVABLE)


def _ladders_run(chain, refine_s):
    """Whether the pivot ladders run: a budget of PIVOT_MIN_S or more per bracket, a certified bracket possible and
    at most PIVOT_LIMIT free coordinates (an arm and its gripper's joint)."""
    return (refine_s >= PIVOT_MIN_S and certification_obstacle(chain) is None
            and free_coordinates(chain).sum() <= PIVOT_LIMIT)


def jacobian_normality(chain, **kw):
    """inf_q sigma_min(QJ)^2 = inf_q lambda_min((QJ)^T QJ) (Definition 2): observed by SVD of QJ; the certified side is
    the best of branch and bound (vertices; with a budget of PIVOT_MIN_S or more also the articulated-body pivots:
    with a deep budget the chain split at a body first, :mod:`inertiaproof.bounds.interface`, then the ladder where
    still short of its goal) and the chain's :func:`triangular_normality_floor`."""
    unit = _unit_bodies(chain)
    result = configuration_bracket(chain, mass_family(chain, unit), "lmin", value_kind="smin", square=True,
                                   quantity_name="inf_q sigma_min(QJ)^2", thetas=unit, **kw)
    result.certify = SpectrumClaim(chain, unit, "lambda_min")
    result.tighten(triangular_normality_floor(chain),
                   "certified side from the block-triangular structure of QJ (unit twist of joint l in column l of "
                   "body l's block, lengths bound the rest): valid for every q")
    refine_s = kw.get("refine_s", 0.0)
    ladders = _ladders_run(chain, refine_s)
    if ladders and refine_s >= DEEP_S:  # the split first (Panda 1.01x in 6 s, the ladder's 1.03x in 32 s)
        gamma, how, proof = split_ladder(chain, unit, result.observed, refine_s, floor=result.lower)
        result.tighten(gamma, f"(QJ)^T QJ - gamma I > 0 (unit bodies) {EVIDENCE}: {how}", proof)
    if ladders and (refine_s < DEEP_S or result.upper > ladder_goal(refine_s) * result.lower):
        gamma, how, proof = pivot_normality(chain, refine_s, kw.get("samples", 2000), detail=True)
        result.tighten(gamma, "a ladder of targets gamma, each proved by branch and bound with the articulated-body "
                              f"pivots of (QJ)^T QJ - gamma I on each box (inertiaproof.bounds.pivot_search): {how}",
                       proof)
    return result.widen(REPROVABLE)


def pivot_normality(chain, refine_s, samples, weights=None, stop=None, detail=False, angular=None):
    """A certified lower bound of inf_q lambda_min(sum_l QJ_l^T diag(mu_l I3, nu_l I3) QJ_l) (mu_l the smallest
    over the rows of ``weights`` (V, N): the form is monotone in mu, so one form bounds the stack; nu = ``angular``
    (N,), mu when None; mu = 1 when None: inf_q sigma_min(QJ)^2) by a ladder of targets proved with the pivot test
    (:func:`inertiaproof.bounds.pivot_search.pivot_ladder`); -inf where none was proved. The ladder stops once
    its bound is ``stop`` or more (default: the form's own observed inf over :func:`ladder_goal`). Its own seed,
    so the same chain and budget give the same number; cached by content. ``detail``: (bound, a note on the
    ladder: the rung proved, boxes tested, partition size, its :class:`PivotProof`)."""
    weights = np.ones((1, chain.bodies)) if weights is None else np.asarray(weights, float)
    weights = weights.min(0, keepdims=True)
    angular = weights if angular is None else np.asarray(angular, float).reshape(weights.shape)
    key = (chain_key(chain), refine_s, samples, weights.tobytes(), angular.tobytes(), stop)
    found = content_memo(_PIVOT_CACHE, key, lambda: _pivot_normality(chain, np.random.default_rng(0), refine_s,
                                                                     samples, weights, angular, stop))
    return found if detail else found[0]


_PIVOT_CACHE = {}


def _pivot_normality(chain, rng, refine_s, samples, weights, angular, stop):
    unit = _block_rows(weights[0], angular[0])[None]  # (1, N, 10): Z_l = diag(mu_l I3, nu_l I3)
    family = PivotFamily(chain, unit)

    def values(q):
        return mass_spectra(chain, unit, q, "lmin")  # (K, 1)

    lo, hi = search_box(chain)
    free = free_coordinates(chain)
    found = bracket_extreme(lambda q: values(q).min(-1), None, lo, hi, sense="min",
                            quantity_name="inf_q lambda_min of the unit form (pivots)", samples=samples,
                            refine_s=refine_s, rng=rng, free=free)
    stop = found.observed / ladder_goal(refine_s) if stop is None else stop
    return _ladder(chain, family, values, found.observed, found.witness, ladder_budget(refine_s), stop, forms=True)


def _ladder(chain, family, values, observed, witness, budget, stop, sign=1.0, forms=False):
    """:func:`pivot_ladder` over the chain's search box within ``budget`` (boxes, seconds): (gamma, a note on the
    rung proved, the partition's size and the boxes tested, its :class:`PivotProof` or None; ``forms``: the family's
    bodies are lower forms of the claim's, which the proof carries)."""
    lo, hi = search_box(chain)
    found = pivot_ladder(family, values, observed, witness, lo, hi, free_coordinates(chain), max_boxes=budget[0],
                         guard_s=budget[1], stop=stop, sign=sign)
    note = ("no target proved" if found.ratio is None else f"target {observed:.6g}{'/' if sign > 0 else '*'}"
            f"{found.ratio:g} proved on a partition of {found.size} boxes ({found.tested} boxes tested)")
    proof = None if found.partition is None else PivotProof(partition_tree(*found.partition, lo, hi),
                                                            family.z if forms else None, (family.metric, family.ridge))
    return found.gamma, note, proof


def form_ladder(chain, forms, refine_s, samples, stop, probe=0, metrics=METRICS[:1]):
    """A certified lower bound of inf_q lambda_min(sum_l QJ_l^T Y_l QJ_l) for body forms ``forms`` (V, N, 6, 6)
    (any symmetric Y_l; :mod:`inertiaproof.bounds.axial_form`) by the ladder of targets proved with the pivot test
    (:func:`inertiaproof.bounds.pivot_search.pivot_ladder`), stopping once its bound is ``stop`` or more; -inf where
    none was proved. ``probe`` k > 0: 1/k of the ci budget only (k = EXTRA: 7,500 boxes; a form the pivots cannot
    handle costs little). ``metrics``: the loss metrics the ladder may calibrate (pivots.METRICS).
    Returns (bound, the form's sampled inf, a note on the ladder, its :class:`PivotProof`); its own seed, cached by
    content."""
    forms = np.ascontiguousarray(forms, float)
    key = (chain_key(chain), refine_s, samples, forms.tobytes(), stop, probe, metrics)
    return content_memo(_PIVOT_CACHE, key, lambda: _form_ladder(chain, forms, refine_s, samples, stop, probe, metrics))


def _form_ladder(chain, forms, refine_s, samples, stop, probe, metrics):
    family = PivotFamily(chain, inertias=forms, metrics=metrics)

    def values(q):
        return form_lmin(chain, forms, q)  # (K, 1)

    lo, hi = search_box(chain)
    free = free_coordinates(chain)
    found = bracket_extreme(lambda q: values(q).min(-1), None, lo, hi, sense="min",
                            quantity_name="inf_q lambda_min of a lower form (pivots)", samples=samples,
                            refine_s=min(refine_s, 2.0), rng=np.random.default_rng(0), free=free)
    boxes, guard_s = ladder_budget(min(refine_s, PIVOT_MIN_S) if probe else refine_s)
    if probe:  # a share of the ci budget whatever the profile: a form that fails here fails with more too (measured)
        boxes, guard_s = boxes // probe, guard_s / probe
    gamma, note, proof = _ladder(chain, family, values, found.observed, found.witness, (boxes, guard_s), stop,
                                 forms=True)
    return gamma, found.observed, note, proof


def block_lower_form(thetas, points, chain, grid=64):
    """(mu, nu) (N,) with diag(mu_l I3, nu_l I3) <= Z(Theta_v)_l for every parameter set v, chosen to make
    inf lambda_min(sum_l QJ_l^T diag(mu_l I3, nu_l I3) QJ_l) large at the configurations ``points`` (coordinate
    ascent over mu_l on a grid of fractions of the mass, nu_l the largest by bisection; a heuristic, starting
    from the isotropic pair lambda_min(Z_l) rounded down). Every pair adopted is checked:
    lambda_min(Z_vl - diag(mu_l I3, nu_l I3)) less ROUNDING eps of its Frobenius norm > 0 (Weyl).

    Measured (Panda +2 kg, inf over 100,000 configurations): the form's inf 1.584e-3 with 16 fractions, 1.603e-3
    with 32, 1.607e-3 with 64 (1.8 s); no such form does better than 1.609e-3 (M: 1.778e-3): the SDP max t
    subject to diag(mu_l I3, nu_l I3) <= Z_vl and the form >= t I at the 150 configurations where it is lowest,
    100 more per round up to 550, gives 1.6092e-3 every round (fewer configurations can only raise it), with a
    coupling k_l I3 between the blocks too 1.6093e-3. So Theorem 2's bracket through this form cannot be narrower
    than 1.105x on Panda."""
    z = spatial_inertia(np.asarray(thetas, float))  # (V, N, 6, 6)
    iso = (spectral(z, "lmin") - ROUNDING * EPS * spectral(z, "absmax")).min(0)

    def holds(l, a, b):
        d = z[:, l] - np.diag([a] * 3 + [b] * 3)
        return bool(np.all(spectral(d, "lmin") - ROUNDING * EPS * np.linalg.norm(d, axis=(-2, -1)) > 0))

    def largest_angular(l, a):
        lo, hi = 0.0, float(spectral(z[:, l], "lmax").max())
        for _ in range(40):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if holds(l, a, mid) else (lo, mid)
        return lo

    def inf_at(mu, nu):
        rows = _block_rows(mu, nu)[None]
        return spectral(composite.mass_matrix(chain, points[:, None], rows[None]), "lmin").min()

    mu, nu = np.maximum(iso, 0.0), np.maximum(iso, 0.0)
    best = inf_at(mu, nu)
    mass = z[:, :, 0, 0].min(0)
    for l in range(len(mu)):
        for fraction in np.geomspace(0.01, 0.95, grid):
            a = fraction * mass[l]
            b = largest_angular(l, a)
            if not holds(l, a, b):
                continue
            trial_mu, trial_nu = mu.copy(), nu.copy()
            trial_mu[l], trial_nu[l] = a, b
            value = inf_at(trial_mu, trial_nu)
            if value > best:
                best, mu, nu = value, trial_mu, trial_nu
    return mu, nu


def mass_inf(chain, thetas, **kw):
    """inf over q and the parameter sets of lambda_min(M(q, Theta)); where branch and bound certifies less, the
    proof of Theorem 2 does: lambda_min(M) >= min_l lambda_min(Z(Phi_l)) inf_q sigma_min(QJ)^2 with the
    :func:`triangular_normality_floor`, and (budget PIVOT_MIN_S or more) body by body, M(q) >= sum_l mu_l
    QJ_l^T QJ_l with mu_l <= lambda_min(Z(Phi_l)), whose inf :func:`pivot_normality` certifies (at least
    min_l mu_l inf sigma_min(QJ)^2, so the unit form's ladder is not run here); where the bracket is wider than
    :func:`ladder_goal`, also the axial form of :func:`inertiaproof.bounds.axial_form.axial_lower_form`
    (mu_l I plus an inertia about joint l's own axis, for the bodies where that raises the form's sampled inf;
    proved by :func:`form_ladder`, a probe of 1/EXTRA of the budget first), the heavy invariant form, and
    M(q) >= sum_l QJ_l^T diag(mu_l I3, nu_l I3) QJ_l with the rotation-invariant lower bounds of
    :func:`block_lower_form` (Panda: the form's inf 1.61e-3 against the isotropic form's 1.44e-3 and M's 1.78e-3;
    harder for the pivots). The forms run in the order of their sampled inf, in ci the others' divided by
    ``AXIAL_FIRST`` against the isotropic one's (easier for the pivots; UR5 1.63x -> 1.09x in ci), until the bracket
    is within the goal. With a deep budget the chain split at a body (:mod:`inertiaproof.bounds.interface`) runs
    before every form (Panda: 1.141x in 39 s with the block form first -> 1.01x in 16 s; UR5 1.01x in 3 s; not in
    ci: SO-101's audit, where it proves nothing, 12 s -> 26 s). Where still wider, the ladder on the parameter sets
    themselves (no form's gap, but anisotropic turns: a probe of 1/``REAL_PROBE``
    of ci's budget first; SO-101's audit in ci 2.87x -> 1.60x). A form whose sampled inf is not above the bracket's
    certified side is skipped (its certified inf cannot be)."""
    result = configuration_bracket(chain, mass_family(chain, thetas), "lmin",
                                   quantity_name="inf lambda_min(M(q, Theta))", thetas=thetas, **kw)
    result.certify = SpectrumClaim(chain, thetas, "lambda_min")
    z = spatial_inertia(np.asarray(thetas, float))
    z_min = float((spectral(z, "lmin") - ROUNDING * EPS * spectral(z, "absmax")).min())  # less its rounding
    floor = max(z_min, 0.0) * triangular_normality_floor(chain) * (1 - ROUNDING * EPS)
    isotropic = PivotProof(".", np.broadcast_to(max(z_min, 0.0) * np.eye(6), (1, chain.bodies, 6, 6)))
    result.tighten(floor, "certified side min_l lambda_min(Z(Phi_l)) times a certified lower bound of "
                          "inf sigma_min(QJ)^2 (block-triangular floor)", isotropic)
    refine_s = kw.get("refine_s", 0.0)
    if _ladders_run(chain, refine_s):
        mu = spectral(z, "lmin") - ROUNDING * EPS * spectral(z, "absmax")  # (V, N), rounded down: Z_l >= mu_l I
        stop = result.observed / ladder_goal(refine_s)
        samples = kw.get("samples", 2000)
        lo, hi = search_box(chain)
        free = free_coordinates(chain)
        q = lo + (hi - lo) * np.random.default_rng(0).random((min(samples, 4000), chain.n))
        q = np.where(free, q, 0.5 * (lo + hi))
        iso = _block_rows(mu.min(0), mu.min(0))[None]
        iso_values = mass_spectra(chain, iso, q, "lmin")[:, 0]
        worst = q[np.argsort(iso_values)[:300]]
        forms, axial = axial_lower_form(chain, thetas, q)
        axial_inf = form_lmin(chain, forms, q).min() if axial.any() else -np.inf

        def short(sampled_inf):  # short of the goal, and the form's sampled inf (>= its certified one) above the bracket
            return result.upper > ladder_goal(refine_s) * result.lower and sampled_inf > result.lower

        def isotropic():
            gamma, how, proof = pivot_normality(chain, refine_s, samples, mu, stop, detail=True)
            result.tighten(gamma, "M(q) >= sum_l mu_l QJ_l^T QJ_l with mu_l <= lambda_min(Z(Phi_l)) (key step, body "
                                  "by body), its inf certified by a ladder of targets proved with articulated-body "
                                  f"pivots (inertiaproof.bounds.pivot_search): {how}", proof)

        def proved(forms, probe=EXTRA, metrics=METRICS[:1]):  # a probe first: forms the pivots cannot handle cost
            gamma, _, how, proof = form_ladder(chain, forms, refine_s, samples, stop, probe, metrics)  # 1/probe of
            if -np.inf < gamma < stop:  # ci's budget
                gamma, _, how, proof = form_ladder(chain, forms, refine_s, samples, stop, 0, metrics)
            return gamma, how, proof

        def axial_form(forms=forms, axial=axial, kind="mu_l I + kappa_l w_l w_l^T (an inertia about joint l's own axis)"):
            gamma, how, proof = proved(forms)
            bodies = ", ".join(str(l + 1) for l in np.flatnonzero(axial))
            result.tighten(gamma, "M(q) >= sum_l QJ_l^T Y_l QJ_l with Y_l <= Z(Phi_l) (checked with rounding; body by "
                                  f"body), Y_l = {kind} for bodies {bodies} (inertiaproof.bounds.axial_form), "
                                  "lambda_min(Z_l) I for the others, its inf certified by a ladder of targets proved "
                                  f"with articulated-body pivots: {how}", proof)

        def block_form(mu, nu):
            gamma, how, proof = pivot_normality(chain, refine_s, samples, mu[None], stop, detail=True, angular=nu)
            result.tighten(gamma, "M(q) >= sum_l QJ_l^T diag(mu_l I3, nu_l I3) QJ_l with diag(mu_l I3, nu_l I3) "
                                  "<= Z(Phi_l) (checked with rounding; body by body), its inf certified by a ladder "
                                  f"of targets proved with articulated-body pivots: {how}", proof)

        def later_forms():  # the heavy invariant and block forms, built where needed (Panda: 0.5 s and 2 s)
            heavy, invariant = axial_lower_form(chain, thetas, q, heavy=True)
            block_mu, block_nu = block_lower_form(thetas, worst, chain)
            out = [(mass_spectra(chain, _block_rows(block_mu, block_nu)[None], q, "lmin").min(), AXIAL_FIRST,
                    functools.partial(block_form, block_mu, block_nu))]
            if invariant.any():
                out.append((form_lmin(chain, heavy, q).min(), AXIAL_FIRST, functools.partial(
                    axial_form, heavy, invariant, "an inertia invariant under joint l's own turn (Z_l's rotation "
                    "average)")))
            return out

        def run_in_order(candidates, handicaps=True):  # (sampled inf, handicap, run): the highest sampled inf
            # (divided by its handicap) first
            for sampled_inf, _, run in sorted(candidates, key=lambda c: -c[0] / (c[1] if handicaps else 1.0)):
                if short(sampled_inf):
                    run()

        def split():
            gamma, how, proof = split_ladder(chain, thetas, result.observed, refine_s, floor=result.lower)
            result.tighten(gamma, f"M(q) - gamma I > 0 {EVIDENCE}: {how}", proof)

        first = [(iso_values.min(), 1.0, isotropic), (axial_inf, AXIAL_FIRST, axial_form)]
        if refine_s >= DEEP_S:  # the split first (no form's gap; Panda 1.01x in 16 s), then every form by its
            split()  # sampled inf alone (a deep ladder nearly closes any form)
            if short(np.inf):
                run_in_order(first + later_forms(), handicaps=False)
        else:
            run_in_order(first)
            if short(np.inf):
                run_in_order(later_forms())
        if short(np.inf):  # still short: the bodies themselves (no form's gap; anisotropic turns: a probe first)
            gamma, how, proof = proved(z, REAL_PROBE, METRICS)  # |F| keeps an indefinite P's light directions
            result.tighten(gamma, "a ladder of targets gamma, each proved by branch and bound with the "
                                  "articulated-body pivots of M(q) - gamma I on each box "
                                  f"(inertiaproof.bounds.pivot_search): {how}", proof)
    return result.widen(REPROVABLE)


def mass_sup(chain, thetas, kind="lmax", name="sup lambda_max(M(q, Theta))", goal=None, boxes=None, attained=None,
             **kw):
    """sup over q and the parameter sets of lambda_max (or sigma_max, kind='absmax') of M(q, Theta): the bracket of
    :func:`configuration_bracket`, whose certified side then adopts :func:`fourier_perron_bound` and
    :func:`_tighten_by_ladder` where sharper (``goal``: the ladder's, default :func:`ladder_goal`; ``boxes``: its
    count of boxes where more than :func:`ladder_budget`'s; ``attained``: a value the true extreme is known to reach (at
    most this sup), to which the ladder's targets are scaled in place of the bracket's observed one)."""
    result = configuration_bracket(chain, mass_family(chain, thetas), kind, quantity_name=name, thetas=thetas, **kw)
    _tighten_by_fourier(result, chain, thetas, kw.get("refine_s", 0.0), square=True)
    if kind == "absmax":  # sigma_max(M) = max(lambda_max(M), lambda_max(-M)): the stack and its negatives
        thetas = np.concatenate([np.asarray(thetas, float), -np.asarray(thetas, float)])
    result.certify = SpectrumClaim(chain, thetas, "lambda_max")
    return _tighten_by_ladder(result, chain, thetas, kw.get("refine_s", 0.0), square=True, goal=goal, boxes=boxes,
                              attained=attained).widen(REPROVABLE)


UPPER_TRIGGER = 1.25  # a sup bracket wider than this (or than the ladder's goal) runs the upper ladder
ROOT_FREE = 3  # free coordinates up to which the checker proves a side without a partition from the root box within
# ci's budget (every 2R and 3R side of a ci run); beyond, a side without one runs the ladder (UR5's Fourier sides in ci
# were not decided in 5,000 units; their ladder proves as sharp a side on a partition of 9,004 boxes in about 1 s)


def _tighten_by_ladder(result, chain, thetas, refine_s, square, goal=None, boxes=None, attained=None):
    """``result`` (a sup of lambda_max(M(q, Theta_v)) over q and the stack; of sigma_max(QJ) when ``square`` is
    False: M of unit bodies) with its certified side tightened by a ladder of targets gamma proved with the
    articulated-body pivots of gamma I - M (:func:`inertiaproof.bounds.pivot_search.pivot_ladder`, sign -1), where
    the ladders run and the bracket is still wider than ``UPPER_TRIGGER`` or :func:`ladder_goal` (in ci the ladder
    stops after its 2x with 1/EXTRA of its budget more: Panda's ci brackets 1.86x -> 1.35x for about 2 s), or its
    side has no partition on a chain of more than ``ROOT_FREE`` free joints (then a looser side proved on a
    partition replaces it). Parameter sets whose every body is <= 0 (Theorem 4's negated rates) are left out of the
    ladder: their M(q) <= 0 lies below any target (Panda's deep Thm4: 183 s -> 126 s, 1.15x -> 1.12x: the splits no
    longer follow a set that cannot fail). ``boxes``, ``attained``: as :func:`mass_sup`'s."""
    goal = ladder_goal(refine_s) if goal is None else goal
    wide = result.upper > min(goal, UPPER_TRIGGER) * result.lower
    untreed = (result.proof is None and np.isfinite(result.upper)  # no partition for the checker to walk, and
               and free_coordinates(chain).sum() > ROOT_FREE)  # too many joints for it to cut one from the root
    if not (_ladders_run(chain, refine_s) and (wide or untreed) and result.observed > 0):
        return result
    observed = result.observed if square else result.observed**2
    if attained is not None:  # the targets observed * ratio, scaled to what the true extreme reaches
        observed = attained
    if not wide:  # narrow already: the ladder aims at the side it has, to hand the checker a partition
        goal = (result.upper if square else result.upper**2) / observed
    thetas = np.asarray(thetas, float)
    thetas = distinct(thetas)  # the set once
    key = (chain_key(chain), refine_s, goal, boxes, thetas.shape, thetas.tobytes(), observed,
           np.asarray(result.witness).tobytes())
    gamma, how, proof = content_memo(_PIVOT_CACHE, key, lambda: _pivot_sup(chain, thetas, refine_s, observed,
                                                                           result.witness, goal, boxes))
    if np.isfinite(gamma) and not square:
        gamma = _root_up(gamma)
    how = ("a ladder of targets gamma, each proved by branch and bound with the articulated-body pivots of gamma I - M "
           "on each box (inertiaproof.bounds.pivot_search)" + ("" if square else ", unit bodies, square root") + f": {how}")
    if not result.tighten(gamma, how, proof) and untreed and proof is not None:
        result.certified, result.proof = gamma, proof  # looser, but what the independent checker can re-prove
        result.note += f"; {how}, reported in place of the sharper side, which has no partition the checker can walk"
    return result


def _pivot_sup(chain, thetas, refine_s, observed, witness, goal, boxes=None):
    z = spatial_inertia(thetas)  # a set whose every Z_l <= 0 (Weyl) has M(q) <= 0: below any gamma > 0, left out
    thetas = thetas[~(spectral(z, "lmax") + ROUNDING * EPS * spectral(z, "absmax") <= 0).all(1)]  # (Thm4: -Thetadot)
    family = PivotFamily(chain, thetas)

    def values(q):
        return mass_spectra(chain, thetas, q, "lmax")  # (K, V)

    budget = ladder_budget(refine_s)
    if boxes is not None and boxes > budget[0]:  # more boxes, and the wall-clock guard in proportion
        budget = (boxes, budget[1] * boxes / budget[0])
    return _ladder(chain, family, values, observed, witness, budget, observed * goal, sign=-1.0)


def _root_up(x):
    """sqrt(x) rounded up (a certified bound of sigma_max(QJ) from one of sigma_max(QJ)^2)."""
    return float(np.sqrt(x) * (1 + 2 * EPS))


def _tighten_by_fourier(result, chain, thetas, refine_s, square):
    """``result`` with its certified side tightened by :func:`fourier_perron_bound` (its square root when the
    bracket is of sigma_max(QJ), ``square`` False: (QJ)^T QJ is M of unit bodies; there pairs of coordinates only
    from a budget of ``FOURIER_DEEP_S``, single ones already close most of the bracket)."""
    if not square and refine_s < FOURIER_DEEP_S:
        refine_s = min(refine_s, 0.5 * FOURIER_PAIRS_S)
    bound = fourier_perron_bound(chain, thetas, refine_s)
    if bound is not None and not square:
        bound = _root_up(bound)
    result.tighten(bound, "spectral radius of certified sups of |M_il(q)| over the search box from the exact Fourier "
                          "coefficients, one or two coordinates on a grid over their joint limits (Perron-Frobenius; "
                          "inertiaproof.bounds.fourier)" + ("" if square else ", unit bodies, square root"))
    return result


FOURIER_PAIRS_S = 0.25  # budget from which pairs of coordinates are gridded too (head entries)
FOURIER_DEEP_S = 5.0  # budget from which four coordinates pair up, on grids twice as fine


def fourier_perron_bound(chain, thetas, refine_s=0.0):
    """max_v rho(S_v) >= sup over the search box of |lambda|_max(M(q, Theta_v)), with S from
    :func:`inertiaproof.bounds.fourier.certified_entry_sups` (pairs of three coordinates from a budget of
    ``FOURIER_PAIRS_S``; of four, on grids twice as fine, from ``FOURIER_DEEP_S``); None where M has no Fourier
    series. Cached by content."""
    if certification_obstacle(chain) is not None:
        return None
    pairs, fine = (0, 1) if refine_s < FOURIER_PAIRS_S else ((4, 2) if refine_s >= FOURIER_DEEP_S else (3, 1))
    thetas = np.asarray(thetas, float)
    key = (chain_key(chain), thetas.shape, thetas.tobytes(), pairs, fine)
    return content_memo(_PERRON_CACHE, key, lambda: _fourier_perron(chain, thetas, pairs, fine))


_PERRON_CACHE = {}


def _fourier_perron(chain, thetas, pairs, fine):
    kept = []  # |M(q, -Theta)| = |M(q, Theta)| entrywise (M is linear in Theta): one of each pair +-Theta
    for theta in thetas:
        if not any(np.array_equal(theta, t) or np.array_equal(-theta, t) for t in kept):
            kept.append(theta)
    family = FourierFamily(chain, np.array(kept))
    if not family.usable:
        return None
    s = certified_entry_sups(family, pairs, fine * SINGLE_CELLS, fine * PAIR_CELLS)
    return float(perron_of(s).max() * (1 + 4 * EPS))


def skew_partials(dqj):
    """Y_p = dK_p/dq - (dK_p/dq)^T for every row p of QJ (DefK, proof of Theorem 5): (..., 6N, n, n)."""
    return dqj - np.swapaxes(dqj, -1, -2)


def skew_partial_sup(chain, *, samples, refine_s, rng, progress=None):
    """Brackets of max_p sup_q sigma_max(Y_p(q)) and of sup_q (sum_p sigma_max(Y_p)^2)^(1/2).

    Y_p has degree <= 1 per coordinate like QJ, so a first-order Bernstein bound
    applies: sigma(Y_p(q)) <= sigma(Y_p(c)) + S rho on a box, with S the sup itself.
    Each certified side cites a ``skew-partials`` certificate (:class:`.certificate.SkewClaim`) carrying the
    partition its branch and bound proved on.
    """
    def sigmas(q):
        return spectral(skew_partials(chain.body_jacobian_derivative(q)), "smax")  # (K, 6N)

    lo, hi = search_box(chain)
    free = free_coordinates(chain)
    obstacle = certification_obstacle(chain)
    factors = derivative_factors(chain, *bernstein_domain(chain), 1)
    same = np.allclose(bernstein_domain(chain)[0][free], lo[free]) and np.allclose(bernstein_domain(chain)[1][free], hi[free])

    def max_bound(c, r):
        rho = (r[:, free] * factors[free]).sum(1)
        return np.where(rho < 1, sigmas(c).max(1) / np.maximum(1 - rho, 1e-300), np.inf)

    usable = obstacle is None and same
    worst = bracket_extreme(lambda q: sigmas(q).max(1), max_bound if usable else None, lo, hi, sense="max",
                            quantity_name="max_p sup_q sigma_max(Y_p)", samples=samples, refine_s=refine_s / 2,
                            rng=rng, free=free, weights=factors, progress=progress, cost=_legacy_cost(free),
                            note=obstacle or ("" if same else "joint limits inside a period: no certified side"),
                            partition=True)
    worst.certify = SkewClaim(chain, "max_sigma") if usable else None
    s = worst.certified

    def rss_bound(c, r):
        rho = (r[:, free] * factors[free]).sum(1)
        return np.sqrt(((sigmas(c) + s * rho[:, None]) ** 2).sum(1))

    rss = bracket_extreme(lambda q: np.sqrt((sigmas(q) ** 2).sum(1)),
                          rss_bound if usable and s is not None and np.isfinite(s) else None, lo, hi, sense="max",
                          quantity_name="sup_q (sum_p sigma_max(Y_p)^2)^(1/2)", samples=samples, refine_s=refine_s / 2,
                          rng=rng, free=free, weights=factors, note=worst.note, cost=_legacy_cost(free),
                          partition=True)
    rss.certify = SkewClaim(chain, "rss_sigma") if usable else None
    return worst, rss


