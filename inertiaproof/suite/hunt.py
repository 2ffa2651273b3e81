"""Hypothesis hunts for counterexamples, run from a check (not from pytest).

``hunt(strategy, margin, ctx, label=...)`` draws examples, evaluates
``margin(example)`` (relative; > 0 means the statement holds there, NaN means
"not applicable, skip"), steers toward the boundary with ``target(-margin)``
and stops at the first margin below ``-tolerance``, which Hypothesis then
shrinks. ``margin`` may also return (margin, resolution): the example's own
numerical resolution, so that a violation must exceed what rounding can do
there (margin < -max(tolerance, resolution)). The seed comes from the run's ``--seed`` and the label, so a hunt is
deterministic for a given seed; the ci profile keeps no example database.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field

import numpy as np

from inertiaproof.result import quantity

from .paths import cache_dir

__all__ = ["Hunt", "hunt", "hunt_settings"]


class _Violation(Exception):
    pass


@dataclass
class Hunt:
    label: str
    examples: int = 0
    worst_margin: float = np.inf  # smallest margin seen over all examples
    worst_example: object = None
    violation: object = None  # the shrunk example whose margin is below -tolerance
    violation_margin: float | None = None
    margins: list = field(default_factory=list)
    resolutions: list = field(default_factory=list)

    def summary(self):
        """Plain data for evidence."""
        out = {
            "examples": quantity(self.examples, "count", "examples drawn by Hypothesis"),
            "smallest_margin": quantity(self.worst_margin, "sampled",
                                        "smallest margin over the examples: an upper estimate of the infimum"),
        }
        if self.resolutions:
            out["largest_resolution"] = quantity(max(self.resolutions), "tolerance",
                                                 "largest numerical resolution of a margin over the examples")
        return out


def hunt_settings(profile, **overrides):
    """Hypothesis settings for a hunt under ``profile``: derandomised with no database in ci."""
    from hypothesis import HealthCheck, settings
    from hypothesis.database import DirectoryBasedExampleDatabase

    kwargs = dict(
        max_examples=profile.examples,
        derandomize=profile.derandomize,
        database=None if profile.derandomize else DirectoryBasedExampleDatabase(str(cache_dir() / "hypothesis")),
        deadline=None,
        print_blob=False,
        suppress_health_check=list(HealthCheck),
    )
    kwargs.update(overrides)
    return settings(**kwargs)


def hunt(strategy, margin, ctx, *, label, tolerance=0.0, **settings_overrides):
    """Search ``strategy`` for an example with margin < -tolerance; returns a :class:`Hunt`."""
    from hypothesis import assume, given, seed, target

    state = Hunt(label)

    def prop(example):
        value = margin(example)
        value, resolution = (float(value[0]), float(value[1])) if isinstance(value, tuple) else (float(value), None)
        assume(np.isfinite(value))
        state.examples += 1
        state.margins.append(value)
        if resolution is not None:
            state.resolutions.append(resolution)
        if value < state.worst_margin:
            state.worst_margin, state.worst_example = value, example
        target(-value, label=label)
        if value < -max(tolerance, resolution or 0.0):
            state.violation, state.violation_margin = example, value
            raise _Violation(value)

    digest = hashlib.sha256(f"{ctx.seed}:{label}".encode()).digest()
    test = seed(int.from_bytes(digest[:8], "little"))(
        hunt_settings(ctx.profile, derandomize=False, **settings_overrides)(given(strategy)(prop))
    )
    try:
        test()
    except _Violation:
        pass  # state.violation holds the last (shrunk) failing example
    return state
