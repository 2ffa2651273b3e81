"""A certificate's partition of its domain: a prefix code of tokens, "." a leaf and an integer k a cut of the box
at the middle of coordinate k followed by its lower and upper halves, so the leaves cover the domain exactly by
construction; and the walk that tests each box once."""

from collections import deque

from .exact import need
from .outcome import REPROVED, UNPROVED, Outcome

LEAVES = 1_000_000  # the most leaves a certificate's tree may have
TRIES = 8  # failing leaves whose centres are tried for a refutation
REPORTED = 10_000  # failing leaves named in an outcome (more: none, the prover grows the whole tree)


class Node:
    """A box of the tree (a list of (lo, hi) rationals), the coordinate ``k`` it is cut at and its two halves, or
    None for a leaf."""

    def __init__(self, box):
        self.box, self.k, self.children = box, None, None

    def cut(self, k):
        middle, lower, upper = (self.box[k][0] + self.box[k][1]) / 2, list(self.box), list(self.box)
        lower[k], upper[k] = (self.box[k][0], middle), (middle, self.box[k][1])
        self.k, self.children = k, [Node(lower), Node(upper)]
        return self.children


def parse(tree, domain):
    """The root :class:`Node` of the prefix code ``tree`` over ``domain``."""
    need(isinstance(tree, str) and tree.count(".") <= LEAVES, f"tree: a string of tokens with at most {LEAVES} leaves")
    root = Node(list(domain))
    stack = [root]
    for i, token in enumerate(tree.split()):
        need(stack, f"tree: token {i} ({token!r}) lies outside the tree: the leaves are already complete")
        node = stack.pop()
        if token != ".":
            need(token.isdigit() and int(token) < len(domain),
                 f"tree: token {i} ({token!r}) is neither '.' nor a coordinate below {len(domain)}")
            stack.extend(reversed(node.cut(int(token))))  # the lower half is read first
    need(not stack, f"tree: {len(stack)} box(es) have no token: the leaves do not cover the domain")
    return root


def prove(problem, walks):
    """The :class:`.outcome.Outcome` of walking every tree of ``walks`` ((label, name, root, test)) once, breadth
    first (an inner box that passes needs none of its own): re-proved where every leaf is proved; refuted where
    ``problem.refute`` finds a witness at one of the first :data:`TRIES` failing leaves' centres; else not re-proved,
    ``where`` naming the failing leaves by tree (up to :data:`REPORTED`, for the prover to grow them)."""
    boxes, failed = 0, []
    for label, name, root, test in walks:
        queue = deque([root])
        while queue:
            node = queue.popleft()
            boxes += 1
            cuts, why = test([((lo + hi) / 2, (hi - lo) / 2) for lo, hi in node.box])
            if cuts is not None and node.children is None:
                failed.append((label, name, node, why))
            elif cuts is not None:
                queue.extend(node.children)
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
