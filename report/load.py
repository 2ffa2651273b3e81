"""Read DIR/results.json and the data files next to it, with one-line errors naming the file."""

from __future__ import annotations

import json
from pathlib import Path

from inertiaproof.errors import InputError

SCHEMA = "inertiaproof.results/1"
VERDICTS = ("HOLDS", "VIOLATED", "INCONCLUSIVE")


def results(out_dir):
    """The results document of out_dir, checked well enough that the report cannot trip over it."""
    out = Path(out_dir)
    path = out / "results.json"
    if not out.is_dir():
        raise InputError(f"{out}: no such folder (make one with 'inertiaproof run --out {out}')")
    if not path.is_file():
        raise InputError(f"{path}: not found (make it with 'inertiaproof run --out {out}')")
    doc = _json(path)
    if not isinstance(doc, dict) or doc.get("schema") != SCHEMA:
        raise InputError(f"{path}: not an inertiaproof results file (schema {SCHEMA})")
    checks = doc.get("checks")
    if not isinstance(checks, list):
        raise InputError(f"{path}: 'checks' must be a list of results")
    for i, r in enumerate(checks):
        where = f"{path}: checks[{i}]"
        if not isinstance(r, dict):
            raise InputError(f"{where}: not an object")
        if not isinstance(r.get("id"), str) or not r["id"]:
            raise InputError(f"{where}: no 'id'")
        if r.get("verdict") not in VERDICTS:
            raise InputError(f"{where} ({r['id']}): verdict {r.get('verdict')!r} is not one of {', '.join(VERDICTS)}")
        for key, kind in (("evidence", dict), ("artifacts", list), ("counterexample", dict)):
            if r.get(key) is not None and not isinstance(r[key], kind):
                raise InputError(f"{where} ({r['id']}): '{key}' must be {'an object' if kind is dict else 'a list'}")
    skipped = doc.get("skipped") or []
    if not isinstance(skipped, list) or not all(isinstance(s, dict) for s in skipped):
        raise InputError(f"{path}: 'skipped' must be a list of {{check, reason}}")
    for key in ("versions", "summary"):
        if doc.get(key) is not None and not isinstance(doc[key], dict):
            raise InputError(f"{path}: '{key}' must be an object")
    return doc


def data_files(out_dir, doc):
    """{artifact name: rows (a list of dicts) or a one-line problem (str)} for every artifact the results name."""
    out = Path(out_dir)
    names = sorted({a for r in doc["checks"] for a in r.get("artifacts") or [] if isinstance(a, str)})
    return {name: _rows(out / name, name) for name in names}


def _rows(path, name):
    if not path.is_file():
        return f"{name}: missing (results.json lists it)"
    try:
        data = _json(path)
    except InputError as exc:
        return str(exc).replace(str(path), name, 1)
    if isinstance(data, dict) and isinstance(data.get("rows"), list):
        data = data["rows"]
    if isinstance(data, list) and all(isinstance(row, dict) for row in data):
        return data
    return data if isinstance(data, dict) else f"{name}: not a list of rows"


def _json(path):
    try:
        return json.loads(Path(path).read_text(encoding="utf-8"))
    except OSError as exc:
        raise InputError(f"{path}: cannot read: {exc.strerror}") from None
    except UnicodeDecodeError:
        raise InputError(f"{path}: not UTF-8 text") from None
    except json.JSONDecodeError as exc:
        raise InputError(f"{path}: not JSON ({exc.msg} at line {exc.lineno}, column {exc.colno})") from None
