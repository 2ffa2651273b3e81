"""Rows of inertial parameters from CSV or JSON, in the paper's or the URDF's columns.

Each row becomes Phi or a per-row error; a malformed row never stops the others.

URDF rows give the mass, the CoM in the link frame, the inertia about the
CoM in the inertial frame's axes and, optionally, that frame's orientation
(``roll``, ``pitch``, ``yaw``). Their verdict is decided on (m, 0, I_c) as
given: consistency does not depend on where the frame is nor how it is
turned (I_Sigma_IsTranslationInvariant), and moving the inertia to the link
frame in floats would round boundary cases (a rod, a plate) off the boundary.
"""

from __future__ import annotations

import csv
import io
import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from inertiaproof.errors import InputError, read_text

from .inertia import PHI_FIELDS, URDF_FIELDS, from_urdf, pack, rotation_rpy, urdf_inertia

__all__ = ["read_rows", "Row", "URDF_ORIENTATION"]

URDF_ORIENTATION = ("roll", "pitch", "yaw")


@dataclass
class Row:
    number: int  # 1-based, as a person counts rows of data
    name: str
    phi: np.ndarray | None = None
    error: str | None = None
    about_com: np.ndarray | None = None  # URDF rows: (m, 0, I_c) as given
    written: tuple | None = None  # the decided-on row as the file writes it (decimal text, Phi order)

    @property
    def decided_on(self):
        """The Phi whose exact values the verdict is decided on."""
        return self.phi if self.about_com is None else self.about_com


def _columns(keys, source):
    names = [k.strip() for k in keys]
    repeated = sorted({k for k in names if names.count(k) > 1})
    if repeated:
        raise InputError(f"{source}: column {repeated[0]!r} appears {names.count(repeated[0])} times: which one is "
                         "meant?")
    keys = set(names)
    if set(PHI_FIELDS) <= keys:
        return "paper", PHI_FIELDS
    if set(URDF_FIELDS) <= keys:
        return "urdf", URDF_FIELDS
    raise InputError(
        f"{source}: columns must include {','.join(PHI_FIELDS)} (paper order) or {','.join(URDF_FIELDS)} (URDF)"
    )


def _parse_row(number, record, fields, convention):
    name = str(record.get("name", "") or "")
    values, texts = [], []
    optional = [f for f in URDF_ORIENTATION if convention == "urdf" and _given(record.get(f))]
    for f in fields + tuple(optional):
        raw = record.get(f)
        if raw is None or (isinstance(raw, str) and not raw.strip()):
            return Row(number, name, error=f"missing field {f}")
        if not isinstance(raw, (str, int, float)) or isinstance(raw, bool):
            return Row(number, name, error=f"field {f} is not a number: {_shown(raw)}")
        try:
            value = float(raw)
        except (TypeError, ValueError):
            return Row(number, name, error=f"field {f} is not a number: {_shown(raw)}")
        if not math.isfinite(value):
            return Row(number, name, error=f"field {f} is not finite: {_shown(raw)}")
        values.append(value)
        texts.append(raw.strip() if isinstance(raw, str) else repr(raw))
    values = np.array(values)
    if convention == "paper":
        return Row(number, name, phi=values, written=tuple(texts))
    rpy = np.zeros(3)
    rpy[[URDF_ORIENTATION.index(f) for f in optional]] = values[len(fields):]
    inertia = urdf_inertia(*values[4:10])
    return Row(number, name, phi=from_urdf(values[0], values[1:4], inertia, rotation_rpy(rpy)),
               about_com=pack(values[0], np.zeros(3), inertia), written=(texts[0], "0", "0", "0", *texts[4:10]))


def _shown(raw, most=40):
    text = repr(raw)
    return text if len(text) <= most else f"{text[:most]}... ({len(text)} characters)"


def _given(raw):
    return raw is not None and not (isinstance(raw, str) and not raw.strip())


def _unique_keys(pairs):
    keys = [k for k, _ in pairs]
    repeated = next((k for k in keys if keys.count(k) > 1), None)
    if repeated is not None:
        raise InputError(f"field {repeated!r} appears {keys.count(repeated)} times in one object: which one is meant?")
    return dict(pairs)


def read_rows(path):
    """Rows from a .csv or .json file (a list of objects, or {"rows": [...]}), numbers kept as written."""
    path = Path(path)
    text = read_text(path)
    if path.suffix.lower() == ".json" or text.lstrip().startswith(("[", "{")):
        return _json_rows(text, path)
    return _csv_rows(text, path)


def _json_rows(text, path):
    try:  # numbers stay text (exact decimals, no 4300-digit limit on integers)
        data = json.loads(text, parse_float=str, parse_int=str, parse_constant=str, object_pairs_hook=_unique_keys)
    except json.JSONDecodeError as exc:
        raise InputError(f"{path}:{exc.lineno}: not valid JSON: {exc.msg} (column {exc.colno})") from None
    except RecursionError:
        raise InputError(f"{path}: not usable JSON: nested too deeply") from None
    except InputError as exc:
        raise InputError(f"{path}: {exc}") from None
    records = data.get("rows") if isinstance(data, dict) else data
    if not isinstance(records, list) or not records:
        raise InputError(f"{path}: expected a non-empty list of rows (or an object with 'rows')")
    dicts = [r for r in records if isinstance(r, dict)]
    if not dicts:
        raise InputError(f"{path}: rows must be objects with named fields")
    convention, fields = _columns(dicts[0].keys(), path)
    return [
        _parse_row(i, r, fields, convention) if isinstance(r, dict) else Row(i, "", error="row is not an object")
        for i, r in enumerate(records, 1)
    ]


def _csv_rows(text, path):
    reader = csv.DictReader(io.StringIO(text, newline=""))
    rows = []
    try:
        if not reader.fieldnames:
            raise InputError(f"{path}: empty CSV file")
        convention, fields = _columns(reader.fieldnames, path)
        for i, record in enumerate(reader, 1):
            record = {(k or "").strip(): v for k, v in record.items() if k is not None}
            rows.append(_parse_row(i, record, fields, convention))
    except csv.Error as exc:
        raise InputError(f"{path}:{reader.line_num}: not usable CSV: {exc}") from None
    if not rows:
        raise InputError(f"{path}: no data rows")
    return rows
