"""The pivot ladders of a bracket: targets proved with the articulated-body pivots on a partition of the search
box (:mod:`inertiaproof.bounds.pivot_search`), for lower forms of M (inf lambda_min: the unit, isotropic, block and
axial forms and the bodies themselves) and for gamma I - M (sup lambda_max). Each ladder's count of boxes is
:func:`inertiaproof.bounds.pivot_search.ladder_budget` of the bracket's rounds; each has its own seed, so the
same chain and budget give the same number."""

from __future__ import annotations

import numpy as np

from inertiaproof.model.inertia import spatial_inertia

from .axial_form import form_lmin
from .certificate import PivotProof, distinct, partition_tree
from .domain import certification_obstacle, free_coordinates, search_box
from .extremes import bracket_extreme
from .families import mass_spectra, root_up
from .lengths import block_rows
from .memo import memo
from .pivot_search import ladder_budget, ladder_goal, pivot_ladder
from .pivots import METRICS, PIVOT_LIMIT, PIVOT_MIN_ROUNDS, PivotFamily
from .spectral import EPS, ROUNDING, spectral

__all__ = ["FORM_ROUNDS", "ROOT_FREE", "UPPER_TRIGGER", "adopt_upper", "form_ladder", "ladders_run", "pivot_normality",
           "pivot_sup", "tighten_by_ladder", "upper_ladder_step"]

FORM_ROUNDS = 80  # rounds of the sampled inf of a lower form before its ladder (its observed side only)
UPPER_TRIGGER = 1.25  # a sup bracket wider than this (or than the ladder's goal) runs the upper ladder
ROOT_FREE = 3  # free coordinates up to which the checker proves a side without a partition from the root box within
# ci's budget (every 2R and 3R side of a ci run); beyond, a side without one runs the ladder (UR5's Fourier sides in ci
# were not decided in 5,000 units; their ladder proves as sharp a side on a partition of 9,004 boxes)


def ladders_run(chain, rounds):
    """Whether the pivot ladders run: a budget of PIVOT_MIN_ROUNDS or more per bracket, a certified bracket possible and
    at most PIVOT_LIMIT free coordinates (an arm and its gripper's joint)."""
    return (rounds >= PIVOT_MIN_ROUNDS and certification_obstacle(chain) is None
            and free_coordinates(chain).sum() <= PIVOT_LIMIT)


def pivot_normality(chain, rounds, samples, weights=None, stop=None, detail=False, angular=None):
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
    found = memo("pivot normality", chain, (rounds, samples, weights, angular, stop),
                 lambda: _pivot_normality(chain, np.random.default_rng(0), rounds, samples, weights, angular, stop))
    return found if detail else found[0]


def _pivot_normality(chain, rng, rounds, samples, weights, angular, stop):
    unit = block_rows(weights[0], angular[0])[None]  # (1, N, 10): Z_l = diag(mu_l I3, nu_l I3)
    family = PivotFamily(chain, unit)

    def values(q):
        return mass_spectra(chain, unit, q, "lmin")  # (K, 1)

    lo, hi = search_box(chain)
    free = free_coordinates(chain)
    found = bracket_extreme(lambda q: values(q).min(-1), None, lo, hi, sense="min",
                            quantity_name="inf_q lambda_min of the unit form (pivots)", samples=samples,
                            rounds=rounds, rng=rng, free=free)
    stop = found.observed / ladder_goal(rounds) if stop is None else stop
    return _ladder(chain, family, values, found.observed, found.witness, ladder_budget(rounds, chain.n), stop,
                   forms=True)


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


def form_ladder(chain, forms, rounds, samples, stop, probe=0, metrics=METRICS[:1]):
    """A certified lower bound of inf_q lambda_min(sum_l QJ_l^T Y_l QJ_l) for body forms ``forms`` (V, N, 6, 6)
    (any symmetric Y_l; :mod:`inertiaproof.bounds.axial_form`) by the ladder of targets proved with the pivot test
    (:func:`inertiaproof.bounds.pivot_search.pivot_ladder`), stopping once its bound is ``stop`` or more; -inf where
    none was proved. ``probe`` k > 0: 1/k of the ci budget only (k = EXTRA: 7,500 boxes; a form the pivots cannot
    handle costs little). ``metrics``: the loss metrics the ladder may calibrate (pivots.METRICS).
    Returns (bound, the form's sampled inf, a note on the ladder, its :class:`PivotProof`); its own seed, cached by
    content."""
    forms = np.ascontiguousarray(forms, float)
    return memo("form ladder", chain, (rounds, samples, forms, stop, probe, metrics),
                lambda: _form_ladder(chain, forms, rounds, samples, stop, probe, metrics))


