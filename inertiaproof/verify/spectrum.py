"""The ``mass-matrix-spectrum`` claim, proved on the certificate's tree of boxes, walked once.

It says: for every q in the box D (``domain``) and every Theta in the convex hull of the parameter sets
(``parameters``),

- ``lambda_min``: lambda_min(M(q, Theta)) >= bound, proved as M - bound I > 0;
- ``lambda_max``: lambda_max(M(q, Theta)) <= bound, proved as bound I - M > 0 (M with -Z(Phi_l)).

M is linear in Theta and lambda_min concave (lambda_max convex), so the hull's extremes are at its vertices:
each parameter set is proved in turn. The ``tree`` (:mod:`.tree`) cuts D into boxes; every leaf must be proved by
the pivots of :meth:`.kinematics.Chain.pivots` (an inner box that passes needs none of its leaves), with the
turns' loss in the certificate's ``metric``: no box is cut beyond the tree, a leaf that fails is not re-proved.
The claim is refuted only at a point: the ``witness`` (tested first) or a failing leaf's centre, where a pivot of
M itself is a negative ball. An upper claim may instead name ``method`` "lengths": the spectral radius of entry
sizes from the chain's lengths bounds lambda_max(M(q)) for every q at once (:mod:`.lengths`).

Optional ``forms`` (lambda_min only): one set of body matrices Y_l for all parameter sets, or one per set, each
Y_l <= Z(Phi_l) (decided exactly); then M(q, Theta) >= sum_l QJ_l^T Y_l QJ_l and the boxes are proved on the
forms. Optional ``split`` (lambda_min only): the chain split at a body k with interface inertias L, one per
parameter set, and two trees, the tail's and the head's (:meth:`Problem.walks`).
"""

from __future__ import annotations

from flint import arb, arb_mat, fmpq

from .bodies import parameter_sets, spatial_inertia
from .exact import BadCertificate, finite, rational, rational_matrix, semidefinite
from .kinematics import Chain, definite
from .lengths import perron_side
from .outcome import REPROVED, UNPROVED, Outcome, refuted
from . import tree
from .tree import parse

__all__ = ["KEYS", "Problem", "domain_of", "metric_of", "prove", "witness_of"]

QUANTITIES = {"lambda_min": (1, -1), "lambda_max": (-1, 1)}  # (sign of Z, sign of the bound in the shift)
KEYS = {"schema", "claim", "chain", "domain", "parameters", "formation", "tree", "metric", "method", "forms", "split",
        "witness", "provenance"}
METRICS = ("shift", "abs")


def _symmetric(rows, where):
    m = rational_matrix(rows, (6, 6), where)
    if any(m[i][j] != m[j][i] for i in range(6) for j in range(i)):
        raise BadCertificate(f"{where}: not symmetric")
    return m


def domain_of(cert, chain):
    """The box of a certificate's ``domain``, one [lo, hi] of rationals per joint, checked to cover every q the
    chain allows, so a claim over it is a claim over them all: each joint's limits, a full turn (2 pi) of a
    revolute joint without them (M is periodic in its angle), anything for the first joint (M does not depend on
    q_1: body twists are seen from the bodies)."""
    domain = cert.get("domain")
    if not (isinstance(domain, list) and len(domain) == chain.n and all(isinstance(e, list) and len(e) == 2
                                                                       for e in domain)):
        raise BadCertificate(f"domain: one [lo, hi] per joint ({chain.n})")
    domain = [tuple(rational(x, f"domain[{k}]") for x in edge) for k, edge in enumerate(domain)]
    for k, ((lo, hi), joint) in enumerate(zip(domain, chain.joints)):
        turn = joint.revolute and arb(hi - lo) >= 2 * arb.pi()
        if lo > hi or k and not (turn or joint.limits and lo <= joint.limits[0] and hi >= joint.limits[1]):
            raise BadCertificate(f"domain[{k}]: does not cover joint {k + 1}'s limits (or a full turn)")
    return domain


