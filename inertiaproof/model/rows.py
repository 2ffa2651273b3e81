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
import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from inertiaproof.errors import InputError, open_text, read_text

from .inertia import PHI_FIELDS, URDF_FIELDS, from_urdf, pack, rotation_rpy, urdf_inertia

__all__ = ["CHUNK_ROWS", "read_rows", "Row", "row_chunks", "URDF_ORIENTATION"]

URDF_ORIENTATION = ("roll", "pitch", "yaw")


CHUNK_ROWS = 65_536  # rows read, converted and classified at a time: a file of any size in flat memory


@dataclass
class Row:
    number: int  # 1-based, as a person counts rows of data
    name: str
    phi: np.ndarray | None = None
    error: str | None = None
    about_com: np.ndarray | None = None  # URDF rows: (m, 0, I_c) as given
    written: tuple | None = None  # the decided-on row as the file writes it (decimal text, Phi order)
    values: list | None = None  # the numbers as read, until :func:`_convert` turns a chunk of them into phi

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
    """A row with its numbers as read (``values``: the fields, then roll, pitch, yaw for URDF rows) or its error."""
    name = str(record.get("name", "") or "")
    values, texts = [], []
    extra = URDF_ORIENTATION if convention == "urdf" else ()
    for f in fields + extra:
        raw = record.get(f)
        if raw is None or (isinstance(raw, str) and not raw.strip()):
            if f in extra:
                values.append(0.0)
                continue
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
    if convention == "urdf":
        texts = [texts[0], "0", "0", "0", *texts[4:10]]
    return Row(number, name, values=values, written=tuple(texts[:10]))


def _convert(rows, convention):
    """``rows`` with phi (and about_com) set from their values, batched over the chunk; returns ``rows``."""
    good = [r for r in rows if r.error is None]
    if not good:
        return rows
    values = np.array([r.values for r in good])
    if convention == "paper":
        phi, about = values, [None] * len(good)
    else:  # a missing orientation is 0: R = I exactly, so R I_c R^T = I_c exactly
        inertia = urdf_inertia(*values[:, 4:10].T)
        phi = from_urdf(values[:, 0], values[:, 1:4], inertia, rotation_rpy(values[:, 10:13]))
        about = pack(values[:, 0], np.zeros((len(good), 3)), inertia)
    for r, p, a in zip(good, phi, about):
        r.phi, r.about_com, r.values = p, a, None
    return rows


def _shown(raw, most=40):
    text = repr(raw)
    return text if len(text) <= most else f"{text[:most]}... ({len(text)} characters)"


def _unique_keys(pairs):
    keys = [k for k, _ in pairs]
    repeated = next((k for k in keys if keys.count(k) > 1), None)
    if repeated is not None:
        raise InputError(f"field {repeated!r} appears {keys.count(repeated)} times in one object: which one is meant?")
    return dict(pairs)


def read_rows(path):
    """Rows from a .csv or .json file (a list of objects, or {"rows": [...]}), numbers kept as written."""
    return [row for chunk in row_chunks(path) for row in chunk]


def row_chunks(path, size=None):
    """The rows of :func:`read_rows` in lists of at most ``size`` (default :data:`CHUNK_ROWS`): a CSV file is read
    as it goes (memory flat in its length), a JSON file whole."""
    path, size = Path(path), size or CHUNK_ROWS
    with open_text(path) as handle:
        try:
            start = handle.read(1024)
            if path.suffix.lower() == ".json" or start.lstrip().startswith(("[", "{")):
                rows = _json_rows(start + handle.read(), path)
                yield from (rows[i:i + size] for i in range(0, len(rows), size))
                return
            handle.seek(0)
            yield from _csv_chunks(handle, path, size)
        except UnicodeDecodeError:
            read_text(path)  # raises the error at its line and column
            raise


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
    return _convert([
        _parse_row(i, r, fields, convention) if isinstance(r, dict) else Row(i, "", error="row is not an object")
        for i, r in enumerate(records, 1)
    ], convention)


def _csv_chunks(handle, path, size):
    reader = csv.reader(handle)
    rows, seen = [], False
    try:
        header = next(reader, None)
        if not header:
            raise InputError(f"{path}: empty CSV file")
        convention, fields = _columns(header, path)
        names = [k.strip() for k in header]
        at = [names.index(f) for f in fields]
        turn = [names.index(f) if f in names else None for f in (URDF_ORIENTATION if convention == "urdf" else ())]
        label = names.index("name") if "name" in names else None
        number = 0
        for cells in reader:
            if not cells:  # a blank line is no row
                continue
            number += 1
            row = _plain_row(number, cells, at, turn, label)
            rows.append(row or _parse_row(number, dict(zip(names, cells)), fields, convention))
            if len(rows) == size:
                yield _convert(rows, convention)
                rows, seen = [], True
    except csv.Error as exc:
        raise InputError(f"{path}:{reader.line_num}: not usable CSV: {exc}") from None
    if not rows and not seen:
        raise InputError(f"{path}: no data rows")
    if rows:
        yield _convert(rows, convention)


def _plain_row(number, cells, at, turn, label):
    """The row of :func:`_parse_row` for the common case (every field a finite number, the orientation blank or a
    finite number) without building a record; None for any other row (then :func:`_parse_row` says what is wrong)."""
    try:
        texts = [cells[j].strip() for j in at]
        values = [float(t) for t in texts]
        angles = [cells[j] if j is not None and j < len(cells) else "" for j in turn]
        values += [float(t) if t.strip() else 0.0 for t in angles]
    except (IndexError, ValueError):
        return None
    if not all(map(math.isfinite, values)) or not all(texts):
        return None
    name = cells[label] if label is not None and label < len(cells) else ""
    if turn:
        texts = [texts[0], "0", "0", "0", *texts[4:10]]
    return Row(number, name, values=values, written=tuple(texts))
