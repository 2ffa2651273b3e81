"""Where splittable work runs: in this process, in forked processes on this machine, or on a Dask cluster.

A computation that splits into independent tasks (the shards of a hunt, the
files of an audit, the certificates to re-prove) hands them to
:meth:`Executor.map` with its *kind*; the executor returns their results in
the order of the tasks, whatever order they finish in, so a run's answers do
not depend on how many workers computed them. Each task must carry everything
it depends on (a shard its own seed), and the split itself must not depend on
the number of workers.

- ``Executor()`` (``--workers 1``): the tasks run one after the other in this
  process.
- ``ForkExecutor(N)`` (``--workers N`` on this machine): N *tokens*, one per
  core the run may use. The run's checks go side by side in N forked lanes
  (:mod:`.lanes`), each holding a token while it computes; a check that maps
  tasks gives its token back while it waits, and its tasks run in forked
  processes, each started only when a token is free. So the cores stay busy
  with whatever is ready, a check's and its neighbours', and no more than N
  processes compute at once. The tasks inherit what they need (no pickling);
  only their results come back.
- ``DaskExecutor(scheduler=ADDRESS)``: an existing cluster (``dask
  scheduler`` + ``dask worker ADDRESS``); every kind goes to it (a
  ``LocalCluster`` with ``DaskExecutor(workers=N)``).

A worker that dies mid-task has its tasks rerun by Dask on another worker;
``on_result(index, result)`` is called in the client as each task arrives (a
hunt writes a violating shard's example there before anything else runs).

Dask is the optional extra ``inertiaproof[distributed]``, needed for
``--scheduler`` only.
"""

from __future__ import annotations

import functools
import math
import multiprocessing
import os
import pickle
import queue
import sys
import threading
import time
from contextlib import contextmanager

from inertiaproof.budget import available_cores
from inertiaproof.errors import InputError

__all__ = ["DaskExecutor", "Executor", "ForkExecutor", "INSTALL_HINT", "KINDS", "executor_for", "Progress",
           "default_workers"]

KINDS = {  # kind of work: where it runs on a LocalCluster
    "hunt": "processes",  # Hypothesis keeps per-process state and holds the GIL
    "audit": "processes",  # XML reading, SymPy-free but Python-bound; MuJoCo per file
    "symbolic": "processes",  # SymPy holds the GIL
    "boxes": "threads",  # batched NumPy of branch and bound (releases the GIL)
    "verify": "processes",  # the independent checker's ball arithmetic (python-flint, Python-bound)
}
INSTALL_HINT = "a Dask cluster needs Dask: pip install 'inertiaproof[distributed]'"


def default_workers():
    """The default of ``--workers``: the number of cores this process may use."""
    return max(1, available_cores())


class Progress:
    """Counts and an ETA for one batch of tasks, when ``say`` is given: a tqdm bar when ``stream`` (stderr) is a
    terminal, else plain lines through ``say`` (at most one per ``min_interval`` seconds, and the last)."""

    def __init__(self, total, label, *, stream=None, say=None, min_interval=2.0):
        self.total, self.label, self.done, self.start = total, label, 0, time.monotonic()
        self.say, self.min_interval, self.last = say, min_interval, -math.inf
        stream = stream if stream is not None else sys.stderr
        self.bar = None
        if say is not None and total > 1 and getattr(stream, "isatty", lambda: False)():
            try:
                from tqdm import tqdm

                self.bar = tqdm(total=total, desc=label, unit="task", file=stream, leave=False)
            except ImportError:  # tqdm missing: plain lines
                self.bar = None

    def eta(self):
        """Seconds left at the rate so far (None before the first task)."""
        if self.done == 0:
            return None
        elapsed = time.monotonic() - self.start
        return elapsed / self.done * (self.total - self.done)

    def update(self, n=1):
        self.done += n
        if self.bar is not None:
            self.bar.update(n)
            return
        now = time.monotonic()
        if self.say is not None and (now - self.last >= self.min_interval or self.done == self.total):
            self.last = now
            eta = self.eta()
            self.say(f"{self.label}: {self.done}/{self.total} tasks" + (f", ETA {eta:.0f} s" if eta else ""))

    def close(self):
        if self.bar is not None:
            self.bar.close()


