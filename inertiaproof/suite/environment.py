"""The versions a result was computed with."""

from __future__ import annotations

import platform
from importlib import metadata

__all__ = ["version", "versions"]

PACKAGES = ("numpy", "scipy", "sympy", "cvxpy", "clarabel", "hypothesis")


def version(name):
    """The installed version of a distribution, or None."""
    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:
        return None


def versions(*extra):
    """Python's version and those of inertiaproof, its numerical dependencies and ``extra`` distributions."""
    return {"python": platform.python_version(), **{name: version(name) for name in ("inertiaproof", *PACKAGES, *extra)}}
