"""Re-run a saved counterexample (``inertiaproof replay FILE``)."""

from __future__ import annotations

import json
from pathlib import Path

from inertiaproof.errors import InputError

from .context import Context
from .discovery import load_checks
from .outputs import COUNTEREXAMPLE_SCHEMA
from .profiles import PROFILES
from .registry import REPLAYERS

__all__ = ["load_counterexample", "replay"]


def load_counterexample(path):
    path = Path(path)
    try:
        data = json.loads(path.read_text())
    except OSError as exc:
        raise InputError(f"{path}: cannot read: {exc.strerror}") from None
    except json.JSONDecodeError as exc:
        raise InputError(f"{path}: not JSON: {exc}") from None
    if not isinstance(data, dict) or data.get("schema") != COUNTEREXAMPLE_SCHEMA:
        raise InputError(f"{path}: not an inertiaproof counterexample (schema {COUNTEREXAMPLE_SCHEMA})")
    for key in ("kind", "data"):
        if key not in data:
            raise InputError(f"{path}: counterexample has no {key!r}")
    return data


def replay(path):
    """The Result of re-running the counterexample in ``path``."""
    data = load_counterexample(path)
    load_checks()
    fn = REPLAYERS.get(data["kind"])
    if fn is None:
        raise InputError(f"{path}: no replayer for counterexample kind {data['kind']!r}")
    ctx = Context(PROFILES.get(data.get("profile", "ci"), PROFILES["ci"]), seed=data.get("seed", 0))
    return fn(data["data"], ctx)
