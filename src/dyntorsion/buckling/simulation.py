"""Torsional buckling (section 6): the dynamic buckling scene (boundary conditions of
eq 30, or any end set, twist history and axial load of :mod:`dyntorsion.buckling.loading`).
The onset of buckling lives in :mod:`dyntorsion.buckling.onset`, the delay law (eqs 33-34) in
:mod:`dyntorsion.buckling.delay_law` and the static critical twist (eqs 31-32) in
:mod:`dyntorsion.buckling.statics`; the package :mod:`dyntorsion.buckling` re-exports them all.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence

import numpy as np

from ..genalpha import ConvergenceError, Grid, Output, Problem, Sources, Stops, integrate
from ..genalpha.guard import check_time_grid
from ..model.cosserat import Cosserat
from ..model.rod import Rod
from .history import History
from .loads import DistributedLoad
from .postbuckling import diagnose
from .run import BucklingRun
from .seed import Perturbation
from .slender import check_slender
from .spec import Scene
from .stops import STRAIGHT, scene_stop

__all__ = ["simulate", "GridWarning", "check_grid"]


class GridWarning(UserWarning):
    """A time step far outside the range the buckling scene was tested on."""


#: the buckling grids the accuracy ladder tested (Fig 8 and the fast scene): time step
#: over the bending time T0, and Courant number c dt / ds of the torsional waves
TESTED_DT_OVER_T0 = (0.00125 / 43.8178046004133, 0.02 / 43.8178046004133)
TESTED_COURANT = (1.8, 462.0)


def check_grid(rod: Rod, n_cells: int, dt: float) -> None:
    """Warn (:class:`GridWarning`) when dt exceeds ten times the largest tested step, in
    units of the rod's own bending time T0 or of its torsional transit per cell."""
    ratio, courant = dt / rod.T0, rod.c * dt * n_cells / rod.L
    if ratio > 10 * TESTED_DT_OVER_T0[1] or courant > 10 * TESTED_COURANT[1]:
        warnings.warn(
            f"dt={dt:.3g} s is {ratio:.3g} T0 (bending time {rod.T0:.3g} s) at Courant number "
            f"{courant:.3g}: the buckling scene was tested up to {TESTED_DT_OVER_T0[1]:.3g} T0 "
            f"and Courant {TESTED_COURANT[1]:g}; use dyntorsion.studies.fidelity.get('buckling', level, rod)",
            GridWarning,
            stacklevel=3,
        )


def _checked(hist: History, t_end: float) -> History:
    """The history, its output checked once before the run: finite numbers, one
    per time, over [0, t_end]; else a ValueError naming the history."""
    t = np.linspace(0.0, t_end, 2001)
    name = f"custom {hist.name!r}" if hasattr(hist, "func") else hist.label()
    try:
        out = np.asarray(hist(t), dtype=float)
    except (TypeError, ValueError) as err:
        raise ValueError(
            f"history={name}: kappa3(0, t) must be a number per time t ({err})"
        ) from None
    if out.shape != t.shape:
        raise ValueError(f"history={name}: kappa3(0, t) of {t.size} times has shape {out.shape}")
    bad = ~np.isfinite(out)
    if bad.any():
        i = int(np.argmax(bad))
        raise ValueError(
            f"history={name}: kappa3(0, t) = {out[i]} at t = {t[i]:.6g} s, must be finite"
        )
    return hist


def _seed_sources(model, seed: Perturbation, s: np.ndarray, length: float, hist) -> Sources:
    """The seed as the source of eq (7): separable (the force times 1, or times the
    impulse's switch), or, fixed in the lab frame, a field turned each level by the
    straight rod's quasi-static twist (:class:`~.seed.Perturbation`)."""
    f = seed.force(s, length)
    if seed.frame != "body" and hist.quantity != "twist":
        raise ValueError(
            f"seed frame={seed.frame!r} turns the seed with the end twist kappa3(0, t); a "
            f"{hist.quantity} history gives none: use frame='body'"
        )
    if seed.frame == "body":
        g = None if seed.duration is None else seed.time_factor
        return Sources(separable=(model.external_force(f), g))

    def turned(s_, t):
        on = seed.time_factor(np.array([t]))[0]
        return on * model.external_force(seed.turned(f, s, length, float(hist(np.array([t]))[0])))

    return Sources(field=turned)


def _with_loads(seed: Sources, model, loads: Sequence[DistributedLoad], s) -> Sources:
    """The seed's sources with the distributed ``loads`` added as a field q(s, t) (the
    seed's sources unchanged without loads)."""
    if not loads:
        return seed
    length = float(s[-1])

    def field(s_, t):
        f = sum(np.asarray(q.force(s, t, length), dtype=float) for q in loads)
        out = model.external_force(f)
        return out if seed.field is None else out + seed.field(s_, t)

    return Sources(separable=seed.separable, field=field)


#: the traces every buckling run keeps: the end displacement and the end twists and spins
RECORDED = {
    "u3_end": ("u3", -1),
    "k3_left": ("k3", 0),
    "k3_right": ("k3", -1),
    "w3_left": ("w3", 0),
    "w3_right": ("w3", -1),
}