class Executor:
    """One worker: the tasks run one after the other in this process."""

    workers = 1
    lanes = 1  # checks side by side (suite.lanes)
    inherits = False  # whether a task is forked from this process (it needs no pickling)
    scheduler = None
    dashboard = None  # the Dask dashboard's address, when there is one
    say = None  # progress lines (a callable taking a message), or None
    where = "client"  # where the tasks run: "client" (this process) or "workers"
    log = None  # one entry per batch: kind, label, tasks, seconds per task, wall seconds (bytes moved on Dask)

    def map(self, fn, items, *, kind, label, on_result=None, stop=None):
        """``[fn(item) for item in items]`` in the order of ``items``.

        ``on_result(i, result)`` runs in the caller as task i arrives; when ``stop(i, result)`` is true, the tasks
        after i are not needed: they are cancelled (or not started) and their places hold None."""
        _known(kind)
        items = list(items)
        results = [None] * len(items)
        progress = Progress(len(items), label, say=self.say if len(items) > 1 else None)
        record = self._record(kind, label, len(items))
        try:
            for i, item in enumerate(items):
                t0 = time.perf_counter()
                results[i] = fn(item)
                record["task_s"].append(time.perf_counter() - t0)
                progress.update()
                if on_result is not None:
                    on_result(i, results[i])
                if stop is not None and stop(i, results[i]):
                    break
        finally:
            progress.close()
            record["wall_s"] = time.perf_counter() - record.pop("_start")
        return results

    def _record(self, kind, label, tasks):
        """A new entry of :attr:`log` (one per batch of tasks): what the scaling benchmark reads."""
        if self.log is None:
            self.log = []
        entry = {"kind": kind, "label": str(label), "where": self.where, "tasks": tasks, "task_s": [], "bytes_in": None,
                 "bytes_out": None, "_start": time.perf_counter()}
        self.log.append(entry)
        return entry

    def portable(self, fn):
        """Whether ``fn`` can be sent to a worker (always, in this process)."""
        return True

    @contextmanager
    def computing(self):
        """Around a check's own computation in a lane (a token held, with :class:`ForkExecutor`)."""
        yield

    def close(self):
        pass

    def describe(self):
        return "1 worker (in this process)"

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


TERMINATE_S = 10.0  # how long Pool.terminate may take before its workers are killed (a safety net, not a verdict)


def _terminate(pool):
    """``pool.terminate()``, which can hang for good in CPython (seen once in .ci/run: ``_terminate_pool`` joining a
    handler thread after a stop, its workers already ended): after :data:`TERMINATE_S` its workers are killed."""
    ender = threading.Thread(target=pool.terminate, daemon=True)
    ender.start()
    ender.join(TERMINATE_S)
    if ender.is_alive():
        for process in getattr(pool, "_pool", []):
            process.kill()
        ender.join(TERMINATE_S)


