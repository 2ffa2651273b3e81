"""The ``mass-matrix-spectrum`` claim, proved on the certificate's tree of boxes, walked once.

For every q in the box D (``domain``) and Theta in the hull of the sets (``parameters``): ``lambda_min`` M - bound I
> 0, ``lambda_max`` bound I - M > 0 (M with -Z(Phi_l)). M is linear in Theta and lambda_min concave (lambda_max
convex), so each set is proved in turn. Every leaf of the ``tree`` (:mod:`.tree`) must be proved by the pivots of
:meth:`.kinematics.Chain.pivots` in the certificate's ``metric``; the claim is refuted only at a point (the
``witness``, tested first, or a failing leaf's centre) where a pivot of M itself is a negative ball. An upper claim
may name ``method`` "lengths" (:mod:`.lengths`). Optional (lambda_min): ``forms`` Y_l <= Z(Phi_l) (decided exactly,
one set or one per parameter set), the boxes proved on sum_l QJ_l^T Y_l QJ_l <= M; ``split``, the chain split at
body k with interface inertias L_v and two trees: on the tail's boxes the pivots of joints k+1.. are positive and
the lower bound of A_k(q) less L_v is definite; on the head's, the chain of joints 0..k with body k's inertia L_v
has positive pivots. The head's recursion is Loewner-monotone in A_k, so together lambda_min(M) > bound on the
product of the two partitions, the whole domain.
"""

from flint import arb, arb_mat, fmpq

from . import tree
from .bodies import parameter_sets, spatial_inertia
from .exact import fields, finite, need, rational, semidefinite, symmetric
from .kinematics import definite
from .lengths import perron_side
from .outcome import REPROVED, UNPROVED, Outcome, refuted

QUANTITIES = {"lambda_min": (1, -1), "lambda_max": (-1, 1)}  # (sign of Z, sign of the bound in the shift)
KEYS = {"schema", "claim", "chain", "domain", "parameters", "formation", "tree", "metric", "method", "forms", "split",
        "witness", "provenance"}
METRICS = ("shift", "abs")


class Problem(tree.Claim):
    """A parsed spectrum claim: what to prove on which tree, and how a point refutes it."""

    def __init__(self, cert):
        super().__init__(cert, KEYS, QUANTITIES)
        self.sign, shift = QUANTITIES[self.quantity]
        self.shift = arb(self.bound) * shift
        n, lower = self.chain.n, self.sign > 0
        self.bodies = [[spatial_inertia(row) for row in rows] for rows in parameter_sets(cert, n)]
        self.real = [[arb_mat(m) * self.sign for m in z] for z in self.bodies]
        self.method = cert.get("method", "tree")
        need(self.method == "tree" or self.method == "lengths" and not lower,
             "method: 'tree', or 'lengths' for a lambda_max claim")
        self.metric = _metric(cert.get("metric")) if lower and self.method == "tree" else None
        forms, split, sets = cert.get("forms"), cert.get("split"), len(self.bodies)
        need(forms is None or lower and isinstance(forms, list) and len(forms) in (1, sets),
             f"forms: for a lambda_min claim, one set of body matrices or one per parameter set ({sets})")
        self.forms = forms and [_matrices(form, n, f"forms[{f}]") for f, form in enumerate(forms)]
        self.split = None
        if split is not None:
            need(lower and forms is None, "split: for a lambda_min claim without forms")
            k = fields(split, ("body", "interfaces", "tail", "head"), "split")["body"]
            need(type(k) is int and 0 < k < n - 1, f"split.body: a body between 1 and {n - 2}")
            self.split = (k, _matrices(split["interfaces"], sets, "split.interfaces"),
                          tree.parse(split["tail"], self.domain), tree.parse(split["head"], self.domain))

    def refute(self, point, why, boxes=0):
        """A refutation at the configuration ``point``: a pivot of M - bound I (bound I - M) a negative ball for
        one parameter set; None where there is none."""
        what = "M - bound I" if self.sign > 0 else "bound I - M"
        for v, inertias in enumerate(self.real):
            failed, value = self.chain.pivots([(x, fmpq(0)) for x in point], inertias, self.shift)
            if failed is not None and value < 0:
                return refuted(f"{why}, parameter set {v}: pivot {failed + 1} of the LDL^T of {what} from the tip is "
                               f"{value.str(5, radius=False)} < 0", {"q": [str(x) for x in point], "parameter_set": v},
                               {"pivot": value.str(10), "bound": str(self.bound)}, boxes)
        return None

    def walks(self):
        """(label, name, root, test) per tree: ``test`` maps a box (centres, radii) to (None, its smallest pivot)
        where it is proved, else (the coordinates above the joint whose pivot failed, widest first; why)."""
        proving = self.real if self.forms is None else [[arb_mat(m) * self.sign for m in y] for y in self.forms]
        out = []
        for v in range(len(self.bodies)):
            inertias = proving[min(v, len(proving) - 1)]
            if self.split is None:
                out.append((f"parameter set {v}", "tree", self.root, self._test(inertias)))
                continue
            k, interfaces, tail, head = self.split
            interface = arb_mat(interfaces[v])
            heads = inertias[:k] + [interface] + inertias[k + 1:]
            out += [(f"parameter set {v}, the tail's tree", "tail", tail, self._test(inertias, None, k, interface)),
                    (f"parameter set {v}, the head's tree", "head", head, self._test(heads, k))]
        return out

    def _test(self, inertias, top=None, stop=None, interface=None):
        memo, last = {}, self.chain.n - 1 if top is None else top

        def test(box):
            failed, pivot = self.chain.pivots(box, inertias, self.shift, self.metric, memo, top, stop)
            if failed is None and interface is not None and not definite(pivot - interface):
                return _cuts(box, stop, last), "A_k - L not definite"
            return (None, pivot) if failed is None else (_cuts(box, failed, last), f"pivot {failed + 1}: {pivot}")
        return test

    def forms_below(self):
        """None where every form lies below its Z(Phi_l) (decided exactly), else why not."""
        for v, z in enumerate(self.bodies if self.forms is not None else []):
            y = self.forms[min(v, len(self.forms) - 1)]
            for l in range(self.chain.n):
                if not semidefinite([[z[l][i][j] - y[l][i][j] for j in range(6)] for i in range(6)]):
                    return f"the form of body {l + 1} is not below Z(Phi) of parameter set {v} (exact arithmetic)"
        return None


def _cuts(box, failed, last):
    return tree.widest([r for _, r in box], range(failed + 1, last + 1))


def _metric(metric):
    """(kind, ridge) of the certificate's ``metric`` (:func:`.kinematics._metric_factor`)."""
    need(fields(metric, ("kind", "ridge"), "metric")["kind"] in METRICS, f"metric.kind: one of {list(METRICS)}")
    ridge = rational(metric["ridge"], "metric.ridge")
    need(0 < ridge <= 1, "metric.ridge: must lie in (0, 1]")
    return metric["kind"], float(ridge)


def _matrices(items, count, where):
    """The ``count`` symmetric 6 x 6 matrices of exact rationals of the list ``items``."""
    need(isinstance(items, list) and len(items) == count, f"{where}: a list of {count} symmetric 6x6 matrices")
    return [symmetric(m, 6, f"{where}[{i}]") for i, m in enumerate(items)]


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
        holds = side <= problem.shift
        return Outcome(REPROVED if holds else UNPROVED, f"rho of the entry sizes from the chain's lengths, "
                       f"{side.str(6)}, " + ("<= the bound (Perron-Frobenius)" if holds else "is not below the bound"))
    return tree.prove(problem, problem.walks())
