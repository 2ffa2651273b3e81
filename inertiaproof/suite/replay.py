"""Re-run a saved counterexample (``inertiaproof replay FILE``)."""

from __future__ import annotations

import json
from pathlib import Path

from inertiaproof.budget import Budget, OutOfBudget, enforced
from inertiaproof.errors import InputError, read_text
from inertiaproof.result import Result, Verdict

from . import certificates  # noqa: F401  (registers the replayer of refuted certificates)
from .context import Context
from .discovery import load_checks
from .outputs import COUNTEREXAMPLE_SCHEMA
from .profiles import PROFILES
from .registry import REPLAYERS

__all__ = ["load_counterexample", "replay"]


def load_counterexample(path):
    path = Path(path)
    text = read_text(path, "counterexample")
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise InputError(f"{path}:{exc.lineno}: not JSON: {exc.msg} (column {exc.colno})") from None
    except RecursionError:
        raise InputError(f"{path}: not usable JSON: nested too deeply") from None
    if not isinstance(data, dict) or data.get("schema") != COUNTEREXAMPLE_SCHEMA:
        raise InputError(f"{path}: not an inertiaproof counterexample (schema {COUNTEREXAMPLE_SCHEMA})")
    for key, kind, what in (("kind", str, "a string"), ("data", dict, "an object")):
        if key not in data:
            raise InputError(f"{path}: counterexample has no {key!r}")
        if not isinstance(data[key], kind):
            raise InputError(f"{path}: counterexample field {key!r} must be {what}, got {_shown(data[key])}")
    if "seed" in data and (not isinstance(data["seed"], int) or isinstance(data["seed"], bool)):
        raise InputError(f"{path}: counterexample field 'seed' must be an integer, got {_shown(data['seed'])}")
    if "profile" in data and not (isinstance(data["profile"], str) and data["profile"] in PROFILES):
        raise InputError(f"{path}: counterexample field 'profile' must be one of {', '.join(PROFILES)}, got "
                         f"{_shown(data['profile'])}")
    return data


def _shown(value, most=60):
    text = json.dumps(value)
    return text if len(text) <= most else text[:most] + "..."


def replay(path):
    """The Result of re-running the counterexample in ``path``; data that do not fit its kind are an InputError
    naming the file."""
    data = load_counterexample(path)
    load_checks()
    fn = REPLAYERS.get(data["kind"])
    if fn is None:
        raise InputError(f"{path}: no replayer for counterexample kind {data['kind']!r}")
    profile = PROFILES[data.get("profile", "ci")]
    ctx = Context(profile, seed=data.get("seed", 0), budget=Budget.of(profile.check_s, profile.memory_mb * 2**20))
    try:
        with enforced(ctx.budget, grace=min(10.0, 0.25 * profile.check_s)):
            return fn(data["data"], ctx)
    except OutOfBudget:
        return Result(str(data.get("id", data["kind"])), Verdict.INCONCLUSIVE,
                      f"no answer within the {profile.name} profile's {profile.check_s:g} s",
                      evidence={"budget": "time"})
    except MemoryError:
        raise InputError(f"{path}: replaying it needs more than the {profile.name} profile's {profile.memory_mb} "
                         "MiB") from None
    except InputError as exc:
        raise InputError(f"{path}: {exc}") from None
    except (KeyError, TypeError, ValueError, IndexError, AttributeError, OverflowError) as exc:
        what = f"no field {exc}" if isinstance(exc, KeyError) else f"{type(exc).__name__}: {exc}"
        raise InputError(f"{path}: the data of this {data['kind']!r} counterexample cannot be replayed: "
                         f"{what}") from None
