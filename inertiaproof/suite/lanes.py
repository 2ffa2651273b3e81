"""Checks side by side: groups of checks in forked processes (lanes), each group whole in one lane.

A lane takes the next group when it is free, runs its checks one after the other and sends each result back as it
ends; the checks of one group share what they compute (``Context.shared``), so a group is the unit of work. What a
check answers does not depend on its lane: only the time it ends.
"""

from __future__ import annotations

import multiprocessing
import pickle
from multiprocessing.connection import wait

from inertiaproof.budget import share_cores

__all__ = ["side_by_side"]


def side_by_side(groups, lanes, run_one, on_result, crashed):
    """``run_one(i)`` for every index ``i`` of ``groups`` (lists of indices) in ``lanes`` forked processes;
    ``on_result(i, result)`` runs in the caller as each arrives. A lane that dies (a signal, memory) leaves its
    group's unfinished checks to ``crashed(i, why)``, whose result takes their place. Each lane writes to its own
    pipe, synchronously, so a result sent is a result received even if the lane dies right after."""
    context = multiprocessing.get_context("fork")
    tasks = context.Queue()
    for g in range(len(groups)):
        tasks.put(g)
    for _ in range(lanes):
        tasks.put(None)
    pipes = [context.Pipe(duplex=False) for _ in range(lanes)]
    procs = [context.Process(target=_lane, args=(tasks, writer, groups, run_one, lanes))  # not daemons: they fork tasks
             for _, writer in pipes]
    for p in procs:
        p.start()
    for _, writer in pipes:
        writer.close()
    open_lanes = {reader: (p, []) for (reader, _), p in zip(pipes, procs)}  # reader -> process, groups it took
    pending = {i for group in groups for i in group}
    try:
        while open_lanes:
            for reader in wait(list(open_lanes)):
                proc, taken = open_lanes[reader]
                try:
                    kind, payload = reader.recv()
                except EOFError:  # the lane ended: every group it took is answered, or it died
                    proc.join()
                    for i in [i for g in taken for i in groups[g] if i in pending]:
                        pending.discard(i)
                        on_result(i, crashed(i, f"its process ended with exit code {proc.exitcode}"))
                    del open_lanes[reader]
                    continue
                if kind == "group":
                    taken.append(payload)
                else:
                    i, data = payload
                    pending.discard(i)
                    on_result(i, pickle.loads(data))
        for i in sorted(pending):  # groups no lane took (every lane died first)
            on_result(i, crashed(i, "no process was left to run it"))
    finally:
        for p in procs:
            p.join(timeout=5)
            if p.is_alive():
                p.kill()


def _lane(tasks, writer, groups, run_one, lanes):
    share_cores(lanes)  # two lanes of two-thread pools on two cores would crowd each other out
    while (g := tasks.get()) is not None:
        writer.send(("group", g))
        for i in groups[g]:
            writer.send(("result", (i, pickle.dumps(run_one(i)))))
    writer.close()
