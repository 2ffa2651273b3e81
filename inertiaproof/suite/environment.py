"""The versions a result was computed with, and how to start this same inertiaproof again in a child process."""

from __future__ import annotations

import platform
import sys
from importlib import metadata
from pathlib import Path

__all__ = ["command", "version", "versions"]

# -P: the child's working directory must not shadow the package (from a source checkout's root, ./inertiaproof is
# the core without its mapped subpackages); the parent's package folder goes first only when it is not already
# on the path (a copy run in place, an editable install), so the child imports what this process imported
_BOOTSTRAP = ("import sys; home = sys.argv.pop(1); sys.path.insert(0, home) if home not in sys.path else None; "
              "from inertiaproof.cli import main; sys.exit(main(sys.argv[1:]))")

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


def command(*args):
    """argv that runs ``inertiaproof ARGS`` with this interpreter and this process's inertiaproof package."""
    import inertiaproof

    return [sys.executable, "-P", "-c", _BOOTSTRAP, str(Path(inertiaproof.__file__).resolve().parents[1]), *args]
