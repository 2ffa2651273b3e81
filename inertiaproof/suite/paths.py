"""Where the suite keeps state between runs."""

from __future__ import annotations

import os
import sys
from pathlib import Path

__all__ = ["cache_dir", "cache_unwritable"]

_WARNED = []  # the cache this process has warned about (once per process)


def cache_dir():
    """Where derivations and Hypothesis examples are cached ($INERTIAPROOF_CACHE or ~/.cache/inertiaproof).

    Never raises: when the folder cannot be made (a read-only place, a path through a regular file) it is still
    returned, what it holds is read where it can be, nothing is stored, and stderr says so once
    (:func:`cache_unwritable`)."""
    root = os.environ.get("INERTIAPROOF_CACHE") or Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "inertiaproof"
    path = Path(root)
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        cache_unwritable(path, exc)
    return path


def cache_unwritable(path, exc):
    """Say once per process, on stderr, that the cache cannot be written; the run goes on without storing in it."""
    if _WARNED:
        return
    _WARNED.append(str(path))
    reason = exc.strerror or type(exc).__name__
    print(f"inertiaproof: warning: the cache {path} cannot be written ({reason}): this run reads what it holds and "
          "stores nothing (set INERTIAPROOF_CACHE to a writable folder)", file=sys.stderr)
