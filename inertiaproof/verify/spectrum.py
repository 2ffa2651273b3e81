"""The ``mass-matrix-spectrum`` claim, proved on the certificate's tree of boxes, walked once.

For every q in the box D (``domain``) and Theta in the hull of the sets (``parameters``): ``lambda_min`` M - bound I
> 0, ``lambda_max`` bound I - M > 0 (M with -Z(Phi_l)). M is linear in Theta and lambda_min concave (lambda_max
convex), so each set is proved in turn. Every leaf of the ``tree`` (:mod:`.tree`) must be proved by the pivots of
:meth:`.kinematics.Chain.pivots` in the certificate's ``metric``; the claim is refuted only at a point (the
``witness``, tested first, or a failing leaf's centre) where a pivot of M itself is a negative ball. An upper claim
may name ``method`` "lengths" (:mod:`.lengths`). Optional (lambda_min): ``forms`` Y_l <= Z(Phi_l) (decided exactly,
one set or one per parameter set), the boxes proved on sum_l QJ_l^T Y_l QJ_l <= M; ``split``, the chain split at
body k with interface inertias L and two trees (:meth:`Problem._split_walks`).
"""

from flint import arb, arb_mat, fmpq

from . import tree
from .bodies import parameter_sets, spatial_inertia
from .exact import finite, known, need, rational, semidefinite, symmetric
from .kinematics import Chain, definite
from .lengths import perron_side
from .outcome import REPROVED, UNPROVED, Outcome, refuted

QUANTITIES = {"lambda_min": (1, -1), "lambda_max": (-1, 1)}  # (sign of Z, sign of the bound in the shift)
KEYS = {"schema", "claim", "chain", "domain", "parameters", "formation", "tree", "metric", "method", "forms", "split",
        "witness", "provenance"}
METRICS = ("shift", "abs")


def fields(cert, keys, quantities):
    """Nothing, or :class:`.exact.BadCertificate` for a field beyond ``keys`` or a quantity not in ``quantities``."""
    known(cert, keys)
    need(cert["claim"].get("quantity") in quantities, f"claim.quantity: one of {sorted(quantities)}")


def domain_of(cert, chain):
    """The box of ``domain``, one [lo, hi] of rationals per joint, checked to cover every q the chain allows: each
    joint's limits, a full turn (2 pi) of a revolute joint without them (M is periodic in its angle), anything for
    the first joint (M does not depend on q_1: body twists are seen from the bodies)."""
    domain = cert.get("domain")
    need(isinstance(domain, list) and len(domain) == chain.n and all(isinstance(e, list) and len(e) == 2
                                                                     for e in domain),
         f"domain: one [lo, hi] per joint ({chain.n})")
    domain = [tuple(rational(x, f"domain[{k}]") for x in edge) for k, edge in enumerate(domain)]
    for k, ((lo, hi), joint) in enumerate(zip(domain, chain.joints)):
        turn = joint.revolute and arb(hi - lo) >= 2 * arb.pi()
        need(lo <= hi and (not k or turn or joint.limits and lo <= joint.limits[0] and hi >= joint.limits[1]),
             f"domain[{k}]: does not cover joint {k + 1}'s limits (or a full turn)")
    return domain


def witness_of(cert, domain):
    """The certificate's ``witness`` (a configuration in the domain), or None."""
    witness = cert.get("witness")
    if witness is None:
        return None
    need(isinstance(witness, list) and len(witness) == len(domain),
         f"witness: one coordinate per joint ({len(domain)})")
    witness = [rational(x, f"witness[{k}]") for k, x in enumerate(witness)]
    need(all(lo <= x <= hi for x, (lo, hi) in zip(witness, domain)), "witness: outside the domain")
    return witness


