"""The prover's and the checker's seconds side by side, per check of a run's OUT folder: each check's own runtime
(the prover; the completion of its certificates' trees is not in it) against the seconds the independent checker
spent on the certificates it cites, and at the end every certificate counted once.

    python bench/certificate_times.py OUT [RESULT.md]
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from inertiaproof.suite.certificates import cited_entries


def table(out):
    results = json.loads((Path(out) / "results.json").read_text())
    rows, seen, prover = ["| check | prover s | certificates | checker s |", "|---|---|---|---|"], {}, 0.0
    for check in results["checks"]:
        files = {e["file"]: e.get("seconds", 0.0) for e in cited_entries(check)}
        if files:
            prover += check["runtime_s"]
            seen.update(files)
            rows.append(f"| {check['id']} | {check['runtime_s']:.1f} | {len(files)} | {sum(files.values()):.1f} |")
    rows.append(f"| all (each certificate once) | {prover:.1f} | {len(seen)} | {sum(seen.values()):.1f} |")
    return "\n".join(rows) + "\n"


if __name__ == "__main__":
    text = table(sys.argv[1])
    print(text, end="")
    if len(sys.argv) > 2:
        Path(sys.argv[2]).write_text(text)
