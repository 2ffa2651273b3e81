"""The ``mass-matrix-spectrum`` claim, proved by branch and bound over the certificate's tree of boxes.

It says: for every q in the box D (``domain``) and every Theta in the convex
hull of the parameter sets (``parameters``),

- ``lambda_min``: lambda_min(M(q, Theta)) >= bound, proved as M - bound I > 0;
- ``lambda_max``: lambda_max(M(q, Theta)) <= bound, proved as bound I - M > 0 (M with -Z(Phi_l)).

M is linear in Theta and lambda_min concave (lambda_max convex), so the hull's extremes are at its vertices:
each parameter set is proved in turn. The ``tree`` (:mod:`.tree`) cuts D into boxes, walked from its root: a box
the pivots of :meth:`.kinematics.Chain.pivots` prove needs none of its halves; a leaf they do not prove is cut
again, within the budget of work spent on the boxes beyond the tree (:data:`.kinematics.WORK`); where the pivots
at its centre are proved negative, the claim is refuted there, and so it is at the optional ``witness`` (a
configuration, tested first). An upper claim is first tried without boxes: the spectral radius of entry sizes
from the chain's lengths bounds lambda_max(M(q)) for every q at once (:mod:`.lengths`), where a long chain's tree
would need too many boxes.

Optional ``forms`` (lambda_min only): one set of body matrices Y_l for all parameter sets, or one per set, each
Y_l <= Z(Phi_l) (decided exactly); then M(q, Theta) >= sum_l QJ_l^T Y_l QJ_l and the boxes are proved on the
forms. A box centre refutes only where M itself fails there. Optional ``split`` (lambda_min only): the chain split
at a body k with interface inertias L, one per parameter set, and two trees, the tail's and the head's
(:func:`_split_walk`).
"""

from __future__ import annotations

from collections import deque

from flint import arb, arb_mat, fmpq

from .bodies import parameter_sets, spatial_inertia
from .exact import BadCertificate, rational, rational_matrix, semidefinite
from .kinematics import WORK, Chain, definite, indefinite
from .lengths import perron_side
from .outcome import Outcome
from .tree import Node, halves, parse

__all__ = ["prove"]

QUANTITIES = {"lambda_min": (1, -1), "lambda_max": (-1, 1)}  # (sign of Z, sign of the bound in the shift)
METRIC = {"kind": "shift", "ridge": "1/10"}  # the turns' loss metric on the lower side where the certificate names
# none (any is sound; on Panda's unit-body ladder every box of the prover's partition holds with it); the upper side
# (bodies -Z(Phi_l) <= 0) measures it in the identity, as the prover does


def _matrices(rows, where):
    """A symmetric 6x6 matrix of exact rationals."""
    m = rational_matrix(rows, (6, 6), where)
    if any(m[i][j] != m[j][i] for i in range(6) for j in range(i)):
        raise BadCertificate(f"{where}: not symmetric")
    return m


