"""``inertiaproof verify PATH ...``: re-prove certificates (files, folders, or a run's OUT folder).

Exit status: 0 every claim re-proved, 1 something refuted, 2 a bad certificate or bad usage, 3 something not
decided and nothing refuted.
"""

from __future__ import annotations

import ast
import hashlib
import json
import re
import sys
import time
from pathlib import Path

from .claims import prove
from .exact import BadCertificate

__all__ = ["check", "configure", "main", "verify_file"]

BUDGET = 2_000_000  # units of work (kinematics.WORK) a certificate may spend on boxes beyond its tree


def configure(parser):
    parser.add_argument("paths", nargs="*", type=Path, help="certificate files, folders of them, or a run's OUT "
                        "folder (its certificates/)")
    parser.add_argument("--budget", type=int, default=BUDGET, help=f"units of work (a joint of the pivot recursion on a box, or an "
                        f"eigen-decomposition) a certificate may spend on boxes beyond its tree (default {BUDGET})")
    parser.add_argument("--json", action="store_true", help="one JSON object per certificate on stdout")
    parser.add_argument("--about", action="store_true", help="what the checker is and its size in lines")


def check(cert, budget=BUDGET):
    """{claim, status, why, boxes, where, seconds} of one certificate (parsed JSON); status "bad certificate" when
    it is malformed (why names the field)."""
    start = time.perf_counter()
    try:
        out = prove(cert, budget).to_json()
        claim = cert["claim"].get("statement", "")
    except (ValueError, TypeError, BadCertificate) as exc:
        claim, out = "", {"status": "bad certificate", "why": str(exc), "boxes": 0, "where": None}
    return {"claim": claim, **out, "seconds": round(time.perf_counter() - start, 4)}


def verify_file(path, budget=BUDGET):
    """:func:`check` of a certificate file, with its name. A file named by 16 hex digits (as a run writes them) must
    hold what they are the SHA-256 of: its canonical JSON (sorted keys), so a number altered in it is a bad
    certificate, not another claim."""
    path = Path(path)
    bad = {"file": str(path), "claim": "", "status": "bad certificate", "boxes": 0, "where": None, "seconds": 0.0}
    try:
        cert = json.loads(path.read_text())
    except (OSError, ValueError) as exc:
        return {**bad, "why": f"cannot be read: {exc}"}
    digest = hashlib.sha256(json.dumps(cert, sort_keys=True).encode()).hexdigest()[:16]
    if re.fullmatch(r"[0-9a-f]{16}", path.stem) and path.stem != digest:
        return {**bad, "why": f"its content is not what its name says (SHA-256 {digest}...): altered"}
    return {"file": str(path), **check(cert, budget)}


def _files(paths):
    for path in paths:
        if path.is_dir():
            folder = path / "certificates" if (path / "certificates").is_dir() else path
            yield from sorted(folder.glob("*.json"))
        else:
            yield path


def code_lines(source):
    """The lines of ``source`` that hold code: not blank, not only a comment, not in a docstring."""
    docs = set()
    for node in ast.walk(ast.parse(source)):
        first = getattr(node, "body", None)
        if isinstance(first, list) and first and isinstance(first[0], ast.Expr) \
                and isinstance(first[0].value, ast.Constant) and isinstance(first[0].value.value, str):
            docs.update(range(first[0].lineno, first[0].end_lineno + 1))
    return sum(1 for i, line in enumerate(source.splitlines(), 1)
               if i not in docs and line.strip() and not line.strip().startswith("#"))


def about():
    here = Path(__file__).parent
    sources = [p.read_text() for p in here.glob("*.py")]
    return (f"inertiaproof's independent checker ({here}): {sum(len(s.splitlines()) for s in sources)} lines of "
            f"Python ({sum(map(code_lines, sources))} of code, the rest docstrings and comments) in {len(sources)} "
            "modules, importing only python-flint and the standard library")


def main(args):
    if args.about:
        print(about())
        return 0
    files = list(_files(args.paths))
    if not files:
        print("inertiaproof verify: no certificate found in " + ", ".join(map(str, args.paths)), file=sys.stderr)
        return 2
    rows = []
    for path in files:
        row = verify_file(path, args.budget)
        rows.append(row)
        if args.json:
            print(json.dumps(row))
        else:
            print(f"{row['status']:>15}  {path.name}: {row['why']} ({row['seconds']:.2f} s)")
    counts = {s: sum(r["status"] == s for r in rows) for s in ("re-proved", "refuted", "not decided", "bad certificate")}
    print(", ".join(f"{n} {s}" for s, n in counts.items()), file=sys.stderr)
    if counts["refuted"]:
        return 1
    if counts["bad certificate"]:
        return 2
    return 3 if counts["not decided"] else 0
