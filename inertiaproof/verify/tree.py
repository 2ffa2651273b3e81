"""A claim proved on a certificate's partition of its domain, and the walk that tests each leaf once.

The ``tree`` is a prefix code of tokens, "." a leaf and an integer k a cut of the box at the middle of coordinate k
followed by its lower and upper halves: the leaves cover the domain exactly by construction. The leaves are what is
proved; a cut is never tested (a tree finer than its proof needs only costs more leaves).
"""

from flint import arb

from .exact import known, need, rational, vector
from .kinematics import Chain
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

    def balls(self):
        """The box as (centre, radius) per coordinate."""
        return [((lo + hi) / 2, (hi - lo) / 2) for lo, hi in self.box]

    def leaves(self):
        """The leaves below this node, in the tree's order."""
        stack = [self]
        while stack:
            node = stack.pop()
            if node.children is None:
                yield node
            else:
                stack.extend(reversed(node.children))


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


class Claim:
    """The fields a claim on a tree of boxes shares: ``claim`` (its quantity one of ``quantities``, its bound),
    ``chain``, ``domain``, ``witness`` (a configuration in the domain, or none) and ``tree``, none beyond ``keys``.
    The domain, one [lo, hi] per joint, must cover every q the chain allows: each joint's limits, a full turn (2 pi)
    of a revolute joint without them (M is periodic in its angle), anything for the first joint (body twists are
    seen from the bodies: nothing depends on q_1)."""

    def __init__(self, cert, keys, quantities):
        known(cert, keys)
        self.quantity = cert["claim"].get("quantity")
        need(self.quantity in quantities, f"claim.quantity: one of {sorted(quantities)}")
        self.bound = rational(cert["claim"].get("bound"), "claim.bound")
        self.chain = chain = Chain(cert.get("chain"))
        domain = cert.get("domain")
        need(isinstance(domain, list) and len(domain) == chain.n, f"domain: one [lo, hi] per joint ({chain.n})")
        self.domain = [tuple(vector(edge, 2, f"domain[{k}]")) for k, edge in enumerate(domain)]
        for k, ((lo, hi), joint) in enumerate(zip(self.domain, chain.joints)):
            turn = joint.revolute and arb(hi - lo) >= 2 * arb.pi()
            need(lo <= hi and (not k or turn or joint.limits and lo <= joint.limits[0] and hi >= joint.limits[1]),
                 f"domain[{k}]: does not cover joint {k + 1}'s limits (or a full turn)")
        witness = cert.get("witness")
        self.witness = None if witness is None else vector(witness, chain.n, "witness")
        need(witness is None or all(lo <= x <= hi for x, (lo, hi) in zip(self.witness, self.domain)),
             "witness: outside the domain")
        self.root = parse(cert.get("tree", "."), self.domain)


def widest(weights, among):
    """The coordinates ``among`` of positive weight, the largest first: where a cut could help."""
    return sorted((k for k in among if weights[k] > 0), key=lambda k: -weights[k])


def prove(problem, walks):
    """The :class:`.outcome.Outcome` of testing every leaf of every tree of ``walks`` ((label, name, root, test))
    once: re-proved where every leaf is proved; refuted where ``problem.refute`` finds a witness at one of the first
    :data:`TRIES` failing leaves' centres; else not re-proved, ``where`` naming the failing leaves by tree (up to
    :data:`REPORTED`, for the prover to grow them)."""
    boxes, failed = 0, []
    for label, name, root, test in walks:
        for node in root.leaves():
            boxes += 1
            cuts, why = test(node.balls())
            if cuts is not None:
                failed.append((label, name, node, why))
    for label, _, node, _ in failed[:TRIES]:
        found = problem.refute([c for c, _ in node.balls()], f"{label}: at the centre q of a leaf", boxes)
        if found:
            return found
    if not failed:
        return Outcome(REPROVED, f"every leaf proved: {boxes} boxes tested", boxes)
    leaves = {}
    for _, name, node, _ in failed if len(failed) <= REPORTED else []:
        leaves.setdefault(name, []).append([[str(lo), str(hi)] for lo, hi in node.box])
    label, _, node, why = failed[0]
    return Outcome(UNPROVED, f"{len(failed)} leaf box(es) not proved; the first: {label} ({why})", boxes,
                   {"leaves": leaves})
