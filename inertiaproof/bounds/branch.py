"""Branch and bound over configurations for a bracket's first certified side: the extreme of the linear part at a box's
vertices plus a Bernstein/Markov remainder (at most ``VERTEX_LIMIT`` free coordinates), else the second-order Taylor
box bound of :mod:`inertiaproof.bounds.taylor`; where it certifies less, the a-priori length bound, the Perron bound
of the entry sizes, or 0 for a PSD form (:func:`with_fallback`). The budget is the bracket's rounds, scaled by the
counted cost of one box bound (:func:`vertex_cost`, :func:`box_cost`)."""

from __future__ import annotations

import numpy as np

from inertiaproof.model.inertia import spatial_inertia

from .apriori import apriori_bound
from .domain import (
    bernstein_domain,
    certification_obstacle,
    derivative_factors,
    free_coordinates,
    search_box,
)
from .extremes import bracket_extreme
from .families import jacobian_family, value_for_norm, vertex_bound
from .ladders import ladders_run
from .pivot_search import DEEP_ROUNDS
from .spectral import CONVEX, Spectral, spectral
from .taylor import MassFamily, box_bounds, perron_bound

__all__ = ["VERTEX_LIMIT", "box_cost", "configuration_bracket", "vertex_cost", "with_fallback"]

VERTEX_LIMIT = 6  # free coordinates up to which the 2^d vertices of the linear part are enumerated (exact linear part)
VERTEX_SHARE = (0.25, 0.05)  # of a bracket's budget (under DEEP_ROUNDS, from it) for branch and bound with vertex bounds
# where the pivot ladders run after it
VERTICES_PER_UNIT = 45  # vertex eigenproblems counted as one unit of box-bound work (box_cost's unit)


def configuration_bracket(chain, family, kind, *, quantity_name, samples, rounds, rng, value_kind=None,
                          square=False, progress=None, thetas=None):
    """Bracket of sup (convex kinds) or inf (lmin) over the chain's configurations of kind(M(q, Theta_v)).

    ``family`` is (evaluate, degree) from :func:`mass_family` (degree 2, with its ``thetas``); the value over a
    stack of parameter sets is the worst over the stack. ``value_kind`` overrides how the observed side is
    computed (e.g. 'smin' of QJ by SVD while the certified side bounds lmin of (QJ)^T QJ); ``square`` squares
    observed singular values to match. The certified side is branch and bound with
    :func:`inertiaproof.bounds.taylor.box_bounds` (polynomial in the number of joints per box). Where the pivot
    ladders run after it (:func:`ladders_run`), it gets ``VERTEX_SHARE`` of the budget (the ladders' certified
    sides are sharper there: bench/results/bounds_timings.md).
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
    if ladders_run(chain, rounds):  # the ladders' certified sides are sharper there
        rounds *= VERTEX_SHARE[rounds >= DEEP_ROUNDS]
    if obstacle is None and (degree != 2 or thetas is None) and free.sum() > VERTEX_LIMIT:
        obstacle = "no polynomial box bound for this family"
    if obstacle is not None:
        return bracket_extreme(value, None, lo, hi, sense=sense, quantity_name=quantity_name, samples=samples,
                               rounds=rounds, rng=rng, free=free, note=obstacle)
    if free.sum() <= VERTEX_LIMIT:
        return _vertex_bracket(chain, family, kind, value, lo, hi, free, quantity_name=quantity_name, samples=samples,
                               rounds=rounds, rng=rng, progress=progress, thetas=thetas)
    apriori = apriori_bound(chain, thetas, "sup")
    fam = MassFamily(chain, thetas)
    weights = fam.factors.max(axis=(0, 1))  # split where the entries can move most

    def box_bound(c, r):
        return box_bounds(fam, kind, c, r)

    note = ("second-order Taylor bound per box: entry sizes from lengths, Bernstein/Markov remainder, "
            "congruence by the centre's Cholesky factor for lambda_min; rounding allowances stated in "
            "inertiaproof.bounds.taylor")
    result = bracket_extreme(value, box_bound, lo, hi, sense=sense, quantity_name=quantity_name, samples=samples,
                             rounds=rounds, rng=rng, free=free, weights=weights, progress=progress, note=note,
                             cost=box_cost(chain.n, len(fam.thetas)))
    psd = bool(np.all(spectral(spatial_inertia(np.asarray(thetas, float)), "lmin") >= 0))
    return with_fallback(result, kind, apriori, psd, chain, thetas)


def _vertex_bracket(chain, family, kind, value, lo, hi, free, *, quantity_name, samples, rounds, rng, progress=None,
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

    stage = rounds / 2 if (sense == "min" or not same) else rounds
    scale, note = None, ""
    norm_kind = "smax" if degree == 1 else "absmax"
    if sense == "min" or not same:
        sup = bracket_extreme(value_for_norm(evaluate, norm_kind), bound_with(None, norm_kind), dlo, dhi, sense="max",
                              quantity_name=f"sup ||A|| for {quantity_name}", samples=samples, rounds=stage,
                              rng=rng, free=free, weights=factors, cost=vertex_cost(free))
        scale = min(np.inf if sup.certified is None else sup.certified, apriori)
        note = f"Taylor remainder scaled by sup ||A|| <= {scale:.6g} over a full period (certified)"
        if not np.isfinite(scale):
            return with_fallback(bracket_extreme(value, None, lo, hi, sense=sense, quantity_name=quantity_name,
                                                  samples=samples, rounds=stage, rng=rng, free=free,
                                                  note="sup ||A|| over a period not certified in the time budget"),
                                  kind, apriori, thetas is not None)
    result = bracket_extreme(value, bound_with(scale, kind), lo, hi, sense=sense, quantity_name=quantity_name,
                             samples=samples, rounds=stage if scale is not None else rounds, rng=rng, free=free,
                             weights=factors, progress=progress, note=note, cost=vertex_cost(free))
    if scale is not None and sense == "max":
        result.tighten(scale, "the sup over a period is sharper")
    psd = thetas is not None and bool(np.all(spectral(spatial_inertia(np.asarray(thetas, float)), "lmin") >= 0))
    return with_fallback(result, kind, apriori, psd, chain, thetas)


def vertex_cost(free):
    """The vertex path's cost of one box bound in units of :func:`box_cost`: its 2^d vertices (d free coordinates),
    ``VERTICES_PER_UNIT`` to a unit; beyond ``VERTEX_LIMIT``, the Taylor box bound's."""
    d = int(np.sum(free))
    return 2.0**d / VERTICES_PER_UNIT if d <= VERTEX_LIMIT else box_cost(len(free))


def box_cost(n, stack=1):
    """Relative cost of one box bound against a 7-joint chain with one parameter set (O(n^4) per box)."""
    return max(1.0, stack * (n / 7.0) ** 4)


def with_fallback(result, kind, apriori, psd, chain=None, thetas=None):
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
