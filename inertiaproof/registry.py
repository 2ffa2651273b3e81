"""Checks, the profiles they run under, and the context they receive.

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

import hashlib
import importlib
import json
import pkgutil
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from . import catalog
from .result import Result


@dataclass(frozen=True)
class Profile:
    """How hard a run looks. Checks scale their work by these numbers."""

    name: str
    examples: int  # Hypothesis examples per hunt
    samples: int  # configurations / times sampled per extreme
    refine_s: float  # seconds a bracket may spend narrowing
    symbolic_max_n: int  # largest n for the abstract symbolic derivation
    derandomize: bool  # Hypothesis: same examples every run, no database
    concrete_chains: tuple = ("2R", "3R")  # concrete chains derived symbolically
    symbolic_parameters: int = 2  # generic M^h, U^h of the abstract derivation (linearity covers any 10N)
    symbolic_rows: int = 2  # generic rows of QJ of the abstract derivation (linearity covers any 6N)
    moment_samples: int = 2**18  # Monte Carlo points per density (EQ-moments)
    bernstein_degree: int = 3  # highest Bernstein degree checked symbolically (EQ-moments)


PROFILES = {
    "ci": Profile("ci", examples=60, samples=2000, refine_s=0.5, symbolic_max_n=3, derandomize=True),
    "deep": Profile("deep", examples=2000, samples=50000, refine_s=20.0, symbolic_max_n=5, derandomize=False,
                    concrete_chains=("2R", "3R", "6R"), symbolic_parameters=10, symbolic_rows=6,
                    moment_samples=2**22, bernstein_degree=8),
}


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


def load_checks():
    """Import every module of inertiaproof.checks so that their checks register."""
    from . import checks as package

    for mod in pkgutil.iter_modules(package.__path__):
        importlib.import_module(f"{package.__name__}.{mod.name}")
    return CHECKS


@dataclass
class Context:
    profile: Profile
    seed: int = 0
    scene: object = None  # inertiaproof.scene.Scene or None
    out_dir: Path | None = None
    counterexample_dir: Path = Path("counterexamples/found")
    progress: Callable[[str], None] = lambda message: None
    artifacts: list = field(default_factory=list)

    def rng(self, salt):
        """A generator seeded by the run's seed and a salt (the check's name): independent streams, same every run."""
        digest = hashlib.sha256(f"{self.seed}:{salt}".encode()).digest()
        return np.random.default_rng(int.from_bytes(digest[:8], "little"))

    def hypothesis_settings(self, **overrides):
        """Settings for a hunt under this profile: derandomised with no database in ci."""
        from hypothesis import HealthCheck, settings
        from hypothesis.database import DirectoryBasedExampleDatabase

        kwargs = dict(
            max_examples=self.profile.examples,
            derandomize=self.profile.derandomize,
            database=None if self.profile.derandomize else DirectoryBasedExampleDatabase(str(cache_dir() / "hypothesis")),
            deadline=None,
            print_blob=False,
            suppress_health_check=list(HealthCheck),
        )
        kwargs.update(overrides)
        return settings(**kwargs)

    def write_data(self, name, obj):
        """Write a JSON data file next to results.json; returns its name (or None without --out)."""
        if self.out_dir is None:
            return None
        path = Path(self.out_dir) / "data" / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(obj, indent=1, sort_keys=True))
        rel = str(path.relative_to(self.out_dir))
        self.artifacts.append(rel)
        return rel

    def save_counterexample(self, result: Result):
        """Write the result's counterexample as a replayable JSON file; returns the path."""
        if not result.counterexample:
            return None
        self.counterexample_dir.mkdir(parents=True, exist_ok=True)
        body = {
            "schema": "inertiaproof.counterexample/1",
            "id": result.id,
            "summary": result.summary,
            "profile": self.profile.name,
            "seed": self.seed,
            **result.counterexample,
        }
        text = json.dumps(body, indent=1, sort_keys=True)
        digest = hashlib.sha256(text.encode()).hexdigest()[:10]
        safe = result.id.replace("/", "_")
        path = self.counterexample_dir / f"{safe}-{digest}.json"
        path.write_text(text)
        return path


def cache_dir():
    """Where derivations and Hypothesis examples are cached ($INERTIAPROOF_CACHE or ~/.cache/inertiaproof)."""
    import os

    root = os.environ.get("INERTIAPROOF_CACHE") or Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "inertiaproof"
    path = Path(root)
    path.mkdir(parents=True, exist_ok=True)
    return path


def timed(fn, *args, **kwargs):
    """(value, seconds) of one call."""
    start = time.perf_counter()
    value = fn(*args, **kwargs)
    return value, time.perf_counter() - start
