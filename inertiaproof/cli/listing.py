"""``inertiaproof list``: the checks, what each needs from a scene, and what a scene leaves out."""

from __future__ import annotations

from inertiaproof.scene.format import load_scene
from inertiaproof.suite.runner import load_checks, select

__all__ = ["configure", "main"]


def configure(parser):
    parser.add_argument("--scene", metavar="FILE")
    parser.add_argument("--symbolic", action="store_true")


def main(args):
    scene = load_scene(args.scene) if args.scene else None
    run, skipped = select(load_checks(), scene=scene, symbolic=args.symbolic)
    for spec in run:
        needs = ", ".join(sorted(spec.needs)) or "paper-level"
        print(f"{spec.name:<18} [{needs}] {spec.entry.statement}")
    for name, reason in skipped:
        print(f"{name:<18} left out: {reason}")
    return 0
