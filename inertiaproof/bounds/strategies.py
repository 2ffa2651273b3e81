"""Declared strategies that tighten the certified side of a Section 4 bracket, and the one loop that runs them.

A strategy declares once which quantities it serves (``quantities``), whether it applies to a walk's chain and
budget (``applies``), the boxes it may test (``boxes``, counted work), the stage it runs in and how hard its form is
for the pivots against the isotropic one (``difficulty``), and ``tighten(bracket, walk) -> Step``: a certified side
with how it was proved and its proof, which :func:`run` adopts through :meth:`Bracket.tighten`. The ordered
registries (:data:`REGISTRY`) list the strategies of each quantity; :func:`run` goes through a registry stage by
stage until the bracket is within its goal: in a stage the strategies that apply are ranked by their form's sampled
value over its difficulty (under ``DEEP_ROUNDS``; from it by the sampled value alone, and the form stages merge: a
deep ladder nearly closes any form), and each runs while the bracket is short of the goal and its sampled value
(which bounds its certified one) is above the bracket's certified side. The walk (:class:`Walk`) holds what every
strategy of one bracket reads, computed once: the chain's certification obstacle, free coordinates, search box,
whether the ladders run, the goal.

The strategies (Definition 2's and Theorem 2's infima, the suprema of Theorems 3 and 4):

- ``vertex``: branch and bound (:mod:`inertiaproof.bounds.branch`), the bracket every strategy starts from;
- ``lengths``: the a-priori floors from link lengths (:mod:`inertiaproof.bounds.apriori`);
- ``split``: the chain split at a body (:mod:`inertiaproof.bounds.interface`), deep budgets;
- ``unit``, ``isotropic``, ``axial``, ``block``, ``heavy``, ``bodies``: pivot ladders on lower forms of M
  (:mod:`inertiaproof.bounds.ladders`, :mod:`inertiaproof.bounds.axial_form`, :mod:`inertiaproof.bounds.block_form`);
- ``fourier``: Perron-Frobenius from M's Fourier series (:mod:`inertiaproof.bounds.perron`);
- ``upper``: the pivot ladder on gamma I - M (:func:`inertiaproof.bounds.ladders.upper_ladder_step`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import NamedTuple

import numpy as np

from inertiaproof.model.inertia import spatial_inertia

from .apriori import triangular_normality_floor
from .axial_form import axial_lower_form, form_lmin
from .block_form import block_lower_form
from .certificate import PivotProof
from .domain import certification_obstacle, free_coordinates, search_box
from .families import mass_spectra
from .interface import EVIDENCE, split_ladder
from .ladders import adopt_upper, form_ladder, pivot_normality, upper_ladder_step
from .lengths import block_rows
from .perron import fourier_fits, fourier_step
from .pivot_search import DEEP_ROUNDS, EXTRA, ladder_budget, ladder_goal
from .pivots import METRICS, PIVOT_LIMIT, PIVOT_MIN_ROUNDS
from .spectral import EPS, ROUNDING, spectral

__all__ = ["REGISTRY", "Step", "Strategy", "Walk", "run"]

AXIAL_FIRST = 1.1  # a form's difficulty against the isotropic one's: under DEEP_ROUNDS it runs first where its
# sampled inf is this much higher
REAL_PROBE = 3  # the bodies' own ladder: a probe of 1/3 of the ci budget first
FORM_POINTS = 4000  # configurations at most on which the forms' sampled infima are taken
WORST_POINTS = 300  # of them, the isotropic form's lowest, on which the block form is chosen


class Step(NamedTuple):
    """What a strategy proved: a certified side (None or -inf: nothing), how, and its proof (or None)."""

    bound: float | None
    how: str
    proof: object = None


@dataclass
class Walk:
    """One bracket's walk over its strategies: the chain, the parameter stack, the budget (rounds per bracket,
    samples), and what every strategy reads, computed once."""

    chain: object
    thetas: np.ndarray | None
    rounds: float
    samples: int
    goal: float | None = None  # the ratio upper / lower the strategies aim at (None: ladder_goal of the rounds)
    boxes: int | None = None  # the upper ladder's count of boxes where more than ladder_budget's
    attained: float | None = None  # a value the true extreme is known to reach (the upper ladder's targets)
    square: bool = True  # False: the bracket is of sigma_max(QJ), the strategies bound its square
    ladder_thetas: np.ndarray | None = None  # the upper ladder's stack (sigma_max: with the negated sets)
    stop: float = np.inf  # the lower ladders stop once their bound is this much (set from the first bracket)
    data: dict = field(default_factory=dict)

    def __post_init__(self):
        self.obstacle = certification_obstacle(self.chain)
        self.free = free_coordinates(self.chain)
        self.lo, self.hi = search_box(self.chain)
        self.ladders = (self.rounds >= PIVOT_MIN_ROUNDS and self.obstacle is None  # as ladders_run, asked once
                        and self.free.sum() <= PIVOT_LIMIT)
        self.deep = self.rounds >= DEEP_ROUNDS
        if self.goal is None:
            self.goal = ladder_goal(self.rounds)

    def wide(self, bracket):
        """Whether the bracket is wider than the goal."""
        return bracket.upper > ladder_goal(self.rounds) * bracket.lower

    def short(self, bracket, sampled):
        """Short of the goal, and a form's sampled value (at least its certified one) above the certified side."""
        return self.wide(bracket) and sampled > bracket.lower


