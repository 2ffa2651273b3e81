"""Repairs written into the file: the replacement text of an inertia element, repaired copies and their diff.

A repair replaces exactly the markup of one element (its span, see
:mod:`.locate`): a URDF ``<inertia .../>`` by the six repaired entries, an
MJCF ``<inertial .../>`` by the same element with its ``diaginertia`` or
``fullinertia`` repaired (MJCF's order: M(1,1), M(2,2), M(3,3), M(1,2),
M(1,3), M(2,3)) and every other attribute kept, an SDFormat ``<inertia>`` by
one with the six repaired child elements. The rest of the file is
copied character for character.
"""

from __future__ import annotations

import difflib
from pathlib import Path
from xml.sax.saxutils import quoteattr

from .locate import decode

__all__ = ["apply", "repaired_copies", "replacement", "unified_diff"]

URDF_ORDER = ("ixx", "iyy", "izz", "ixy", "iyz", "ixz")
MJCF_ORDER = {"diaginertia": ("ixx", "iyy", "izz"), "fullinertia": ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")}


def replacement(source, written):
    """The text that replaces ``source``'s element, given the repaired entries as strings (URDF names)."""
    if source.kind == "urdf":
        return "<inertia " + " ".join(f'{name}="{written[name]}"' for name in URDF_ORDER) + "/>"
    if source.kind == "sdf":  # an SDFormat <inertia> with its six child elements
        return "<inertia>" + "".join(f"<{name}>{written[name]}</{name}>" for name in URDF_ORDER) + "</inertia>"
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


def repaired_copies(files, paths, out):
    """{original path: (target, encoding, original text, repaired text, links left as written)} (``--write-repaired``).

    ``files`` is the audit's ``files``; ``paths`` the arguments it was given. One file argument: ``out`` is the
    copy (or a folder to put it in); otherwise ``out`` is a folder holding each copy at its path relative to its
    argument. Only changes inside the audited file itself are made (an MJCF include is left alone, and said so).
    """
    out = Path(out)
    single = len(paths) == 1 and Path(paths[0]).is_file()
    copies = {}
    for path, f in files.items():
        if f["status"] != "ok":
            continue
        source = Path(path)
        if single:
            target = out / source.name if out.is_dir() else out
        else:
            base = next((Path(p) for p in paths if Path(p).is_dir() and source.is_relative_to(p)), source.parent)
            target = out / source.relative_to(base)
        if target.resolve() == source.resolve():
            raise ValueError(f"{target}: --write-repaired would overwrite the audited file")
        text, encoding = decode(source.read_bytes())
        changes, left = [], []
        for name, link in f["links"].items():
            repair = link["repair"]
            if repair is None:
                continue
            r = repair.get("replacement")
            if r is not None and Path(r["path"]).resolve() == source.resolve():
                changes.append((r["start"], r["end"], r["text"]))
            else:
                why = repair["note"] if repair["written"] is None else "its element is not in this file or not located"
                left.append((name, why))
        copies[path] = (target, encoding, text, apply(text, changes), left)
    return copies
