"""The outcome of :func:`~dyntorsion.genalpha.integrate`: traces, snapshots, Newton
statistics and the final state."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = ["Run"]


@dataclass
class Run:
    """The outcome of :func:`integrate`.

    Attributes
    ----------
    t
        Times at which the traces were recorded (t_0 first).
    traces
        Name -> array over ``t`` (the recorded fields at their nodes).
    snapshot_times, snapshots
        Whole fields (n_snap, N+1, nf) at chosen times.
    iterations, residual_evaluations, factorisations
        Newton statistics per step.
    retries
        1 for a step whose first Newton solve failed and was retried (from the
        other predictor, refactorising at every iteration), else 0.
    y, y_t
        The state and its time derivative at the last completed level.
    stopped
        Why the run ended (``"t_end"`` or the reason returned by ``stop``).
    substeps, rejections
        With step-size control (``scheme.control``): the steps accepted on each
        interval (t_i, t_{i+1}) of the fixed grid, and every rejected step as
        (t_start, dt, reason, iterations, residual).  Without: ones and [].
    """

    s: np.ndarray
    t: np.ndarray
    traces: dict[str, np.ndarray]
    snapshot_times: np.ndarray
    snapshots: np.ndarray
    iterations: np.ndarray
    residual_evaluations: np.ndarray
    factorisations: np.ndarray
    residuals: np.ndarray
    retries: np.ndarray
    y: np.ndarray
    y_t: np.ndarray
    t_final: float
    steps: int
    wall_time: float
    stopped: str
    names: tuple[str, ...]
    meta: dict[str, Any] = field(default_factory=dict)
    substeps: np.ndarray | None = None
    rejections: list[tuple[float, float, str, int, float]] = field(default_factory=list)

    def __getitem__(self, name: str) -> np.ndarray:
        return self.traces[name]

    def snapshot(self, t: float) -> np.ndarray:
        """Whole state at the snapshot time nearest to t."""
        if len(self.snapshot_times) == 0:
            raise ValueError("this run recorded no snapshots")
        return self.snapshots[int(np.argmin(np.abs(self.snapshot_times - t)))]

    def field(self, name: str, t: float) -> np.ndarray:
        return self.snapshot(t)[:, self.names.index(name)]
