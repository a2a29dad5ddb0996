"""``dyntorsion warmup``: compile every kernel of the package ahead, once.

Nothing compiles at import (:mod:`dyntorsion._numba`): a kernel compiles at its first
call and its machine code goes to the disk cache, so only the first run of a new
installation waits.  This command makes that wait up front, for every kernel with a
declared signature (the engine's march, the contact march, the stop tests, the models'
loads), and says how long it took; ``make test`` runs it first.
"""

from __future__ import annotations

import argparse
import time

from .. import _numba

__all__ = ["add_warmup", "warmup"]


def warmup(args: argparse.Namespace) -> int:
    """Compile (or load from the disk cache) every declared kernel; print what it took."""
    start = time.perf_counter()
    count = _numba.warmup()
    print(f"warmup     {count} kernels compiled or loaded in {time.perf_counter() - start:.1f} s")
    return 0


def add_warmup(sub: argparse._SubParsersAction) -> None:
    """Register the ``warmup`` subcommand on the command line's subparsers."""
    sub.add_parser(
        "warmup", help="compile every kernel now (else each compiles at its first use, once)"
    ).set_defaults(func=warmup)