class ForkExecutor(Executor):
    """``workers`` tokens on this machine: checks in as many lanes, tasks in forked processes (see the module)."""

    where = "workers"
    inherits = True

    def __init__(self, workers, *, say=None):
        self.workers = self.lanes = workers
        self.say = say
        self.tokens = multiprocessing.get_context("fork").BoundedSemaphore(workers)
        self._holding = False  # whether this process holds a token (each lane its own copy of the flag)

    def describe(self):
        return f"{self.workers} workers (forked processes on this machine)"

    @contextmanager
    def computing(self):
        self.tokens.acquire()
        self._holding = True
        try:
            yield
        finally:
            self._holding = False
            self.tokens.release()

    def map(self, fn, items, *, kind, label, on_result=None, stop=None):
        items = list(items)
        if len(items) < 2 or _FORKED_TASK:  # one task, or a task's own tasks: here
            results = Executor.map(self, fn, items, kind=kind, label=label, on_result=on_result, stop=stop)
            self.log[-1]["where"] = "client"
            return results
        _known(kind)
        record = self._record(kind, label, len(items))
        record["bytes_in"], record["bytes_out"] = 0, 0
        progress = Progress(len(items), label, say=self.say)
        results, arrived, finished = [None] * len(items), {}, queue.Queue()
        running, start, deliver, stopped = set(), 0, 0, False
        _BATCH[:] = [(fn, items)]
        holding, self._holding = self._holding, False
        if holding:  # this process waits: its token goes to its tasks
            self.tokens.release()
        pool = multiprocessing.get_context("fork").Pool(min(self.workers, len(items)), initializer=_forked)
        try:
            while deliver < len(items) and not stopped:
                while start < len(items) and self.tokens.acquire(block=not running):
                    pool.apply_async(_forked_task, (start,), callback=finished.put,
                                     error_callback=lambda exc, i=start: finished.put((i, exc, 0.0, 0)))
                    running.add(start)
                    start += 1
                try:
                    i, result, seconds, nbytes = finished.get(timeout=0.2)
                except queue.Empty:  # none ended: try for a token again
                    continue
                running.discard(i)
                self.tokens.release()
                if isinstance(result, BaseException):
                    raise result
                record["task_s"].append(seconds)
                record["bytes_out"] += nbytes
                arrived[i] = result
                progress.update()
                while deliver in arrived and not stopped:  # in the order of the tasks, as Executor.map
                    results[deliver] = arrived.pop(deliver)
                    if on_result is not None:
                        on_result(deliver, results[deliver])
                    stopped = stop is not None and stop(deliver, results[deliver])
                    deliver += 1
        finally:
            _terminate(pool)  # the tasks not needed (after a stop), or all of them on an error
            for _ in running:
                self.tokens.release()
            _BATCH[:] = []
            progress.close()
            record["wall_s"] = time.perf_counter() - record.pop("_start")
            if holding:
                self.tokens.acquire()
                self._holding = True
        return results


_BATCH = []  # (fn, items) of the batch a ForkExecutor maps: its forked processes inherit it
_FORKED_TASK = False  # true in a forked task's process: its own maps run there


def _forked():
    global _FORKED_TASK
    _FORKED_TASK = True


def _forked_task(i):
    """Task ``i`` of the inherited batch: (i, its result, seconds, the bytes of the result sent back)."""
    fn, items = _BATCH[0]
    t0 = time.perf_counter()
    result = fn(items[i])
    seconds = time.perf_counter() - t0
    return i, result, seconds, len(pickle.dumps(result))


