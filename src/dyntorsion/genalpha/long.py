"""Long time steps over the quiet start of a run (``Scheme(long_steps=LongSteps(...))``).

Long steps while the solution is quiet (:class:`~.scheme.LongSteps`): the first
phase of a run, in steps of H = factor * dt on the levels t_0 + i H of the fixed
grid, each one step of eq (10)-(12) with the coefficients of H
(:func:`~.discrete.constants`), until the gate of the phase closes (a gauge limit or
the local error estimate of :func:`~.march.closes`); then the run goes on at dt."""

from __future__ import annotations

from typing import Any

import numpy as np

from .discrete import constants
from .march import (
    AT_ERROR,
    AT_LIMIT,
    WHY,
    Halt,
    Recording,
    closed,
    gauge,
    make_gate,
    march,
)
from .newton import REASONS, Status
from .plan import RunParts
from .scheme import LongSteps
from .watch import NO_WATCH, never

__all__ = ["LongPhase"]

_WHY = {AT_LIMIT: "limit", AT_ERROR: "error"}


class LongPhase:
    """The long-step phase of one :func:`~.integrate.integrate` call.

    ``active`` while the phase lasts; ``steps`` long steps taken, the last one ending
    at ``until``; ``ended`` says why the phase ended (``"limit"``, ``"error"``,
    ``"newton: ..."``, ``"landing"``, or None while it lasts).  ``marks`` are the
    indices i of the intervals (t_i, t_{i+1}) on which a long step ended.
    """

    def __init__(self, spec: LongSteps, parts: RunParts):
        system, scheme, grid, left, right, _, ctx = parts
        work = ctx.work
        self.spec, self.factor, self.work, self.system = spec, spec.factor, work, system
        self.con = constants(system, scheme, grid.ds, spec.factor * grid.dt, left, right)
        #: the run's step context with the constants of the long step H
        self.ctx = ctx._replace(con=self.con)
        fields = [system.index(name) for name in spec.fields]
        self.gate = make_gate(fields, grid.ds, spec.limit, spec.tol)
        # the first estimate uses the levels after t_0: the load starts at t_0 with a
        # kink (the ramp's rate and the seed switch on), not a smooth response
        self.active = gauge(work.y_old, self.gate) < spec.limit
        self.steps, self.until = 0, float(grid.t0)
        self.ended: str | None = None if self.active else "limit"
        self.marks: list[int] = []

    def end(self, k0: int, k1: int, hard: int) -> int | None:
        """Where a chunk of long steps from level k0 ends: the planned end k1 rounded up
        to a whole number of long steps, but not past ``hard`` (the next level that
        must be landed on); None (and the phase ends) when no long step fits before it."""
        f = self.factor
        k = k0 + f * max(1, -(-(k1 - k0) // f))
        if k > hard:
            k = k0 + f * ((hard - k0) // f)
        if k == k0:
            self._stop("landing")
            return None
        return k

    def chunk(self, k0, k1, levels, plan, stats, rec_t, rec_vals):
        """March long steps from level k0 to k1 (a multiple of factor steps); append
        the recorded levels to rec_t, rec_vals and each step's statistics to the row
        of its last interval.  Returns the level reached."""
        times, work = levels.times, self.work
        f = self.factor
        idx = np.arange(k0, k1 + 1, f)
        n = idx.size - 1
        forcing = levels.forcing(idx)
        rec = Recording(plan.fields, plan.nodes, 1, 0, np.zeros((n, len(plan.fields))))
        st = np.zeros((n, 5))
        if self.steps == 0:
            work.factored[0] = 0  # the factors of dt do not fit H
        system = self.system
        done, out = march(
            system.F, system.dF, never, self.ctx, forcing, rec, Halt(self.gate, NO_WATCH), st
        )
        levels = idx[1 : done + 1]
        stats[levels - 1 - k0] = st[:done]
        keep = levels % plan.every == 0
        rec_t.extend(times[levels[keep]])
        rec_vals.extend(rec.out[:done][keep])
        self.marks.extend(levels - 1)
        self.steps += done
        if done:
            self.until = float(times[levels[-1]])
        if out.status != Status.CONVERGED:
            self._stop(f"newton: {REASONS.get(Status(out.status), 'unknown')} at t = "
                       f"{float(times[idx[done + 1]]):.6g}")  # fmt: skip
        elif closed(self.gate):
            self._stop(_WHY[self.gate.state[WHY]])
        return k0 + f * done

    def _stop(self, why: str) -> None:
        self.active = False
        self.work.factored[0] = 0  # the factors of H do not fit dt
        if self.ended is None:
            self.ended = why

    def substeps(self, base: np.ndarray) -> np.ndarray:
        """``base`` (the steps that ended on each interval of the fixed grid) with the
        long phase in it: 1 on the last interval of each long step, 0 on the others."""
        out = base.copy()
        if self.steps:
            out[: min(self.marks[-1] + 1, out.size)] = 0
            out[[m for m in self.marks if m < out.size]] = 1
        return out

    def summary(self) -> dict[str, Any]:
        """What the phase did, for the run's ``meta``."""
        return {
            "factor": self.factor,
            "steps": self.steps,
            "until": self.until,
            "ended": self.ended or "t_end",
        }
