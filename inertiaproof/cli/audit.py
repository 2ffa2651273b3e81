"""``inertiaproof audit ROBOT.urdf|MODEL.xml|DIR ...``: the audit of robot descriptions.

A ``*.xacro`` file is expanded with the ``xacro`` package (``--xacro-arg
NAME:=VALUE``) and audited as the URDF it expands to; its positions are lines
of the expanded text. Printed as tables, or as JSON (``--json``), GitHub Actions annotations
(``--github``) or the unified diff of repaired copies (``--write-repaired``);
also as SARIF 2.1.0 (``--sarif FILE``) and as a report (``--report DIR``).
When stdout carries annotations or a diff, the tables go to stderr.

Exit status: 0 every moving link and every body is consistent, no moving link has a hard finding on the
bodies inside its geometry (``--max-density``) and every total mass is the expected (``--expect-mass``); 1 some
is not or has; with ``--baseline FILE`` 1 only for a new or updated error (one the earlier audit in FILE does not
have as it is now); 2 some input could not be read (the others are still audited), or a bad option value.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np

from inertiaproof.audit.bodies_inside import DENSEST
from inertiaproof.audit.annotations import github_commands, sarif_log
from inertiaproof.audit.baseline import read_baseline
from inertiaproof.audit.document import BOUNDS_MODES, audit_paths, document
from inertiaproof.audit.mesh_files import parse_packages
from inertiaproof.audit.repair import DEFAULT_SLACK
from inertiaproof.audit.rewrite import repaired_copies, unified_diff
from inertiaproof.audit.text import format_audit
from inertiaproof.audit.total_mass import DEFAULT_TOLERANCE, parse_expectations
from inertiaproof.audit.xacro_files import parse_arguments
from inertiaproof.budget import Budget, enforced
from inertiaproof.errors import InputError
from inertiaproof.suite.environment import versions
from inertiaproof.suite.execution import executor_for
from inertiaproof.suite.profiles import PROFILES

QUIET_S = 2.0  # an audit prints its progress (files done, ETA) from this many seconds on: a quick one prints none

__all__ = ["configure", "main", "write_repaired", "write_report"]


def configure(parser):
    parser.add_argument("paths", nargs="+", metavar="URDF_MJCF_OR_DIR",
                        help="URDF, MJCF or SDFormat (*.sdf) files, xacro files (*.xacro, expanded with the xacro "
                             "package), or folders searched for *.urdf, MJCF *.xml and *.sdf")
    shown = parser.add_mutually_exclusive_group()
    shown.add_argument("--json", action="store_true", help="print the audit as JSON instead of tables")
    shown.add_argument("--github", action="store_true",
                       help="print GitHub Actions workflow annotations (::error file=...,line=...::) on stdout")
    shown.add_argument("--write-repaired", metavar="OUT",
                       help="write a copy of each file with every repairable link replaced by its repair (OUT: the "
                            "copy for one file, else a folder) and print the unified diff; the originals are untouched")
    parser.add_argument("--sarif", metavar="FILE", help="also write the findings as SARIF 2.1.0 to FILE")
    parser.add_argument("--report", metavar="DIR", help="also write DIR/audit.json and its report: audit.html, "
                        "audit.tex (and audit.pdf when latexmk is installed)")
    parser.add_argument("--profile", choices=sorted(PROFILES), default="ci")
    parser.add_argument("--bounds", choices=BOUNDS_MODES, default="arms",
                        help="which chains get M(q) bounds: serial arms with a quick budget (default: M(q) certified "
                             "nonsingular, lower sides loose), every chain with the full budget (the pivot ladders: "
                             "certified sides within about 2x), none")
    parser.add_argument("--floating-base", action="store_true",
                        help="the root moves (legged robots, humanoids): judge its links too")
    parser.add_argument("--repair-slack", type=float, default=DEFAULT_SLACK, metavar="EPS",
                        help="relative triangle slack the repaired inertia keeps (default %(default)g)")
    parser.add_argument("--max-density", type=float, default=DENSEST, metavar="KG_M3",
                        help="the densest material a link may be made of, the premise of the findings on the bodies "
                             "inside each link's geometry (default %(default)g kg/m^3, osmium's)")
    parser.add_argument("--package", action="append", default=[], metavar="NAME=DIR",
                        help="the folder of ROS package NAME, for package://NAME/... mesh URIs (repeat for more); "
                             "default: the folder holding a package.xml naming NAME, or named NAME, found upward "
                             "from the URDF's folder and among those folders' subfolders")
    parser.add_argument("--expect-mass", action="append", default=[], metavar="KG|NAME=KG",
                        help="the model's total mass (the sum of its links' masses): KG for every file audited, "
                             "NAME=KG for the file whose path, file name or robot name is NAME (repeat for more); a "
                             "total off by more than --mass-tolerance is a finding counted in the exit status")
    parser.add_argument("--mass-tolerance", type=float, default=DEFAULT_TOLERANCE, metavar="REL",
                        help="relative tolerance of --expect-mass, of the expected mass (default %(default)g)")
    parser.add_argument("--baseline", metavar="FILE",
                        help="an earlier SARIF or JSON output of the audit of the same files: every finding is new, "
                             "updated, unchanged or absent (SARIF baselineState; matched by rule, file and link, not "
                             "by line) and the exit status counts only the new and updated errors")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--xacro-arg", action="append", default=[], metavar="NAME:=VALUE",
                        help="an argument for the xacro files (repeat for more); their positions are in the expanded "
                             "text, as `xacro FILE NAME:=VALUE` prints it")
    parser.add_argument("--workers", type=int, metavar="N",
                        help="audit the files in N forked processes at once; default: the number of cores")
    parser.add_argument("--scheduler", metavar="ADDRESS", help="audit the files on an existing Dask cluster (needs "
                        "inertiaproof[distributed])")


def main(args):
    if args.seed < 0:
        raise InputError(f"--seed must be a nonnegative integer, got {args.seed}")
    if not 0 < args.max_density < float("inf"):
        raise InputError(f"--max-density must be a positive number of kg/m^3, got {args.max_density}")
    if not 0 < args.repair_slack < 1:
        raise InputError(f"--repair-slack must lie in (0, 1), got {args.repair_slack}")
    expected_mass = parse_expectations(args.expect_mass, args.mass_tolerance)
    try:
        packages = parse_packages(args.package)
    except ValueError as exc:
        raise InputError(str(exc)) from None
    baseline = read_baseline(args.baseline) if args.baseline else None
    profile = PROFILES[args.profile]
    start = time.perf_counter()
    samples, rounds = profile.audit_budget(args.bounds)
    options = dict(samples=samples, rounds=rounds, bounds=args.bounds, **profile.audit_chains(args.bounds),
                   floating_base=args.floating_base, slack=args.repair_slack, seed=args.seed,
                   max_density=args.max_density, **({"packages": packages} if packages else {}))
    xacro_args = parse_arguments(args.xacro_arg)
    if xacro_args:
        options["xacro_args"] = xacro_args
    memory = Budget(memory_bytes=profile.memory_mb * 2**20)
    def say(message):  # Dask's address, and on an audit past its first seconds the files done and an ETA
        if args.workers or args.scheduler or time.perf_counter() - start >= QUIET_S:
            print(f"inertiaproof: {message}", file=sys.stderr)

    with np.errstate(all="ignore"), enforced(memory, grace=0.0), \
            executor_for(args.workers, args.scheduler, say=say) as executor:
        executor.say = say
        files = audit_paths(args.paths, executor=executor, **options)  # overflow inside margins falls back to LAPACK
    doc = document(files, profile=args.profile, seed=args.seed, bounds=args.bounds, floating_base=args.floating_base,
                   slack=args.repair_slack, runtime_s=time.perf_counter() - start, versions=versions("yourdfpy", "mujoco"),
                   expected_mass=expected_mass, baseline=baseline)
    for path, f in files.items():
        if f["status"] == "error":
            print(f"inertiaproof: error: {f['error']}", file=sys.stderr)
        for warning in f.get("warnings", ()):
            print(f"inertiaproof: warning: {path}: {warning}", file=sys.stderr)
    if args.sarif:
        _write(Path(args.sarif), json.dumps(sarif_log(doc, version=versions()["inertiaproof"]), indent=1))
    if args.json:
        print(json.dumps(doc, allow_nan=False))
    elif args.github:
        print(format_audit(doc), file=sys.stderr)
        print("\n".join(github_commands(doc)))
    elif args.write_repaired:
        print(format_audit(doc), file=sys.stderr)
        write_repaired(files, args.paths, args.write_repaired)
    else:
        print(format_audit(doc))
    if args.report:
        say = sys.stdout if not (args.json or args.github or args.write_repaired) else sys.stderr
        for path in write_report(doc, Path(args.report)):
            print(f"report: {path}", file=say)
    return doc["summary"]["exit_status"]


def write_repaired(files, paths, out):
    """The repaired copies of ``--write-repaired``, their unified diff on stdout, what stays as written on stderr."""
    try:
        copies = repaired_copies(files, paths, out)
    except ValueError as exc:
        raise InputError(str(exc)) from None
    for path, (target, encoding, old, new, left) in copies.items():
        target.parent.mkdir(parents=True, exist_ok=True)
        _write(target, new, encoding)
        sys.stdout.write(unified_diff(old, new, path, str(target)))
        for name, why in left:
            print(f"inertiaproof: {path}: link {name} left as written: {why}", file=sys.stderr)


def _write(path, text, encoding="utf-8"):
    try:
        path.write_bytes(text.encode(encoding, errors="surrogateescape"))
    except OSError as exc:
        raise InputError(f"{exc.filename or path}: cannot write: {exc.strerror}") from None


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
