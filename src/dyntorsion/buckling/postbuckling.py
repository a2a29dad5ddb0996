"""After the onset (section 6, Fig 7 (e)): why a buckling run stopped early.

A Newton failure of the buckling scene has three different causes, and each gets its
own message:

* ill-posed end conditions -- refused before the first step
  (:class:`~dyntorsion.model.ends.IllPosedEndsError`, raised by
  :class:`~dyntorsion.model.ends.Ends`);
* a time step far too large for the rod -- the failure comes in the first steps,
  before the rod has moved off the straight state (:class:`GridTooCoarseError`);
* the whip after buckling -- the failure comes after |u3(L, t)| has passed the onset
  level u_ref = L / T0 of :func:`~dyntorsion.buckling.onset.detect_onset`
  (:class:`PostBucklingError`); with step-size control
  (:class:`~dyntorsion.genalpha.StepControl`) it is raised only at dt_min.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..genalpha import ConvergenceError
from ..model.rod import Rod
from .onset import reference_level

if TYPE_CHECKING:
    from .run import BucklingRun

__all__ = [
    "GridTooCoarseError",
    "PostBucklingError",
    "FIRST_STEPS",
    "diagnose",
    "ContactMeasures",
    "contact_measures",
    "localisation_width",
    "EnergyBalance",
    "energy_balance",
]

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
    u_ref = reference_level(rod)
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
            f"dyntorsion.studies.fidelity.get('buckling', level, rod): {err.reason}",
        )
    return err


# ================================================================= measures at contact
@dataclass(frozen=True)
class ContactMeasures:
    """The buckled rod at self-contact (the paper has none of these).

    ``time_to_contact`` = t_contact - t_c (t_c of :func:`~dyntorsion.buckling.onset.detect_onset`),
    ``twist`` the end twist kappa3(0, t_contact), ``max_curvature`` the largest bending
    curvature sqrt(k1^2 + k2^2) along the rod, ``width`` the :func:`localisation_width`
    of the bending energy (as a fraction of L).
    """

    t_contact: float
    t_c: float
    time_to_contact: float
    twist: float
    max_curvature: float
    width: float


def localisation_width(s: np.ndarray, density: np.ndarray, share: float = 0.5) -> float:
    """The smallest total length of cells holding ``share`` of the integral of ``density``
    (node values on the grid s, cell values by the trapezoidal rule), over the length:
    1/2 for a uniform density, -> 0 as it localises."""
    if not 0 < share < 1:
        raise ValueError(f"share={share!r} must lie in (0, 1)")
    s, e = np.asarray(s, float), np.asarray(density, float)
    ds = np.diff(s)
    cell = 0.5 * (e[1:] + e[:-1]) * ds
    total = cell.sum()
    if not total > 0:
        raise ValueError("the density is zero everywhere: nothing to localise")
    order = np.argsort(cell / ds)[::-1]
    k = int(np.searchsorted(np.cumsum(cell[order]), share * total))
    return float(ds[order[: k + 1]].sum() / (s[-1] - s[0]))


def contact_measures(run: BucklingRun) -> ContactMeasures:
    """:class:`ContactMeasures` of a buckling run that ended at self-contact."""
    from .onset import detect_onset

    if not run.stopped.startswith("self-contact"):
        raise ValueError(f"the run did not end at self-contact: {run.stopped[:120]}")
    y, names = run.run.y, run.run.names
    k1, k2 = y[:, names.index("k1")], y[:, names.index("k2")]
    energy = 0.5 * (run.rod.B1 * k1**2 + run.rod.B2 * k2**2)
    t_contact = float(run.run.t_final)
    t_c = detect_onset(run).t_c
    return ContactMeasures(
        t_contact=t_contact,
        t_c=t_c,
        time_to_contact=t_contact - t_c,
        twist=float(run.end_twist(t_contact)),
        max_curvature=float(np.max(np.hypot(k1, k2))),
        width=localisation_width(run.run.s, energy),
    )


# ================================================================= energy
@dataclass(frozen=True)
class EnergyBalance:
    """E(t) - E(0) - W(t) along a run: the engine's own check of the violent phase.

    E is the kinetic and elastic energy of :meth:`~dyntorsion.model.cosserat.Cosserat.energy_density`
    (trapezoidal rule in s); W the work of the ends and of the seed force,
    W(t) = int_0^t ([u.n + w.m]_0^L + int f.u ds) dt (trapezoidal rule in t), which is
    dE/dt of eq (6) with m = diag(B1, B2, C) k (every other term does no work).
    """

    t: np.ndarray
    E: np.ndarray
    W: np.ndarray

    @property
    def defect(self) -> np.ndarray:
        """E - E(0) - W."""
        return self.E - self.E[0] - self.W


def energy_balance(run: BucklingRun) -> EnergyBalance:
    """:class:`EnergyBalance` of a buckling run that kept a snapshot at every level
    (``simulate(Scene(rod=..., kappa0=0.0), snapshots=...)`` with the run's time levels)."""
    from ..model.cosserat import Cosserat

    snaps, t = run.run.snapshots, run.run.snapshot_times
    if t.size < 2:
        raise ValueError("energy_balance needs snapshots at (at least two) time levels")
    scene = run.scene
    model = Cosserat(
        run.rod, terms=dict(scene.terms), rotary_inertia_scale=scene.rotary_inertia_scale
    )
    seed = scene.seed
    if scene.loads:
        raise ValueError("energy_balance counts the seed's work only: the scene has loads=")
    if not seed.constant or not scene.pretwisted:
        raise ValueError(
            "energy_balance covers a constant body-frame seed on the pretwisted rod "
            f"(got seed frame={seed.frame!r}, duration={seed.duration!r}, start="
            f"{scene.start!r})"
        )
    s = run.run.s
    f = seed.force(s, run.rod.L)
    stiff = np.array([run.rod.B1, run.rod.B2, run.rod.C])
    E = np.trapezoid(model.energy_density(snaps), s, axis=1)

    def end_power(y):
        return np.sum(y[..., 0:3] * y[..., 9:12], axis=-1) + np.sum(
            y[..., 3:6] * stiff * y[..., 6:9], axis=-1
        )

    power = (
        end_power(snaps[:, -1])
        - end_power(snaps[:, 0])
        + np.trapezoid(np.sum(f * snaps[..., 0:3], axis=-1), s, axis=1)
    )
    W = np.concatenate([[0.0], np.cumsum(0.5 * np.diff(t) * (power[1:] + power[:-1]))])
    return EnergyBalance(t=t, E=E, W=W)
