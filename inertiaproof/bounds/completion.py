"""The prover's last steps on a certificate: its trees fitted to the checker's own test of a box, which the
checker applies once to every leaf and to nothing else (:func:`inertiaproof.verify.tree.prove`).

The prover's partitions are proved by its own numerics, which the checker's pivots in ball arithmetic do not
always match. :func:`pruned`, as a certificate is made, makes a leaf of an inner box that test proves;
:func:`complete`, where the checker did not re-prove a certificate, halves each leaf that test does not prove
(those the checker named, where it named them) at the coordinate it names, within a count of boxes. A leaf still
unproved when the count is spent stays a leaf: the checker then says "not re-proved" and the run INCONCLUSIVE. An
upper spectrum claim that the chain's lengths prove at once names ``method`` "lengths" and needs no tree.
"""

from __future__ import annotations

from collections import deque

from inertiaproof.verify import payload as checked_payload
from inertiaproof.verify import skew, spectrum
from inertiaproof.verify.exact import BadCertificate
from inertiaproof.verify.lengths import perron_side

__all__ = ["complete", "pruned"]

PRUNE_SHARE = 2  # leaves of a tree per inner node pruning tests before it has removed any
PRUNE_TESTS = 4096  # and at most this many inner nodes before it has removed any


def complete(cert, boxes, where=None):
    """``cert`` (a new dict) with its trees completed, and those of its ingredients and terms, testing at most
    ``boxes`` boxes beyond each tree as given; ``where``: the checker's ``where`` of it (its failing leaves by tree,
    ``leaves``, and a product's or sum's failing parts by index, ``ingredients`` or ``terms``: only those are grown),
    or None (every leaf of every part is tested)."""
    kind, where = cert["claim"]["kind"], where or {}
    if kind in ("product", "sum"):
        label = "ingredients" if kind == "product" else "terms"
        named = where.get(label)
        return {**cert, label: [c if named is not None and str(i) not in named else
                                complete(c, boxes, (named or {}).get(str(i))) for i, c in enumerate(cert[label])]}
    return _reshaped(cert, lambda problem, walks: _grow(problem, walks, boxes, where.get("leaves")))


def pruned(cert):
    """``cert`` (None, or a new dict) with its own trees cut back where the checker's test proves an inner box
    (:func:`_prune`): the checker tests every leaf, and a prover that closed its bracket, or widened its certified
    side, made leaves finer than the checker's bound needs. A certificate the checker cannot read stays as it is
    (the checker says why)."""
    if cert is None or cert["claim"]["kind"] in ("product", "sum"):
        return cert
    try:
        return _reshaped(cert, _prune)
    except (BadCertificate, ArithmeticError):
        return cert


def _reshaped(cert, reshape):
    """``cert`` with the trees of its claim reshaped in place by ``reshape(problem, walks)``."""
    kind = cert["claim"]["kind"]
    if kind == "mass-matrix-spectrum":
        return {**cert, **_spectrum(cert, reshape)}
    if kind == "payload-envelope" and cert["claim"]["quantity"] != "lambda_max_f":
        return {**cert, **_spectrum(checked_payload.inner_spectrum(cert), reshape)}
    if kind == "skew-partials":
        problem = skew.Problem(cert)
        reshape(problem, problem.walks())
        return {**cert, "tree": encode(problem.root)}
    return cert


def _spectrum(cert, reshape):
    """The fields of a spectrum certificate that say how it is proved: ``method`` and ``tree``, or ``split``."""
    problem = spectrum.Problem(cert)
    if problem.sign < 0 and _lengths_prove(problem):
        return {"method": "lengths", "tree": "."}
    reshape(problem, problem.walks())
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
    return [node for node in root.leaves() if tuple((str(lo), str(hi)) for lo, hi in node.box) in wanted]


def _lengths_prove(problem):
    """Whether the chain's lengths prove the upper claim at once (a ball that is not finite proves nothing)."""
    try:
        return perron_side(problem.chain, problem.domain, problem.bodies) <= problem.shift
    except ArithmeticError:
        return False


def _grow(problem, walks, boxes, leaves=None):
    """Each tree of ``walks`` (label, name, root, test) grown in place at its leaves, or at the ``leaves`` named for
    it: a leaf its test does not prove is cut at the coordinate the test names first, until ``boxes`` boxes beyond
    the given tree are tested, or the centre of a failing leaf refutes the claim (no cut helps then: tried at the
    1st, 2nd, 4th, 8th, ... failing leaf, for a refutation costs a test or more)."""
    for _, name, root, test in walks:
        queue = deque(root.leaves() if not leaves else leaf_nodes(root, leaves.get(name, [])))
        tested = failed = 0
        while queue and tested < boxes:
            node = queue.popleft()
            cuts, _ = test(node.balls())
            if not cuts:
                continue
            failed += 1
            if failed & (failed - 1) == 0 and problem.refute([(lo + hi) / 2 for lo, hi in node.box], ""):
                break
            tested += 2
            queue.extend(node.cut(cuts[0]))


def _prune(problem, walks):
    """Each tree of ``walks`` (label, name, root, test) cut back in place, breadth first: an inner node that every
    test of its tree proves becomes a leaf. It tests one inner node per :data:`PRUNE_SHARE` leaves, at most
    :data:`PRUNE_TESTS`, and half a node more per leaf it removes (a test the checker no longer makes): on a tree the
    checker's test needs whole, it spends at most PRUNE_TESTS tests and 1/PRUNE_SHARE of the checker's work."""
    trees = {}
    for _, _, root, test in walks:
        trees.setdefault(id(root), (root, []))[1].append(test)
    for root, tests in trees.values():
        budget, queue = min(len(list(root.leaves())) / PRUNE_SHARE, PRUNE_TESTS), deque([root])
        while queue and budget >= 1:
            node = queue.popleft()
            if node.children is None:
                continue
            budget -= 1
            if all(test(node.balls())[0] is None for test in tests):
                budget += (len(list(node.leaves())) - 1) / 2
                node.children = None
            else:
                queue.extend(node.children)
