"""``python -m dyntorsion``: the command line (see :mod:`dyntorsion.app.cli`)."""

import sys

from .app.cli import main

if __name__ == "__main__":
    sys.exit(main())
