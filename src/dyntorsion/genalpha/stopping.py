"""Stopping: when a run ends before t_end.  A stop test is either a Python callable
``stop(t, y) -> reason or None``, checked at the levels :class:`~.plan.Plan` makes due, or a
:class:`~.watch.CompiledStop` that the compiled march consults itself; a gate
(:class:`~.march.Gate`) skips the tests while they cannot fire, so that the march runs in
long chunks until then."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from .march import NO_GATE, Gate, closed, gauge
from .plan import Plan
from .watch import NO_WATCH, CompiledStop, never

__all__ = ["Stopper"]


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