class DaskExecutor(Executor):
    """Tasks go to a Dask cluster: a LocalCluster of ``workers`` (started on first use), or ``scheduler``'s."""

    where = "workers"

    def __init__(self, workers=None, scheduler=None, *, say=None):
        try:
            import distributed  # noqa: F401
        except ImportError:
            raise InputError(INSTALL_HINT) from None
        self.workers, self.scheduler, self.say = workers, scheduler, say
        self._clients = {}  # "processes" / "threads" / "remote": Client
        self._clusters = []
        if scheduler is not None:
            from distributed import Client

            try:
                self._clients["remote"] = Client(scheduler, timeout="10s")
            except (OSError, TimeoutError) as exc:
                raise InputError(f"--scheduler {scheduler}: cannot connect: {exc}") from None
            self.dashboard = self._clients["remote"].dashboard_link
            self.workers = len(self._clients["remote"].scheduler_info(n_workers=-1)["workers"])
            self._announce(self._clients["remote"])
        else:  # start the worker processes now, before a check lowers this process's memory limit (inherited)
            self.client("hunt")

    def client(self, kind):
        """The client for ``kind`` (starting its LocalCluster on first use)."""
        if "remote" in self._clients:
            return self._clients["remote"]
        how = KINDS[kind]
        if how not in self._clients:
            import logging

            from distributed import Client, LocalCluster

            processes = how == "processes"
            cluster = LocalCluster(n_workers=self.workers if processes else 1,
                                   threads_per_worker=1 if processes else self.workers, processes=processes,
                                   dashboard_address=":0", silence_logs=logging.ERROR)
            self._clusters.append(cluster)
            self._clients[how] = Client(cluster)
            self.dashboard = self.dashboard or self._clients[how].dashboard_link
            self._announce(self._clients[how], how)
        return self._clients[how]

    def _announce(self, client, how="remote"):
        if self.say is not None:
            where = f"scheduler {self.scheduler}" if how == "remote" else f"a local cluster ({how})"
            self.say(f"dask: {self.workers} worker(s) on {where}; dashboard {client.dashboard_link}")

    def describe(self):
        where = f"the cluster at {self.scheduler}" if self.scheduler else "a Dask LocalCluster"
        return f"{self.workers} workers on {where}"

    def map(self, fn, items, *, kind, label, on_result=None, stop=None):
        _known(kind)
        from distributed import as_completed

        items = list(items)
        if not items:
            return []
        client = self.client(kind)
        record = self._record(kind, label, len(items))
        record["bytes_in"] = _size(functools.partial(fn, items[0])) * len(items)
        record["bytes_out"] = 0
        futures = [client.submit(_timed, fn, item, pure=False, key=f"{_key(label)}-{i}-{os.urandom(4).hex()}")
                   for i, item in enumerate(items)]
        index = {f.key: i for i, f in enumerate(futures)}
        results, done = [None] * len(items), [False] * len(items)
        first_stop = len(items)
        progress = Progress(len(items), label, say=self.say if len(items) > 1 else None)
        try:
            for future in as_completed(futures):
                i = index[future.key]
                if i > first_stop:
                    continue
                results[i], seconds, nbytes = future.result()
                record["task_s"].append(seconds)
                record["bytes_out"] += nbytes
                done[i] = True
                progress.update()
                if on_result is not None:
                    on_result(i, results[i])
                if stop is not None and i < first_stop and stop(i, results[i]):
                    first_stop = i
                    client.cancel([f for f in futures[i + 1:] if not f.done()])
                if all(done[: first_stop + 1] if first_stop < len(items) else done):
                    break
        finally:
            progress.close()
            client.cancel([f for f in futures if not f.done()])
            record["wall_s"] = time.perf_counter() - record.pop("_start")
        return [r if i <= first_stop else None for i, r in enumerate(results)]

    def portable(self, fn):
        import cloudpickle

        try:
            cloudpickle.dumps(fn)
        except Exception:  # pickling fails in many ways
            return False
        return True

    def close(self):
        for client in self._clients.values():
            try:
                client.close()
            except Exception:  # closing is best effort
                pass
        for cluster in self._clusters:
            try:
                cluster.close()
            except Exception:
                pass
        self._clients, self._clusters = {}, []


def _known(kind):
    if kind not in KINDS:
        raise KeyError(f"unknown kind of work {kind!r}; known: {', '.join(KINDS)}")


def _timed(fn, item):
    """A task on a worker: its result, the seconds it took and the size of the result sent back."""
    t0 = time.perf_counter()
    result = fn(item)
    return result, time.perf_counter() - t0, _size(result)


def _size(obj):
    try:
        import cloudpickle

        return len(cloudpickle.dumps(obj))
    except Exception:  # unpicklable here: Dask would have failed first
        return 0


def _key(label):
    return "".join(c if c.isalnum() or c in "-_." else "_" for c in str(label))[:60]


def executor_for(workers=None, scheduler=None, *, say=None):
    """The executor of ``--workers`` / ``--scheduler``: in-process for one worker, forked processes for more (default:
    the cores), a Dask cluster with a scheduler."""
    if scheduler is not None:
        return DaskExecutor(scheduler=scheduler, say=say)
    workers = default_workers() if workers is None else workers
    if workers < 1:
        raise InputError(f"--workers must be at least 1, got {workers}")
    return Executor() if workers == 1 else ForkExecutor(workers, say=say)

