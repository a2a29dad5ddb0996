"""The outcome of a buckling scene (section 6): the traces every step, the snapshots and
the engine's :class:`~dyntorsion.genalpha.Run`, with the shape of section 4 on demand."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import shapes
from ..genalpha import Run
from ..model.rod import Rod

if TYPE_CHECKING:
    from ..model.ends import Ends
    from .loading import History
    from .loads import EndLoad

__all__ = ["BucklingRun"]


@dataclass
class BucklingRun:
    """The buckling scene's outcome: traces every step, snapshots, and the run."""

    t: np.ndarray
    u3_end: np.ndarray
    kappa3_left: np.ndarray
    kappa3_right: np.ndarray
    omega3_left: np.ndarray
    omega3_right: np.ndarray
    theta_left: np.ndarray
    run: Run
    rod: Rod
    #: the :class:`~dyntorsion.buckling.spec.Scene` that was run (None for a trace made by hand)
    scene: Any = None
    history: History | None = None
    load: EndLoad | None = None
    ends: Ends | None = None

    def end_twist(self, t: float | np.ndarray) -> float | np.ndarray:
        """kappa3(0, t) imposed by the run's history (interpolated from the recorded
        kappa3(0, t) when the run carries no history)."""
        if self.history is not None:
            out = self.history(t)
            return float(out) if np.ndim(out) == 0 else out
        return np.interp(t, self.t, self.kappa3_left)

    @property
    def stopped(self) -> str:
        return self.run.stopped

    def shape(self, t: float) -> tuple[float, np.ndarray]:
        """(time, centreline (N+1, 3)) of the snapshot nearest to t (spatial route, the
        left end turned by the integrated end spin)."""
        i = int(np.argmin(np.abs(self.run.snapshot_times - t)))
        ts = float(self.run.snapshot_times[i])
        theta = float(np.interp(ts, self.t, self.theta_left))
        ds = self.run.s[1] - self.run.s[0]
        return ts, shapes.shape(self.run.snapshots[i], ds, theta)