def _parse(cert):
    claim = cert["claim"]
    if claim.get("quantity") not in QUANTITIES:
        raise BadCertificate(f"claim.quantity: one of {sorted(QUANTITIES)}")
    bound = rational(claim.get("bound"), "claim.bound")
    chain = Chain(cert.get("chain"))
    domain = cert.get("domain")
    if not isinstance(domain, list) or len(domain) != chain.n:
        raise BadCertificate(f"domain: one [lo, hi] per joint ({chain.n})")
    domain = [tuple(rational(x, f"domain[{k}]") for x in edge) if isinstance(edge, list) and len(edge) == 2
              else _bad(f"domain[{k}]: [lo, hi]") for k, edge in enumerate(domain)]
    if any(lo > hi for lo, hi in domain):
        raise BadCertificate("domain: lo > hi")
    bodies = [[spatial_inertia(row) for row in rows] for rows in parameter_sets(cert.get("parameters"), chain.n)]
    forms = cert.get("forms")
    if forms is not None:
        if claim["quantity"] != "lambda_min":
            raise BadCertificate("forms: only a lambda_min claim is proved on lower forms")
        if not isinstance(forms, list) or len(forms) not in (1, len(bodies)):
            raise BadCertificate(f"forms: one set of body matrices, or one per parameter set ({len(bodies)})")
        forms = [[_matrices(y, f"forms[{f}][{l}]") for l, y in enumerate(form)]
                 if isinstance(form, list) and len(form) == chain.n else _bad(f"forms[{f}]: one matrix per body")
                 for f, form in enumerate(forms)]
    split = cert.get("split")
    if split is not None:
        if claim["quantity"] != "lambda_min" or forms is not None:
            raise BadCertificate("split: only for a lambda_min claim without forms")
        body = split.get("body") if isinstance(split, dict) else None
        if not isinstance(body, int) or not 0 < body < chain.n - 1:
            raise BadCertificate(f"split.body: a body between 1 and {chain.n - 2}")
        inner = split.get("interfaces")
        if not isinstance(inner, list) or len(inner) != len(bodies):
            raise BadCertificate(f"split.interfaces: one 6x6 matrix per parameter set ({len(bodies)})")
        split = (body, [_matrices(m, f"split.interfaces[{v}]") for v, m in enumerate(inner)],
                 parse(split.get("tail"), domain), parse(split.get("head"), domain))
    witness = cert.get("witness")
    if witness is not None:
        if not isinstance(witness, list) or len(witness) != chain.n:
            raise BadCertificate(f"witness: one coordinate per joint ({chain.n})")
        witness = [rational(x, f"witness[{k}]") for k, x in enumerate(witness)]
        if any(not lo <= x <= hi for x, (lo, hi) in zip(witness, domain)):
            raise BadCertificate("witness: outside the domain")
    sign, shift = QUANTITIES[claim["quantity"]]
    metric = cert.get("metric", METRIC) if sign > 0 else None
    if metric is not None:
        if not isinstance(metric, dict) or metric.get("kind") not in ("shift", "abs"):
            raise BadCertificate("metric.kind: 'shift' or 'abs'")
        metric = (metric["kind"], float(rational(metric.get("ridge"), "metric.ridge")))
    return (chain, domain, bodies, forms, split, sign, arb(bound) * shift, parse(cert.get("tree", "."), domain),
            witness, metric)


def _bad(why):
    raise BadCertificate(why)


def _where(box):
    return [[str(lo), str(hi)] for lo, hi in box]


