"""The Section 4 quantities over configurations for a chain and a parameter stack: Definition 2's
inf_q sigma_min(QJ)^2 (:func:`jacobian_normality`), sup_q sigma_max(QJ) (:func:`jacobian_sup`), Theorem 2's
inf lambda_min(M(q, Theta)) (:func:`mass_inf`), the sups of lambda_max and sigma_max of M (:func:`mass_sup`:
Theorems 3 and 4) and Theorem 5's skew partials (:func:`inertiaproof.bounds.skew.skew_partial_sup`).

Each quantity is a bracket: branch and bound over the search box gives its first certified side
(:func:`inertiaproof.bounds.branch.configuration_bracket`); the declared strategies of
:mod:`inertiaproof.bounds.strategies` then tighten it, each through
:meth:`inertiaproof.bounds.extremes.Bracket.tighten`, in the registry's order until the bracket is within its goal.
The certified side rests on two facts:

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

Over time, Theta(t) of payloads and scalings lies on segments
Theta_base + s Phi_load with s in the profile's range; spectral extremes that
are concave or convex in Theta are then attained at the segment's ends (exact
for one load per body). Moving masses are bounded by positivity (Z(Phi_load) >= 0)
and by the profile's rate and acceleration bounds.

The entry point for audits is :func:`inertiaproof.bounds.constants.mass_matrix_bounds`.
"""

from __future__ import annotations

import numpy as np

from .apriori import apriori_bound, apriori_jacobian_blocks, triangular_normality_floor
from .block_form import block_lower_form
from .branch import VERTEX_LIMIT, box_cost, configuration_bracket
from .certificate import SpectrumClaim
from .domain import certification_obstacle, free_coordinates
from .families import (
    jacobian_family,
    mass_family,
    mass_spectra,
    root_up,
    skew_partials,
    value_for_norm,
    vertex_bound,
)
from .ladders import form_ladder, pivot_normality
from .lengths import column_bounds, lever_bounds, unit_bodies
from .perron import FOURIER_DEEP_ROUNDS, FOURIER_PAIRS_ROUNDS, fourier_perron_bound
from .skew import skew_partial_sup
from .spectral import CONVEX, EPS, ROUNDING
from .strategies import Walk, run

__all__ = [
    "apriori_bound", "apriori_jacobian_blocks", "block_lower_form", "column_bounds", "configuration_bracket", "CONVEX",
    "EPS", "FOURIER_DEEP_ROUNDS", "FOURIER_PAIRS_ROUNDS", "form_ladder", "fourier_perron_bound", "jacobian_family",
    "jacobian_normality", "jacobian_sup", "lever_bounds", "mass_family", "mass_inf", "mass_spectra", "mass_sup",
    "REPROVABLE", "ROUNDING", "box_cost", "pivot_normality", "skew_partial_sup", "VERTEX_LIMIT", "skew_partials",
    "triangular_normality_floor", "unit_bodies", "value_for_norm", "vertex_bound",
]

REPROVABLE = 1 + 2**-10  # the narrowest bracket reported: a certified side within 1e-6 of an extreme attained along a
# curve (spatial 3R's sup lambda_max((QJ)^T QJ)) is beyond the independent checker's boxes (not within 50,000 cuts;
# 1e-4 away: 49,000 boxes; 1e-3: 1,400), so a narrower bracket is widened to this ratio (Bracket.widen)


def _walk(chain, thetas, kw, **more):
    return Walk(chain, thetas, kw.get("rounds", 0.0), kw.get("samples", 2000), **more)


def jacobian_sup(chain, **kw):
    """sup_q sigma_max(QJ) (SVD), tightened by the ``jacobian_sup`` strategies on unit bodies (Z = I: (QJ)^T QJ is
    their mass matrix). Beyond ``VERTEX_LIMIT`` free coordinates: the square root of the bracket of
    sup_q lambda_max((QJ)^T QJ), whose box bounds are polynomial."""
    obstacle = certification_obstacle(chain)
    unit = unit_bodies(chain)
    if free_coordinates(chain).sum() <= VERTEX_LIMIT or obstacle is not None:
        b = configuration_bracket(chain, jacobian_family(chain), "smax", quantity_name="sup_q sigma_max(QJ)", **kw)
        if obstacle is None:
            run("jacobian_sup", b, _walk(chain, unit, kw, square=False))
            b.certify = SpectrumClaim(chain, unit, "lambda_max", square=True)
        return b.widen(REPROVABLE)
    b = configuration_bracket(chain, mass_family(chain, unit), "lmax", value_kind="smax", square=True,
                              quantity_name="sup_q sigma_max(QJ)", thetas=unit, **kw)
    run("jacobian_sup", b, _walk(chain, unit, kw))
    root = (lambda x: None if x is None else float(np.sqrt(max(x, 0.0))))
    b.observed, b.certified = root(b.observed), None if b.certified is None else root_up(max(b.certified, 0.0))
    b.convergence = [[t, root(lo), root(hi)] for t, lo, hi in b.convergence]
    b.note += "; square roots of the bracket of sup_q lambda_max((QJ)^T QJ) (unit bodies)"
    b.certify = SpectrumClaim(chain, unit, "lambda_max", square=True)
    return b.widen(REPROVABLE)


