"""``inertiaproof run``: run the checks, print the table, write results.json (and JUnit XML, the report)."""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

from inertiaproof.errors import InputError
from inertiaproof.scene.format import load_scene
from inertiaproof.suite import runner
from inertiaproof.suite.execution import executor_for
from inertiaproof.suite.outputs import checked_outputs
from inertiaproof.suite.profiles import PROFILES

from .status import exit_status

__all__ = ["configure", "main"]


def configure(parser):
    parser.add_argument("--profile", choices=sorted(PROFILES), default="ci")
    parser.add_argument("--only", nargs="+", metavar="ID", help="catalog IDs (or check names) to run")
    parser.add_argument("--scene", metavar="FILE", help="check one scene (TOML): only the checks it needs")
    parser.add_argument("--symbolic", action="store_true", help="with --scene: also derive its equations symbolically")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--budget", type=float, metavar="SECONDS",
                        help=f"seconds one check may run (default: the profile's, {PROFILES['ci'].check_s:g} in "
                             "ci); then it ends INCONCLUSIVE")
    parser.add_argument("--out", default="out", metavar="DIR", help="where results.json and data files go (default: out)")
    parser.add_argument("--junit", metavar="FILE", help="also write JUnit XML")
    parser.add_argument("--report", action="store_true", help="also write the HTML/LaTeX report into --out")
    parser.add_argument("--counterexamples", default="counterexamples/found", metavar="DIR",
                        help="where counterexamples are saved (default: counterexamples/found)")
    parser.add_argument("--quiet", action="store_true", help="no progress lines on stderr")
    parser.add_argument("--no-verify", action="store_true", help="write the certificates (OUT/certificates) but do "
                        "not re-prove them with the independent checker")
    parser.add_argument("--workers", type=int, metavar="N",
                        help="processes computing at once: 1 runs everything in this process; N > 1 runs the checks "
                             "side by side in N forked processes and their split work (hunt shards, certificates) in "
                             "forked processes, never more than N computing; default: the number of cores. The answers "
                             "do not depend on N (apart from timings)")
    parser.add_argument("--scheduler", metavar="ADDRESS",
                        help="run the splittable work on an existing Dask cluster (e.g. tcp://host:8786 of 'dask "
                             "scheduler'; needs inertiaproof[distributed]), the checks one after the other here")


def main(args):
    scene = load_scene(args.scene) if args.scene else None
    out = Path(args.out)
    say = runner.progress_printer() if not args.quiet else None
    if scene is not None and say:
        say(f"scene {scene.source}: {scene.description or scene.name}; it has: {', '.join(sorted(scene.features()))}")
    profile = PROFILES[args.profile]
    if args.budget is not None:
        if not 0 < args.budget < float("inf"):
            raise InputError(f"--budget must be a positive number of seconds, got {args.budget:g}")
        profile = dataclasses.replace(profile, check_s=args.budget)
    found = checked_outputs(out, args.junit, args.counterexamples, lambda message: print(message, file=sys.stderr))
    with executor_for(args.workers, args.scheduler, say=say) as executor:
        run = runner.run_checks(profile=profile, seed=args.seed, only=args.only, scene=scene, symbolic=args.symbolic,
                                out_dir=out, counterexample_dir=found, progress=say, executor=executor,
                                verify=not args.no_verify)
        runner.write_execution_log(out / "execution.json", executor)
    doc = runner.results_document(run, profile=args.profile, seed=args.seed, scene=args.scene)
    path = runner.write_results(out / "results.json", doc)
    print(runner.format_table(run))
    print(f"results: {path}")
    print(runner.certificate_line(run))
    if args.junit:
        print(f"junit: {runner.write_junit(args.junit, run)}")
    if args.report:
        from inertiaproof.report.cli import build

        for written in build(out, only=("report",)):
            print(f"report: {written}")
    return exit_status(run.results)