def _form_ladder(chain, forms, rounds, samples, stop, probe, metrics):
    family = PivotFamily(chain, inertias=forms, metrics=metrics)

    def values(q):
        return form_lmin(chain, forms, q)  # (K, 1)

    lo, hi = search_box(chain)
    free = free_coordinates(chain)
    found = bracket_extreme(lambda q: values(q).min(-1), None, lo, hi, sense="min",
                            quantity_name="inf_q lambda_min of a lower form (pivots)", samples=samples,
                            rounds=min(rounds, FORM_ROUNDS), rng=np.random.default_rng(0), free=free)
    boxes, guard_s = ladder_budget(min(rounds, PIVOT_MIN_ROUNDS) if probe else rounds, chain.n)
    if probe:  # a share of the ci budget whatever the profile: a form that fails here fails with more too (measured)
        boxes, guard_s = boxes // probe, guard_s / probe
    gamma, note, proof = _ladder(chain, family, values, found.observed, found.witness, (boxes, guard_s), stop,
                                 forms=True)
    return gamma, found.observed, note, proof


def tighten_by_ladder(result, chain, thetas, rounds, square, goal=None, boxes=None, attained=None):
    """``result`` (a sup of lambda_max(M(q, Theta_v)) over q and the stack; of sigma_max(QJ) when ``square`` is
    False: M of unit bodies) with its certified side tightened by :func:`upper_ladder_step` where it runs
    (:func:`adopt_upper`). ``goal``, ``boxes``, ``attained``: as :func:`inertiaproof.bounds.configuration.mass_sup`'s."""
    step = upper_ladder_step(result, chain, thetas, rounds, square, goal, boxes, attained)
    return result if step is None else adopt_upper(result, *step)


def upper_ladder_step(result, chain, thetas, rounds, square, goal=None, boxes=None, attained=None):
    """(gamma, how, proof, untreed) of a ladder of targets gamma proved with the articulated-body pivots of gamma I - M
    (:func:`inertiaproof.bounds.pivot_search.pivot_ladder`, sign -1), or None where it does not run: it runs where
    the ladders run and the bracket is still wider than ``UPPER_TRIGGER`` or :func:`ladder_goal` (in ci the ladder
    stops after its 2x with 1/EXTRA of its budget more), or its side has no partition on a chain of more than
    ``ROOT_FREE`` free joints (``untreed``: then a looser side proved on a partition replaces it). Parameter sets whose
    every body is <= 0 (Theorem 4's negated rates) are left out of the ladder: their M(q) <= 0 lies below any
    target."""
    goal = ladder_goal(rounds) if goal is None else goal
    wide = result.upper > min(goal, UPPER_TRIGGER) * result.lower
    untreed = (result.proof is None and np.isfinite(result.upper)  # no partition for the checker to walk, and
               and free_coordinates(chain).sum() > ROOT_FREE)  # too many joints for it to cut one from the root
    if not (ladders_run(chain, rounds) and (wide or untreed) and result.observed > 0):
        return None
    observed = result.observed if square else result.observed**2
    if attained is not None:  # the targets observed * ratio, scaled to what the true extreme reaches
        observed = attained
    if not wide:  # narrow already: the ladder aims at the side it has, to hand the checker a partition
        goal = (result.upper if square else result.upper**2) / observed
    thetas = np.asarray(thetas, float)
    thetas = distinct(thetas)  # the set once
    gamma, how, proof = memo("upper ladder", chain, (rounds, goal, boxes, thetas, observed,
                                                     np.asarray(result.witness, float)),
                             lambda: pivot_sup(chain, thetas, rounds, observed, result.witness, goal, boxes))
    if np.isfinite(gamma) and not square:
        gamma = root_up(gamma)
    how = ("a ladder of targets gamma, each proved by branch and bound with the articulated-body pivots of gamma I - M "
           "on each box (inertiaproof.bounds.pivot_search)" + ("" if square else ", unit bodies, square root") + f": {how}")
    return gamma, how, proof, untreed


def adopt_upper(result, gamma, how, proof, untreed):
    """``result`` with the upper ladder's side adopted where sharper; where not, but the bracket's side has no
    partition the checker can walk (``untreed``), the ladder's looser side proved on one in its place."""
    if not result.tighten(gamma, how, proof) and untreed and proof is not None:
        result.certified, result.proof = gamma, proof  # looser, but what the independent checker can re-prove
        result.note += f"; {how}, reported in place of the sharper side, which has no partition the checker can walk"
    return result


def pivot_sup(chain, thetas, rounds, observed, witness, goal, boxes=None):
    z = spatial_inertia(thetas)  # a set whose every Z_l <= 0 (Weyl) has M(q) <= 0: below any gamma > 0, left out
    thetas = thetas[~(spectral(z, "lmax") + ROUNDING * EPS * spectral(z, "absmax") <= 0).all(1)]  # (Thm4: -Thetadot)
    family = PivotFamily(chain, thetas)

    def values(q):
        return mass_spectra(chain, thetas, q, "lmax")  # (K, V)

    budget = ladder_budget(rounds, chain.n)
    if boxes is not None and boxes > budget[0]:  # more boxes, and the wall-clock guard in proportion
        budget = (boxes, budget[1] * boxes / budget[0])
    return _ladder(chain, family, values, observed, witness, budget, observed * goal, sign=-1.0)
