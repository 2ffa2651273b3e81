"""Which fields of results.json depend on the wall clock (and so differ between two runs of the same seed).

Everything else is a function of the profile, the seed and the scene: the
same for one worker or many (:mod:`.execution`). Timing-dependent are:

- every ``runtime_s`` and every key ending in ``seconds`` (derivation times,
  ``choi_seconds``, a stability study's solver times) or named ``time_per_n``;
- ``convergence`` series of brackets: ``[[seconds, lower, upper], ...]``, and the ``lines`` of any plotted series
  whose ``x_label`` or ``y_label`` is ``"seconds"`` (GRE's derivation time per n);
- ``versions`` (the environment, not the answer).

Budgets that decide values are counts (a bracket's boxes and rounds, a study's right-hand sides, a hunt's
examples and runs), the same on every machine. Wall-clock limits are safety nets only: work one stops is
INCONCLUSIVE, so its values are never compared.
"""

from __future__ import annotations

__all__ = ["TIMING_KEYS", "is_timing_key", "without_timings"]

TIMING_KEYS = frozenset({"runtime_s", "time_per_n", "convergence", "versions"})


def is_timing_key(key):
    """Whether a key of results.json names a wall-clock-dependent field."""
    key = str(key)
    return key in TIMING_KEYS or key.endswith("seconds")


def without_timings(document):
    """``document`` (results.json as loaded) without its wall-clock-dependent fields: what must not depend on the
    number of workers."""
    if isinstance(document, dict):
        timed = "seconds" in (document.get("x_label"), document.get("y_label"))
        return {k: without_timings(v) for k, v in document.items()
                if not is_timing_key(k) and not (timed and k == "lines")}
    if isinstance(document, list):
        return [without_timings(v) for v in document]
    return document
