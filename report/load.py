"""Read DIR/results.json and the data files next to it, or DIR/audit.json, with one-line errors naming the file."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

from inertiaproof.errors import InputError

__all__ = [
    "AUDIT", "audit", "AUDIT_SCHEMA", "CHECKOUT_MUTATION", "data_files", "Each", "FILE", "LINK", "MUTATION",
    "mutation", "MUTATION_SCHEMA", "OPTIONAL", "read_json", "REPAIR", "results", "SCHEMA", "SUMMARY", "TYPE_NAMES",
    "VERDICTS",
]

SCHEMA = "inertiaproof.results/1"
VERDICTS = ("HOLDS", "VIOLATED", "INCONCLUSIVE")
AUDIT = "audit.json"
AUDIT_SCHEMA = "inertiaproof.audit/1"
MUTATION = "mutation.json"
MUTATION_SCHEMA = "inertiaproof.mutation/1"
CHECKOUT_MUTATION = Path(__file__).resolve().parent.parent / "bench" / "results" / MUTATION  # bench/mutation.py's
NARROWING = "bracket_narrowing.json"
CHECKOUT_NARROWING = Path(__file__).resolve().parent.parent / "bench" / "results" / NARROWING  # bench/bracket_narrowing.py's
OPTIONAL = type(None)




@dataclass(frozen=True)
class Each:
    """An object of any keys (file paths, link names), every value of this shape."""

    shape: object


# What the audit's report reads, as shapes: a type (or tuple of types), {key: shape}, [shape] a list, Each(shape).
LINK = {"role": str, "group": str, "moving": bool, "massless_frame": bool, "verdict": str, "reason": str,
        "signs": [{"text": str}], "repair": (dict, OPTIONAL)}
REPAIR = {"note": str, "inertia": (dict, OPTIONAL)}
FILE = {"robot": str, "consistent": bool, "not_consistent": [str], "serial_arm": bool, "links": Each(LINK),
        "bodies": Each({"joint": (str, OPTIONAL), "links": [str], "verdict": str, "reason": str}),
        "chains": Each({"name": str, "kinds": str, "joints": [str], "bodies_consistent": bool,
                        "bounds": (dict, OPTIONAL), "singular": {"verdict": str, "argument": str}}),
        "left_out_joints": [{"joint": str, "type": str, "reason": str}], "mimic_joints": [{"joint": str, "mimics": str}]}
SUMMARY = {"files": int, "files_consistent": int, "files_not_consistent": int, "unreadable": int,
           "links": Each(int), "moving_not_consistent": int, "signs": Each(int)}
TYPE_NAMES = {dict: "an object", list: "a list", str: "a string", int: "an integer", float: "a number",
              bool: "true or false", OPTIONAL: "null"}


def results(out_dir):
    """The results document of out_dir, checked well enough that the report cannot trip over it."""
    out = Path(out_dir)
    path = out / "results.json"
    if not out.is_dir():
        raise InputError(f"{out}: no such folder (make one with 'inertiaproof run --out {out}')")
    if not path.is_file():
        raise InputError(f"{path}: not found (make it with 'inertiaproof run --out {out}', or audit robots with "
                         f"'inertiaproof audit URDF --report {out}')")
    doc = read_json(path)
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


def audit(path):
    """The audit document at path (DIR/audit.json), checked well enough that the report cannot trip over it."""
    path = Path(path)
    doc = read_json(path)
    if not isinstance(doc, dict) or doc.get("schema") != AUDIT_SCHEMA:
        raise InputError(f"{path}: not an inertiaproof audit file (schema {AUDIT_SCHEMA})")
    _check(doc, {"files": Each(dict), "summary": SUMMARY}, path, "")
    _check(doc.get("versions", {}), dict, path, "versions")
    for name, f in doc["files"].items():
        where = f"files[{name!r}]"
        if f.get("status") not in ("ok", "error"):
            raise InputError(f"{path}: {where}.status: must be 'ok' or 'error'")
        _check(f, FILE if f["status"] == "ok" else {"error": str}, path, where)
        for link, entry in f["links"].items() if f["status"] == "ok" else ():
            if entry["repair"] is not None:
                _check(entry["repair"], REPAIR, path, f"{where}.links[{link!r}].repair")
    return doc


def _check(x, shape, path, where):
    """Raise a one-line error naming the file and the place where x departs from shape."""
    if isinstance(shape, Each):
        _check(x, dict, path, where)
        for key, value in x.items():
            _check(value, shape.shape, path, f"{where}[{key!r}]")
    elif isinstance(shape, dict):
        _check(x, dict, path, where)
        for key, inner in shape.items():
            if key not in x:
                raise InputError(f"{path}: {where or 'the top level'}: no '{key}'")
            _check(x[key], inner, path, f"{where}.{key}" if where else key)
    elif isinstance(shape, list):
        _check(x, list, path, where)
        for i, item in enumerate(x):
            _check(item, shape[0], path, f"{where}[{i}]")
    else:
        kinds = shape if isinstance(shape, tuple) else (shape,)
        if not isinstance(x, kinds) or (isinstance(x, bool) and bool not in kinds):
            raise InputError(f"{path}: {where or 'the top level'}: must be {' or '.join(TYPE_NAMES[k] for k in kinds)}")


def data_files(out_dir, doc):
    """{artifact name: rows (a list of dicts) or a one-line problem (str)} for every artifact the results name."""
    out = Path(out_dir)
    names = sorted({a for r in doc["checks"] for a in r.get("artifacts") or [] if isinstance(a, str)})
    return {name: _rows(out / name, name) for name in names}


def mutation(out_dir, fallback=CHECKOUT_MUTATION):
    """(path, the mutation table of bench/mutation.py) from DIR/mutation.json, else from ``fallback`` (a source
    checkout's bench/results/mutation.json); (path, a one-line problem) for a file that is not one; None without."""
    for path in (Path(out_dir) / MUTATION, Path(fallback)):
        if not path.is_file():
            continue
        try:
            data = read_json(path)
        except InputError as exc:
            return path, str(exc)
        if not (isinstance(data, dict) and data.get("schema") == MUTATION_SCHEMA and isinstance(data.get("mutants"), list)
                and all(isinstance(m, dict) for m in data["mutants"])):
            return path, f"{path}: not a mutation table (schema {MUTATION_SCHEMA})"
        return path, data
    return None


def bracket_narrowing(out_dir, fallback=CHECKOUT_NARROWING):
    """bench/bracket_narrowing.py's data from DIR/bracket_narrowing.json, else from ``fallback`` (a source checkout's
    bench/results/); None without one or for a file that is not one."""
    for path in (Path(out_dir) / NARROWING, Path(fallback)):
        if not path.is_file():
            continue
        try:
            data = read_json(path)
        except InputError:
            return None
        if isinstance(data, dict) and isinstance(data.get("brackets"), list):
            return data
        return None
    return None


def _rows(path, name):
    if not path.is_file():
        return f"{name}: missing (results.json lists it)"
    try:
        data = read_json(path)
    except InputError as exc:
        return str(exc).replace(str(path), name, 1)
    if isinstance(data, dict) and isinstance(data.get("rows"), list):
        columns = data.get("columns")
        data = data["rows"]
        if isinstance(columns, list) and all(isinstance(row, list) and len(row) == len(columns) for row in data):
            data = [dict(zip(map(str, columns), row)) for row in data]
    if isinstance(data, list) and all(isinstance(row, dict) for row in data):
        return data
    return data if isinstance(data, dict) else f"{name}: not a list of rows"


def read_json(path):
    """The JSON document at path; a file that cannot be read or parsed is an InputError naming it."""
    try:
        return json.loads(Path(path).read_text(encoding="utf-8"))
    except OSError as exc:
        raise InputError(f"{path}: cannot read: {exc.strerror}") from None
    except UnicodeDecodeError:
        raise InputError(f"{path}: not UTF-8 text") from None
    except json.JSONDecodeError as exc:
        raise InputError(f"{path}: not JSON ({exc.msg} at line {exc.lineno}, column {exc.colno})") from None
