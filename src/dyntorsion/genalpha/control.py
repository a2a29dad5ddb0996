"""Step-size control: a step whose Newton solve fails is rejected and retried with half
the step (:class:`~.scheme.StepControl`).

The run keeps its fixed grid t_i = t_0 + i dt.  An interval (t_i, t_{i+1}) is crossed
in one step of dt (the compiled :func:`~.march.march`, chunk by chunk, exactly as
without control) or, after a rejection or inside a ``refine`` window, in substeps of
h = dt / 2**m that land exactly on t_{i+1}.  Each substep is one step of eq (10)-(12)
with the coefficients of its own h (:func:`~.discrete.constants`) from the carried
y^{i-1} and y_t^{i-1}; the rate update of eq (11) uses the same h.  A rejected step
leaves y^{i-1}, y_t^{i-1} untouched (they are overwritten only on convergence), so a
retry starts from the same level.  After ``grow_after`` accepted substeps at a
position that is a multiple of 2h, h doubles; the level m is remembered across
intervals, so the whip after buckling is not re-attempted at dt at every interval.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .discrete import constants
from .march import NO_GATE, Forcing, Gate, Halt, Recording, closes, march
from .newton import REASONS, ConvergenceError, Status
from .plan import RunParts
from .scheme import StepControl
from .watch import NO_WATCH, Watch, never

__all__ = ["Adaptive"]

_NEVER = 2**62  # a Recording period that records nothing


def _reason(status: int) -> str:
    return REASONS.get(Status(status), "unknown")


class Adaptive:
    """The controlled march of one :func:`~.integrate.integrate` call.

    ``rejections`` lists every rejected step as (t_start, h, reason, iterations,
    residual); ``substeps[i]`` is the number of steps accepted on (t_i, t_{i+1}).
    """

    def __init__(self, control: StepControl, parts: RunParts):
        system, scheme, grid, left, right, levels, ctx = parts
        self.control, self.system, self.scheme = control, system, scheme
        self.ds, self.dt, self.left, self.right = grid.ds, grid.dt, left, right
        self.levels, self.times, self.src = levels, levels.times, levels.src
        self.ctx = ctx
        self.con, self.work = ctx.con, ctx.work
        self.level = 0  # m of the last accepted substep (0: whole steps)
        self.deepest = 0  # the largest m accepted
        self.rejections: list[tuple[float, float, str, int, float]] = []
        self.substeps = np.ones(self.times.size - 1, dtype=np.int64)
        self._con = {0: self.con}
        self._last = 0  # the level whose Jacobian the LU factors belong to

    # -------------------------------------------------------------- one step
    def _constants(self, m: int):
        if m not in self._con:
            h = self.dt / 2**m
            self._con[m] = constants(self.system, self.scheme, self.ds, h, self.left, self.right)
        return self._con[m]

    def _try(self, m: int, ta: float, tb: float, stats: np.ndarray, whole: int | None):
        """One step from ta to tb at level m; True when accepted."""
        if m != self._last:
            self.work.factored[0] = 0
            self._last = m
        if whole is not None:
            forcing = self.levels.forcing(slice(whole, whole + 2))
        else:
            tt = np.array([ta, tb])
            gL, gR, qt = self.left.at(tt), self.right.at(tt), self.src.time_factor(tt)
            forcing = Forcing(gL, gR, self.src.q_space, qt, self.src.field_at(tt))
        rec = Recording(np.zeros(0, np.int64), np.zeros(0, np.int64), _NEVER, 0, np.zeros((0, 0)))
        one = np.zeros((1, 5))
        done, out = march(
            self.system.F, self.system.dF, never, self.ctx._replace(con=self._constants(m)),
            forcing, rec, Halt(NO_GATE, NO_WATCH), one,
        )  # fmt: skip
        stats[0:3] += one[0, 0:3]
        stats[3] = one[0, 3]
        stats[4] += one[0, 4]
        if done == 1:
            return True, out
        self.work.factored[0] = 0
        h = self.dt / 2**m
        self.rejections.append((ta, h, _reason(out.status), int(out.corrections), out.residual))
        return False, out

    # -------------------------------------------------------------- one interval
    def cross(self, i: int, m: int, stats: np.ndarray) -> ConvergenceError | None:
        """Cross (t_i, t_{i+1}) in substeps, starting at level m; None on success."""
        c = self.control
        M = c.max_halvings
        units, unit = 2**M, self.dt / 2**M
        t_i = float(self.times[i])
        floor = c.min_halvings(t_i, float(self.times[i + 1]))
        m = max(m, floor)
        pos, accepted, run_ok = 0, 0, 0
        while pos < units:
            step = 2 ** (M - m)
            ta = t_i + pos * unit
            end = pos + step == units
            tb = float(self.times[i + 1]) if end else t_i + (pos + step) * unit
            ok, out = self._try(m, ta, tb, stats, i if (m == 0) else None)
            if ok:
                self.deepest = max(self.deepest, m)
                pos += step
                accepted += 1
                run_ok += 1
                if run_ok >= c.grow_after and m > floor and pos % (2 * step) == 0:
                    m, run_ok = m - 1, 0
                continue
            if m >= M:
                return ConvergenceError(
                    tb,
                    i + 1,
                    out.corrections,
                    out.residual,
                    _reason(out.status)
                    + f" (at the smallest step dt_min = dt/2^{M} = {self.dt / 2**M:.3g} s)",
                    dt=self.dt / 2**m,
                )
            m, run_ok = m + 1, 0
        self.substeps[i] = accepted
        self.level = m
        self.deepest = max(self.deepest, m)
        return None

    # -------------------------------------------------------------- a chunk
    def chunk(
        self, k0: int, k1: int, rec: Recording, stats: np.ndarray, gate: Gate = NO_GATE,
        test=never, watch: Watch = NO_WATCH,
    ):  # fmt: skip
        """Advance from level k0 to k1 (what :func:`march` does without control):
        (levels completed, failure or None); rec.out gets the recorded levels.  Fewer
        levels than asked and no failure: ``gate`` closed the chunk, or ``test`` said
        stop at a level of ``watch``."""
        every = rec.every
        k = k0
        while k < k1:
            if self.level == 0 and self.control.min_halvings(*self._span(k)) == 0:
                j = k + 1
                while j < k1 and self.control.min_halvings(*self._span(j)) == 0:
                    j += 1
                if self._last != 0:
                    self.work.factored[0] = 0
                    self._last = 0
                row = k // every - k0 // every
                sub = Recording(rec.fields, rec.nodes, every, k, rec.out[row:])
                forcing = self.levels.forcing(slice(k, j + 1))
                done, out = march(
                    self.system.F, self.system.dF, test, self.ctx, forcing, sub,
                    Halt(gate, watch), stats[k - k0 : j - k0],
                )  # fmt: skip
                k += done
                if k == j:
                    continue
                if out.status == Status.CONVERGED:
                    return k - k0, None
                self.work.factored[0] = 0
                self.rejections.append(
                    (float(self.times[k]), self.dt, _reason(out.status), int(out.corrections),
                     out.residual)
                )  # fmt: skip
                start = 1
            else:
                start = self.level
            failure = self.cross(k, start, stats[k - k0])
            if failure is not None:
                return k - k0, failure
            k += 1
            if k % every == 0:
                row = k // every - k0 // every - 1
                rec.out[row] = self.work.y_old[rec.nodes, rec.fields]
            if gate.limit < np.inf and closes(self.work.y_old, gate):
                return k - k0, None
            if watch.every > 0 and k % watch.every == 0 and k < watch.until:
                if test(self.work.y_old, watch):
                    return k - k0, None
        return k1 - k0, None

    def _span(self, i: int) -> tuple[float, float]:
        return float(self.times[i]), float(self.times[i + 1])

    def summary(self, done: int) -> dict[str, Any]:
        """What the controller did on the first ``done`` intervals, for the run's ``meta``."""
        return {
            "accepted": int(self.substeps[:done].sum()),
            "rejected": len(self.rejections),
            "smallest_dt": self.dt / 2**self.deepest,
        }
