"""A certified lower bound of inf_q lambda_min(M(q, Theta)) over a box of configurations by a ladder of targets,
each proved by branch and bound with the articulated-body pivot test (:func:`inertiaproof.bounds.pivots.pivot_test`).

Section 4's infima (Definition 2's inf sigma_min(QJ)^2 = inf lambda_min((QJ)^T QJ), Theorem 2's
inf lambda_min(M)) are flat over the joint limits of a real arm (Panda: every sampled configuration within 1.5x of
the infimum), so a bound per box that is a fixed fraction of the box's value would need every box equally fine.
Instead the search proves targets: for gamma = observed / ratio with ratio running down ``LADDER`` (observed is
attained at a witness, so gamma <= observed), a box passes when :func:`pivot_test` shows M(q) - gamma I > 0 on it
(every pivot of the tip-first LDL^T bounded below: Loewner-monotone steps, rounding added outward, see
:mod:`inertiaproof.bounds.pivots`); a box that fails is halved, and the boxes that passed gamma are where the next
target starts. The certified side is the last gamma for which every box of a partition of the domain passed:
lambda_min(M(q)) >= gamma for every q of the domain and every parameter set. Nothing is sampled on the certified
side; which coordinate is halved is a heuristic (any choice is sound): the one whose radius is largest against
its calibrated radius (:func:`calibrated_radii`; on the upper side times the turn's absolute loss on the box:
Panda, 45,000 boxes, 2-8x fewer boxes per rung; on the lower side the radii alone: times the turns' relative
losses, Panda's unit form reaches 1.05x instead of 1.10x but its weighted form 1.05x instead of 1.03x), so that
boxes get fine only where the turns lose; so is the
metric of the turns' loss and its ridge (pivots.METRICS, RIDGES: the pair whose calibration boxes hold widest).

The budget is a count of tested boxes (the same bracket on any machine for a seed) with a wall-clock guard; a
ladder that runs out keeps its last proved target. It does not start a rung that :func:`rung_cost` forecasts to
run out (a rung that runs out costs the rest of the budget: Panda's five deep brackets spent 20-40% of their boxes
on it), and it goes on to the furthest rung the forecast has room for, leaving the ones between out (every rung
tests its whole partition again: Panda's deep Thm4 1.12x -> 1.10x within the same budget).
"""

from __future__ import annotations

import itertools
import time
from typing import NamedTuple

import numpy as np

from .pivots import METRICS, RIDGES, pivot_test

__all__ = ["CHUNK", "LADDER", "LADDER_JOINTS", "Ladder", "calibrated_radii", "ladder_budget", "ladder_goal",
           "partition", "pivot_ladder", "rung_cost"]

LADDER = (64.0, 16.0, 8.0, 4.0, 2.8, 1.95, 1.6, 1.45, 1.35, 1.25, 1.18, 1.15, 1.12, 1.1, 1.08, 1.05, 1.03, 1.02, 1.01)  # observed / target
CHUNK = 4096  # boxes per pivot test call
GRID = np.geomspace(0.003, 3.0, 11)  # radii tried by the calibration
BOXES = (40_000, 250, 400)  # boxes a ladder may test: the first plus the second (from DEEP_ROUNDS the third) per
# round of a bracket's budget
LADDER_JOINTS = 8  # a ladder's count of work is its boxes times n^3 (the pivots of a box: O(n^3) on n joints): a
# chain of more joints gets the boxes of this many joints' work, (LADDER_JOINTS / n)^3 of BOXES' (a 7-joint arm and
# its gripper's slide: all of them)
EXTRA = 6  # after the goal, a ladder goes on with 1/EXTRA of its budget
DEEP_ROUNDS = 200  # rounds per bracket from which a ladder goes on below the 2x (the deep profile's 800)
LADDER_GUARD = (30.0, 0.3)  # a ladder's wall-clock safety net, seconds: the first plus the second per round
FORECAST_MIN = 5_000  # boxes of a rung from which the next rung's cost is forecast (rung_cost)
GROWTH = 3.0  # a partition's size grows as m^-GROWTH, m of rung_cost (Panda, 2 kg, deep ladders from 1.25x on: 1.4-3.1)
SLACK = 2.0  # a rung is tried while its forecast is within SLACK times the boxes left (the forecast is high near a
# ladder's end: Panda's deep Thm2 block form, 1.05x -> 1.03x, forecast 471,000 boxes, tested 176,000)
CALIBRATION_POINTS = 8  # configurations the calibration looks at: the witness and seeded random ones


class Ladder(NamedTuple):
    """What :func:`pivot_ladder` proved: the certified side gamma, the boxes tested, the partition's size, the ratio
    of the rung proved, the rungs tried, and the partition (centres, radii) every box of which passed gamma (None
    when no rung was proved)."""

    gamma: float
    tested: int
    size: int
    ratio: float | None
    rungs: list
    partition: tuple | None = None