class Strategy:
    """A way to tighten a bracket's certified side. Subclasses declare ``name``, ``quantities``, ``stage`` (shallow,
    deep), ``difficulty`` and ``unconditional`` (runs whatever the bracket's width), and define ``tighten``."""

    name = ""
    quantities = frozenset()
    stage = (0, 0)
    difficulty = 1.0
    unconditional = False

    def applies(self, walk):
        """Whether the strategy applies to the walk's chain and budget."""
        return walk.ladders

    def boxes(self, walk):
        """The count of boxes the strategy may test (its counted work)."""
        return ladder_budget(walk.rounds, walk.chain.n)[0]

    def sampled(self, walk):
        """The sampled value of the strategy's form (it cannot certify more); inf where it has none."""
        return np.inf

    def wanted(self, bracket, walk, sampled):
        """Whether to run now: unconditional, or short of the goal with a sampled value above the certified side."""
        return self.unconditional or walk.short(bracket, sampled)

    def tighten(self, bracket, walk):
        raise NotImplementedError

    def adopt(self, bracket, step):
        bracket.tighten(step.bound, step.how, step.proof)


def run(quantity, bracket, walk, registry=None):
    """``bracket`` tightened by the strategies of ``quantity`` in :data:`REGISTRY` (or ``registry``), stage by stage:
    a stage is skipped once the bracket is within its goal (its unconditional strategies aside); in a stage, the
    strategies that apply are ranked by sampled value over difficulty (from DEEP_ROUNDS by sampled value alone)."""
    strategies = [s for s in (REGISTRY if registry is None else registry) if quantity in s.quantities]
    for stage in sorted({s.stage[walk.deep] for s in strategies}):
        members = [s for s in strategies if s.stage[walk.deep] == stage]
        if not any(s.unconditional for s in members) and not walk.wide(bracket):
            continue
        sampled = {s.name: s.sampled(walk) for s in members if s.applies(walk)}
        members = sorted((s for s in members if s.name in sampled),
                         key=lambda s: -sampled[s.name] / (1.0 if walk.deep else s.difficulty))
        for strategy in members:
            if strategy.wanted(bracket, walk, sampled[strategy.name]):
                step = strategy.tighten(bracket, walk)
                if step is not None:
                    strategy.adopt(bracket, step)
    return bracket


# -- the lower sides: Definition 2's inf sigma_min(QJ)^2 and Theorem 2's inf lambda_min(M) -------------------------

class UnitFloor(Strategy):
    name, quantities, unconditional = "lengths", frozenset({"jacobian_normality"}), True

    def applies(self, walk):
        return True

    def boxes(self, walk):
        return 0

    def tighten(self, bracket, walk):
        return Step(triangular_normality_floor(walk.chain),
                    "certified side from the block-triangular structure of QJ (unit twist of joint l in column l of "
                    "body l's block, lengths bound the rest): valid for every q")


class IsotropicFloor(UnitFloor):
    quantities = frozenset({"mass_inf"})

    def tighten(self, bracket, walk):
        z_min = float(bodies(walk).mu.min())
        floor = max(z_min, 0.0) * triangular_normality_floor(walk.chain) * (1 - ROUNDING * EPS)
        isotropic = PivotProof(".", np.broadcast_to(max(z_min, 0.0) * np.eye(6), (1, walk.chain.bodies, 6, 6)))
        return Step(floor, "certified side min_l lambda_min(Z(Phi_l)) times a certified lower bound of "
                           "inf sigma_min(QJ)^2 (block-triangular floor)", isotropic)


