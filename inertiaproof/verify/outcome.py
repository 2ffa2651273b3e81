"""The outcome of re-proving one claim."""

from __future__ import annotations

__all__ = ["Outcome"]


class Outcome:
    """``status``: "re-proved", "refuted", "not decided"; ``why`` in words; ``boxes`` tested; ``where`` (data: the
    box or point that refutes, or where the budget ran out)."""

    def __init__(self, status, why, boxes=0, where=None):
        self.status, self.why, self.boxes, self.where = status, why, boxes, where

    def to_json(self):
        return {"status": self.status, "why": self.why, "boxes": self.boxes, "where": self.where}
