"""``inertiaproof inertia FILE``: classify rows of inertial parameters (Definition 1, Theorem 1)."""

from __future__ import annotations

import json
import sys

import numpy as np

from inertiaproof.model.consistency import CONSISTENT, LABELS, physical_consistency
from inertiaproof.model.rows import row_chunks

__all__ = ["configure", "main"]


def configure(parser):
    parser.add_argument("file")
    parser.add_argument("--json", action="store_true")


def classified(chunk):
    """One entry per row of a chunk: row, name and verdict with its reason (or the row's error)."""
    good = [r for r in chunk if r.error is None]
    verdicts = physical_consistency(np.array([r.decided_on for r in good]),
                                    written=[r.written for r in good]).rows() if good else iter(())
    for r in chunk:
        entry = {"row": r.number, "name": r.name}
        entry.update(next(verdicts) if r.error is None else {"verdict": "error", "reason": r.error})
        yield entry


def main(args):
    """Rows are read, classified and printed a chunk at a time (memory flat in the file's length); the text
    table's name column is as wide as the first chunk's names."""
    first_error, errors, all_consistent, width = None, 0, True, None
    out = sys.stdout
    for index, chunk in enumerate(row_chunks(args.file)):
        entries = list(classified(chunk))
        if args.json:
            out.write(("[\n" if index == 0 else ",\n") + ",\n".join(json.dumps(e, indent=1) for e in entries))
        else:
            if width is None:
                width = max([len(e["name"]) for e in entries] + [4])
                out.write(f"{'row':>4}  {'name':<{width}}  {'verdict':<12}  reason\n")
            out.write("".join(f"{e['row']:>4}  {e['name']:<{width}}  {e['verdict']:<12}  {e['reason']}\n"
                              for e in entries))
        for e in entries:
            if e["verdict"] == "error":
                errors += 1
                first_error = first_error or e
            elif e["verdict"] != LABELS[CONSISTENT]:
                all_consistent = False
    if args.json:
        out.write("\n]\n")
    if first_error:
        more = f" (and {errors - 1} more rows)" if errors > 1 else ""
        print(f"inertiaproof: error: {args.file}: row {first_error['row']}: {first_error['reason']}{more}",
              file=sys.stderr)
        return 2
    return 0 if all_consistent else 1
