"""The ``mass-matrix-spectrum`` claim, proved by branch and bound over the certificate's tree of boxes.

It says: for every q in the box D (``domain``) and every Theta in the convex
hull of the parameter sets (``parameters``),

- ``lambda_min``: lambda_min(M(q, Theta)) >= bound, proved as M - bound I > 0;
- ``lambda_max``: lambda_max(M(q, Theta)) <= bound, proved as bound I - M > 0 (M with -Z(Phi_l)).

M is linear in Theta and lambda_min concave (lambda_max convex), so the hull's extremes are at its vertices:
each parameter set is proved in turn. The ``tree`` (:mod:`.tree`) cuts D into boxes, walked from its root: a box
the pivots of :meth:`.kinematics.Chain.pivots` prove needs none of its halves; a leaf they do not prove is cut
again, within the budget of cuts; where the pivots at its centre are proved negative, the claim is refuted
there, and so it is at the optional ``witness`` (a configuration, tested first).

Optional ``forms`` (lambda_min only): one set of body matrices Y_l for all parameter sets, or one per set, each
Y_l <= Z(Phi_l) (decided exactly); then M(q, Theta) >= sum_l QJ_l^T Y_l QJ_l and the boxes are proved on the
forms. A box centre refutes only where M itself fails there.
"""

from __future__ import annotations

from collections import deque

from flint import arb, arb_mat, fmpq

from .bodies import parameter_sets, spatial_inertia
from .exact import BadCertificate, rational, semidefinite
from .kinematics import Chain
from .outcome import Outcome
from .tree import Node, halves, parse

__all__ = ["prove"]

QUANTITIES = {"lambda_min": (1, -1), "lambda_max": (-1, 1)}  # (sign of Z, sign of the bound in the shift)
# the turns' loss is measured relative to the turned matrix on the lower side, in the identity metric on the upper
# (where the bodies are -Z(Phi_l) <= 0; measured on Panda's ladders, as the prover does)


def _matrices(rows, where):
    if not (isinstance(rows, list) and len(rows) == 6 and all(isinstance(r, list) and len(r) == 6 for r in rows)):
        raise BadCertificate(f"{where}: a 6x6 matrix")
    m = [[rational(x, f"{where}[{i}][{j}]") for j, x in enumerate(r)] for i, r in enumerate(rows)]
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
    witness = cert.get("witness")
    if witness is not None:
        if not isinstance(witness, list) or len(witness) != chain.n:
            raise BadCertificate(f"witness: one coordinate per joint ({chain.n})")
        witness = [rational(x, f"witness[{k}]") for k, x in enumerate(witness)]
        if any(not lo <= x <= hi for x, (lo, hi) in zip(witness, domain)):
            raise BadCertificate("witness: outside the domain")
    sign, shift = QUANTITIES[claim["quantity"]]
    return chain, domain, bodies, forms, sign, arb(bound) * shift, parse(cert.get("tree", "."), domain), witness


def _bad(why):
    raise BadCertificate(why)


def _balls(matrices, sign):
    return [arb_mat(m) * sign for m in matrices]


def _where(box):
    return [[str(lo), str(hi)] for lo, hi in box]


def prove(cert, budget):
    """The :class:`Outcome` of the certificate's claim, cutting at most ``budget`` boxes beyond the tree's leaves."""
    chain, domain, bodies, forms, sign, shift, root, witness = _parse(cert)
    real = [_balls(z, sign) for z in bodies]
    proving = real
    if forms is not None:
        for v, z in enumerate(bodies):
            y = forms[v if len(forms) > 1 else 0]
            for l in range(chain.n):
                if not semidefinite([[z[l][i][j] - y[l][i][j] for j in range(6)] for i in range(6)]):
                    return Outcome("refuted", f"the form of body {l + 1} is not below Z(Phi) of parameter set {v} "
                                   "(exact rational arithmetic)", 0, {"parameter_set": v, "body": l + 1})
        proving = [_balls(y, sign) for y in forms]
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
    cuts = 0
    for v, inertias in enumerate(proving):  # the tree from its root: a box that passes needs none of its own
        queue, memo = deque([root]), {}
        while queue:
            node = queue.popleft()
            centred = [((lo + hi) / 2, (hi - lo) / 2) for lo, hi in node.box]
            boxes += 1
            failed, pivot = chain.pivots(centred, inertias, shift, relative=sign > 0, memo=memo)
            if failed is None:
                continue
            if node.children is not None:
                queue.extend(node.children)
                continue
            found = refuted([c for c, _ in centred], "at the centre q of a box")
            if found:
                found.where["box"] = _where(node.box)
                return found
            cut = max(range(failed + 1, chain.n), key=lambda k: centred[k][1], default=None)
            if cut is None or centred[cut][1] == 0 or cuts >= budget:
                why = (f"the budget of {budget} cuts ran out" if cut is not None and centred[cut][1] != 0
                       else f"pivot {failed + 1} is not decided at a point ({pivot.str(5)})")
                return Outcome("not decided", why, boxes, {"box": _where(node.box), "parameter_set": v})
            cuts += 1
            queue.extend(Node(half) for half in halves(node.box, cut))
    return Outcome("re-proved", f"the tree from its root and {cuts} cut(s) more: {boxes} boxes tested", boxes)
