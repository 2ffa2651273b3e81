"""The prover's and the checker's seconds side by side, per check of a run's OUT folder: each check's own runtime
and the prover's seconds completing its certificates' trees for the checker (results.json's ``completion_seconds``)
against the seconds the independent checker spent on the certificates it cites, and at the end every certificate
counted once. A check that cites certificates another check proved (its prover reuses them) shows their checking
seconds again.

    python bench/certificate_times.py OUT [RESULT.md]
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from inertiaproof.suite.certificates import cited_entries


def table(out):
    results = json.loads((Path(out) / "results.json").read_text())
    rows = ["| check | prover s | completion s | certificates | checker s |", "|---|---|---|---|---|"]
    seen, prover, grown = {}, 0.0, 0.0
    for check in results["checks"]:
        entries = cited_entries(check)
        files = {e["file"]: e.get("seconds", 0.0) for e in entries}
        completion = sum(e.get("completion_seconds") or 0.0 for e in entries)
        if files:
            prover, grown = prover + check["runtime_s"], grown + completion
            seen.update(files)
            rows.append(f"| {check['id']} | {check['runtime_s']:.1f} | {completion:.1f} | {len(files)} | "
                        f"{sum(files.values()):.1f} |")
    rows.append(f"| all (each certificate once) | {prover:.1f} | {grown:.1f} | {len(seen)} | "
                f"{sum(seen.values()):.1f} |")
    return "\n".join(rows) + "\n"


if __name__ == "__main__":
    text = table(sys.argv[1])
    print(text, end="")
    if len(sys.argv) > 2:
        Path(sys.argv[2]).write_text(text)
