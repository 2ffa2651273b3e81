import sys

from inertiaproof.cli import main

sys.exit(main())