def ladder_budget(rounds, joints=None):
    """(boxes, seconds): the count of boxes a ladder may test for a bracket budget of ``rounds`` (ci's 20: 45,000;
    deep's 800: 360,000) on a chain of ``joints`` joints (more than ``LADDER_JOINTS``: the boxes whose count times
    n^3 is that of LADDER_JOINTS joints) and the wall-clock safety net ``LADDER_GUARD`` (a loaded machine ends with
    a lower, still certified target)."""
    per_round = BOXES[1] if rounds < DEEP_ROUNDS else BOXES[2]
    boxes = BOXES[0] + per_round * rounds
    if joints is not None and joints > LADDER_JOINTS:
        boxes = boxes * LADDER_JOINTS**3 / joints**3
    return int(boxes), LADDER_GUARD[0] + LADDER_GUARD[1] * rounds


def ladder_goal(rounds):
    """The ratio observed / certified from which a ladder goes on with a small extra budget only: 2 (the issue's
    ci goal) for budgets under ``DEEP_ROUNDS`` rounds, else 1.01 (the end of the ladder)."""
    return 2.0 if rounds < DEEP_ROUNDS else 1.01


def calibrated_radii(family, points, values, lo, hi, free, drop=0.1, sign=1.0):
    """Per coordinate the radius at which boxes wide in that coordinate alone start to fail: for each of the
    configurations ``points`` (P, n) with lambda_min ``values`` (P, V) there, the first radius of ``GRID`` at which
    the pivot test of M - (1 - drop) lambda_min I fails on the box about the point (the largest grid radius if
    none), geometric mean over the points; 1 for fixed coordinates. ``sign`` -1: ``values`` are lambda_max and the
    test is of (1 + drop) lambda_max I - M. A heuristic for splitting."""
    points, values = np.atleast_2d(points), np.atleast_2d(values)
    n = len(lo)
    idx = np.flatnonzero(free)
    rho = np.ones(n)
    if not len(idx):
        return rho
    radii = np.zeros((len(points), len(idx), len(GRID), n))
    for k, j in enumerate(idx):
        radii[:, k, :, j] = np.minimum(GRID, 0.5 * (hi[j] - lo[j]))
    centres = np.broadcast_to(points[:, None, None, :], radii.shape).reshape(-1, n)
    armature = -sign * (1 - sign * drop) * np.broadcast_to(values[:, None, None, :], radii.shape[:3] + values.shape[-1:])
    ok, _ = pivot_test(family, sign, armature.reshape(-1, values.shape[-1]), centres, radii.reshape(-1, n))
    held = ok.all(1).reshape(len(points), len(idx), len(GRID))
    first = np.where(held.all(-1), len(GRID) - 1, np.argmin(held, -1))  # (P, d)
    rho[idx] = np.exp(np.log(GRID[first]).mean(0))
    return rho


def _prove(family, sign, gamma, centres, radii, rho, budget, deadline):
    """Halve boxes until every one passes the pivot test of sign (M - gamma I): the passing partition (centres,
    radii) and the boxes tested, or None (and the boxes tested) when the budget or the deadline ran out first."""
    stack = family.z.shape[0]

    def test(c, r):
        ok, losses = pivot_test(family, sign, np.full((len(c), stack), -sign * gamma), c, r)
        return ok.all(1), losses

    def score(r, losses):
        return r / rho if sign > 0 else np.where(r > 0, losses, -1.0) * (r / rho)

    return partition(test, score, centres, radii, budget, deadline)


def partition(test, score, centres, radii, budget, deadline):
    """Branch and bound: halve the boxes (centres, radii) that fail ``test`` (c, r) -> (ok (K,), losses (K, n)),
    each in the coordinate of the largest ``score`` (r, losses) (a heuristic), until every box passes: (the passing
    partition (centres, radii), boxes tested), or (None, boxes tested) when ``budget`` boxes or the ``deadline``
    ran out first, or a box of radius below 1e-9 failed (the target is above the value there)."""
    pending = [(centres, radii)]
    done_c, done_r = [], []
    tested = 0
    while pending:
        c, r = pending.pop()
        if len(c) > CHUNK:
            pending.append((c[CHUNK:], r[CHUNK:]))
            c, r = c[:CHUNK], r[:CHUNK]
        tested += len(c)
        if tested > budget or time.perf_counter() > deadline:
            return None, tested
        ok, losses = test(c, r)
        losses = losses[~ok]
        done_c.append(c[ok])
        done_r.append(r[ok])
        c, r = c[~ok], r[~ok]
        if not len(c):
            continue
        if r.max() < 1e-9:  # a point fails: gamma is above the value there
            return None, tested
        axis = np.argmax(score(r, losses), 1)
        rows = np.arange(len(c))
        half = r.copy()
        half[rows, axis] *= 0.5
        shift = np.zeros_like(r)
        shift[rows, axis] = half[rows, axis]
        pending.append((np.concatenate([c - shift, c + shift]), np.concatenate([half, half])))
    return (np.concatenate(done_c), np.concatenate(done_r)), tested


