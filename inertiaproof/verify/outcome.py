"""The outcome of re-proving one claim: re-proved; refuted, only with a witness at which both sides are enclosed
and the claim fails; or not re-proved, a step of the proof that did not go through (the claim may still be true)."""

from collections import namedtuple

REPROVED, REFUTED, UNPROVED = "re-proved", "refuted", "not re-proved"
# status, one of the three; why, in words; boxes tested; where (data: the refuting witness, or the box where the
# proof did not go through)
Outcome = namedtuple("Outcome", "status why boxes where", defaults=(0, None))


def refuted(why, witness, sides, boxes=0):
    """A refutation at ``witness`` (data: q, the parameter set, t), ``sides`` the enclosures (strings) of both sides
    of the inequality that fails there."""
    return Outcome(REFUTED, why, boxes, {"witness": witness, "sides": sides})
