"""Which certified numbers of a run cite a certificate:

    python bench/certificate_coverage.py OUT

Walks OUT/results.json for quantities of the certified kinds (lower_bound, upper_bound, certified_constant,
paper_constant) and prints how many cite a certificate, then every one that does not (check: kind: path). An
infinite side (no certified bound: a lower side -inf, an upper side +inf) claims nothing and is not counted.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

CERTIFIED = {"lower_bound", "upper_bound", "certified_constant", "paper_constant"}


def quantities(node, path=()):
    """(path, quantity) of every certified-kind quantity under ``node``."""
    if isinstance(node, dict):
        if node.get("kind") in CERTIFIED and "value" in node:
            yield path, node
        for key, value in node.items():
            yield from quantities(value, path + (str(key),))
    elif isinstance(node, list):
        for i, value in enumerate(node):
            yield from quantities(value, path + (str(i),))


def main(out):
    checks = json.loads((Path(out) / "results.json").read_text())["checks"]
    found = [(r["id"], path, q) for r in checks for path, q in quantities(r["evidence"])
             if q["value"] not in ("inf", "-inf", None)]
    bare = [(rid, path, q) for rid, path, q in found if "certificate" not in q]
    print(f"{len(found) - len(bare)} of {len(found)} certified numbers cite a certificate")
    for rid, path, q in bare:
        print(f"  {rid}: {q['kind']}: {'/'.join(path)}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "OUT")
