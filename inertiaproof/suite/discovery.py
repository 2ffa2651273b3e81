"""Find the checks: import every module of ``inertiaproof.checks`` so that their checks and replayers register."""

from __future__ import annotations

import importlib
import pkgutil

from .registry import CHECKS

__all__ = ["load_checks"]


def load_checks():
    """The registered checks, after importing every module of inertiaproof.checks."""
    package = importlib.import_module("inertiaproof.checks")
    for mod in pkgutil.iter_modules(package.__path__):
        importlib.import_module(f"{package.__name__}.{mod.name}")
    return CHECKS
