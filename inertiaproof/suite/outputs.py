"""What a check writes next to results.json: data files and replayable counterexamples."""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass, field
from pathlib import Path

from inertiaproof.result import Result

__all__ = ["COUNTEREXAMPLE_SCHEMA", "Outputs"]

COUNTEREXAMPLE_SCHEMA = "inertiaproof.counterexample/1"


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

    def save_counterexample(self, result: Result, *, profile, seed):
        """Write the result's counterexample as a replayable JSON file; returns the path."""
        if not result.counterexample:
            return None
        self.counterexample_dir.mkdir(parents=True, exist_ok=True)
        body = {"schema": COUNTEREXAMPLE_SCHEMA, "id": result.id, "summary": result.summary, "profile": profile,
                "seed": seed, **result.counterexample}
        text = json.dumps(body, indent=1, sort_keys=True)
        digest = hashlib.sha256(text.encode()).hexdigest()[:10]
        path = self.counterexample_dir / f"{result.id.replace('/', '_')}-{digest}.json"
        path.write_text(text)
        return path
