"""Where a URDF ``<mesh filename>`` points: ``package://``, ``file://``, absolute and relative URIs resolved to files.

- ``package://NAME/REST`` (``package:///NAME/REST`` too, read as urdfdom strips the scheme): the folder of the
  package NAME, then REST in it. The folder is the one given by ``--package NAME=DIR``, else found by searching
  upward from the folder of the file that names the mesh: at each folder A from there to the root, A itself, then
  its subfolders (a ROS workspace keeps packages side by side), is NAME's folder when its ``package.xml`` has
  ``<name>NAME</name>`` or when it is named NAME (as pybullet and Pinocchio's package directories find a
  package: example-robot-data ships ``share/example-robot-data`` with a package.xml naming
  ``example_robot_descriptions``, iCub ``share/iCub`` with none). The nearest folder wins.
- ``model://NAME/REST`` (SDFormat's): the same search.
- ``file:///PATH``: PATH; an absolute path: itself; anything else: relative to the naming file's folder.

A URI that resolves to no file raises :class:`MeshUnread` naming what was searched.
"""

from __future__ import annotations

import os
import re
from functools import lru_cache
from pathlib import Path
from urllib.parse import unquote, urlparse

__all__ = ["MeshUnread", "package_folders", "parse_packages", "resolve"]

_NAME = re.compile(rb"<name>\s*([^<\s]+)\s*</name>")


class MeshUnread(ValueError):
    """A mesh that cannot be resolved or read: the message is one line."""


def parse_packages(values):
    """{NAME: Path} of ``--package NAME=DIR`` values; ValueError naming a bad one."""
    out = {}
    for value in values or ():
        name, sep, folder = value.partition("=")
        if not sep or not name.strip() or not folder.strip():
            raise ValueError(f"--package needs NAME=DIR, got {value!r}")
        if not Path(folder).expanduser().is_dir():
            raise ValueError(f"--package {value}: {folder} is not a folder")
        out[name.strip()] = Path(folder).expanduser().resolve()
    return out


@lru_cache(maxsize=4096)
def _package_name(folder):
    """The ``<name>`` of ``folder/package.xml``, or None."""
    try:
        found = _NAME.search((Path(folder) / "package.xml").read_bytes())
    except OSError:
        return None
    return found.group(1).decode(errors="replace") if found else None


@lru_cache(maxsize=4096)
def _subfolders(folder):
    try:
        return tuple(sorted(e.path for e in os.scandir(folder) if e.is_dir(follow_symlinks=True)))
    except OSError:
        return ()


def _is_package(folder, name):
    return Path(folder).name == name or _package_name(folder) == name


@lru_cache(maxsize=1024)
def _search(start, name):
    for folder in (Path(start), *Path(start).parents):
        if _is_package(str(folder), name):
            return folder
        for sub in _subfolders(str(folder)):
            if _is_package(sub, name):
                return Path(sub)
    return None


def package_folders(name, base, packages=None):
    """The folder of package ``name`` for a file in ``base`` (see the module), or None."""
    if packages and name in packages:
        return Path(packages[name])
    return _search(str(Path(base).resolve()), name)


def resolve(uri, base, packages=None):
    """The file a mesh URI names, for a file in folder ``base`` (see the module); MeshUnread when there is none."""
    parsed = urlparse(uri)
    if parsed.scheme in ("package", "model"):
        rest = uri.split("://", 1)[1].lstrip("/")
        name, _, inside = rest.partition("/")
        folder = package_folders(name, base, packages)
        if folder is None:
            raise MeshUnread(f"{uri}: package '{name}' not found (no package.xml naming it and no folder of that "
                             f"name in {base}, its parents or their subfolders); give --package {name}=DIR")
        path = folder / unquote(inside)
    elif parsed.scheme == "file":
        path = Path(unquote(parsed.path))
    elif parsed.scheme and len(parsed.scheme) > 1:
        raise MeshUnread(f"{uri}: a URI scheme the audit does not read ({parsed.scheme}://)")
    else:
        path = Path(uri) if Path(uri).is_absolute() else Path(base) / uri
    if not path.is_file():
        raise MeshUnread(f"{uri}: no such file {path}")
    return path
