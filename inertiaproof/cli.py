"""The ``inertiaproof`` command.

Exit status: 0 nothing VIOLATED (or all rows consistent), 1 something
VIOLATED (or a check crashed, or a row is not consistent), 2 bad usage or
bad input, with a one-line message naming the problem.

Subcommands that live elsewhere (gate, report, audit) are plug-ins: a module
with ``configure(parser)`` and ``main(args) -> int``.
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import json
import sys
from pathlib import Path

from .errors import InputError

PLUGINS = {
    "gate": ("inertiaproof.symbolic.gate", "fingerprint derivations and compare with the lockfile"),
    "report": ("inertiaproof.report.cli", "write report.html, report.tex (and report.pdf) from a results folder"),
    "audit": ("inertiaproof.audit", "audit URDF robots for physical consistency and mass-matrix bounds"),
}


def _run(args):
    from . import runner
    from .scene import load_scene

    scene = load_scene(args.scene) if args.scene else None
    out = Path(args.out)
    say = runner.progress_printer() if not args.quiet else None
    if scene is not None and say:
        say(f"scene {scene.source}: {scene.description or scene.name}; it has: {', '.join(sorted(scene.features()))}")
    run = runner.run_checks(profile=args.profile, seed=args.seed, only=args.only, scene=scene, symbolic=args.symbolic,
                            out_dir=out, counterexample_dir=Path(args.counterexamples), progress=say)
    doc = runner.results_document(run, profile=args.profile, seed=args.seed, scene=args.scene)
    path = runner.write_results(out / "results.json", doc)
    print(runner.format_table(run))
    print(f"results: {path}")
    if args.junit:
        print(f"junit: {runner.write_junit(args.junit, run)}")
    if args.report:
        from .report.cli import build

        for written in build(out, only=("report",)):
            print(f"report: {written}")
    crashed = any(r.evidence.get("crashed") for r in run.results)
    return 1 if run.violated or crashed else 0


def _inertia(args):
    import numpy as np

    from .consistency import CONSISTENT, LABELS, physical_consistency
    from .rows import read_rows

    rows = read_rows(args.file)
    good = [r for r in rows if r.error is None]
    verdicts = physical_consistency(np.array([r.decided_on for r in good])) if good else None
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
    if any(r.error for r in rows):
        return 2
    return 0 if all(v == LABELS[CONSISTENT] for v in verdicts.labels) else 1


def _replay(args):
    from .replay import replay

    result = replay(args.file)
    print(f"{result.id}: {result.verdict}: {result.summary}")
    if args.json:
        print(json.dumps(result.to_json(), indent=1))
    return 1 if str(result.verdict) == "VIOLATED" else 0


def _list(args):
    from .registry import load_checks
    from .runner import select

    from .scene import load_scene

    scene = load_scene(args.scene) if args.scene else None
    run, skipped = select(load_checks(), scene=scene, symbolic=args.symbolic)
    for spec in run:
        needs = ", ".join(sorted(spec.needs)) or "paper-level"
        print(f"{spec.name:<18} [{needs}] {spec.entry.statement}")
    for name, reason in skipped:
        print(f"{name:<18} left out: {reason}")
    return 0


def parser():
    from .registry import PROFILES

    p = argparse.ArgumentParser(prog="inertiaproof", description="Proof-check 'On robotic manipulators with "
                                "time-dependent inertial parameters' (Kaufmann & Reger).")
    sub = p.add_subparsers(dest="command", required=True)

    r = sub.add_parser("run", help="run the proof-check suite")
    r.add_argument("--profile", choices=sorted(PROFILES), default="ci")
    r.add_argument("--only", nargs="+", metavar="ID", help="catalog IDs (or check names) to run")
    r.add_argument("--scene", metavar="FILE", help="check one scene (TOML): only the checks it needs")
    r.add_argument("--symbolic", action="store_true", help="with --scene: also derive its equations symbolically")
    r.add_argument("--seed", type=int, default=0)
    r.add_argument("--out", default="out", metavar="DIR", help="where results.json and data files go (default: out)")
    r.add_argument("--junit", metavar="FILE", help="also write JUnit XML")
    r.add_argument("--report", action="store_true", help="also write the HTML/LaTeX report into --out")
    r.add_argument("--counterexamples", default="counterexamples/found", metavar="DIR",
                   help="where counterexamples are saved (default: counterexamples/found)")
    r.add_argument("--quiet", action="store_true", help="no progress lines on stderr")
    r.set_defaults(func=_run)

    i = sub.add_parser("inertia", help="classify rows of inertial parameters (CSV or JSON)")
    i.add_argument("file")
    i.add_argument("--json", action="store_true")
    i.set_defaults(func=_inertia)

    rp = sub.add_parser("replay", help="re-run a saved counterexample")
    rp.add_argument("file")
    rp.add_argument("--json", action="store_true")
    rp.set_defaults(func=_replay)

    ls = sub.add_parser("list", help="list the checks (and, with --scene, which ones that scene needs)")
    ls.add_argument("--scene", metavar="FILE")
    ls.add_argument("--symbolic", action="store_true")
    ls.set_defaults(func=_list)

    for name, (module, help_text) in PLUGINS.items():
        if importlib.util.find_spec(module.rsplit(".", 1)[0]) is None:
            continue
        try:
            spec = importlib.util.find_spec(module)
        except ModuleNotFoundError:
            spec = None
        if spec is None:
            continue
        mod = importlib.import_module(module)
        sp = sub.add_parser(name, help=help_text)
        mod.configure(sp)
        sp.set_defaults(func=mod.main)
    return p


def main(argv=None):
    args = parser().parse_args(argv)
    try:
        return args.func(args)
    except InputError as exc:
        print(f"inertiaproof: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:  # reading or writing a file the user named
        where = f"{exc.filename}: " if exc.filename else ""
        print(f"inertiaproof: error: {where}{exc.strerror or exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("inertiaproof: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
