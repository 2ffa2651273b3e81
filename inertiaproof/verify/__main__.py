"""``python -m inertiaproof.verify PATH ...``: the checker in a process of its own (as ``inertiaproof verify``)."""

import sys

from .cli import command

sys.exit(command(sys.argv[1:]))
