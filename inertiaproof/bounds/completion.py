"""The prover's last step on a certificate: its trees grown until every leaf passes the checker's own test of a
box, so that the checker walks them once and cuts nothing (:func:`inertiaproof.verify.tree.prove`).

The prover's partitions are proved by its own numerics, which the checker's pivots in ball arithmetic do not
always match; here each leaf the checker's test does not prove (those the checker named, where it named them) is
halved at the coordinate that test names, within a count of boxes. A leaf still unproved when the count is spent stays a leaf: the checker then says "not re-proved"
and the run INCONCLUSIVE. An upper spectrum claim that the chain's lengths prove at once names ``method``
"lengths" and needs no tree.
"""

from __future__ import annotations

from collections import deque

from inertiaproof.verify import payload as checked_payload
from inertiaproof.verify import skew, spectrum
from inertiaproof.verify.lengths import perron_side

__all__ = ["complete"]


def complete(cert, boxes, leaves=None):
    """``cert`` (a new dict) with its trees completed, and those of its ingredients and terms, testing at most
    ``boxes`` boxes beyond each tree as given; ``leaves``: the failing leaves by tree, as the checker named them
    (``where["leaves"]``: only those are grown), or None (every tree is walked from its root)."""
    kind = cert["claim"]["kind"]
    if kind == "product":
        return {**cert, "ingredients": [complete(c, boxes) for c in cert["ingredients"]]}
    if kind == "sum":
        return {**cert, "terms": [complete(c, boxes) for c in cert["terms"]]}
    if kind == "mass-matrix-spectrum":
        return {**cert, **_spectrum(cert, boxes, leaves)}
    if kind == "payload-envelope" and cert["claim"]["quantity"] != "lambda_max_f":
        return {**cert, **_spectrum(checked_payload.inner_spectrum(cert), boxes, leaves)}
    if kind == "skew-partials":
        problem = skew.Problem(cert)
        _grow(problem, problem.walks(), boxes, leaves)
        return {**cert, "tree": encode(problem.root)}
    return cert


def _spectrum(cert, boxes, leaves):
    """The fields of a spectrum certificate that say how it is proved: ``method`` and ``tree``, or ``split``."""
    problem = spectrum.Problem(cert)
    if problem.sign < 0 and _lengths_prove(problem):
        return {"method": "lengths", "tree": "."}
    _grow(problem, problem.walks(), boxes, leaves)
    if problem.split is None:
        return {"method": "tree", "tree": encode(problem.root)}
    k, _, tail, head = problem.split
    return {"method": "tree", "split": {**cert["split"], "tail": encode(tail), "head": encode(head)}}


def encode(root):
    """The prefix code of the tree below ``root`` (the inverse of :func:`inertiaproof.verify.tree.parse`)."""
    tokens, stack = [], [root]
    while stack:
        node = stack.pop()
        tokens.append("." if node.children is None else str(node.k))
        stack.extend(reversed(node.children or []))
    return " ".join(tokens)


def leaf_nodes(root, boxes):
    """The leaves of the tree below ``root`` whose boxes (as an outcome writes them) are among ``boxes``."""
    wanted = {tuple(map(tuple, box)) for box in boxes}
    leaves, stack = [], [root]
    while stack:
        node = stack.pop()
        if node.children is None and tuple((str(lo), str(hi)) for lo, hi in node.box) in wanted:
            leaves.append(node)
        stack.extend(node.children or [])
    return leaves


def _lengths_prove(problem):
    """Whether the chain's lengths prove the upper claim at once (a ball that is not finite proves nothing)."""
    try:
        return perron_side(problem.chain, problem.domain, problem.bodies) <= problem.shift
    except ArithmeticError:
        return False


def _grow(problem, walks, boxes, leaves=None):
    """Each tree of ``walks`` (label, name, root, test) grown in place from its root, or from the ``leaves`` named
    for it: a leaf its test does not prove is cut at the coordinate the test names first, until ``boxes`` boxes
    beyond the given tree are tested, or a leaf's centre refutes the claim (no cut helps then)."""
    for _, name, root, test in walks:
        start = [root] if not leaves else leaf_nodes(root, leaves.get(name, []))
        queue, tested = deque(start), 0
        while queue:
            node = queue.popleft()
            cuts, _ = test(node.balls())
            if cuts is None:
                continue
            if node.children is not None:
                queue.extend(node.children)
            elif cuts and tested < boxes and not problem.refute([(lo + hi) / 2 for lo, hi in node.box], ""):
                tested += 2
                queue.extend(node.cut(cuts[0]))
