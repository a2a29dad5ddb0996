"""After the onset (section 6, Fig 7 (e)): why a buckling run stopped early.

A Newton failure of the buckling scene has three different causes, and each gets its
own message:

* ill-posed end conditions -- refused before the first step
  (:class:`~dyntorsion.loading.IllPosedEndsError`, raised by
  :class:`~dyntorsion.loading.Ends`);
* a time step far too large for the rod -- the failure comes in the first steps,
  before the rod has moved off the straight state (:class:`GridTooCoarseError`);
* the whip after buckling -- the failure comes after |u3(L, t)| has passed the onset
  level u_ref = L / T0 of :func:`~dyntorsion.buckling.detect_onset`
  (:class:`PostBucklingError`); with step-size control
  (:class:`~dyntorsion.genalpha.StepControl`) it is raised only at dt_min.
"""

from __future__ import annotations

import numpy as np

from .genalpha import ConvergenceError
from .rod import Rod

__all__ = ["GridTooCoarseError", "PostBucklingError", "FIRST_STEPS", "diagnose"]

#: a failure within this many steps of the start is blamed on the time step
FIRST_STEPS = 10


class GridTooCoarseError(ConvergenceError):
    """A Newton failure in the first steps of a buckling run: dt is far too large."""


class PostBucklingError(ConvergenceError):
    """A Newton failure in the violent motion after the onset of buckling."""


def _again(cls, err: ConvergenceError, reason: str) -> ConvergenceError:
    new = cls(err.t, err.step, err.iterations, err.residual, reason, run=err.run, dt=err.dt)
    return new


def diagnose(
    err: ConvergenceError, rod: Rod, n_cells: int, dt: float, u3_end: np.ndarray, t: np.ndarray
) -> ConvergenceError:
    """The failure ``err`` of a buckling run (on ``n_cells`` cells with step ``dt``,
    whose u3(L, t) up to the failure is ``u3_end`` at times ``t``) as the error of its
    cause: :class:`PostBucklingError`, :class:`GridTooCoarseError`, or ``err`` itself
    (a failure before the onset but not in the first steps)."""
    u_ref = rod.L / rod.T0
    above = np.nonzero(np.abs(np.asarray(u3_end)) >= u_ref)[0]
    if above.size:
        t_on = float(np.asarray(t)[above[0]])
        control = (
            "at the smallest step the controller allows"
            if err.dt is not None
            else "at fixed steps; Scheme(control=StepControl()) retries it with smaller steps"
        )
        return _again(
            PostBucklingError,
            err,
            f"post-buckling whip, {err.t - t_on:.4g} s after |u3(L)| first reached "
            f"u_ref = {u_ref:.3g} m/s (at t = {t_on:.6g} s), {control}: {err.reason}",
        )
    if err.step <= FIRST_STEPS:
        courant = rod.c * dt * n_cells / rod.L
        return _again(
            GridTooCoarseError,
            err,
            f"failed in the first {FIRST_STEPS} steps, before the rod moved: dt = {dt:.3g} s "
            f"is {dt / rod.T0:.3g} T0 (bending time {rod.T0:.3g} s) at Courant number "
            f"{courant:.3g} -- far too large for this rod; use "
            f"dyntorsion.fidelity.get('buckling', level, rod): {err.reason}",
        )
    return err
