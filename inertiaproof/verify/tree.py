"""A certificate's partition of its domain: a prefix code of tokens, "." a leaf and an integer k a cut of the box
at the middle of coordinate k followed by its lower and upper halves, so the leaves cover the domain exactly by
construction."""

from __future__ import annotations

from collections import deque

from .exact import BadCertificate
from .outcome import REPROVED, UNPROVED, Outcome

__all__ = ["LEAVES", "Node", "encode", "halves", "leaf_nodes", "parse", "prove", "walk"]

LEAVES = 1_000_000  # the most leaves a certificate's tree may have
TRIES = 8  # failing leaves whose centres are tried for a refutation
REPORTED = 10_000  # failing leaves named in an outcome (more: none, the prover grows the whole tree)


class Node:
    """A box of the tree (a list of (lo, hi) rationals), the coordinate ``k`` it is cut at and its two halves, or
    None for a leaf."""

    def __init__(self, box):
        self.box, self.k, self.children = box, None, None

    def cut(self, k):
        self.k, self.children = k, [Node(half) for half in halves(self.box, k)]
        return self.children


def halves(box, k):
    """The lower and upper halves of ``box`` cut at the middle of coordinate k."""
    middle = (box[k][0] + box[k][1]) / 2
    lower, upper = list(box), list(box)
    lower[k], upper[k] = (box[k][0], middle), (middle, box[k][1])
    return lower, upper


def parse(tree, domain):
    """The root :class:`Node` of the prefix code ``tree`` over ``domain``."""
    if not isinstance(tree, str) or tree.count(".") > LEAVES:
        raise BadCertificate(f"tree: a string of tokens with at most {LEAVES} leaves")
    root = Node(list(domain))
    stack = [root]
    for i, token in enumerate(tree.split()):
        if not stack:
            raise BadCertificate(f"tree: token {i} ({token!r}) lies outside the tree: the leaves are already complete")
        node = stack.pop()
        if token == ".":
            continue
        if not token.isdigit() or int(token) >= len(domain):
            raise BadCertificate(f"tree: token {i} ({token!r}) is neither '.' nor a coordinate below {len(domain)}")
        stack.extend(reversed(node.cut(int(token))))  # the lower half is read first
    if stack:
        raise BadCertificate(f"tree: {len(stack)} box(es) have no token: the leaves do not cover the domain")
    return root


def leaf_nodes(root, boxes):
    """The leaves of the tree below ``root`` whose boxes (as an outcome writes them) are among ``boxes``."""
    wanted, found, stack = {tuple(map(tuple, box)) for box in boxes}, [], [root]
    while stack:
        node = stack.pop()
        if node.children is None:
            found += [node] if tuple((str(lo), str(hi)) for lo, hi in node.box) in wanted else []
        else:
            stack.extend(node.children)
    return found


def encode(root):
    """The prefix code of the tree below ``root`` (the inverse of :func:`parse`)."""
    tokens, stack = [], [root]
    while stack:
        node = stack.pop()
        tokens.append("." if node.children is None else str(node.k))
        stack.extend(reversed(node.children or []))
    return " ".join(tokens)


def walk(root, test):
    """(every leaf of the tree below ``root`` that ``test`` does not prove, with why; boxes tested): an inner box
    that passes needs none of its own."""
    queue, failed, boxes = deque([root]), [], 0
    while queue:
        node = queue.popleft()
        boxes += 1
        cuts, why = test([((lo + hi) / 2, (hi - lo) / 2) for lo, hi in node.box])
        if cuts is None:
            continue
        if node.children is None:
            failed.append((node, why))
        else:
            queue.extend(node.children)
    return failed, boxes


def prove(problem, walks):
    """The :class:`.outcome.Outcome` of walking every tree of ``walks`` ((label, name, root, test)) once: re-proved
    where every leaf is proved; refuted where ``problem.refute`` finds a witness at one of the first
    :data:`TRIES` failing leaves' centres; else not re-proved, ``where`` naming the failing leaves by tree (up to
    :data:`REPORTED`, for the prover to grow them)."""
    boxes, failed = 0, []
    for label, name, root, test in walks:
        found, tested = walk(root, test)
        boxes += tested
        failed += [(label, name, node, why) for node, why in found]
    for label, _, node, _ in failed[:TRIES]:
        found = problem.refute([(lo + hi) / 2 for lo, hi in node.box], f"{label}: at the centre q of a leaf", boxes)
        if found:
            return found
    if not failed:
        return Outcome(REPROVED, f"every leaf proved: {boxes} boxes tested", boxes)
    leaves = {}
    for _, name, node, _ in failed[:REPORTED]:
        leaves.setdefault(name, []).append([[str(lo), str(hi)] for lo, hi in node.box])
    label, _, node, why = failed[0]
    return Outcome(UNPROVED, f"{len(failed)} leaf box(es) not proved; the first: {label} ({why})", boxes,
                   {"leaves": leaves if len(failed) <= REPORTED else {}})