def simulate(
    scene: Scene,
    *,
    snapshots: Sequence[float] = (),
    progress: bool | None = None,
    on_failure: str = "raise",
    stop_at_contact: bool = True,
    check_every: int | None = None,
) -> BucklingRun:
    """Run one buckling :class:`~dyntorsion.buckling.scene.Scene` (section 6, or any
    extension of it): its rod, end conditions, end twist or spin history, axial load,
    distributed loads, model switches, seed, grid, scheme and Newton options, to its
    ``duration()``.  The initial state is y = 0 except k3 = kappa3(0, 0) and n3 = T(0)
    (``start="pretwisted"``: a straight rod pretwisted without stress in bending, in
    equilibrium under the axial load; section 5 reads the paper's kappa0 so) or y = 0
    except n3 (``"step"`` and ``"smooth"``: section 6's "y(s, 0) = 0"; with
    kappa3(0, 0) != 0 the end twist of ``"step"`` then jumps at t = 0, the incompatible
    data of section 5).  With no seed (magnitude 0) the straight rod is an exact solution
    of the discrete equations and the run stays straight to round-off.

    The run options: ``snapshots`` (times [s] at which the whole state is kept),
    ``progress`` (a progress bar; None: only for long runs on a terminal), ``on_failure``
    and the contact check.  The run ends at the scene's ``duration()`` or, with
    ``stop_at_contact``, at the first check (every ``check_every`` steps, default about
    every 0.1 s of simulated time, or every step with step-size control: between checks
    0.1 s apart the whipping rod can pass through itself unseen; checked every step, a
    pair of segments that crossed between two levels counts as contact too) at which two
    non-neighbouring parts of the centreline come closer than the rod's thickness;
    ``result.stopped`` says which ("t_end" or "self-contact ...").  A scene with
    ``until="first-peak"`` ends, too, at the first check at which ``|u3(L, t)|``, having
    reached u_ref = L / T0, has fallen below :data:`~dyntorsion.buckling.onset.PEAK_FALL`
    (0.7) of its running maximum: the trace then holds the first peak and the fall after
    it, all that :func:`~dyntorsion.buckling.onset.detect_onset` and the rules of
    :mod:`~dyntorsion.buckling.onset_rules` read.

    Past the onset the rod whips round violently; a Newton failure there raises
    :class:`~dyntorsion.buckling.postbuckling.PostBucklingError`, one in the first steps
    :class:`~dyntorsion.buckling.postbuckling.GridTooCoarseError` (both are
    :class:`~dyntorsion.genalpha.ConvergenceError`; ``on_failure="raise"``), or, with
    ``on_failure="return"``, ends the run at the last completed step with
    ``stopped = "failed: ..."`` (the traces up to it are what the onset needs).  A time
    step far outside the tested range for this rod warns (:class:`GridWarning`).

    Raises TypeError for a ``scene`` that is no Scene, ValueError for bad run options.
    """
    if not isinstance(scene, Scene):
        raise TypeError(
            f"scene={scene!r} must be a dyntorsion.buckling.scene.Scene (simulate(Scene(a=..., "
            "n_cells=..., dt=..., t_end=...)))"
        )
    if on_failure not in ("raise", "return"):
        raise ValueError(f"on_failure={on_failure!r}; allowed: 'raise', 'return'")
    rod, n_cells, dt, t_end = scene.rod, scene.n_cells, scene.dt, scene.duration()
    scheme, newton, load, end_set = scene.scheme, scene.newton, scene.tension, scene.ends
    stop_after_first_peak = scene.until == "first-peak"
    check_time_grid(dt, t_end, 0.0, snapshots, check_every)
    hist = _checked(scene.twist, t_end)
    model = Cosserat(rod, terms=dict(scene.terms), rotary_inertia_scale=scene.rotary_inertia_scale)
    system = model.system()
    check_slender(rod)
    check_grid(rod, n_cells, dt)
    s = np.linspace(0.0, rod.L, n_cells + 1)
    y0 = np.zeros((n_cells + 1, 12))
    if scene.pretwisted:
        y0[:, system.index("k3")] = hist.initial_twist
    y0[:, system.index("n3")] = load(np.zeros(1))[0]
    left, right = end_set.rows(system, hist, load)
    sources = _with_loads(_seed_sources(model, scene.seed, s, rod.L, hist), model, scene.loads, s)

    if check_every is None:
        check_every = 1 if scheme.control is not None else max(1, int(round(0.1 / dt)))
    stop = None
    if stop_at_contact or stop_after_first_peak:
        stop = scene_stop(
            system, rod, n_cells, contact=stop_at_contact, first_peak=stop_after_first_peak,
            every_level=check_every == 1,
        )  # fmt: skip
    try:
        run = integrate(
            Problem(system, y0, left, right, sources=sources),
            Grid(n_cells, rod.L, dt, t_end),
            scheme=scheme,
            newton=newton,
            output=Output(record=RECORDED, snapshots=snapshots, progress=progress),
            stops=Stops(
                test=stop,
                check_every=check_every if stop is not None else None,
                # the contact test does nothing below STRAIGHT (the same gauge): the march
                # skips it in long chunks (the first-peak test then starts at the first check
                # past it: it can only stop later, never before the fall after the first peak)
                gate=(("k1", "k2"), STRAIGHT) if stop_at_contact else None,
            ),
        )
    except ConvergenceError as raw:
        u3 = raw.run["u3_end"] if raw.run is not None else np.zeros(0)
        t_run = raw.run.t if raw.run is not None else np.zeros(0)
        err = diagnose(raw, rod, n_cells, dt, u3, t_run)
        if on_failure == "raise" or err.run is None:
            raise err from None
        run = err.run
        run.stopped = f"failed: {err}"
    t = run.t
    w0 = run["w3_left"]
    theta = np.concatenate([[0.0], np.cumsum(0.5 * np.diff(t) * (w0[1:] + w0[:-1]))])
    return BucklingRun(
        t=t,
        u3_end=run["u3_end"],
        kappa3_left=run["k3_left"],
        kappa3_right=run["k3_right"],
        omega3_left=w0,
        omega3_right=run["w3_right"],
        theta_left=theta,
        run=run,
        rod=rod,
        scene=scene,
        history=hist,
        load=load,
        ends=end_set,
    )
