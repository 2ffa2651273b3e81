"""``inertiaproof inertia FILE``: classify rows of inertial parameters (Definition 1, Theorem 1)."""

from __future__ import annotations

import json
import sys

import numpy as np

from inertiaproof.model.consistency import CONSISTENT, LABELS, physical_consistency
from inertiaproof.model.rows import read_rows

__all__ = ["configure", "main"]


def configure(parser):
    parser.add_argument("file")
    parser.add_argument("--json", action="store_true")


def main(args):
    rows = read_rows(args.file)
    good = [r for r in rows if r.error is None]
    verdicts = physical_consistency(np.array([r.decided_on for r in good]),
                                    written=[r.written for r in good]) if good else None
    by_number = dict(zip((r.number for r in good), verdicts.rows() if good else ()))
    out = []
    for r in rows:
        entry = {"row": r.number, "name": r.name}
        entry.update(by_number[r.number] if r.error is None else {"verdict": "error", "reason": r.error})
        out.append(entry)
    if args.json:
        print(json.dumps(out, indent=1))
    else:
        width = max([len(e["name"]) for e in out] + [4])
        print(f"{'row':>4}  {'name':<{width}}  {'verdict':<12}  reason")
        for e in out:
            print(f"{e['row']:>4}  {e['name']:<{width}}  {e['verdict']:<12}  {e['reason']}")
    bad = [r for r in rows if r.error]
    if bad:
        more = f" (and {len(bad) - 1} more rows)" if len(bad) > 1 else ""
        print(f"inertiaproof: error: {args.file}: row {bad[0].number}: {bad[0].error}{more}", file=sys.stderr)
        return 2
    return 0 if all(v == LABELS[CONSISTENT] for v in verdicts.labels) else 1