def witness_of(cert, domain):
    """The certificate's ``witness`` (a configuration in the domain), or None."""
    witness = cert.get("witness")
    if witness is None:
        return None
    if not isinstance(witness, list) or len(witness) != len(domain):
        raise BadCertificate(f"witness: one coordinate per joint ({len(domain)})")
    witness = [rational(x, f"witness[{k}]") for k, x in enumerate(witness)]
    if any(not lo <= x <= hi for x, (lo, hi) in zip(witness, domain)):
        raise BadCertificate("witness: outside the domain")
    return witness


def metric_of(cert):
    """The turns' loss metric (kind, ridge): kind "shift" or "abs", 0 < ridge <= 1."""
    metric = cert.get("metric")
    if not isinstance(metric, dict) or set(metric) != {"kind", "ridge"} or metric["kind"] not in METRICS:
        raise BadCertificate(f"metric: {{kind, ridge}}, kind one of {list(METRICS)}")
    ridge = rational(metric["ridge"], "metric.ridge")
    if not 0 < ridge <= 1:
        raise BadCertificate("metric.ridge: must lie in (0, 1]")
    return metric["kind"], float(ridge)


class Problem:
    """A parsed spectrum claim: what to prove on which tree, and how a point refutes it."""

    def __init__(self, cert):
        if not set(cert) <= KEYS:
            raise BadCertificate(f"unknown field(s) {sorted(set(cert) - KEYS)}")
        claim = cert["claim"]
        if claim.get("quantity") not in QUANTITIES:
            raise BadCertificate(f"claim.quantity: one of {sorted(QUANTITIES)}")
        self.quantity = claim["quantity"]
        self.sign, shift = QUANTITIES[self.quantity]
        self.bound = rational(claim.get("bound"), "claim.bound")
        self.shift = arb(self.bound) * shift
        self.chain = Chain(cert.get("chain"))
        self.domain = domain_of(cert, self.chain)
        self.bodies = [[spatial_inertia(row) for row in rows]
                       for rows in parameter_sets(cert, self.chain.n)]
        self.real = [[arb_mat(m) * self.sign for m in z] for z in self.bodies]
        self.witness = witness_of(cert, self.domain)
        self.method = cert.get("method", "tree")
        if self.method not in ("tree", "lengths") or self.method == "lengths" and self.sign > 0:
            raise BadCertificate("method: 'tree', or 'lengths' for a lambda_max claim")
        self.metric = metric_of(cert) if self.sign > 0 and self.method == "tree" else None
        self.root = parse(cert.get("tree", "."), self.domain)
        self.forms = self._forms(cert.get("forms"))
        self.split = self._split(cert.get("split"))

    def _forms(self, forms):
        if forms is None:
            return None
        if self.sign < 0 or not isinstance(forms, list) or len(forms) not in (1, len(self.bodies)):
            raise BadCertificate(f"forms: for a lambda_min claim, one set of body matrices or one per parameter set "
                                 f"({len(self.bodies)})")
        return [[_symmetric(y, f"forms[{f}][{l}]") for l, y in enumerate(form)]
                if isinstance(form, list) and len(form) == self.chain.n else _bad(f"forms[{f}]: one matrix per body")
                for f, form in enumerate(forms)]

    def _split(self, split):
        if split is None:
            return None
        if self.sign < 0 or self.forms is not None or not isinstance(split, dict) \
                or set(split) != {"body", "interfaces", "tail", "head"}:
            raise BadCertificate("split: {body, interfaces, tail, head}, for a lambda_min claim without forms")
        body, inner = split["body"], split["interfaces"]
        if type(body) is not int or not 0 < body < self.chain.n - 1:
            raise BadCertificate(f"split.body: a body between 1 and {self.chain.n - 2}")
        if not isinstance(inner, list) or len(inner) != len(self.bodies):
            raise BadCertificate(f"split.interfaces: one 6x6 matrix per parameter set ({len(self.bodies)})")
        return (body, [_symmetric(m, f"split.interfaces[{v}]") for v, m in enumerate(inner)],
                parse(split["tail"], self.domain), parse(split["head"], self.domain))

    def refute(self, point, why, boxes=0):
        """A refutation at the configuration ``point``: a pivot of M - bound I (bound I - M) a negative ball for
        one parameter set; None where there is none."""
        for v, inertias in enumerate(self.real):
            failed, value = self.chain.pivots([(x, fmpq(0)) for x in point], inertias, self.shift)
            if failed is not None and value < 0:
                what = "M - bound I" if self.sign > 0 else "bound I - M"
                return refuted(f"{why}, parameter set {v}: pivot {failed + 1} of the LDL^T of {what} from the tip is "
                               f"{value.str(5, radius=False)} < 0", {"q": [str(x) for x in point], "parameter_set": v},
                               {"pivot": value.str(10), "bound": str(self.bound)}, boxes)
        return None

    def walks(self):
        """(label, name, root, test) for each tree to walk: ``test`` maps a box (centres, radii) to (None, its smallest
        pivot) where it is proved, else (the coordinates at which a cut could help, best first: those above the
        joint whose pivot failed, widest first; why)."""
        proving = self.real if self.forms is None else [[arb_mat(m) * self.sign for m in y] for y in self.forms]
        out = []
        for v in range(len(self.bodies)):
            inertias = proving[v if len(proving) > 1 else 0]
            if self.split is None:
                out.append((f"parameter set {v}", "tree", self.root, self._test(inertias, self.chain.n - 1)))
            else:
                out += self._split_walks(v, inertias)
        return out

    def _test(self, inertias, last, memo=None, **kw):
        memo = {} if memo is None else memo

        def test(box):
            failed, pivot = self.chain.pivots(box, inertias, self.shift, self.metric, memo=memo, **kw)
            return (None, pivot) if failed is None else (_cuts(box, failed, last), f"pivot {failed + 1}: {pivot}")
        return test

    def _split_walks(self, v, inertias):
        """The split at body k: on the tail's boxes the pivots of joints k+1.. are positive and the lower bound of
        A_k(q) less L is definite; on the head's, the chain of joints 0..k with body k's inertia L has positive
        pivots. The head's recursion is Loewner-monotone in A_k, so together lambda_min(M) > bound on the product of
        the two partitions, the whole domain."""
        k, interfaces, tail, head = self.split
        interface, memo, last = arb_mat(interfaces[v]), {}, self.chain.n - 1

        def tail_test(box):
            failed, lower = self.chain.pivots(box, inertias, self.shift, self.metric, memo=memo, stop=k)
            if failed is not None:
                return _cuts(box, failed, last), f"pivot {failed + 1}: {lower}"
            return (None, lower) if definite(lower - interface) else (_cuts(box, k, last), "A_k - L not definite")

        heads = inertias[:k] + [interface] + inertias[k + 1:]
        return [(f"parameter set {v}, the tail's tree", "tail", tail, tail_test),
                (f"parameter set {v}, the head's tree", "head", head, self._test(heads, k, top=k))]

    def forms_below(self):
        """None where every form lies below its Z(Phi_l) (decided exactly), else why not."""
        for v, z in enumerate(self.bodies if self.forms is not None else []):
            y = self.forms[v if len(self.forms) > 1 else 0]
            for l in range(self.chain.n):
                if not semidefinite([[z[l][i][j] - y[l][i][j] for j in range(6)] for i in range(6)]):
                    return f"the form of body {l + 1} is not below Z(Phi) of parameter set {v} (exact arithmetic)"
        return None


def _bad(why):
    raise BadCertificate(why)


def _cuts(box, failed, last):
    return sorted((k for k in range(failed + 1, last + 1) if box[k][1] > 0), key=lambda k: -box[k][1])


def prove(cert):
    """The :class:`Outcome` of the certificate's claim: every leaf of its tree proved, or where it is not."""
    problem = Problem(cert)
    why = problem.forms_below()
    if why:
        return Outcome(UNPROVED, why)
    if problem.witness is not None:  # where the prover saw the extreme: a claim beyond the value there is refuted
        found = problem.refute(problem.witness, "at the witness q")
        if found:
            return found
    if problem.method == "lengths":
        side = finite(perron_side(problem.chain, problem.domain, problem.bodies), "the lengths' side")
        if side <= problem.shift:
            return Outcome(REPROVED, f"rho of the entry sizes from the chain's lengths, {side.str(6)} <= the bound "
                           "(Perron-Frobenius)")
        return Outcome(UNPROVED, f"rho of the entry sizes from the chain's lengths, {side.str(6)}, is not below the "
                       "bound")
    return tree.prove(problem, problem.walks())
