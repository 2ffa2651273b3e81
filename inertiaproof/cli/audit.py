"""``inertiaproof audit ROBOT.urdf|DIR ...``: the audit of robot descriptions, printed, as JSON or as a report.

Exit status: 0 every moving link and every body is consistent; 1 some is not;
2 some input could not be read (the others are still audited).
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np

from inertiaproof.audit.document import BOUNDS_MODES, audit_paths, document
from inertiaproof.audit.repair import DEFAULT_SLACK
from inertiaproof.audit.text import format_audit
from inertiaproof.budget import Budget, enforced
from inertiaproof.errors import InputError
from inertiaproof.suite.environment import versions
from inertiaproof.suite.profiles import PROFILES

__all__ = ["configure", "main", "write_report"]


def configure(parser):
    parser.add_argument("paths", nargs="+", metavar="URDF_OR_DIR", help="URDF files, or folders searched for *.urdf")
    parser.add_argument("--json", action="store_true", help="print the audit as JSON instead of tables")
    parser.add_argument("--report", metavar="DIR", help="also write DIR/audit.json and its report: audit.html, "
                        "audit.tex (and audit.pdf when latexmk is installed)")
    parser.add_argument("--profile", choices=sorted(PROFILES), default="ci")
    parser.add_argument("--bounds", choices=BOUNDS_MODES, default="arms",
                        help="which chains get M(q) bounds: serial arms (default), all, none")
    parser.add_argument("--floating-base", action="store_true",
                        help="the root moves (legged robots, humanoids): judge its links too")
    parser.add_argument("--repair-slack", type=float, default=DEFAULT_SLACK, metavar="EPS",
                        help="relative triangle slack the repaired inertia keeps (default %(default)g)")
    parser.add_argument("--seed", type=int, default=0)


def main(args):
    if args.seed < 0:
        raise InputError(f"--seed must be a nonnegative integer, got {args.seed}")
    if not 0 < args.repair_slack < 1:
        raise InputError(f"--repair-slack must lie in (0, 1), got {args.repair_slack}")
    profile = PROFILES[args.profile]
    start = time.perf_counter()
    options = dict(samples=profile.audit_samples, refine_s=profile.audit_refine_s, bounds=args.bounds,
                   floating_base=args.floating_base, slack=args.repair_slack, seed=args.seed)
    memory = Budget(memory_bytes=profile.memory_mb * 2**20)
    with np.errstate(all="ignore"), enforced(memory, grace=0.0):  # overflow inside margins falls back to LAPACK
        files = audit_paths(args.paths, **options)
    doc = document(files, profile=args.profile, seed=args.seed, bounds=args.bounds, floating_base=args.floating_base,
                   slack=args.repair_slack, runtime_s=time.perf_counter() - start, versions=versions("yourdfpy"))
    for path, f in files.items():
        if f["status"] == "error":
            print(f"inertiaproof: error: {f['error']}", file=sys.stderr)
        for warning in f.get("warnings", ()):
            print(f"inertiaproof: warning: {path}: {warning}", file=sys.stderr)
    if args.json:
        print(json.dumps(doc, allow_nan=False))
    else:
        print(format_audit(doc))
    if args.report:
        say = sys.stderr if args.json else sys.stdout
        for path in write_report(doc, Path(args.report)):
            print(f"report: {path}", file=say)
    return doc["summary"]["exit_status"]


def write_report(doc, out_dir):
    """DIR/audit.json and the report made from it; returns the written paths."""
    from inertiaproof.report.cli import build

    try:
        out_dir.mkdir(parents=True, exist_ok=True)
        path = out_dir / "audit.json"
        path.write_text(json.dumps(doc, allow_nan=False), encoding="utf-8")
    except OSError as exc:
        raise InputError(f"{exc.filename or out_dir}: cannot write: {exc.strerror}") from None
    return [path, *build(out_dir, only=("audit",))]