def rung_cost(rungs, ratio, sign=1.0):
    """A forecast of the boxes that proving ``ratio`` tests, from the last proved rung (r0, tested, size) of
    ``rungs``: the partition grows to size (m(r0) / m(ratio))^``GROWTH`` with m the target's relative distance from
    the observed extreme (1 - 1/ratio on the lower side, ratio - 1 on the upper), and every split adds two boxes for
    one, so the rung tests twice the new size less the old one (exact when nothing fails). None while the last
    rung tested fewer than ``FORECAST_MIN`` boxes. A heuristic (it decides which rungs a ladder tries, not what they
    prove)."""
    if not rungs or rungs[-1][2] is None or rungs[-1][1] < FORECAST_MIN:
        return None
    r0, _, size = rungs[-1]
    margin = (lambda r: 1 - 1 / r) if sign > 0 else (lambda r: r - 1)
    return size * (2 * (margin(r0) / margin(ratio)) ** GROWTH - 1)


def pivot_ladder(family, value, observed, witness, lo, hi, free, *, max_boxes, guard_s, floor=None, stop=None,
                 ladder=LADDER, sign=1.0):
    """The largest gamma = observed / ratio (ratio from ``ladder``, only targets above ``floor``; after a proved
    gamma >= ``stop`` with 1/EXTRA of the budget more) proved by
    branch and bound over the box [lo, hi] (fixed coordinates at the centre) within ``max_boxes`` tested boxes and
    ``guard_s`` seconds: a certified lower bound of inf lambda_min(M(q, Theta_v)) over the box and the stack, or
    -inf when none was proved. ``observed`` must be attained (at ``witness``); ``value(q)`` (K, n) -> (K, V) the
    lambda_min per parameter set, for the calibration only. Returns a :class:`Ladder` (its rungs
    [(ratio, boxes tested, partition size or None where it ran out)] per rung tried).

    ``sign`` -1, the upper side: the smallest gamma = observed * ratio (only targets below ``floor``, stopping
    once gamma <= ``stop``) for which gamma I - M(q, Theta_v) > 0 is proved, a certified upper bound of
    sup lambda_max(M) (inf when none was proved); ``observed`` and ``value`` then of lambda_max."""
    lo, hi, free = np.asarray(lo, float), np.asarray(hi, float), np.asarray(free, bool)
    floor = -sign * np.inf if floor is None else floor
    stop = sign * np.inf if stop is None else stop
    if not observed > 0:
        return Ladder(-sign * np.inf, 0, 0, None, [])
    deadline = time.perf_counter() + guard_s
    rng = np.random.default_rng(0)
    points = np.vstack([np.asarray(witness, float)[None],
                        np.where(free, lo + (hi - lo) * rng.random((CALIBRATION_POINTS - 1, len(lo))), 0.5 * (lo + hi))])
    values = value(points)
    best_score = -np.inf
    choices = itertools.product(family.metrics, RIDGES) if sign > 0 else [(METRICS[0], RIDGES[0])]
    for choice in choices:  # the metric and ridge whose calibration boxes hold widest (any is sound; the upper
        # side's turns are bounded in the identity metric)
        family.metric, family.ridge = choice
        trial = calibrated_radii(family, points, values, lo, hi, free, sign=sign)
        if np.log(trial).sum() > best_score:
            best_score, rho, chosen = np.log(trial).sum(), trial, choice
    family.metric, family.ridge = chosen
    centres, radii = (0.5 * (lo + hi))[None], np.where(free, 0.5 * (hi - lo), 0.0)[None]
    best, best_ratio, used, size, reached, rungs, proved = -sign * np.inf, None, 0, 0, False, [], None
    for k, ratio in enumerate(ladder):
        gamma = float(observed / ratio if sign > 0 else observed * ratio)
        if sign * gamma <= sign * floor:
            continue
        forecast, left = rung_cost(rungs, ratio, sign), max_boxes - used
        if forecast is not None:
            if forecast > SLACK * left:  # it would run out: end with the last proved target
                break
            if k + 1 < len(ladder) and rung_cost(rungs, ladder[k + 1], sign) <= left:  # the next fits too: go there
                continue
        partition, tested = _prove(family, sign, gamma, centres, radii, rho, max_boxes - used, deadline)
        used += tested
        rungs.append((ratio, tested, None if partition is None else len(partition[0])))
        if partition is None:
            break
        (centres, radii), best, best_ratio, size, proved = partition, gamma, ratio, len(partition[0]), partition
        if sign * best >= sign * stop and not reached:  # the goal: go on only as far as a small extra budget goes
            reached, max_boxes = True, min(max_boxes, used + max_boxes // EXTRA)
    return Ladder(best, used, size, best_ratio, rungs, proved)
