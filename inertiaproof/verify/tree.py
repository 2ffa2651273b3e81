"""A certificate's partition of its domain: a prefix code of tokens, "." a leaf and an integer k a cut of the box
at the middle of coordinate k followed by its lower and upper halves, so the leaves cover the domain exactly by
construction."""

from __future__ import annotations

from .exact import BadCertificate

__all__ = ["Node", "halves", "parse"]


class Node:
    """A box of the tree (a list of (lo, hi) rationals) and its two halves, or None for a leaf; ``cut``: a box the
    checker made beyond the certificate's tree."""

    def __init__(self, box, cut=False):
        self.box, self.children, self.cut = box, None, cut


def halves(box, k):
    """The lower and upper halves of ``box`` cut at the middle of coordinate k."""
    middle = (box[k][0] + box[k][1]) / 2
    lower, upper = list(box), list(box)
    lower[k], upper[k] = (box[k][0], middle), (middle, box[k][1])
    return lower, upper


def parse(tree, domain):
    """The root :class:`Node` of the prefix code ``tree`` over ``domain``."""
    if not isinstance(tree, str):
        raise BadCertificate("tree: a string of tokens")
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
        node.children = [Node(half) for half in halves(node.box, int(token))]
        stack.extend(reversed(node.children))  # the lower half is read first
    if stack:
        raise BadCertificate(f"tree: {len(stack)} box(es) have no token: the leaves do not cover the domain")
    return root

