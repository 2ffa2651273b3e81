"""``robot.urdf.xacro``: expanded by the ``xacro`` package (PyPI: ``pip install xacro``), then read as a URDF.

The expanded text is what ``xacro FILE name:=value ...`` prints; the audit
reads it as it reads a URDF (:func:`.urdf.read_urdf`), so lines and columns
are those of the expanded text, and the audit says so: each location carries
``"expanded": "xacro"``, annotations name the line in the message instead of
pointing into the ``.xacro`` file, and ``--write-repaired`` leaves such files
alone (the repair's entries are printed, to be written into the macro).
What xacro says on stderr becomes the file's warnings; what it cannot expand
(a ``$(find pkg)`` without ROS, a missing argument) is one line naming the file.
"""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

from inertiaproof.errors import InputError

__all__ = ["expand", "is_xacro", "parse_arguments", "read_xacro"]

_ARGUMENT = re.compile(r"^([A-Za-z_][\w.-]*):=(.*)$", re.S)


def is_xacro(path):
    return Path(path).suffix.lower() == ".xacro"


def parse_arguments(pairs):
    """{name: value} of ``--xacro-arg name:=value`` (InputError naming the bad one)."""
    out = {}
    for pair in pairs or ():
        m = _ARGUMENT.match(pair)
        if m is None:
            raise InputError(f"--xacro-arg {pair!r}: expected name:=value")
        out[m.group(1)] = m.group(2)
    return out


def expand(path, arguments=None):
    """(the expanded text, what xacro warned about) of a xacro file; InputError naming the file otherwise."""
    path = Path(path)
    try:
        import xacro
    except ImportError:
        raise InputError(f"{path}: expanding xacro files needs the xacro package: pip install xacro") from None
    if not path.is_file():
        raise InputError(f"{path}: cannot read: {'not a file' if path.exists() else 'No such file or directory'}")
    said = io.StringIO()
    try:
        with contextlib.redirect_stderr(said), contextlib.redirect_stdout(said):
            doc = xacro.process_file(str(path), mappings=dict(arguments or {}), verbosity=1)
            text = doc.toprettyxml(indent="  ")
    except Exception as exc:  # XacroException, ExpatError, NameError of an expression, KeyError of an argument ...
        what = " ".join(str(exc).split()) or type(exc).__name__
        if isinstance(exc, KeyError):
            what = f"no value for argument {exc}: give it with --xacro-arg NAME:=VALUE"
        raise InputError(f"{path}: xacro cannot expand it: {what}") from None
    finally:
        xacro.init_stacks(None)  # xacro keeps its file stack in module globals
    warnings = [f"xacro: {' '.join(line.split())}" for line in said.getvalue().splitlines() if line.strip()]
    return text, warnings


def read_xacro(path, arguments=None):
    """The robot in a xacro file, read from its expansion (see the module's docstring)."""
    from .urdf import read_urdf

    text, warnings = expand(path, arguments)
    return read_urdf(path, data=text.encode("utf-8"), expanded="xacro", warnings=warnings)
