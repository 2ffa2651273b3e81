"""How long each check took the last time it ran, kept in the cache: lanes start the longest groups first.

One file, ``cache_dir()/check_seconds.json``: {profile / scene: {check: seconds}}. It orders the work only (which
group a free lane takes next), never what a check answers. A check this machine has not run takes its seconds from
the file of that name beside this module (a ci and a deep run of the whole suite, as bench/results/ has them), so a
fresh clone's deep run starts the payload envelope first; a check in neither is ordered by whether it works on
chains.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

from .paths import cache_dir, cache_unwritable

__all__ = ["expected_seconds", "last_seconds", "remember_seconds"]

FILE = "check_seconds.json"


def _key(profile, scene):
    return f"{profile}/{scene or 'suite'}"


def _read(folder):
    try:
        data = json.loads((folder / FILE).read_text())
    except (OSError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}


def _seconds(data, profile, scene):
    found = data.get(_key(profile, scene), {})
    return {k: float(v) for k, v in found.items() if isinstance(v, (int, float))} if isinstance(found, dict) else {}


def last_seconds(profile, scene=None):
    """{check: seconds} of the last run of ``profile`` (on ``scene``), {} when there was none."""
    return _seconds(_read(cache_dir()), profile, scene)


def expected_seconds(profile, scene=None):
    """{check: seconds}: :func:`last_seconds`, and for the checks it lacks those shipped with the package."""
    return {**_seconds(_read(Path(__file__).parent), profile, scene), **last_seconds(profile, scene)}


def remember_seconds(profile, scene, seconds):
    """Keep ``seconds`` ({check: seconds}) as the last run's of ``profile`` (on ``scene``), beside the others."""
    data = _read(cache_dir())
    data[_key(profile, scene)] = {**data.get(_key(profile, scene), {}), **seconds}
    path = cache_dir() / FILE
    partial = path.with_name(f"{FILE}.{os.getpid()}")
    try:
        partial.write_text(json.dumps(data, indent=1, sort_keys=True))
        os.replace(partial, path)  # whole: a run beside this one reads the old file or the new, never half of one
    except OSError as exc:
        cache_unwritable(path.parent, exc)