class Problem:
    """A parsed spectrum claim: what to prove on which tree, and how a point refutes it."""

    def __init__(self, cert):
        fields(cert, KEYS, QUANTITIES)
        self.quantity = cert["claim"]["quantity"]
        self.sign, shift = QUANTITIES[self.quantity]
        self.bound = rational(cert["claim"].get("bound"), "claim.bound")
        self.shift = arb(self.bound) * shift
        self.chain = Chain(cert.get("chain"))
        self.domain = domain_of(cert, self.chain)
        self.bodies = [[spatial_inertia(row) for row in rows] for rows in parameter_sets(cert, self.chain.n)]
        self.real = [[arb_mat(m) * self.sign for m in z] for z in self.bodies]
        self.witness = witness_of(cert, self.domain)
        self.method = cert.get("method", "tree")
        need(self.method == "tree" or self.method == "lengths" and self.sign < 0,
             "method: 'tree', or 'lengths' for a lambda_max claim")
        self.metric = None
        if self.sign > 0 and self.method == "tree":
            metric = cert.get("metric")
            need(isinstance(metric, dict) and set(metric) == {"kind", "ridge"} and metric["kind"] in METRICS,
                 f"metric: {{kind, ridge}}, kind one of {list(METRICS)}")
            ridge = rational(metric["ridge"], "metric.ridge")
            need(0 < ridge <= 1, "metric.ridge: must lie in (0, 1]")
            self.metric = metric["kind"], float(ridge)
        self.root = tree.parse(cert.get("tree", "."), self.domain)
        forms, split, sets = cert.get("forms"), cert.get("split"), len(self.bodies)
        need(forms is None or self.sign > 0 and isinstance(forms, list) and len(forms) in (1, sets),
             f"forms: for a lambda_min claim, one set of body matrices or one per parameter set ({sets})")
        for f, form in enumerate(forms or []):
            need(isinstance(form, list) and len(form) == self.chain.n, f"forms[{f}]: one matrix per body")
        self.forms = forms and [[symmetric(y, 6, f"forms[{f}][{l}]") for l, y in enumerate(form)]
                                for f, form in enumerate(forms)]
        self.split = None
        if split is not None:
            need(self.sign > 0 and forms is None and isinstance(split, dict)
                 and set(split) == {"body", "interfaces", "tail", "head"},
                 "split: {body, interfaces, tail, head}, for a lambda_min claim without forms")
            body, inner = split["body"], split["interfaces"]
            need(type(body) is int and 0 < body < self.chain.n - 1,
                 f"split.body: a body between 1 and {self.chain.n - 2}")
            need(isinstance(inner, list) and len(inner) == sets,
                 f"split.interfaces: one 6x6 matrix per parameter set ({sets})")
            self.split = (body, [symmetric(m, 6, f"split.interfaces[{v}]") for v, m in enumerate(inner)],
                          tree.parse(split["tail"], self.domain), tree.parse(split["head"], self.domain))

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
            out += [(f"parameter set {v}", "tree", self.root, self._test(inertias, self.chain.n - 1))] \
                if self.split is None else self._split_walks(v, inertias)
        return out

    def _test(self, inertias, last, interface=None, **kw):
        memo = {}

        def test(box):
            failed, pivot = self.chain.pivots(box, inertias, self.shift, self.metric, memo=memo, **kw)
            if failed is None and interface is not None and not definite(pivot - interface):
                return _cuts(box, kw["stop"], last), "A_k - L not definite"
            return (None, pivot) if failed is None else (_cuts(box, failed, last), f"pivot {failed + 1}: {pivot}")
        return test

    def _split_walks(self, v, inertias):
        """The split at body k: on the tail's boxes the pivots of joints k+1.. are positive and the lower bound of
        A_k(q) less L is definite; on the head's, the chain of joints 0..k with body k's inertia L has positive
        pivots. The head's recursion is Loewner-monotone in A_k, so together lambda_min(M) > bound on the product of
        the two partitions, the whole domain."""
        k, interfaces, tail, head = self.split
        interface, last = arb_mat(interfaces[v]), self.chain.n - 1
        tail_test = self._test(inertias, last, stop=k, interface=interface)
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


def _cuts(box, failed, last):
    return sorted((k for k in range(failed + 1, last + 1) if box[k][1] > 0), key=lambda k: -box[k][1])


def prove(cert):
    """The :class:`Outcome` of the certificate's claim: every leaf of its tree proved, or where it is not."""
    problem = Problem(cert)
    why = problem.forms_below()
    if why:
        return Outcome(UNPROVED, why)
    found = problem.witness is not None and problem.refute(problem.witness, "at the witness q")
    if found:  # where the prover saw the extreme: a claim beyond the value there is refuted
        return found
    if problem.method == "lengths":
        side = finite(perron_side(problem.chain, problem.domain, problem.bodies), "the lengths' side")
        return Outcome(REPROVED if side <= problem.shift else UNPROVED, f"rho of the entry sizes from the chain's "
                       f"lengths, {side.str(6)}, " + ("<= the bound (Perron-Frobenius)" if side <= problem.shift
                                                     else "is not below the bound"))
    return tree.prove(problem, problem.walks())