def jacobian_normality(chain, **kw):
    """inf_q sigma_min(QJ)^2 = inf_q lambda_min((QJ)^T QJ) (Definition 2): observed by SVD of QJ; the certified side is
    the best of branch and bound and the ``jacobian_normality`` strategies (the block-triangular floor; where the
    ladders run, deep budgets the chain split at a body, then the unit form's ladder where still short of its goal)."""
    unit = unit_bodies(chain)
    result = configuration_bracket(chain, mass_family(chain, unit), "lmin", value_kind="smin", square=True,
                                   quantity_name="inf_q sigma_min(QJ)^2", thetas=unit, **kw)
    result.certify = SpectrumClaim(chain, unit, "lambda_min")
    walk = _walk(chain, unit, kw)
    walk.data["unit"] = True
    return run("jacobian_normality", result, walk).widen(REPROVABLE)


def mass_inf(chain, thetas, **kw):
    """inf over q and the parameter sets of lambda_min(M(q, Theta)); where branch and bound certifies less, the
    ``mass_inf`` strategies do (:mod:`inertiaproof.bounds.strategies`): the proof of Theorem 2,
    lambda_min(M) >= min_l lambda_min(Z(Phi_l)) inf_q sigma_min(QJ)^2 with the block-triangular floor, and where the
    ladders run, lower forms M(q) >= sum_l QJ_l^T Y_l QJ_l with Y_l <= Z(Phi_l) body by body whose inf a ladder of
    pivot targets certifies: the isotropic form (Y_l = mu_l I), the axial and heavy invariant forms
    (:mod:`inertiaproof.bounds.axial_form`), the block form (:func:`block_lower_form`), ranked by their sampled inf,
    then the bodies themselves; with a deep budget the chain split at a body first
    (:mod:`inertiaproof.bounds.interface`). A form whose sampled inf is not above the bracket's certified side is
    skipped (its certified inf cannot be)."""
    result = configuration_bracket(chain, mass_family(chain, thetas), "lmin",
                                   quantity_name="inf lambda_min(M(q, Theta))", thetas=thetas, **kw)
    result.certify = SpectrumClaim(chain, thetas, "lambda_min")
    walk = _walk(chain, thetas, kw)
    walk.stop = result.observed / walk.goal
    return run("mass_inf", result, walk).widen(REPROVABLE)


def mass_sup(chain, thetas, kind="lmax", name="sup lambda_max(M(q, Theta))", goal=None, boxes=None, attained=None,
             **kw):
    """sup over q and the parameter sets of lambda_max (or sigma_max, kind='absmax') of M(q, Theta): the bracket of
    :func:`configuration_bracket`, tightened by the ``mass_sup`` strategies (``goal``: the upper ladder's, default
    :func:`inertiaproof.bounds.pivot_search.ladder_goal`; ``boxes``: its count of boxes where more than
    ``ladder_budget``'s; ``attained``: a value the true extreme is known to reach (at most this sup), to which the
    ladder's targets are scaled in place of the bracket's observed one)."""
    result = configuration_bracket(chain, mass_family(chain, thetas), kind, quantity_name=name, thetas=thetas, **kw)
    signed = thetas
    if kind == "absmax":  # sigma_max(M) = max(lambda_max(M), lambda_max(-M)): the stack and its negatives
        signed = np.concatenate([np.asarray(thetas, float), -np.asarray(thetas, float)])
    result.certify = SpectrumClaim(chain, signed, "lambda_max")
    walk = _walk(chain, thetas, kw, goal=goal, boxes=boxes, attained=attained, ladder_thetas=signed)
    return run("mass_sup", result, walk).widen(REPROVABLE)
