"""The stepping part of a run with a state-dependent source (:mod:`.state`).

A step of dt is taken whole when the source couples nothing over it and the state is slow
(:meth:`~.state.StateSource.too_fast`).  Otherwise it is crossed by substeps h_j = dt /
(``count`` 2^j), j >= 0, the longest for which the state is not too fast; a step whose
Newton solve fails is retried at the next shorter level (down to ``shortest``), and after a
success the level may grow by one where the substeps align.  Each substep is one step of
eq (10)-(12) with the coefficients of its own h, the source at the old level on the right
and at the new level inside the solve.
"""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np

from .._numba import JACOBIAN_SIGNATURE, LOAD_SIGNATURE
from .discrete import constants
from .march import StepContext
from .newton import ConvergenceError
from .plan import RunParts
from .state import (
    Address,
    StateSource,
    free_newton,
    prepare,
    state_newton,
)

__all__ = ["StateSteps"]


class _Length:
    """The constants of steps of one length h: the engine's and the source's."""

    def __init__(self, system, scheme, ds, h, left, right, source: StateSource):
        self.h = h
        self.con = constants(system, scheme, ds, h, left, right)
        self.own = source.level(h, self.con)


class StateSteps:
    """The steps of one :func:`~.integrate.integrate` run whose sources hold a
    :class:`~.state.StateSource` (module docstring); it keeps the source at the old level
    and the cost of the coupled steps (:meth:`summary`)."""

    def __init__(self, source: StateSource, parts: RunParts):
        system, scheme, grid, left, right, levels, ctx = parts
        self.source, self.system, self.scheme = source, system, scheme
        self.grid, self.left, self.right, self.ctx = grid, left, right, ctx
        self.w, self.fac = ctx.work, ctx.fac
        self.qs = np.ascontiguousarray(levels.src.q_space, float)
        n1, nf = self.qs.shape
        self.zeros = np.zeros((n1, nf))
        self.q_old, self.current = self.zeros, None
        count, shortest = source.substeps
        self.count = count
        h0 = grid.dt / count
        self.j_max = max(0, int(math.floor(math.log2(h0 / shortest)))) if h0 > shortest else 0
        self.units = count * 2**self.j_max  # the shortest substep's count in a whole step
        self.lengths: dict[int, _Length] = {}
        self.whole = _Length(system, scheme, grid.ds, grid.dt, left, right, source)
        self.F = Address(system.F, LOAD_SIGNATURE)
        self.dF = Address(system.dF, JACOBIAN_SIGNATURE)
        opts = ctx.opts
        self.opts = opts
        self.retry = opts._replace(reuse=False, rate_predictor=not opts.rate_predictor)
        self.coupled_opts = opts._replace(max_iter=min(opts.max_iter, source.max_iterations))
        self.check_every = source.check_every(grid.dt)
        self.j, self.steps, self.t = 0, 0, float(grid.t0)
        self.cost = {"coupled_steps": 0, "coupled_iterations": 0, "coupled_seconds": 0.0,
                     "free_seconds": 0.0, "failed_solves": 0, "shortest_step": math.inf}  # fmt: skip
        self.reason: str | None = None

    def length(self, j: int) -> _Length:
        if j not in self.lengths:
            g = self.grid
            h = g.dt / self.count / 2**j
            self.lengths[j] = _Length(self.system, self.scheme, g.ds, h, self.left, self.right,
                                      self.source)  # fmt: skip
        return self.lengths[j]

    def _step(self, lv: _Length, t_new: float, step) -> bool:
        tick = time.perf_counter()
        w, source, F, dF = self.w, self.source, self.F, self.dF
        if self.current is not lv:
            w.factored[0] = 0  # the factors held are of the other step length
            self.current = lv
        con, h = lv.con, lv.h
        prepare(F, con, w, self.qs, self.q_old, self.zeros)
        gL, gR = self.left.at(np.array([t_new]))[0], self.right.at(np.array([t_new]))[0]
        w.y[:, :] = w.y_old
        q_new, ok = self.zeros, True
        if step is None:
            if free_newton(F, dF, con, gL, gR, w, self.fac, self.opts) != 0:
                w.y[:, :] = w.y_old + h * w.rate_old
                w.factored[0] = 0
                ok = free_newton(F, dF, con, gL, gR, w, self.fac, self.retry) == 0
            self.cost["free_seconds"] += time.perf_counter() - tick
        else:
            w.y[:, :] = w.y_old + h * w.rate_old  # the rate predictor
            ctx = StepContext(con, w, self.fac, self.coupled_opts)
            ok, its, src = state_newton(F, dF, ctx, gL, gR, source, step)
            q_new = src.q
            self.cost["coupled_steps"] += 1
            self.cost["coupled_iterations"] += its
            if ok:
                source.converged(step)
            self.cost["coupled_seconds"] += time.perf_counter() - tick
        if not ok:
            w.factored[0] = 0
            self.cost["failed_solves"] += 1
            return False
        g_t = con.co.g_t  # eq (11): the new rate from the new level
        rate = (w.y - w.y_old) / (g_t * h) - (1.0 - g_t) / g_t * w.rate_old
        source.step_taken(con.co, h, (w.y_old, w.rate_old), (w.y, rate), self.q_old, q_new)
        w.rate_old[:, :] = rate
        w.y_old[:, :] = w.y
        self.q_old = q_new
        self.t, self.steps = t_new, self.steps + 1
        self.cost["shortest_step"] = min(self.cost["shortest_step"], h)
        source.moved(w.y_old)
        return True

    def _failed(self, t_new: float, h: float) -> ConvergenceError:
        return ConvergenceError(t_new, self.steps + 1, self.opts.max_iter, float("nan"),
                                self.source.failure, dt=h)  # fmt: skip

    def chunk(self, k0: int, k1: int) -> tuple[int, ConvergenceError | None]:
        """The fixed-grid steps k0 to k1: the levels completed, and the error of a step
        that failed at the shortest substep.  A reason from the source ends the chunk
        (:attr:`reason`)."""
        g, source, units, count = self.grid, self.source, self.units, self.count
        for k in range(k0, k1):
            t0, t1 = g.t0 + k * g.dt, g.t0 + (k + 1) * g.dt
            check = (k + 1) % self.check_every == 0
            reason = None
            if not self.q_old.any() and not source.too_fast(self.whole.h):
                step = source.begin(self.whole.own, self.w.y_old)
                if step is None and self._step(self.whole, t1, None):
                    reason = source.level_reached(self.t, self.w.y_old, self.whole.h, check)
                    if reason:
                        self.reason = reason
                        return k + 1 - k0, None
                    continue
            pos, grow = 0, True  # pos in units of the shortest substep
            while pos < units:
                j = self.j
                if grow and j > 0 and pos % (units // (count * 2 ** (j - 1))) == 0:
                    if not source.too_fast(self.length(j - 1).h):
                        j -= 1  # one level longer where the longer substep aligns
                while j < self.j_max and source.too_fast(self.length(j).h):
                    j += 1
                self.j = j
                lv, span = self.length(j), units // (count * 2**j)
                t_new = t1 if pos + span >= units else t0 + (pos + span) * g.dt / units
                if not self._step(lv, t_new, source.begin(lv.own, self.w.y_old)):
                    if j >= self.j_max:
                        return k - k0, self._failed(t_new, lv.h)
                    self.j, grow = j + 1, False
                    continue
                pos, grow = pos + span, True
                reason = source.level_reached(self.t, self.w.y_old, lv.h, check and pos >= units)
                if reason:
                    break
            if reason:
                self.reason = reason
                return k + 1 - k0, None
        return k1 - k0, None

    def summary(self) -> dict[str, Any]:
        """The steps accepted and what the coupled ones cost: their count, Newton
        iterations and wall time, the free steps' wall time, the solves retried shorter
        and the shortest step [s]."""
        return {"steps": self.steps, **self.cost}
