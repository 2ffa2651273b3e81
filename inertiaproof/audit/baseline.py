"""``--baseline FILE``: the findings of an audit against those of an earlier one (SARIF or JSON) of the same files.

A finding is identified by its rule, the audited file and its subject (``link NAME``, ``body NAME``, ``chain
NAME``, ``model`` for the total mass, ``file`` for an unreadable one; :func:`.annotations.keyed_findings`), not by
its line, which moves when the file is edited. Each finding of this run gets a state (SARIF 2.1.0 §3.27.24
``baselineState``): ``unchanged`` (the baseline has it with the same level and message, positions left aside),
``updated`` (the baseline has it, with another level or message: the link was edited and is still at fault),
``new`` (not in the baseline); and each finding of the baseline that this run does not have is ``absent``.
Files are matched by their resolved path (a SARIF URI relative to the working folder, or the ``file:`` URI
``--sarif`` writes for files outside it; a JSON document's paths relative to the working folder), and else by
their file name when it is unique in both runs (the same repository checked out elsewhere).
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from urllib.parse import unquote, urlparse

from inertiaproof.errors import InputError

__all__ = ["COUNTED", "compare", "file_key", "normalised", "read_baseline", "STATES"]

STATES = ("new", "updated", "unchanged", "absent")
COUNTED = ("new", "updated")  # the states the exit status counts (findings of level error)
AUDIT_SCHEMA = "inertiaproof.audit/1"
_EXPANDED = re.compile(r"\s*\(line \d+ of the text .* expands the file to\)$")
_POSITION = re.compile(r"\b(line|column) \d+")


def file_key(path):
    """The resolved path of an audited file or of a SARIF artifact URI, as a string."""
    text = str(path)
    if text.startswith("file:"):
        text = unquote(urlparse(text).path)
    try:
        return str(Path(text).resolve())
    except (OSError, RuntimeError, ValueError):
        return text


def normalised(message):
    """A finding's message without its positions (lines and columns move when the file is edited)."""
    return _POSITION.sub(r"\1 ?", _EXPANDED.sub("", message or ""))


_SUBJECT = re.compile(r"^(link|body) '([^']*)'|^chain (\S+):")


def _subject_of(result):
    """A SARIF result's subject: its ``properties.subject`` (written by this audit), else read off its message."""
    props = result.get("properties") or {}
    if isinstance(props.get("subject"), str):
        return props["subject"]
    if result.get("ruleId") == "unreadable":
        return "file"
    if result.get("ruleId") == "total-mass-mismatch":
        return "model"
    m = _SUBJECT.match((result.get("message") or {}).get("text", ""))
    if m is None:
        return None
    return f"{m.group(1)} {m.group(2)}" if m.group(1) else f"chain {m.group(3)}"


def read_baseline(path):
    """The findings of an earlier audit: ``{"path", "format": "sarif" | "json", "findings": [{"rule", "file",
    "subject", "level", "message", "result"}]}`` (``result``: the SARIF result as written, for ``absent``).

    One-line :class:`InputError` when the file cannot be read or is not an audit's SARIF or JSON output."""
    try:
        text = Path(path).read_text(encoding="utf-8")
    except OSError as exc:
        raise InputError(f"--baseline {path}: cannot read: {exc.strerror or exc}") from None
    except UnicodeDecodeError:
        raise InputError(f"--baseline {path}: not UTF-8 text: not a SARIF or JSON audit output") from None
    try:
        data = json.loads(text)
    except ValueError as exc:
        raise InputError(f"--baseline {path}: not JSON ({exc.msg} at line {exc.lineno}): not a SARIF or JSON "
                         "audit output") from None
    try:
        if isinstance(data, dict) and data.get("version") == "2.1.0" and isinstance(data.get("runs"), list):
            found = _from_sarif(data)
            kind = "sarif"
        elif isinstance(data, dict) and data.get("schema") == AUDIT_SCHEMA and isinstance(data.get("files"), dict):
            found = _from_json(data)
            kind = "json"
        else:
            raise ValueError
    except (KeyError, TypeError, ValueError, AttributeError, IndexError):
        raise InputError(f"--baseline {path}: not the SARIF or JSON output of inertiaproof audit") from None
    return {"path": str(path), "format": kind, "findings": found}


def _from_sarif(log):
    out = []
    for run in log["runs"]:
        if run["tool"]["driver"]["name"] != "inertiaproof":
            raise ValueError("another tool's SARIF")
        for result in run.get("results", ()):
            if result.get("baselineState") == "absent":  # a finding of that run's own baseline, not of that run
                continue
            props = result.get("properties") or {}
            uri = props.get("file") or result["locations"][0]["physicalLocation"]["artifactLocation"]["uri"]
            out.append({"rule": result["ruleId"], "file": file_key(uri), "subject": _subject_of(result),
                        "level": result.get("level", "warning"), "message": result["message"]["text"],
                        "result": result})
    return out


def _from_json(doc):
    if isinstance(doc.get("findings"), list):
        listed = doc["findings"]
    else:  # a document written before the findings were listed: derive them as this version does
        from .annotations import keyed_findings  # noqa: PLC0415

        listed = [{"rule": rule, "level": level, "file": path, "location": where, "message": message,
                   "subject": subject} for rule, level, path, where, message, _, subject in keyed_findings(doc)]
    return [{"rule": f["rule"], "file": file_key(f["file"]), "subject": f["subject"], "level": f["level"],
             "message": f["message"], "result": None, "location": f.get("location")}
            for f in listed if f.get("baseline_state") != "absent"]


def _map_files(current_files, baseline_files):
    """baseline file key -> current file key: the same resolved path, else the same file name when it is unique
    on both sides and the baseline's path is none of this run's."""
    current = set(current_files)
    names = {}
    for key in current:
        names.setdefault(Path(key).name, []).append(key)
    baseline_names = {}
    for key in set(baseline_files):
        baseline_names.setdefault(Path(key).name, []).append(key)
    out = {}
    for key in set(baseline_files):
        if key in current:
            out[key] = key
        else:
            name = Path(key).name
            if len(names.get(name, ())) == 1 and len(baseline_names[name]) == 1:
                out[key] = names[name][0]
            else:
                out[key] = key
    return out


def compare(current, baseline):
    """The state of each of this run's ``current`` findings (dicts with ``rule``, ``file``, ``subject``,
    ``level``, ``message``) against the ``baseline`` ones (:func:`read_baseline`), and the baseline's findings
    this run does not have: ``(states, absent)``; ``states[k]`` is the state of ``current[k]``.

    Pairs are made first among findings equal in level and message (``unchanged``), then by rule, file and subject
    alone (``updated``); a key found several times pairs in order."""
    mapping = _map_files([file_key(c["file"]) for c in current], [b["file"] for b in baseline])
    pool = {}
    for b in baseline:
        pool.setdefault((b["rule"], mapping[b["file"]], b["subject"]), []).append(b)
    keys = [(c["rule"], file_key(c["file"]), c["subject"]) for c in current]
    states = [None] * len(current)
    for k, (c, key) in enumerate(zip(current, keys)):
        same = [b for b in pool.get(key, ()) if b["level"] == c["level"]
                and normalised(b["message"]) == normalised(c["message"])]
        if same:
            pool[key].remove(same[0])
            states[k] = "unchanged"
    for k, key in enumerate(keys):
        if states[k] is None:
            states[k] = "updated" if pool.get(key) else "new"
            if pool.get(key):
                pool[key].pop(0)
    absent = [b for left in pool.values() for b in left]
    return states, absent
