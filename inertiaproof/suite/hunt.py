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

import dataclasses
import functools
import hashlib
import importlib
import sys
import types
import warnings
from contextlib import contextmanager
from dataclasses import dataclass, field

import numpy as np

from inertiaproof.result import quantity

from .paths import cache_dir

__all__ = ["collectable", "detached", "Hunt", "hunt", "hunt_settings", "is_pure", "merge", "Shard", "portable",
           "shard_seed", "shard_sizes", "StrategyRef"]


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
    collected: list | None = None  # a shard's additions to its margin's lists and counts (see collectable)

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
    """Hypothesis settings for a hunt under ``profile``: derandomised with no database in ci. One bug is enough: with
    ``report_multiple_bugs`` Hypothesis goes on generating for up to 10 s of wall clock after the first, so how many
    examples a hunt draws would depend on the machine."""
    from hypothesis import HealthCheck, settings
    from hypothesis.database import DirectoryBasedExampleDatabase

    kwargs = dict(
        max_examples=profile.examples,
        derandomize=profile.derandomize,
        database=None if profile.derandomize else DirectoryBasedExampleDatabase(str(cache_dir() / "hypothesis")),
        deadline=None,
        print_blob=False,
        report_multiple_bugs=False,
        suppress_health_check=list(HealthCheck),
    )
    kwargs.update(overrides)
    return settings(**kwargs)