class Split(Strategy):
    name, quantities, unconditional = "split", frozenset({"jacobian_normality", "mass_inf"}), True

    def applies(self, walk):
        return walk.ladders and walk.deep

    def tighten(self, bracket, walk):
        gamma, how, proof = split_ladder(walk.chain, walk.thetas, bracket.observed, walk.rounds, floor=bracket.lower)
        what = "(QJ)^T QJ - gamma I > 0 (unit bodies)" if walk.data.get("unit") else "M(q) - gamma I > 0"
        return Step(gamma, f"{what} {EVIDENCE}: {how}", proof)


class UnitLadder(Strategy):
    name, quantities, stage, unconditional = "unit", frozenset({"jacobian_normality"}), (1, 1), True

    def wanted(self, bracket, walk, sampled):  # under DEEP_ROUNDS whatever the width: the unit form is the easiest
        return not walk.deep or walk.wide(bracket)

    def tighten(self, bracket, walk):
        gamma, how, proof = pivot_normality(walk.chain, walk.rounds, walk.samples, detail=True)
        return Step(gamma, "a ladder of targets gamma, each proved by branch and bound with the articulated-body "
                           f"pivots of (QJ)^T QJ - gamma I on each box (inertiaproof.bounds.pivot_search): {how}", proof)


@dataclass
class Bodies:
    """The lower forms of one walk's bodies, built where a strategy asks for them."""

    walk: Walk

    @cached_property
    def z(self):
        return spatial_inertia(np.asarray(self.walk.thetas, float))

    @cached_property
    def mu(self):  # (V, N), rounded down: Z_l >= mu_l I
        return spectral(self.z, "lmin") - ROUNDING * EPS * spectral(self.z, "absmax")

    @cached_property
    def q(self):
        walk = self.walk
        q = walk.lo + (walk.hi - walk.lo) * np.random.default_rng(0).random((min(walk.samples, FORM_POINTS),
                                                                             walk.chain.n))
        return np.where(walk.free, q, 0.5 * (walk.lo + walk.hi))

    @cached_property
    def iso_values(self):
        return mass_spectra(self.walk.chain, block_rows(self.mu.min(0), self.mu.min(0))[None], self.q, "lmin")[:, 0]

    @cached_property
    def axial(self):
        return axial_lower_form(self.walk.chain, self.walk.thetas, self.q)

    @cached_property
    def heavy(self):
        return axial_lower_form(self.walk.chain, self.walk.thetas, self.q, heavy=True)

    @cached_property
    def block(self):
        return block_lower_form(self.walk.thetas, self.q[np.argsort(self.iso_values)[:WORST_POINTS]], self.walk.chain)


def bodies(walk):
    """The walk's :class:`Bodies`, once."""
    if "bodies" not in walk.data:
        walk.data["bodies"] = Bodies(walk)
    return walk.data["bodies"]


def proved(walk, forms, probe=EXTRA, metrics=METRICS[:1]):
    """(gamma, how, proof) of :func:`form_ladder` on ``forms``: a probe of 1/``probe`` of the ci budget first (forms
    the pivots cannot handle cost little), the whole ladder where it proved something short of the stop."""
    gamma, _, how, proof = form_ladder(walk.chain, forms, walk.rounds, walk.samples, walk.stop, probe, metrics)
    if -np.inf < gamma < walk.stop:
        gamma, _, how, proof = form_ladder(walk.chain, forms, walk.rounds, walk.samples, walk.stop, 0, metrics)
    return gamma, how, proof


class Isotropic(Strategy):
    name, quantities, stage = "isotropic", frozenset({"mass_inf"}), (1, 1)

    def sampled(self, walk):
        return bodies(walk).iso_values.min()

    def tighten(self, bracket, walk):
        gamma, how, proof = pivot_normality(walk.chain, walk.rounds, walk.samples, bodies(walk).mu, walk.stop,
                                            detail=True)
        return Step(gamma, "M(q) >= sum_l mu_l QJ_l^T QJ_l with mu_l <= lambda_min(Z(Phi_l)) (key step, body by "
                           "body), its inf certified by a ladder of targets proved with articulated-body pivots "
                           f"(inertiaproof.bounds.pivot_search): {how}", proof)


