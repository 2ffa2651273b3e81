"""``inertiaproof replay FILE``: re-run a saved counterexample."""

from __future__ import annotations

import json

from inertiaproof.suite.replay import replay

from .status import exit_status

__all__ = ["configure", "main"]


def configure(parser):
    parser.add_argument("file")
    parser.add_argument("--json", action="store_true")


def main(args):
    result = replay(args.file)
    print(f"{result.id}: {result.verdict}: {result.summary}")
    if args.json:
        print(json.dumps(result.to_json(), indent=1))
    return exit_status([result])
