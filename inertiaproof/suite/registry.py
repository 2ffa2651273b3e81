"""The checks and replayers, registered by the modules of ``inertiaproof.checks``.

A check is a function ``fn(ctx: Context) -> Result`` registered with
:func:`check`. It declares what it needs from a scene (``needs``):

- ``()`` (empty): a statement about the paper itself (identities,
  certificates, hunts over random objects); it runs without a scene.
- a set of scene features (``"chain"``, ``"time_varying"``,
  ``"internal_motion"``, ``"symbolic"``): it checks the statement on one
  scene, ``ctx.scene``; without ``--scene`` it runs on the built-in scenes.

A check that can report VIOLATED also registers a replayer with
:func:`replayer`, which re-runs a saved counterexample.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from . import catalog

__all__ = ["CHECKS", "REPLAYERS", "CheckSpec", "check", "replayer"]


@dataclass(frozen=True)
class CheckSpec:
    id: str
    name: str  # unique: id for the paper-level check, id:variant otherwise
    fn: Callable
    needs: frozenset

    @property
    def entry(self):
        return catalog.BY_ID[self.id]


CHECKS: dict[str, CheckSpec] = {}
REPLAYERS: dict[str, Callable] = {}


def check(check_id, *, needs=(), variant=None):
    """Register ``fn(ctx) -> Result`` for a catalog ID."""
    if check_id not in catalog.BY_ID:
        raise KeyError(f"{check_id!r} is not a catalog ID")

    def register(fn):
        name = check_id if variant is None else f"{check_id}:{variant}"
        if name in CHECKS and CHECKS[name].fn.__qualname__ != fn.__qualname__:
            raise KeyError(f"check {name} registered twice")
        CHECKS[name] = CheckSpec(check_id, name, fn, frozenset(needs))
        return fn

    return register


def replayer(kind):
    """Register ``fn(data: dict, ctx) -> Result`` that re-runs a counterexample of this ``kind``."""

    def register(fn):
        REPLAYERS[kind] = fn
        return fn

    return register
