"""What a check writes next to results.json: data files and replayable counterexamples."""

from __future__ import annotations

import hashlib
import json
import os
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from inertiaproof.errors import InputError
from inertiaproof.result import Result

__all__ = ["checked_outputs", "COUNTEREXAMPLE_SCHEMA", "journal_path", "Outputs", "unwritable"]

COUNTEREXAMPLE_SCHEMA = "inertiaproof.counterexample/1"


def journal_path(out_dir):
    """Where the violations found by tasks are journaled as they arrive (see :meth:`Outputs.journal`)."""
    return Path(out_dir) / "data" / "arrived-counterexamples.jsonl"


@dataclass
class Outputs:
    out_dir: Path | None = None
    counterexample_dir: Path = Path("counterexamples/found")
    artifacts: list = field(default_factory=list)  # names of the data files written, relative to out_dir

    def write_data(self, name, obj):
        """Write a JSON data file next to results.json; returns its name (or None without an output folder)."""
        if self.out_dir is None:
            return None
        path = Path(self.out_dir) / "data" / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(obj, indent=1, sort_keys=True))
        rel = str(path.relative_to(self.out_dir))
        self.artifacts.append(rel)
        return rel

    def journal(self, record):
        """Append one line (JSON; objects by their repr) to ``OUT/data/arrived-counterexamples.jsonl`` at once, flushed
        to disk: a violation found by a task is on disk before the run goes on. Nothing without an output folder."""
        if self.out_dir is None:
            return None
        path = journal_path(self.out_dir)
        path.parent.mkdir(parents=True, exist_ok=True)
        with path.open("a") as f:
            f.write(json.dumps(record, sort_keys=True, default=repr) + "\n")
            f.flush()
            os.fsync(f.fileno())
        return path

    def save_counterexample(self, result: Result, *, profile, seed):
        """Write the result's counterexample as a replayable JSON file; returns the path. Where the counterexample
        folder cannot be written, it goes beside results.json (``out_dir/counterexamples``) instead."""
        if not result.counterexample:
            return None
        body = {"schema": COUNTEREXAMPLE_SCHEMA, "id": result.id, "summary": result.summary, "profile": profile,
                "seed": seed, **result.counterexample}
        text = json.dumps(body, indent=1, sort_keys=True)
        name = f"{result.id.replace('/', '_')}-{hashlib.sha256(text.encode()).hexdigest()[:10]}.json"
        folders = [self.counterexample_dir] + ([Path(self.out_dir) / "counterexamples"] if self.out_dir else [])
        for folder in folders:
            try:
                folder.mkdir(parents=True, exist_ok=True)
                (folder / name).write_text(text)
                return folder / name
            except OSError as exc:
                problem = exc
        raise problem


def unwritable(folder):
    """Why files cannot be written into ``folder`` (made if missing), or None if they can."""
    folder = Path(folder)
    try:
        folder.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=folder):
            pass
    except OSError as exc:
        return exc.strerror or str(exc)
    return None


def checked_outputs(out_dir, junit, counterexample_dir, say):
    """Check before any work that the run can write its results; returns the counterexample folder to use (beside
    results.json when the one asked for cannot be written, which ``say`` reports)."""
    problem = unwritable(out_dir)
    if problem:
        raise InputError(f"{out_dir}: cannot write results there: {problem}")
    if junit is not None:
        junit = Path(junit)
        problem = "it is a folder" if junit.is_dir() else unwritable(junit.parent)
        if problem:
            raise InputError(f"{junit}: cannot write JUnit XML there: {problem}")
    problem = unwritable(counterexample_dir)
    if problem is None:
        return Path(counterexample_dir)
    fallback = Path(out_dir) / "counterexamples"
    say(f"inertiaproof: warning: {counterexample_dir}: cannot write counterexamples there ({problem}); they go to "
        f"{fallback}")
    return fallback
