"""Recording: what a run keeps of its levels (the traces of :class:`~.plan.Plan` every
``record_every`` levels, whole states at the snapshot times, the Newton statistics of every
step) and the :class:`~.run.Run` they make."""

from __future__ import annotations

import numpy as np

from .march import Recording
from .plan import Plan

__all__ = ["Recorder"]


class Recorder:
    """The lists a run fills as it goes, from the initial level on."""

    def __init__(self, plan: Plan, times: np.ndarray, y0: np.ndarray, record_every: int) -> None:
        self.plan, self.times, self.every = plan, times, record_every
        self.t: list[float] = [times[0]]
        self.values: list[np.ndarray] = [y0[plan.nodes, plan.fields].copy()]
        snap = 0 in plan.snap_steps
        self.snapshot_times: list[float] = [times[0]] if snap else []
        self.snapshots: list[np.ndarray] = [y0.copy()] if snap else []
        #: per step: Newton corrections, residual evaluations, factorisations, residual, retries
        self.stats = np.zeros((times.size - 1, 5))

    def buffer(self, k0: int, k1: int) -> tuple[Recording, np.ndarray]:
        """The compiled march's recording buffer for the levels k0+1..k1, and their steps."""
        first = (k0 // self.every + 1) * self.every
        steps = np.arange(first, k1 + 1, self.every)
        out = np.zeros((steps.size, len(self.plan.fields)))
        return Recording(self.plan.fields, self.plan.nodes, self.every, k0, out), steps

    def keep(self, rec: Recording, steps: np.ndarray, reached: int, t0: float, dt: float) -> None:
        """Keep what the march recorded up to the level it reached."""
        kept = steps <= reached
        self.t.extend(t0 + dt * steps[kept])
        self.values.extend(rec.out[kept])

    def level(self, done: int, y: np.ndarray) -> None:
        """The state at level ``done``, kept if it is a snapshot level."""
        if done in self.plan.snap_steps:
            self.snapshot_times.append(float(self.times[done]))
            self.snapshots.append(y.copy())

    def traces(self) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        """The recorded times and traces (name -> values)."""
        rv = np.array(self.values).reshape(len(self.values), len(self.plan.fields))
        names = self.plan.names
        return np.array(self.t), {name: rv[:, m].copy() for m, name in enumerate(names)}

    def whole_states(self, n1: int, nf: int) -> tuple[np.ndarray, np.ndarray]:
        snaps = np.array(self.snapshots) if self.snapshots else np.zeros((0, n1, nf))
        return np.array(self.snapshot_times), snaps
