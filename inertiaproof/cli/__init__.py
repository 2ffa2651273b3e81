"""The ``inertiaproof`` command: one module per command, each with ``configure(parser)`` and ``main(args) -> int``.

Exit status (:mod:`.status`, shown by every command's ``--help``): 0 every
check HOLDS (or every row consistent), 1 something VIOLATED (or a check
crashed, or a row is not consistent), 2 bad usage or bad input, with a
one-line message naming the problem, 3 something INCONCLUSIVE and nothing
VIOLATED.

The commands of the top-level folders (``gate`` in ``symbolic``, ``report`` in
``report``) have the same shape. This package is the only part of the core that
hands results to ``inertiaproof.report``.
"""

from __future__ import annotations

import os

for _threads in ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):  # before NumPy loads BLAS: one thread on any machine,
    os.environ.setdefault(_threads, "1")  # so its sums round alike and a run that a count stops stops at the same
    # point (extreme_lengths' Radau reference: t = 0.076 loaded with two threads, 0.077 with one, whatever the limit)

import argparse
import importlib
import sys

__all__ = ["COMMANDS", "main", "parser"]

COMMANDS = {  # name: (module, help)
    "run": ("inertiaproof.cli.run", "run the proof-check suite"),
    "list": ("inertiaproof.cli.listing", "list the checks (and, with --scene, which ones that scene needs)"),
    "replay": ("inertiaproof.cli.replay", "re-run a saved counterexample"),
    "inertia": ("inertiaproof.cli.inertia", "classify rows of inertial parameters (CSV or JSON)"),
    "gate": ("inertiaproof.symbolic.gate", "fingerprint derivations and compare with the lockfile"),
    "report": ("inertiaproof.report.cli", "write report.html, report.tex (and report.pdf) from a results folder"),
    "audit": ("inertiaproof.cli.audit", "audit URDF robots for physical consistency and mass-matrix bounds"),
    "verify": ("inertiaproof.verify.cli", "re-prove certificates with the independent checker"),
    "envelope": ("inertiaproof.cli.envelope", "certified alpha1, alpha2, chi for every payload a link may carry"),
    "adapt": ("inertiaproof.cli.adapt", "adaptive tracking of a scene's reference: time series of errors and spectra"),
    "identify": ("inertiaproof.cli.identify", "identify a robot's (or a payload's) inertial parameters from torques"),
}


def parser(command=None):
    """The command line's parser; only ``command``'s module is imported and configures its arguments (a command
    starts without the others' imports)."""
    from .status import EXIT_STATUS  # noqa: PLC0415 - not for ``verify``, whose process imports only the checker

    p = argparse.ArgumentParser(prog="inertiaproof", description="Proof-check 'On robotic manipulators with "
                                "time-dependent inertial parameters' (Kaufmann & Reger).", epilog=EXIT_STATUS["run"])
    sub = p.add_subparsers(dest="command", required=True)
    for name, (module, help_text) in COMMANDS.items():
        sp = sub.add_parser(name, help=help_text, epilog=EXIT_STATUS.get(name))
        if name == command:
            chosen = importlib.import_module(module)
            chosen.configure(sp)
            sp.set_defaults(func=chosen.main)
    return p


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv[:1] == ["verify"]:  # the independent checker, in a process that imports nothing of the prover
        from inertiaproof.verify.cli import command  # noqa: PLC0415

        return command(argv[1:])
    from inertiaproof.errors import InputError  # noqa: PLC0415

    args = parser(next((a for a in argv if not a.startswith("-")), None)).parse_args(argv)
    try:
        return args.func(args)
    except InputError as exc:
        print(f"inertiaproof: error: {' '.join(str(exc).splitlines())}", file=sys.stderr)
        return 2
    except OSError as exc:  # reading or writing a file the user named
        where = f"{exc.filename}: " if exc.filename else ""
        print(f"inertiaproof: error: {where}{exc.strerror or exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("inertiaproof: interrupted", file=sys.stderr)
        return 130
