"""Repairs written into the file: the replacement text of an inertia element, repaired copies and their diff.

A repair replaces exactly the markup of one element (its span, see
:mod:`.locate`): a URDF ``<inertia .../>`` by the six repaired entries, an
MJCF ``<inertial .../>`` by the same element with its ``diaginertia`` or
``fullinertia`` repaired (MJCF's order: M(1,1), M(2,2), M(3,3), M(1,2),
M(1,3), M(2,3)) and every other attribute kept. The rest of the file is
copied character for character.
"""

from __future__ import annotations

import difflib
from xml.sax.saxutils import quoteattr

__all__ = ["apply", "replacement", "unified_diff"]

URDF_ORDER = ("ixx", "iyy", "izz", "ixy", "iyz", "ixz")
MJCF_ORDER = {"diaginertia": ("ixx", "iyy", "izz"), "fullinertia": ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")}


def replacement(source, written):
    """The text that replaces ``source``'s element, given the repaired entries as strings (URDF names)."""
    if source.kind == "urdf":
        return "<inertia " + " ".join(f'{name}="{written[name]}"' for name in URDF_ORDER) + "/>"
    value = " ".join(written[name] for name in MJCF_ORDER[source.kind])
    attributes = [(name, value if name == source.kind else old) for name, old in source.attributes]
    return "<inertial " + " ".join(f"{name}={quoteattr(text)}" for name, text in attributes) + "/>"


def apply(text, changes):
    """``text`` with every (start, end, new text) change made; changes must not overlap."""
    out, at = [], 0
    for start, end, new in sorted(changes):
        if start < at:
            raise ValueError("overlapping changes")
        out += [text[at:start], new]
        at = end
    return "".join(out + [text[at:]])


def unified_diff(old, new, old_name, new_name):
    return "".join(difflib.unified_diff(old.splitlines(keepends=True), new.splitlines(keepends=True),
                                        fromfile=old_name, tofile=new_name))
