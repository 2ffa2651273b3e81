"""Where the suite keeps state between runs."""

from __future__ import annotations

import os
from pathlib import Path

__all__ = ["cache_dir"]


def cache_dir():
    """Where derivations and Hypothesis examples are cached ($INERTIAPROOF_CACHE or ~/.cache/inertiaproof)."""
    root = os.environ.get("INERTIAPROOF_CACHE") or Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "inertiaproof"
    path = Path(root)
    path.mkdir(parents=True, exist_ok=True)
    return path
