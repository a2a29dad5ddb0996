"""Stop tests compiled into the march, consulted at every time level.

Compiled stop tests: ``integrate(stops=Stops(test=CompiledStop(...)))``.

A stop test that must be consulted at every level (the self-contact of a whipping
rod) costs, written in Python, a return from the compiled march at every level.  A
:class:`CompiledStop` is consulted by the march itself (:func:`~.march.march`) at the
same levels a Python ``stop`` would be, so the steps between snapshots run in one
compiled call.  Its ``test(y, watch)`` is a kernel compiled with
:data:`STOP_SIGNATURE`; it keeps what it needs between levels in ``watch.state`` and
``watch.work`` and, when it returns True, sets ``watch.state[0]`` to a nonzero code
and leaves in ``watch.state`` what ``reason(t, state)`` turns into the run's
``stopped`` message.  Its fixed numbers are in ``watch.params``, its integers (field
indices) in ``watch.index`` and its scratch arrays in ``watch.work``, all built once
for the run.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numba
import numpy as np

from .._numba import A2, Indices, Vector, jit, named

__all__ = ["Watch", "CompiledStop", "STOP_SIGNATURE", "NO_WATCH", "never"]


class Watch(NamedTuple):
    """A :class:`CompiledStop` as the march sees it: consulted at every level i of the
    fixed grid with ``i % every == 0`` and ``i < until`` (``every = 0``: never)."""

    every: int
    until: int
    params: Vector
    state: Vector
    work: Vector
    index: Indices


for _name, _doc in (
    ("every", "the test is consulted at the levels i with i % every == 0, never if 0"),
    ("until", "and only at the levels i < until"),
    ("params", "the test's fixed numbers"),
    ("state", "what the test keeps between levels, state[0] != 0 once it said stop"),
    ("work", "the test's scratch arrays"),
    ("index", "the test's integers (field indices)"),
):
    getattr(Watch, _name).__doc__ = _doc

WATCH = named(Watch)
#: signature of a compiled stop test  test(y, watch) -> stop?
STOP_SIGNATURE = numba.boolean(A2, WATCH)


@jit(signature=STOP_SIGNATURE)
def never(y, watch):
    """The test of :data:`NO_WATCH`."""
    return False


#: the watch the march never consults
NO_WATCH = Watch(0, 0, np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0, np.int64))


@dataclass(frozen=True)
class CompiledStop:
    """A stop test for :func:`~.integrate.integrate` in compiled code.

    ``test`` is compiled with :data:`STOP_SIGNATURE` and returns True at a level where
    the run must stop; ``params``, ``state`` and ``work`` are its arrays (``state`` and
    ``work`` change from level to level: one CompiledStop serves one run; ``state[0]``
    is 0 until the test says stop, then a nonzero code); ``reason(t, state)`` is the
    message of a stop at time t; ``index`` holds the test's integers (int64).
    """

    test: Any
    params: np.ndarray
    state: np.ndarray
    work: np.ndarray
    reason: Callable[[float, np.ndarray], str]
    index: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))

    def watch(self, every: int, until: int) -> Watch:
        return Watch(int(every), int(until), self.params, self.state, self.work, self.index)

    def fired(self) -> bool:
        """Whether the test has said stop."""
        return bool(self.state[0] != 0.0)

    def __call__(self, t: float, y: np.ndarray) -> str | None:
        """Consult the test from Python (the levels the march does not reach)."""
        watch = self.watch(1, 1)
        return self.reason(t, self.state) if self.test(y, watch) else None
