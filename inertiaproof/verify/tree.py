"""A certificate's partition of its domain: a prefix code of tokens, "." a leaf and an integer k a cut of the box
at the middle of coordinate k followed by its lower and upper halves, so the leaves cover the domain exactly by
construction."""

from __future__ import annotations

from collections import deque

from .exact import BadCertificate

__all__ = ["LEAVES", "Node", "encode", "halves", "parse", "walk"]

LEAVES = 1_000_000  # the most leaves a certificate's tree may have


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


def encode(root):
    """The prefix code of the tree below ``root`` (the inverse of :func:`parse`)."""
    tokens, stack = [], [root]
    while stack:
        node = stack.pop()
        tokens.append("." if node.children is None else str(node.k))
        stack.extend(reversed(node.children or []))
    return " ".join(tokens)


def walk(root, test, boxes=0):
    """(the first leaf of the tree below ``root`` that ``test`` does not prove and why, boxes tested): an inner box
    that passes needs none of its own."""
    queue = deque([root])
    while queue:
        node = queue.popleft()
        boxes += 1
        cuts, why = test([((lo + hi) / 2, (hi - lo) / 2) for lo, hi in node.box])
        if cuts is None:
            continue
        if node.children is None:
            return (node, why), boxes
        queue.extend(node.children)
    return None, boxes
