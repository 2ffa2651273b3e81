"""``--expect-mass KG`` and ``--expect-mass NAME=KG``: the model's total mass against its datasheet's.

The total mass of a file is the sum of its links' masses as the audit reads them (``links[name].inertial.mass``;
a link without an ``<inertial>`` counts 0, a MuJoCo body computed from its geoms counts MuJoCo's mass). A bare
``KG`` is expected of every file audited; ``NAME=KG`` of the file whose path as given, file name or robot name is
NAME (it overrides a bare ``KG``). A total more than ``tolerance`` (relative, of the expected) away is a finding
of the file (``total_mass`` in the JSON; rule ``total-mass-mismatch``) counted in the exit status.
"""

from __future__ import annotations

import math
from pathlib import Path

from inertiaproof.errors import InputError
from inertiaproof.result import quantity

__all__ = ["DEFAULT_TOLERANCE", "check_total_mass", "parse_expectations", "total_mass"]

DEFAULT_TOLERANCE = 1e-3  # relative, of the expected mass
HEAVIEST = 3  # the links a mismatch names, heaviest first


def _kilograms(text, option):
    try:
        value = float(text)
    except ValueError:
        raise InputError(f"{option}: {text!r} is not a number of kg") from None
    if not math.isfinite(value) or value <= 0:
        raise InputError(f"{option}: the expected mass must be a positive number of kg, got {text}")
    return value


def parse_expectations(values, tolerance=DEFAULT_TOLERANCE):
    """``(--expect-mass values, --mass-tolerance)`` -> ``{"default": KG or None, "named": {NAME: KG},
    "tolerance": REL}``, or None when no mass is expected. A bad value is a one-line :class:`InputError`."""
    if not math.isfinite(tolerance) or not 0 <= tolerance < 1:
        raise InputError(f"--mass-tolerance must be a relative tolerance in [0, 1), got {tolerance}")
    if not values:
        return None
    default, named = None, {}
    for value in values:
        name, sep, kg = value.rpartition("=")
        if not sep:
            if default is not None:
                raise InputError(f"--expect-mass {value}: a mass for every file is already given ({default:g} kg); "
                                 "name the file for another: --expect-mass NAME=KG")
            default = _kilograms(value, f"--expect-mass {value}")
            continue
        if not name.strip():
            raise InputError(f"--expect-mass {value}: NAME=KG needs a file or robot name before '='")
        mass = _kilograms(kg, f"--expect-mass {value}")
        if named.get(name, mass) != mass:
            raise InputError(f"--expect-mass {value}: {name} is already expected to weigh {named[name]:g} kg")
        named[name] = mass
    return {"default": default, "named": named, "tolerance": tolerance}


def total_mass(f):
    """The sum of a readable file's link masses as read, and its links by mass, heaviest first."""
    masses = [(name, link["inertial"]["mass"]) for name, link in f["links"].items() if link.get("inertial")]
    return math.fsum(m for _, m in masses), sorted(masses, key=lambda item: -item[1])


def _names(path, f):
    names = {str(path), Path(path).name}
    if f.get("status") == "ok" and f.get("robot"):
        names.add(f["robot"])
    return names


def check_total_mass(files, expectations):
    """Add ``total_mass`` to every readable file of ``files`` ({path: entry}, as :func:`.document.audit_paths`
    returns them); with ``expectations`` (:func:`parse_expectations`) its expected mass and whether the total
    matches. A NAME that matches no file, or a file matched by two NAMEs, is a one-line :class:`InputError`."""
    expected = {}
    if expectations:
        claimed = {}
        for name, kg in expectations["named"].items():
            hits = [path for path, f in files.items() if name in _names(path, f)]
            if not hits:
                raise InputError(f"--expect-mass {name}={kg:g}: {name} is no file audited (path, file name or robot "
                                 "name)")
            for path in hits:
                if path in claimed and claimed[path][1] != kg:
                    raise InputError(f"--expect-mass: {path} is named twice, as {claimed[path][0]} and {name}")
                claimed[path] = (name, kg)
        for path in files:
            kg = claimed[path][1] if path in claimed else expectations["default"]
            if kg is not None:
                expected[path] = kg
    tolerance = expectations["tolerance"] if expectations else DEFAULT_TOLERANCE
    for path, f in files.items():
        if f.get("status") != "ok":
            continue
        total, ranked = total_mass(f)
        entry = {"total": quantity(total, "value", "the sum of the links' masses as read", unit="kg"),
                 "expected": None, "tolerance_rel": tolerance, "matches": None, "message": None,
                 "heaviest": [{"link": name, "mass": quantity(m, "value", unit="kg")} for name, m in ranked[:HEAVIEST]]}
        if path in expected:
            kg = expected[path]
            off = (total - kg) / kg
            entry.update(expected=quantity(kg, "value", "--expect-mass", unit="kg"),
                         off_rel=quantity(off, "value", "(total - expected) / expected"),
                         matches=abs(total - kg) <= tolerance * kg)
            if not entry["matches"]:
                heavy = ", ".join(f"'{name}' {m:.6g} kg" + (f" ({m / total:.0%})" if total > 0 else "")
                                  for name, m in ranked[:HEAVIEST]) or "none"
                entry["message"] = (f"{Path(path).name} (robot '{f['robot']}'): total mass {total:.6g} kg, expected "
                                    f"{kg:.6g} kg ({off:+.3%}, beyond the tolerance of {tolerance:.3g} relative); "
                                    f"heaviest links: {heavy}")
        f["total_mass"] = entry
