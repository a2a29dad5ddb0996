"""Stopping: when a run ends before t_end.  A stop test is either a Python callable
``stop(t, y) -> reason or None``, checked at the levels :class:`~.plan.Plan` makes due, or a
:class:`~.watch.CompiledStop` that the compiled march consults itself; a gate
(:class:`~.march.Gate`) skips the tests while they cannot fire, so that the march runs in
long chunks until then."""

from __future__ import annotations

import math
import signal
import threading
from collections.abc import Callable
from contextlib import contextmanager

import numpy as np

from .march import NO_GATE, Gate, closed, gauge
from .plan import Plan
from .watch import NO_WATCH, CompiledStop, never

__all__ = ["Stopper", "deferred_signals", "CHUNK_WORK"]

#: the user's stop signals, deferred while a run's compiled chunks execute
_DEFERRED = (signal.SIGINT, signal.SIGTERM)
#: the most work (nodes x fields x steps) one compiled chunk may do before it returns to
#: Python, where a deferred signal is acted on: about a quarter of a second
CHUNK_WORK = 2_000_000


@contextmanager
def deferred_signals():
    """Within the block, SIGINT and SIGTERM only note that they came (the list yielded);
    :func:`act_on` re-raises the first under the handler that was in force, between two
    compiled chunks.  A Python-level exception raised while compiled code returns to
    Python crashed the process (Ctrl-C and SIGTERM gave signal 11); a handler
    that only notes the signal lets the chunk return normally.  Outside the main thread
    (where handlers cannot be set) nothing changes, nor for a signal ignored on entry (a
    background job's SIGINT): it stays ignored."""
    caught: list[int] = []
    if threading.current_thread() is not threading.main_thread():
        yield caught
        return
    old = {s: h for s in _DEFERRED if (h := signal.getsignal(s)) is not signal.SIG_IGN}
    try:  # a signal between two installs still finds the old handlers restored
        for s in old:
            signal.signal(s, lambda signum, frame: caught.append(signum))
        yield caught
    finally:
        for s, handler in old.items():
            signal.signal(s, signal.SIG_DFL if handler is None else handler)
        if caught:
            signal.raise_signal(caught[0])  # now under the handler that was in force


def act_on(caught: list[int]) -> None:
    """Stop the run if a deferred signal came (it is re-raised when the block ends)."""
    if caught:
        raise _Interrupted(caught[0])


class _Interrupted(Exception):
    """A deferred stop signal came; :func:`deferred_signals` re-raises it on the way out."""


class Stopper:
    """The stop test of a run, its gate and its compiled watch."""

    def __init__(
        self,
        stop: Callable[[float, np.ndarray], str | None] | CompiledStop | None,
        gate: Gate,
        plan: Plan,
        n_steps: int,
        y0: np.ndarray,
    ) -> None:
        self.stop, self.gate, self.plan, self.n_steps = stop, gate, plan, n_steps
        self.test, self.watch = never, NO_WATCH
        if isinstance(stop, CompiledStop):
            self.test, self.watch = stop.test, stop.watch(plan.check, n_steps)
        #: while the gate is open the stop cannot fire: no watch, no Python test
        self.quiet = gate.limit < math.inf and gauge(y0, gate) < gate.limit

    def for_chunk(self) -> tuple[Gate, object]:
        """The gate and the watch the compiled march runs the next chunk with."""
        return (self.gate, NO_WATCH) if self.quiet else (NO_GATE, self.watch)

    def watched(self, in_long: bool) -> bool:
        """Whether the compiled watch is consulted in the next chunk."""
        return self.watch.every > 0 and not self.quiet and not in_long

    def after(
        self, done: int, k1: int, in_long: bool, watched: bool, t: float, y: np.ndarray
    ) -> str | None:
        """Why the run stops at level ``done`` (reached at time t, state y), or None."""
        if self.quiet and closed(self.gate):
            self.quiet = False
        if watched and done % self.watch.every == 0 and done < self.n_steps:
            if self.stop.fired():  # the march consulted the test at this level
                return self.stop.reason(t, self.stop.state)
            return None
        due = self.plan.due(done) or (in_long and done == k1)
        if self.stop is not None and done < self.n_steps and not self.quiet and due:
            reason = self.stop(t, y)
            if reason:
                return str(reason)
        return None
