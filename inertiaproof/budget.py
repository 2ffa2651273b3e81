"""Budgets: how long a computation may run and how much memory it may take.

A run gives every check a :class:`Budget` (its profile's seconds per check,
within the run's own seconds, and its memory). Long computations consult it
(``remaining()``, ``expired``, ``fits(nbytes)``) and end honestly, with what
they have, when it runs out; :func:`enforced` is the safety net for those
that do not: past the deadline and a grace period it raises
:class:`OutOfBudget` in the main thread, and the memory budget is the
process's address-space limit, so an allocation past it raises MemoryError
at once instead of growing the process without end.
"""

from __future__ import annotations

import math
import os
import signal
import sys
import threading
import time
from contextlib import contextmanager
from dataclasses import dataclass

__all__ = ["available_cores", "share_cores", "Budget", "enforced", "OutOfBudget", "UNLIMITED"]


class OutOfBudget(BaseException):
    """The budget ran out. A BaseException, like KeyboardInterrupt: ``except Exception`` must not swallow it,
    and a Hypothesis hunt stops instead of mistaking it for a counterexample."""


@dataclass(frozen=True)
class Budget:
    deadline: float = math.inf  # time.monotonic() at which the time is up
    memory_bytes: int | None = None  # None: no memory budget
    seconds: float = math.inf  # the budget as given, for messages

    @classmethod
    def of(cls, seconds=math.inf, memory_bytes=None, *, until=math.inf):
        """A budget of ``seconds`` from now, ending no later than the monotonic time ``until``."""
        return cls(min(time.monotonic() + seconds, until), memory_bytes, seconds)

    def remaining(self):
        """Seconds left (0 once expired, inf without a deadline)."""
        return max(0.0, self.deadline - time.monotonic())

    @property
    def expired(self):
        return time.monotonic() >= self.deadline

    def capped(self, seconds):
        """``seconds``, or what is left of the budget if that is less."""
        return min(seconds, self.remaining())

    def fits(self, nbytes):
        """Whether an array of ``nbytes`` may be allocated under the memory budget."""
        return self.memory_bytes is None or nbytes <= self.memory_bytes

    def describe(self):
        parts = [] if math.isinf(self.seconds) else [f"{self.seconds:g} s"]
        if self.memory_bytes is not None:
            parts.append(f"{self.memory_bytes / 2**30:g} GiB")
        return " and ".join(parts) or "no limit"


UNLIMITED = Budget()
REPEAT_S = 0.5


@contextmanager
def enforced(budget, grace):
    """Hold ``budget`` by force for the block: OutOfBudget in the main thread ``grace`` seconds past the deadline
    (and every REPEAT_S after, should something swallow it, like a garbage-collector callback), and the memory budget as the process's address-space limit (lowered only, and restored after). Outside the
    main thread only the memory limit applies."""
    with _address_space(budget.memory_bytes), _alarm(budget.remaining() + grace, budget):
        yield


@contextmanager
def _alarm(seconds, budget):
    if math.isinf(seconds) or threading.current_thread() is not threading.main_thread():
        yield
        return

    active = [True]

    def stop(signum, frame):
        if active[0]:
            raise OutOfBudget(f"no answer within the time budget ({budget.describe()})")

    def unraisable(info, hook=sys.unraisablehook):  # one that struck in a callback is ignored: no noise
        if not isinstance(info.exc_value, OutOfBudget):
            hook(info)

    previous, previous_hook = signal.signal(signal.SIGALRM, stop), sys.unraisablehook
    sys.unraisablehook = unraisable
    signal.setitimer(signal.ITIMER_REAL, max(seconds, 1e-3), REPEAT_S)
    try:
        yield
    finally:
        while active[0]:
            try:
                active[0] = False
                signal.setitimer(signal.ITIMER_REAL, 0)
                signal.signal(signal.SIGALRM, previous)
                sys.unraisablehook = previous_hook
            except OutOfBudget:  # it struck during the clean-up itself: the block has ended, so clean up again
                active[0] = True


@contextmanager
def _address_space(nbytes):
    try:
        import resource
    except ImportError:  # not on POSIX
        resource = None
    if nbytes is None or resource is None:
        yield
        return
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    used = _address_space_used()
    limit = used + nbytes
    if soft != resource.RLIM_INFINITY and soft <= limit or hard != resource.RLIM_INFINITY and hard < limit:
        yield
        return
    resource.setrlimit(resource.RLIMIT_AS, (limit, hard))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


def _address_space_used():
    """This process's virtual size in bytes (0 where /proc is missing)."""
    try:
        with open("/proc/self/statm") as f:
            return int(f.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError):
        return 0


def available_cores():
    """The cores this process's thread pools may use: its CPU affinity, or the share :func:`share_cores` set (a
    lane of ``inertiaproof run`` beside others)."""
    if _SHARE:
        return _SHARE[0]
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1


def share_cores(parts):
    """From now on this process uses 1/``parts`` of the cores in its thread pools (at least one); BLAS keeps one
    thread (inertiaproof.cli.main)."""
    from threadpoolctl import threadpool_limits

    _SHARE[:] = [max(1, available_cores() // parts)]
    threadpool_limits(_SHARE[0], user_api="openmp")


_SHARE = []
