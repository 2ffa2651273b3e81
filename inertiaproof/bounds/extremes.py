"""Two-sided brackets of an extreme of a batched function over a box of configurations.

``bracket_extreme(value, box_bound, lo, hi, sense=...)`` estimates
inf or sup of ``value`` over the box [lo, hi] from both sides:

- the observed side: the best of random samples, improved by a batched local
  pattern search; it is attained at ``witness``, so it is a true value of the
  function (an upper estimate of an inf, a lower estimate of a sup);
- the certified side: branch and bound over sub-boxes with ``box_bound``
  (centres, radii) -> a certified bound of the function on each sub-box; the
  worst bound over the boxes that are left is certified for the whole box.

Both sides are recorded against run time in ``convergence`` so the narrowing
can be plotted. The budget is a count of refinement ``rounds``, so the bracket is the same for a given seed on any
machine. Everything is batched over configurations; the only Python loop is over refinement rounds.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from inertiaproof.citation import Certificate

from .completion import pruned

__all__ = ["Bracket", "bracket_extreme", "GUARD", "LOCAL_ROUNDS_PER_ROUND", "local_search"]

GUARD = (1.0, 0.1)  # the refinement's wall-clock safety net, seconds: the first plus the second per round of its budget
LOCAL_ROUNDS_PER_ROUND = 5  # rounds of local search (of LOCAL_POINTS trials) per refinement round, at most 40
LOCAL_POINTS = 128  # trial configurations per round of local search (8 starts up to 8 free coordinates, then fewer
# starts, and from 64 coordinates fewer than 4 rounds at least)


@dataclass
class Bracket:
    quantity: str
    sense: str  # "min" (an infimum) or "max" (a supremum)
    observed: float  # attained at ``witness``
    certified: float | None  # None: no certified side
    witness: np.ndarray
    convergence: list = field(default_factory=list)  # [seconds, lower, upper]
    boxes: int = 0
    note: str = ""
    certify: object = None  # certified side -> its certificate (inertiaproof.bounds.certificate), where one exists
    proof: object = None  # what the certificate of the certified side carries of its proof (a PivotProof), if any
    _made: tuple = field(default=None, init=False, repr=False, compare=False)  # (claim and proof, sides, certificate)

    @property
    def lower(self):
        if self.sense == "min":
            return -np.inf if self.certified is None else self.certified
        return self.observed

    @property
    def upper(self):
        if self.sense == "max":
            return np.inf if self.certified is None else self.certified
        return self.observed

    @property
    def width(self):
        return self.upper - self.lower

    def tighten(self, certified, how, proof=None):
        """Adopt another certified bound of the same extreme where it is sharper (a larger lower bound of an inf, a
        smaller upper bound of a sup, or any where there was none): the one place a bracket is tightened. ``how``
        joins the note, ``proof`` (the proof's partition and forms) goes to the certificate; the convergence record's
        certified side follows. Returns whether it was adopted."""
        if certified is None or np.isnan(certified):
            return False
        sign = 1.0 if self.sense == "min" else -1.0
        current = self.certified if self.certified is not None and np.isfinite(self.certified) else -sign * np.inf
        if not sign * float(certified) > sign * current:
            return False
        self.certified, self.proof = float(certified), proof
        self.note = (self.note + "; " if self.note else "") + how
        side = 1 if self.sense == "min" else 2
        for point in self.convergence:
            old = point[side]
            point[side] = float(certified) if old is None else (max(old, certified) if sign > 0 else min(old, certified))
        return True

    def widen(self, ratio):
        """The bracket with its certified side moved out to ``ratio`` times (an inf: 1/ratio of) the observed side
        where it lies between the two (a larger upper bound is as certified; an inverted bracket stays as it is, for
        the checks to see); returns the bracket."""
        if self.certified is not None and np.isfinite(self.certified) and self.observed > 0:
            far = self.observed * ratio if self.sense == "max" else self.observed / ratio
            if self.observed <= self.certified < far if self.sense == "max" else far < self.certified <= self.observed:
                self.certified = float(far)
                self.note += f"; widened to {ratio:.6g}x of the observed side, so the independent checker re-proves it"
        return self

    def certificate(self):
        """The certificate of the certified side (a :class:`inertiaproof.citation.Certificate`), or None: made once
        from the claim ``certify`` (with the certified side, note, witness and ``proof``), its trees cut back to what
        the checker needs (:func:`.completion.pruned`), and kept while those stay."""
        if not self.certify or self.certified is None:
            return None
        witness = np.asarray(self.witness, float)
        sources, values = (self.certify, self.proof), (self.certified, self.note, witness.tobytes())
        kept = self._made
        if kept is None or any(a is not b for a, b in zip(kept[0], sources)) or kept[1] != values:
            cert = pruned(self.certify(self.certified, self.note, witness, self.proof))
            self._made = (sources, values, Certificate.of(cert))
        return self._made[2]


def local_search(value, q, lo, hi, free, *, sign, rounds=40, step=0.25):
    """Batched pattern search from starting points q (K, n): each round tries +-step along every free coordinate."""
    q = np.array(q, dtype=float)
    best = sign * value(q)
    width = np.where(free, hi - lo, 0.0)
    steps = np.full(len(q), step)
    dirs = np.concatenate([np.diag(width), -np.diag(width)])[np.concatenate([free, free])]
    if not len(dirs):
        return q, sign * best
    for _ in range(rounds):
        trial = np.clip(q[:, None, :] + steps[:, None, None] * dirs[None], lo, hi)  # (K, 2d, n)
        vals = sign * value(trial.reshape(-1, q.shape[1])).reshape(trial.shape[:2])
        k = np.argmin(vals, 1)
        better = vals[np.arange(len(q)), k] < best
        q[better] = trial[better, k[better]]
        best = np.where(better, vals[np.arange(len(q)), k], best)
        steps = np.where(better, steps, steps * 0.5)
        if steps.max() < 1e-6:  # of the box width: at an interior optimum the value is then within ~1e-12
            break
    return q, sign * best


def bracket_extreme(value, box_bound, lo, hi, *, sense, quantity_name, samples, rounds, rng, free=None,
                    progress=None, rtol=1e-6, batch=64, max_boxes=200_000, weights=None, note="", cost=1.0,
                    partition=False):
    """Bracket inf (sense 'min') or sup ('max') of ``value`` over the box [lo, hi].

    ``value(q)`` maps configurations (K, n) to (K,). ``box_bound(centres, radii)``
    returns a certified lower (min) or upper (max) bound of ``value`` on each box,
    or is None when no certified bound is available. ``free`` marks the
    coordinates the function depends on (the others stay at the box centre).
    ``weights`` scale the widths when choosing the coordinate to split. ``cost`` is the relative cost of a
    box bound (1 for a 7-joint chain): the budget is ``max(1, rounds) / cost`` rounds of ``2 batch`` boxes (under
    one round: one round of as many boxes as it pays for; under one box: none, and no certified side), a count (the
    same bracket for a seed on any machine), with the wall-clock safety net ``GUARD`` (a loaded machine ends with a
    wider, still certified bracket).
    ``partition``: the bracket's ``proof`` is the prefix code (:mod:`inertiaproof.verify.tree`) of the halvings
    made: its leaves, the boxes set aside as unable to beat the observed side and those left, tile the box and
    every one's bound is within the certified side.
    """
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    n = lo.size
    free = np.ones(n, bool) if free is None else np.asarray(free, bool)
    weights = np.ones(n) if weights is None else np.asarray(weights, float)
    sign = 1.0 if sense == "min" else -1.0
    start = time.perf_counter()
    best_q, best = _sampled_best(value, lo, hi, free, samples, rng, sign, rounds)
    conv = []
    work = max(1.0, rounds) * 2 * batch / cost  # boxes the budget pays for (a round at least)
    if box_bound is None or work < 1:
        conv.append(_point(start, sense, None, best))
        if box_bound is not None:
            note = f"no branch and bound: one box bound costs {cost:.3g} units, the budget pays for {work:.3g}"
        return Bracket(quantity_name, sense, best, None, best_q, conv, 0, note)
    batch = max(1, min(batch, int(work / 2)))  # under one round of 2 batch boxes (costly box bounds): one of fewer
    budget = max(1, int(work / (2 * batch)))
    found = _branch_and_bound(value, box_bound, lo, hi, free, weights, sense, (best, best_q), conv, start, batch,
                              budget, start + GUARD[0] + GUARD[1] * rounds, rtol, max_boxes,
                              progress and (lambda boxes: progress(f"{quantity_name}: [{_sides(conv)}] after {boxes} boxes")))
    (best, best_q), certified, boxes, splits = found
    proof = _prefix_code(splits) if partition else None
    return Bracket(quantity_name, sense, best, certified, best_q, _thin(conv), boxes, note, proof=proof)


def _sampled_best(value, lo, hi, free, samples, rng, sign, rounds):
    """(configuration, value) of the best of ``samples`` random configurations, improved by a local search of
    ``LOCAL_ROUNDS_PER_ROUND`` rounds per refinement round (at most 40), paid for in trial configurations."""
    mid = 0.5 * (lo + hi)
    q = np.where(free, lo + (hi - lo) * rng.random((samples, lo.size)), mid)
    vals = value(q)
    trials = 2 * max(1, int(free.sum()))  # configurations a round of local search tries per start
    top = np.argsort(sign * vals)[: min(8, samples, max(1, LOCAL_POINTS // trials))]
    share = min(1.0, LOCAL_POINTS / (len(top) * trials))  # rounds are paid for in trial configurations
    local = min(40, max(min(4, 4 * share), rounds * LOCAL_ROUNDS_PER_ROUND * share))
    qs, vs = local_search(value, q[top], lo, hi, free, sign=sign, rounds=max(1, int(local)))
    k = int(np.argmin(sign * vs))
    best_q, best = qs[k].copy(), float(vs[k])
    if sign * vals[top[0]] < sign * best:
        best_q, best = q[top[0]].copy(), float(vals[top[0]])
    return best_q, best


def _point(start, sense, cert, best):
    """A convergence point [seconds, lower, upper]."""
    lower, upper = (cert, best) if sense == "min" else (best, cert)
    return [round(time.perf_counter() - start, 6), _finite(lower), _finite(upper)]


def _sides(conv):
    return ", ".join("unbounded" if x is None else f"{x:.6g}" for x in conv[-1][1:])  # None: not finite yet


def _halves(c, r, weights):
    """The two halves (centres, radii) of boxes (c, r) along each one's widest weighted coordinate, and the axes."""
    axis = np.argmax(r * weights, 1)
    half = r.copy()
    half[np.arange(len(r)), axis] *= 0.5
    shift = np.zeros_like(r)
    shift[np.arange(len(r)), axis] = half[np.arange(len(r)), axis]
    return np.concatenate([c - shift, c + shift]), np.concatenate([half, half]), axis


def _branch_and_bound(value, box_bound, lo, hi, free, weights, sense, best, conv, start, batch, budget, guard, rtol,
                      max_boxes, report):
    """Rounds of branch and bound from the root box: ((best value, its configuration), the certified side, boxes
    bounded, the halvings made per round: (parents, axes, the first child's number)), at most ``budget`` rounds of
    ``2 batch`` boxes, until the wall-clock ``guard``; ``conv`` gets a point per round."""
    sign = 1.0 if sense == "min" else -1.0
    best, best_q = best
    centres, radii = 0.5 * (lo + hi)[None].copy(), np.where(free, 0.5 * (hi - lo), 0.0)[None]
    bounds = sign * box_bound(centres, radii)
    boxes = 1
    ids, splits = np.zeros(1, int), []  # every box's number (the root's 0), and per round the halvings made:
    # (parents, axes, the first child's number); a box set aside (it cannot beat the observed side) stays a leaf
    certified = sign * float(np.min(bounds))
    conv.append(_point(start, sense, certified, best))
    last_report, done = start, 0
    while done < budget and len(bounds) and time.perf_counter() < guard:
        done += 1
        keep = bounds < sign * best  # boxes that cannot beat the observed value are done
        centres, radii, bounds, ids = centres[keep], radii[keep], bounds[keep], ids[keep]
        if not len(bounds):
            certified = best
            break
        take = np.argsort(bounds)[:batch] if len(bounds) > batch else np.arange(len(bounds))
        rest = np.ones(len(bounds), bool)
        rest[take] = False
        child_c, child_r, axis = _halves(centres[take], radii[take], weights)
        splits.append((ids[take], axis, boxes))  # children numbered from boxes: the lower halves first
        ids = np.concatenate([ids[rest], boxes + np.arange(len(child_c))])
        child_v = value(child_c)
        k = int(np.argmin(sign * child_v))
        if sign * child_v[k] < sign * best:
            best, best_q = float(child_v[k]), child_c[k].copy()
        child_b = sign * box_bound(child_c, child_r)
        child_b = np.maximum(child_b, np.concatenate([bounds[take], bounds[take]]))  # a child lies in its parent
        boxes += len(child_c)
        centres, radii = np.concatenate([centres[rest], child_c]), np.concatenate([radii[rest], child_r])
        bounds = np.concatenate([bounds[rest], child_b])
        certified = sign * float(min(np.min(bounds), sign * best))
        conv.append(_point(start, sense, certified, best))
        if abs(best - certified) <= rtol * max(abs(best), 1e-300) or len(bounds) > max_boxes:
            break
        if report and time.perf_counter() - last_report > 2.0:
            report(boxes)
            last_report = time.perf_counter()
    if len(bounds) == 0:
        certified = best
    conv.append(_point(start, sense, certified, best))
    return (best, best_q), certified, boxes, splits


def _prefix_code(splits):
    """The prefix code of the halvings ``splits`` (per round: parents, axes, the first child's number) from the root
    (box 0): an axis k for a box halved along coordinate k, then its lower and upper halves; "." for a leaf."""
    cut = {}
    for parents, axes, first in splits:
        for t, (parent, axis) in enumerate(zip(parents.tolist(), axes.tolist())):
            cut[parent] = (axis, first + t, first + len(parents) + t)
    tokens, stack = [], [0]
    while stack:
        box = stack.pop()
        if box in cut:
            axis, lower, upper = cut[box]
            tokens.append(str(axis))
            stack += [upper, lower]
        else:
            tokens.append(".")
    return " ".join(tokens)


def _finite(x):
    return None if x is None or not np.isfinite(x) else float(x)


def _thin(points, keep=60):
    """At most ``keep`` convergence points, always the first and the last."""
    if len(points) <= keep:
        return points
    idx = np.unique(np.round(np.geomspace(1, len(points), keep)).astype(int) - 1)
    return [points[i] for i in idx]