def shard_sizes(examples, per_shard):
    """How many examples each shard of a hunt of ``examples`` draws: ceil(examples / per_shard) shards as equal as
    possible. It depends on the profile only, never on the number of workers."""
    examples = max(int(examples), 1)
    count = max(1, -(-examples // max(int(per_shard), 1)))
    return [examples // count + (i < examples % count) for i in range(count)]


def shard_seed(run_seed, label, index, count):
    """The Hypothesis seed of shard ``index`` of ``count``: from the run's seed and the hunt's label (a hunt of one
    shard keeps the seed hunts always had)."""
    text = f"{run_seed}:{label}" if count == 1 else f"{run_seed}:{label}:{index}/{count}"
    return int.from_bytes(hashlib.sha256(text.encode()).digest()[:8], "little")


@dataclass(frozen=True)
class Shard:
    label: str
    index: int
    count: int
    examples: int
    seed: int


def hunt(strategy, margin, ctx, *, label, tolerance=0.0, pure=None, **settings_overrides):
    """Search ``strategy`` for an example with margin < -tolerance; returns a :class:`Hunt`.

    The hunt is split into shards of at most ``ctx.profile.shard_examples`` examples, each with its own seed
    (:func:`shard_seed`); they run on ``ctx.executor`` (on workers when the margin is pure, see :func:`is_pure`,
    or only records into lists and counts, see :func:`collectable`; else in this process) and are merged in shard
    order, so the answer is the same for any number of workers.
    A shard stops at its first violation; the shards after the first violating one are not needed. A violating
    shard's example is appended to ``OUT/data/arrived-counterexamples.jsonl`` as soon as it arrives."""
    from .execution import Executor

    examples = settings_overrides.pop("max_examples", ctx.profile.examples)
    sizes = shard_sizes(examples, getattr(ctx.profile, "shard_examples", examples))
    shards = [Shard(label, i, len(sizes), n, shard_seed(ctx.seed, label, i, len(sizes))) for i, n in enumerate(sizes)]
    executor = getattr(ctx, "executor", None) or Executor()
    here = functools.partial(_run_shard, strategy, margin, ctx.profile, tolerance, settings_overrides, None)
    task, collected = here, None  # collected: closure cells of the margin that the shards add to (lists, counts)
    if executor.workers != 1 or executor.scheduler is not None:
        shipped, sent = strategy if executor.inherits else portable(strategy), margin
        if pure is None and not is_pure(margin):
            collected = collectable(margin)
            sent = None if collected is None else detached(margin, collected)
        elif pure is False:
            sent = None
        task = functools.partial(_run_shard, shipped, sent, ctx.profile, tolerance, settings_overrides, collected)
        if shipped is None or sent is None or not executor.portable(task):
            # its margin writes into the check's own objects, or it cannot be sent: its shards run here
            log = executor.log if executor.log is not None else []
            executor.log = log
            executor, task, collected = Executor(), here, None
            executor.log = log
    outputs = getattr(ctx, "outputs", None)

    def arrived(i, state):
        if state.violation is not None and outputs is not None and hasattr(outputs, "journal"):
            outputs.journal({"hunt": label, "shard": i, "of": len(shards), "seed": shards[i].seed,
                             "margin": state.violation_margin, "example": state.violation})

    states = executor.map(task, shards, kind="hunt", label=label, on_result=arrived,
                          stop=lambda i, state: state.violation is not None)
    states = [s for s in states if s is not None]
    if collected is not None:  # what the shards added to the margin's lists and counts, in shard order
        for state in states:
            for i, value in zip(collected, state.collected):
                _add(margin.__closure__[i].cell_contents, value)
    return merge(states, label)


def merge(states, label):
    """The hunt made of its shards, in shard order (up to the first violating one)."""
    out = Hunt(label)
    for s in states:
        out.examples += s.examples
        out.margins.extend(s.margins)
        out.resolutions.extend(s.resolutions)
        if s.worst_margin < out.worst_margin:
            out.worst_margin, out.worst_example = s.worst_margin, s.worst_example
        if s.violation is not None:
            out.violation, out.violation_margin = s.violation, s.violation_margin
            break
    return out


def is_pure(margin):
    """Whether ``margin`` may run in another process: it keeps no mutable object of its caller (list, dict, set or
    an instance in its closure or defaults, searched through the functions it closes over)."""
    seen = set()

    def pure(fn):
        if id(fn) in seen:
            return True
        seen.add(id(fn))
        if isinstance(fn, functools.partial):
            return pure(fn.func) and all(_immutable(a, pure) for a in (*fn.args, *fn.keywords.values()))
        cells = [c.cell_contents for c in (getattr(fn, "__closure__", None) or ()) if _filled(c)]
        defaults = list(getattr(fn, "__defaults__", None) or ())
        return all(_immutable(v, pure) for v in cells + defaults)

    return pure(margin)


def collectable(margin):
    """The indexes of ``margin``'s closure cells that hold a list or a dict of numbers (what a margin records as it
    goes), when everything else it keeps is immutable (see :func:`is_pure`); else None. A shard on a worker starts
    them empty and sends back what it added; the client adds that in shard order, as if the shards had run here."""
    if not isinstance(margin, types.FunctionType) or not margin.__closure__:
        return None
    out = []
    for i, cell in enumerate(margin.__closure__):
        if not _filled(cell):
            continue
        value = cell.cell_contents
        if isinstance(value, list) or (isinstance(value, dict) and all(
                isinstance(v, (int, float)) and not isinstance(v, bool) for v in value.values())):
            out.append(i)
        elif not _immutable(value, is_pure):
            return None
    if not all(_immutable(v, is_pure) for v in (margin.__defaults__ or ())):
        return None
    return out or None


def detached(margin, cells):
    """A copy of ``margin`` whose closure ``cells`` hold empty lists and zero counts (what is sent to a worker)."""
    closure = tuple(types.CellType(_empty(c.cell_contents)) if i in cells else c
                    for i, c in enumerate(margin.__closure__))
    fn = types.FunctionType(margin.__code__, margin.__globals__, margin.__name__, margin.__defaults__, closure)
    fn.__kwdefaults__, fn.__qualname__, fn.__module__ = margin.__kwdefaults__, margin.__qualname__, margin.__module__
    return fn


def _empty(value):
    return [] if isinstance(value, list) else {k: type(v)(0) for k, v in value.items()}


def _add(into, value):
    if isinstance(into, list):
        into.extend(value)
    else:
        for k, v in value.items():
            into[k] = into.get(k, 0) + v


def _filled(cell):
    try:
        cell.cell_contents
    except ValueError:
        return False
    return True


def _immutable(value, pure):
    if value is None or isinstance(value, (bool, int, float, complex, str, bytes, type, types.ModuleType)):
        return True
    if isinstance(value, (tuple, frozenset)):
        return all(_immutable(v, pure) for v in value)
    if isinstance(value, (types.FunctionType, functools.partial)):
        return pure(value)
    if isinstance(value, (types.BuiltinFunctionType, np.ufunc, np.generic)):
        return True
    if dataclasses.is_dataclass(value) and not isinstance(value, type) and value.__dataclass_params__.frozen:
        return all(_immutable(getattr(value, f.name), pure) for f in dataclasses.fields(value))
    return False  # lists, dicts, sets, arrays, instances: possibly written by the margin


@dataclass(frozen=True)
class StrategyRef:
    """A Hypothesis strategy shipped by name: ``module.name(*args, **kwargs)`` rebuilt in the worker (strategies
    themselves do not pickle)."""
    module: str
    name: str
    args: tuple
    kwargs: tuple

    def build(self):
        return getattr(importlib.import_module(self.module), self.name)(*self.args, **dict(self.kwargs))


def portable(strategy):
    """``strategy`` in a form another process can rebuild (itself, or a :class:`StrategyRef` to the module-level
    function that made it), or None."""
    import cloudpickle

    try:
        cloudpickle.dumps(strategy)
        return strategy
    except Exception:  # most strategies hold functions that do not pickle
        pass
    try:
        from hypothesis.strategies._internal.lazy import LazyStrategy
    except ImportError:  # Hypothesis moved it: run in the client
        return None
    if not isinstance(strategy, LazyStrategy) or getattr(strategy, "_transformations", True):
        return None  # not made by one call, or with .map/.filter applied after it: not rebuilt by name
    fn, args, kwargs = strategy.function, strategy._LazyStrategy__args, strategy._LazyStrategy__kwargs
    for module_name, module in list(sys.modules.items()):
        if not module_name.startswith("inertiaproof") or module is None:
            continue
        maker = getattr(module, fn.__name__, None)
        if maker is not None and (maker is fn or getattr(maker, "__wrapped__", None) is fn):
            ref = StrategyRef(module_name, fn.__name__, tuple(args), tuple(sorted(kwargs.items())))
            try:
                cloudpickle.dumps(ref)
                return ref
            except Exception:
                return None
    return None


def _run_shard(strategy, margin, profile, tolerance, settings_overrides, collected, shard):
    """One shard of a hunt (a task: it carries its own seed and runs in any process). With ``collected`` (closure
    cells of a detached margin), the shard's state carries what the margin added to them in this shard."""
    from hypothesis import assume, given, seed, target
    from hypothesis.errors import Unsatisfiable

    if isinstance(strategy, StrategyRef):
        strategy = strategy.build()
    for i in collected or ():  # empty at each shard's start, whatever ran before it in this process
        margin.__closure__[i].cell_contents = _empty(margin.__closure__[i].cell_contents)

    state = Hunt(shard.label)

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
        target(-value, label=shard.label)
        if value < -max(tolerance, resolution or 0.0):
            state.violation, state.violation_margin = example, value
            raise _Violation(value)

    chosen = hunt_settings(profile, derandomize=False, max_examples=shard.examples, **settings_overrides)
    test = seed(shard.seed)(chosen(given(strategy)(prop)))
    # the example database (deep profile) keeps each shard's examples under its own key, not one shared by all hunts
    test._hypothesis_internal_database_key = hashlib.sha256(
        f"{shard.label}:{shard.index}/{shard.count}".encode()).digest()
    with _fixed_constants(), _shrinking_unclocked(), warnings.catch_warnings():
        # the strategies draw from NumPy generators seeded by Hypothesis; what moves the global `random` state during
        # a shard is another thread of a Dask worker (its heartbeats), which Hypothesis cannot tell apart
        warnings.filterwarnings("ignore", "Do not use the `random` module inside strategies")
        try:
            test()
        except _Violation:
            pass  # state.violation holds the last (shrunk) failing example
        except Unsatisfiable:
            pass  # every example was discarded (a margin of nan): the state counts none
    if collected is not None:
        state.collected = [margin.__closure__[i].cell_contents for i in collected]
    return state


@contextmanager
def _fixed_constants():
    """Hypothesis mixes into its draws the literals of every "local" module imported so far (not in site-packages),
    so its examples would depend on what this process happened to import (and on an editable install): a worker
    and the client would draw different examples from the same seed. During a shard that pool is empty."""
    try:
        from hypothesis.internal.conjecture import providers

        empty = type(providers._local_constants)(**{k: type(v)(key=getattr(v, "key", None))
                                                    for k, v in vars(providers._local_constants).items()})
        original = providers._get_local_constants
    except (ImportError, AttributeError, TypeError):  # a Hypothesis without the pool
        yield
        return
    providers._get_local_constants = lambda: empty
    _clear(providers)  # constants filtered from the pool before are cached by their constraints
    try:
        yield
    finally:
        providers._get_local_constants = original
        _clear(providers)


@contextmanager
def _shrinking_unclocked():
    """Hypothesis stops shrinking after 300 s of wall clock (``MAX_SHRINKING_SECONDS``), which would make a slow
    margin's shrunk example depend on the machine. During a shard only its counts bound shrinking (at most 500
    shrinks, 200 calls without progress); the margins budget their own work."""
    from hypothesis.internal.conjecture import engine

    original = engine.MAX_SHRINKING_SECONDS
    engine.MAX_SHRINKING_SECONDS = float("inf")
    try:
        yield
    finally:
        engine.MAX_SHRINKING_SECONDS = original


def _clear(providers):
    cache = getattr(getattr(providers, "CONSTANTS_CACHE", None), "cache", None)
    if cache is not None:
        cache.clear()