def prove(cert, budget):
    """The :class:`Outcome` of the certificate's claim, spending at most ``budget`` units of work
    (:data:`.kinematics.WORK`) on boxes beyond the tree."""
    chain, domain, bodies, forms, split, sign, shift, root, witness, metric = _parse(cert)
    real = [[arb_mat(m) * sign for m in z] for z in bodies]
    proving = real
    if forms is not None:
        for v, z in enumerate(bodies):
            y = forms[v if len(forms) > 1 else 0]
            for l in range(chain.n):
                if not semidefinite([[z[l][i][j] - y[l][i][j] for j in range(6)] for i in range(6)]):
                    return Outcome("refuted", f"the form of body {l + 1} is not below Z(Phi) of parameter set {v} "
                                   "(exact rational arithmetic)", 0, {"parameter_set": v, "body": l + 1})
        proving = [[arb_mat(m) * sign for m in y] for y in forms]
    boxes = 0

    def refuted(point, why):  # M - bound I (or bound I - M) indefinite at a point: the claim fails there
        nonlocal boxes
        for v, inertias in enumerate(real):
            boxes += 1
            failed, value = chain.pivots([(x, fmpq(0)) for x in point], inertias, shift)
            if failed is not None and value < 0:
                return Outcome("refuted", f"{why}, parameter set {v}: pivot {failed + 1} of the LDL^T from the tip is "
                               f"{value.str(5, radius=False)} < 0", boxes, {"q": [str(x) for x in point],
                                                                            "parameter_set": v})
        return None

    if witness is not None:  # where the prover saw the extreme: a claim beyond the value there is refuted at once
        found = refuted(witness, "at the witness q")
        if found:
            return found
    if sign < 0:
        side = perron_side(chain, domain, bodies)
        if side <= shift:  # an upper claim from lengths alone, no tree needed
            return Outcome("re-proved", f"rho of the entry sizes from the chain's lengths, {side.str(6)} <= the "
                           "bound (Perron-Frobenius: inertiaproof.verify.lengths)", 0)
    cuts, spent = [0], [0]

    def walk(root, v, test, last):  # the tree from its root: a box that passes needs none of its own
        queue = deque([root])
        while queue:
            node = queue.popleft()
            centred = [((lo + hi) / 2, (hi - lo) / 2) for lo, hi in node.box]
            nonlocal boxes
            boxes += 1
            before = WORK[0]
            failed, pivot = test(centred)
            if node.cut:
                spent[0] += WORK[0] - before
            if failed is None:
                continue
            if node.children is not None:
                queue.extend(node.children)
                continue
            before = WORK[0]
            found = refuted([c for c, _ in centred], "at the centre q of a box")
            spent[0] += WORK[0] - before  # a leaf that fails costs its centre's test too
            if found:
                found.where["box"] = _where(node.box)
                return found
            cut = max(range(failed + 1, last + 1), key=lambda k: centred[k][1], default=None)
            if cut is None or centred[cut][1] == 0 or spent[0] >= budget:
                why = (f"the budget of {budget} units of work ran out" if cut is not None and centred[cut][1] != 0
                       else f"pivot {failed + 1} is not decided at a point ({pivot})")
                return Outcome("not decided", why, boxes, {"box": _where(node.box), "parameter_set": v})
            cuts[0] += 1
            queue.extend(Node(half, cut=True) for half in halves(node.box, cut))
        return None

    for v, inertias in enumerate(proving):
        if split is None:
            memo = {}
            found = walk(root, v, lambda c: chain.pivots(c, inertias, shift, metric, memo=memo), chain.n - 1)
        else:
            found = _split_walk(chain, split, v, inertias, shift, metric, walk)
        if found:
            return found
    return Outcome("re-proved", f"the tree{'s' if split else ''} from the root and {cuts[0]} cut(s) more: {boxes} "
                   "boxes tested", boxes)


def _split_walk(chain, split, v, inertias, shift, metric, walk):
    """The split at body k: on the tail's boxes the pivots of joints k+1.. are positive and the lower bound of
    A_k(q) less L is definite; on the head's, the chain of joints 0..k with body k's inertia L has positive pivots.
    The head's recursion is Loewner-monotone in A_k, so together lambda_min(M) > bound on the product of the two
    partitions, the whole domain."""
    k, interfaces, tail, head = split
    interface = arb_mat(interfaces[v])
    tail_memo, head_memo = {}, {}

    def tail_test(c):
        failed, lower = chain.pivots(c, inertias, shift, metric, memo=tail_memo, stop=k)
        if failed is not None or definite(lower - interface):
            return failed, lower
        point = [(x, fmpq(0)) for x, _ in c]  # A_k at the box's centre, where a valid split has it above L
        failed, exact = chain.pivots(point, inertias, shift, metric, stop=k)
        if failed is None and indefinite(exact - interface):
            raise BadCertificate(f"split.interfaces[{v}]: not below the tail's articulated inertia A_{k + 1} at q = "
                                 f"[{', '.join(str(x) for x, _ in point)}]: the split at body {k + 1} does not hold")
        return k, "the tail's A_k is not above L"

    heads = inertias[:k] + [interface] + inertias[k + 1:]
    return (walk(tail, v, tail_test, chain.n - 1)
            or walk(head, v, lambda c: chain.pivots(c, heads, shift, metric, memo=head_memo, top=k), k))