class Axial(Strategy):
    name, quantities, stage, difficulty = "axial", frozenset({"mass_inf"}), (1, 1), AXIAL_FIRST
    kind = "mu_l I + kappa_l w_l w_l^T (an inertia about joint l's own axis)"

    def form(self, walk):
        return bodies(walk).axial

    def sampled(self, walk):
        forms, axial = self.form(walk)
        return form_lmin(walk.chain, forms, bodies(walk).q).min() if axial.any() else -np.inf

    def tighten(self, bracket, walk):
        forms, axial = self.form(walk)
        gamma, how, proof = proved(walk, forms)
        listed = ", ".join(str(l + 1) for l in np.flatnonzero(axial))
        return Step(gamma, "M(q) >= sum_l QJ_l^T Y_l QJ_l with Y_l <= Z(Phi_l) (checked with rounding; body by "
                           f"body), Y_l = {self.kind} for bodies {listed} (inertiaproof.bounds.axial_form), "
                           "lambda_min(Z_l) I for the others, its inf certified by a ladder of targets proved "
                           f"with articulated-body pivots: {how}", proof)


class Block(Strategy):
    name, quantities, stage, difficulty = "block", frozenset({"mass_inf"}), (2, 1), AXIAL_FIRST

    def sampled(self, walk):
        block_mu, block_nu = bodies(walk).block
        return mass_spectra(walk.chain, block_rows(block_mu, block_nu)[None], bodies(walk).q, "lmin").min()

    def tighten(self, bracket, walk):
        block_mu, block_nu = bodies(walk).block
        gamma, how, proof = pivot_normality(walk.chain, walk.rounds, walk.samples, block_mu[None], walk.stop,
                                            detail=True, angular=block_nu)
        return Step(gamma, "M(q) >= sum_l QJ_l^T diag(mu_l I3, nu_l I3) QJ_l with diag(mu_l I3, nu_l I3) "
                           "<= Z(Phi_l) (checked with rounding; body by body), its inf certified by a ladder "
                           f"of targets proved with articulated-body pivots: {how}", proof)


class Heavy(Axial):
    name, stage = "heavy", (2, 1)
    kind = "an inertia invariant under joint l's own turn (Z_l's rotation average)"

    def form(self, walk):
        return bodies(walk).heavy

    def applies(self, walk):
        return walk.ladders and bool(self.form(walk)[1].any())


class OwnBodies(Strategy):
    name, quantities, stage = "bodies", frozenset({"mass_inf"}), (3, 3)

    def boxes(self, walk):
        return (ladder_budget(walk.rounds, walk.chain.n)[0]
                + ladder_budget(min(walk.rounds, 20), walk.chain.n)[0] // REAL_PROBE)

    def tighten(self, bracket, walk):  # |F| keeps an indefinite P's light directions: every metric
        gamma, how, proof = proved(walk, bodies(walk).z, REAL_PROBE, METRICS)
        return Step(gamma, "a ladder of targets gamma, each proved by branch and bound with the articulated-body "
                           f"pivots of M(q) - gamma I on each box (inertiaproof.bounds.pivot_search): {how}", proof)


# -- the upper sides: sup lambda_max(M), sup sigma_max(M), sup sigma_max(QJ) -----------------------------------------

class Fourier(Strategy):
    name, quantities, unconditional = "fourier", frozenset({"mass_sup", "jacobian_sup"}), True

    def applies(self, walk):  # its terms 5^m n^2 within the count its rounds pay for (perron.fourier_fits)
        return walk.obstacle is None and fourier_fits(walk.chain, walk.rounds)

    def boxes(self, walk):
        return 0

    def tighten(self, bracket, walk):
        return Step(*fourier_step(walk.chain, walk.thetas, walk.rounds, walk.square))


class Upper(Strategy):
    name, quantities, stage, unconditional = "upper", frozenset({"mass_sup", "jacobian_sup"}), (1, 1), True

    def boxes(self, walk):
        return max(ladder_budget(walk.rounds, walk.chain.n)[0], walk.boxes or 0)

    def tighten(self, bracket, walk):
        thetas = walk.thetas if walk.ladder_thetas is None else walk.ladder_thetas
        return upper_ladder_step(bracket, walk.chain, thetas, walk.rounds, walk.square, walk.goal, walk.boxes,
                                 walk.attained)

    def adopt(self, bracket, step):
        adopt_upper(bracket, *step)


REGISTRY = (UnitFloor(), IsotropicFloor(), Split(), UnitLadder(), Isotropic(), Axial(), Block(), Heavy(), OwnBodies(),
            Fourier(), Upper())
