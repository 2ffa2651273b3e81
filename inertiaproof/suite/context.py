"""The context a check receives: the run's profile, seed and scene, its random streams and outputs."""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from inertiaproof.budget import UNLIMITED, Budget

from .execution import Executor
from .outputs import Outputs
from .profiles import Profile

__all__ = ["Context"]


@dataclass
class Context:
    profile: Profile
    seed: int = 0
    scene: object = None  # inertiaproof.scene.format.Scene or None
    outputs: Outputs = field(default_factory=Outputs)
    progress: Callable[[str], None] = lambda message: None
    memo: dict = field(default_factory=dict)  # shared by the checks of one run (see :meth:`shared`)
    budget: Budget = UNLIMITED  # this check's time and memory (the runner's, from the profile)
    executor: Executor = field(default_factory=Executor)  # where splittable work runs (inertiaproof.suite.execution)

    def rng(self, salt):
        """A generator seeded by the run's seed and a salt (the check's name): independent streams, same every run."""
        digest = hashlib.sha256(f"{self.seed}:{salt}".encode()).digest()
        return np.random.default_rng(int.from_bytes(digest[:8], "little"))

    def shared(self, key, compute):
        """compute() once per run for ``key``: what one check computes, another of the same run may reuse."""
        key = (key, self.profile.name, self.seed)
        if key not in self.memo:
            self.memo[key] = compute()
        return self.memo[key]

    def save_counterexample(self, result):
        """Write the result's counterexample (with this run's profile and seed) as a replayable file; returns the path."""
        return self.outputs.save_counterexample(result, profile=self.profile.name, seed=self.seed)
