"""Accuracy on demand: the onset of a buckling scene to a requested relative tolerance,
with an a-posteriori error estimate (beyond the paper).

**Rungs.**  The onset time t_c of section 6 has no exact solution; its discretisation
error is estimated from the scene run on a sequence of grids that halve ``ds`` and ``dt``
together, the rungs of the fidelity ladder (:data:`~dyntorsion.studies.fidelity.PRESETS`,
``buckling``: N = 50 ``quick``, 100 ``standard``, 200 ``fine``) below a coarse rung at
N = 25 and above ``fine`` at N = 400 (:data:`CELLS`):

    N_k = 25 * 2^k,    dt_k = dt_0 / 2^k,        k = 0, 1, 2, ...

``dt_0`` is paced (:mod:`~dyntorsion.studies.pacing`): the onset time of the fast linear
estimate (:func:`~dyntorsion.beyond.predictions.estimate`) over 96 steps, so that the
``standard`` rung reaches the onset in the pacing's 384 steps whatever the rate; where
the linear estimate does not reach (an axial load) the paper's delay law at this rod's
and load's static kappa_cri (eqs 33-34) sets the time instead, and where neither does
(other histories, other ends) the ladder's own steps are used (``quick``'s dt doubled,
scaled to the rod).  Every rung runs until the first peak of ``|u3(L)|`` (the same onset,
without the whip) with the scene's own Newton options.

**Grid estimate.**  With d_k = v_k - v_{k-1} the differences of a value v (t_c or
kappa3) on successive rungs, the error of v_K on the finest rung run so far is

    e_K = max(abs(d_K), abs(d_{K-1}))                     (the sample reading),
    e_K = (2/3) max(abs(d_K), abs(d_{K-1}) / 4)           (the continuous reading).

The sample reading (the window rule on the samples) converges irregularly -- its t_c
moves by a fraction of a step whenever a sample enters or leaves the window -- so its
estimate trusts no single difference: for a scheme of order p >= 1 the first term
bounds the error abs(d_K) / (2^p - 1), the second keeps two rungs that agree by
coincidence from making it small.  The continuous reading
(:func:`~dyntorsion.buckling.onset.continuous_window_fit`, the records'
``t_c_continuous``) converges at the scheme's second order: Richardson's abs(d_K) / 3
with a safety factor of 2, the previous difference scaled by 2^2 for the same reason.
An estimate needs three rungs, and only rungs from ``fine`` on are vouched for.

**Solver share.**  Below a seed of about 1e-13 N/m the lateral perturbation the Newton
solve leaves at its tolerance acts as a seed as well, and moves the onset by more than
the grid does.  :func:`onset_within` therefore runs the ``standard`` rung once more with
the Newton tolerance times :data:`SOLVER_FACTOR` (:func:`solver_check`) and adds the
change of the onset to the estimate.

**Contract.**  :func:`onset_within` runs the rungs from the coarsest and returns the
onset of the first rung (from ``fine`` on) whose estimated errors of t_c and kappa3 are
within ``rtol`` of their values, read in continuous time unless told otherwise
(:data:`DEFAULT_READING`), as a :class:`ToleranceOnset` (``met`` False, with the finest
rung's values and a note, when no rung up to ``max_cells`` meets ``rtol``); ``rtol``
outside (0, 1] or an unknown reading raise ValueError naming the parameter.  How often the
estimate covers the true error against a converged reference, and by how much it
overstates it, is measured over hold-out sets of scenes by
:mod:`~dyntorsion.studies.tolerance_study` and :mod:`~dyntorsion.studies.solver_share`,
and shown, with the measured sequences that fixed these rules, on the "Accuracy and
cost" page.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field, replace
from functools import lru_cache
from pathlib import Path
from typing import Any

from ..beyond.predictions import estimate
from ..buckling.delay_law import paper_law
from ..buckling.scene import Scene, run_scene
from ..store.results import Store
from . import fidelity
from .pacing import STEPS
from .sweep import run_sweep

__all__ = [
    "CELLS",
    "DEFAULT_READING",
    "READINGS",
    "RUNG_NAMES",
    "ToleranceOnset",
    "check_reading",
    "check_rtol",
    "error_estimate",
    "REFERENCE_TOL",
    "SOLVER_FACTOR",
    "solver_check",
    "onset_change",
    "onset_within",
    "pacing_time",
    "rungs",
]

#: cells of the rungs, coarsest first: the ladder's quick, standard and fine with a
#: coarse rung below and one more above
CELLS: tuple[int, ...] = (25, 50, 100, 200, 400)
#: the name of each rung
RUNG_NAMES: dict[int, str] = {25: "coarse", 50: "quick", 100: "standard", 200: "fine"}
#: the coarsest rung whose estimate is vouched for (module docstring)
VOUCHED = 200
#: steps to the paced onset time on the N = 25 rung (the pacing's 384 at N = 100)
COARSE_STEPS = STEPS * CELLS[0] // 100
#: the solver check (module docstring): the rung it runs on and its Newton tolerance as a
#: multiple of the scene's
SOLVER_RUNG = 100
SOLVER_FACTOR = 0.01
#: the Newton tolerance of the references converged in the solver (preset
#: ``tolerance-reference-tight``); 1e-14 is below what the solve can reach in double
#: precision (the Fig 10 scene at a = 1.09, seed 1e-17 N/m: no onset at N = 100 and 200)
REFERENCE_TOL = 1e-13


#: the readings of the onset a ladder can be judged on: the paper's window rule on the
#: samples (``t_c``, ``kappa3``) or the same window read in continuous time
#: (:func:`~dyntorsion.buckling.onset.continuous_window_fit`), each the record's fields
READINGS: dict[str, tuple[str, str]] = {
    "samples": ("t_c", "kappa3"),
    "continuous": ("t_c_continuous", "kappa3_continuous"),
}
#: the reading :func:`onset_within` and ``--rtol`` judge unless told: the one whose
#: estimate, with the solver check, covers at least 95 % of the fine rung's true errors and
#: is within 3 times them in most, on the set computed after the check and on all four
#: ("Accuracy and cost", "The solver's share"; off the samples it is several times too large)
DEFAULT_READING = "continuous"


def check_reading(reading: Any) -> tuple[str, str]:
    """The record fields of ``reading`` (:data:`READINGS`), else a ValueError naming it."""
    if reading not in READINGS:
        raise ValueError(f"reading={reading!r}; allowed: {', '.join(map(repr, READINGS))}")
    return READINGS[reading]


def check_rtol(rtol: Any) -> float:
    """``rtol`` as a float if it is a relative tolerance in (0, 1], else a ValueError
    naming it."""
    if isinstance(rtol, bool) or not isinstance(rtol, int | float):
        raise ValueError(f"rtol={rtol!r} must be a number in (0, 1] (a relative tolerance)")
    if not (math.isfinite(rtol) and 0.0 < rtol <= 1.0):
        raise ValueError(f"rtol={rtol!r} must be in (0, 1] (a relative tolerance, e.g. 0.005)")
    return float(rtol)


def rung_name(n_cells: int) -> str:
    return RUNG_NAMES.get(n_cells, f"N={n_cells}")


@lru_cache(maxsize=256)
def pacing_time(scene: Scene) -> tuple[float | None, str]:
    """The onset time the rungs are paced by, and where it comes from: the linear
    estimate (``"linear estimate"``), else the paper's delay law at the scene's static
    kappa_cri (``"delay law"``), else None (``"ladder"``: the fidelity ladder's steps).
    Kept per scene in this process (scenes are immutable; an unhashable one is not kept):
    the presets and the studies ask for the same scenes' rungs many times."""
    try:
        hash(scene)
    except TypeError:
        return _pacing_time(scene)
    return _kept_pacing_time(scene)


def _pacing_time(scene: Scene) -> tuple[float | None, str]:
    try:
        t = estimate(scene).t_ref
        if math.isfinite(t) and t > 0:
            return t, "linear estimate"
    except ValueError:
        pass
    if scene.history is None and scene.tension.constant is not None:
        try:
            kc = scene.kappa_cri()
        except ValueError:
            return None, "ladder"
        t = (float(paper_law(scene.a, scene.rod, kc)) - scene.kappa0) / scene.a
        if math.isfinite(t) and t > 0:
            return t, "delay law"
    return None, "ladder"


_kept_pacing_time = lru_cache(maxsize=4096)(_pacing_time)


def rungs(scene: Scene, count: int = len(CELLS)) -> list[Scene]:
    """The first ``count`` rungs of ``scene``: N = 25 * 2^k cells, dt = dt_0 / 2^k, until
    the first peak; everything else as in ``scene``."""
    if isinstance(count, bool) or not isinstance(count, int) or not 2 <= count <= 8:
        raise ValueError(f"count={count!r} must be an integer in [2, 8]")
    t_pace, _ = pacing_time(scene)
    if t_pace is None:
        dt0 = 2.0 * fidelity.get("buckling", "quick", rod=scene.rod).dt
    else:
        dt0 = float(f"{t_pace / COARSE_STEPS:.3g}")
    return [
        replace(scene, n_cells=CELLS[0] * 2**k, dt=dt0 / 2**k, until="first-peak")
        for k in range(count)
    ]


def solver_check(scene: Scene) -> Scene:
    """The solver check of ``scene`` (module docstring): its ``standard`` rung with the
    Newton tolerance times :data:`SOLVER_FACTOR`, but not below :data:`REFERENCE_TOL`, the
    tightest the solve reaches (a scene already at or below it is checked at its own
    tolerance: the change is then zero, the solver's share beyond it unmeasured)."""
    sc = rungs(scene, CELLS.index(SOLVER_RUNG) + 1)[-1]
    tol = max(sc.newton.tol * SOLVER_FACTOR, min(sc.newton.tol, REFERENCE_TOL))
    return replace(sc, newton=replace(sc.newton, tol=tol))


def error_estimate(values: Sequence[float], reading: str = "samples", solver: float = 0.0) -> float:
    """The estimated error of ``values[-1]`` from values on rungs refined by 2 (module
    docstring; at least three values): read off the samples, ``max(|d_K|, |d_{K-1}|)``;
    read in continuous time, ``(2/3) max(|d_K|, |d_{K-1}| / 4)``; plus ``solver``, the
    change of the value in the solver check (:func:`solver_check`)."""
    check_reading(reading)
    v = [float(x) for x in values]
    if len(v) < 3 or not all(math.isfinite(x) for x in v):
        raise ValueError(f"values={values!r}: need at least three finite values (three rungs)")
    if isinstance(solver, bool) or not (isinstance(solver, int | float) and solver >= 0.0
                                        and math.isfinite(solver)):  # fmt: skip
        raise ValueError(f"solver={solver!r} must be a finite number >= 0 (an onset's change)")
    d_k, d_k1 = abs(v[-1] - v[-2]), abs(v[-2] - v[-3])
    if reading == "continuous":
        return 2.0 / 3.0 * max(d_k, d_k1 / 4.0) + solver
    return max(d_k, d_k1) + solver


@dataclass(frozen=True)
class ToleranceOnset:
    """The onset of a scene to a tolerance (:func:`onset_within`): t_c [s] and kappa3
    [1/m] on the rung ``n_cells`` x ``dt`` with their estimated errors, whether the
    tolerance was ``met``, every rung run (``grids``) and the solver check (``solver``:
    its grid, Newton tolerance, onset and the changes ``t_c_change``, ``kappa3_change``
    added to the estimates; None before the ``standard`` rung)."""

    t_c: float | None
    t_c_error: float | None
    kappa3: float | None
    kappa3_error: float | None
    n_cells: int
    dt: float
    rung: str
    met: bool
    status: str
    rtol: float
    paced_by: str
    note: str = ""
    grids: tuple[dict[str, Any], ...] = field(default_factory=tuple)
    reading: str = "samples"
    solver: dict[str, Any] | None = None

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready: every field, ``grids`` as a list."""
        out = asdict(self)
        out["grids"] = [dict(g) for g in self.grids]
        return out


Runner = Callable[[Scene], dict[str, Any]]
_FIELDS = ("status", *(f for pair in READINGS.values() for f in pair))


def _store_runner(store: Store | str | Path | None, compute: bool) -> Runner:
    def run(sc: Scene) -> dict[str, Any]:
        stale = "recompute" if compute else "error"
        row = run_sweep([sc], store, compute=compute, on_stale=stale, progress=False).iloc[0]
        return {k: (None if _missing(row.get(k)) else row[k]) for k in _FIELDS}

    return run


def _missing(x: Any) -> bool:
    return x is None or (isinstance(x, float) and math.isnan(x))


def onset_within(
    scene: Scene,
    rtol: float,
    *,
    max_cells: int = CELLS[-1],
    store: Store | str | Path | None = None,
    compute: bool = True,
    reading: str = DEFAULT_READING,
) -> ToleranceOnset:
    """The onset of ``scene`` on the cheapest rung (from ``fine``, N = 200) whose estimated
    errors of t_c and kappa3 are at most ``rtol`` times their values.

    The rungs (:func:`rungs`) run from the coarsest, the solver check
    (:func:`solver_check`) after the ``standard`` one; after each, the errors of the
    finest onset so far are estimated (:func:`error_estimate`, with the check's change
    of the onset as the solver's share); the first rung that
    meets ``rtol`` is returned, or, if none up to ``max_cells`` cells does, the finest
    one with ``met=False`` and a note saying what it reached.  Rungs without a buckled
    onset (a coarse grid that misses it) take no part in the estimate.  ``store``:
    read and write each rung as a record (:func:`~dyntorsion.studies.sweep.run_sweep`;
    ``compute=False`` only reads); without it the rungs are computed here and kept
    nowhere (``compute=False`` then is an error).  ``scene``'s own grid plays no part.
    ``reading``: which onset the rungs give, ``"continuous"`` (the default,
    :data:`DEFAULT_READING`) or ``"samples"`` (the paper's rule; :data:`READINGS`).
    """
    rtol = check_rtol(rtol)
    f_t, f_k = check_reading(reading)
    if not isinstance(scene, Scene):
        raise TypeError(f"scene={scene!r} must be a dyntorsion.buckling.scene.Scene")
    allowed = [n for n in CELLS if n >= VOUCHED]
    if max_cells not in allowed:
        raise ValueError(f"max_cells={max_cells!r}; allowed: {', '.join(map(str, allowed))}")
    if store is None and not compute:
        raise ValueError("compute=False reads the rungs from a store: give store")
    run: Runner = run_scene if store is None else _store_runner(store, compute)
    ladder = rungs(scene, CELLS.index(max_cells) + 1)
    _, paced_by = pacing_time(scene)
    grids: list[dict[str, Any]] = []
    solver: dict[str, Any] | None = None
    best: ToleranceOnset | None = None
    for sc in ladder:
        res = run(sc)
        grids.append(
            {
                "rung": rung_name(sc.n_cells),
                "n_cells": sc.n_cells,
                "dt": sc.dt,
                "status": res["status"],
                "t_c": res.get(f_t),
                "kappa3": res.get(f_k),
            }
        )
        if sc.n_cells == SOLVER_RUNG:
            solver = _solver(run, scene, grids[-1], f_t, f_k)
        best = _judge(grids, sc, rtol, paced_by, reading, solver)
        if best.met:
            return best
    assert best is not None
    rungs_buckled = sum(g["status"] == "buckled" and g["t_c"] is not None for g in best.grids)
    if best.t_c_error is None and rungs_buckled >= 3 and best.grids[-1]["status"] == "buckled":
        note = "the solver check found no onset: no error estimate"
    elif best.t_c_error is None:
        note = f"fewer than three rungs up to N = {max_cells} buckled: no error estimate"
    else:
        worst = max(best.t_c_error / abs(best.t_c), best.kappa3_error / abs(best.kappa3))
        note = (
            f"rtol={rtol:g} not met up to N = {max_cells} cells: the finest rung's estimated "
            f"relative error is {worst:.2g}; allow more cells (max_cells) or a looser rtol"
        )
    return replace(best, note=note)


def _solver(
    run: Runner, scene: Scene, standard: dict[str, Any], f_t: str, f_k: str
) -> dict[str, Any]:
    """The solver check of ``scene`` (:func:`solver_check`) beside its ``standard`` rung:
    the changes of t_c and kappa3 (None where either has no onset)."""
    sc = solver_check(scene)
    res = run(sc)
    out = {"n_cells": sc.n_cells, "dt": sc.dt, "newton_tol": sc.newton.tol,
           "status": res["status"], "t_c": res.get(f_t), "kappa3": res.get(f_k)}  # fmt: skip
    for q in ("t_c", "kappa3"):
        out[f"{q}_change"] = onset_change(
            (res["status"], standard["status"]), (out[q], standard[q])
        )
    return out


def onset_change(status: tuple[str, str], values: tuple[Any, Any]) -> float | None:
    """``|values[0] - values[1]|`` where both runs (``status``) buckled and both values are
    there (not None or nan), else None: the solver check's change of an onset against its
    ``standard`` rung."""
    if tuple(status) != ("buckled", "buckled") or any(_missing(v) for v in values):
        return None
    return abs(float(values[0]) - float(values[1]))


def _judge(
    grids: list[dict[str, Any]],
    sc: Scene,
    rtol: float,
    paced_by: str,
    reading: str,
    solver: dict[str, Any] | None,
) -> ToleranceOnset:
    """The onset of the last rung in ``grids`` with its error estimate, met or not."""
    last = grids[-1]
    seq = [g for g in grids if g["status"] == "buckled" and g["t_c"] is not None]
    common = dict(n_cells=sc.n_cells, dt=sc.dt, rung=last["rung"], rtol=rtol, paced_by=paced_by,
                  reading=reading, solver=solver)  # fmt: skip
    no_check = solver is None or solver["t_c_change"] is None or solver["kappa3_change"] is None
    if last not in seq or len(seq) < 3 or no_check:
        return ToleranceOnset(
            t_c=last["t_c"], t_c_error=None, kappa3=last["kappa3"], kappa3_error=None,
            met=False, status=last["status"], grids=tuple(grids), **common,
        )  # fmt: skip
    assert solver is not None
    e_t = error_estimate([g["t_c"] for g in seq], reading, solver["t_c_change"])
    e_k = error_estimate([g["kappa3"] for g in seq], reading, solver["kappa3_change"])
    met = (
        sc.n_cells >= VOUCHED
        and e_t <= rtol * abs(last["t_c"])
        and e_k <= rtol * abs(last["kappa3"])
    )
    return ToleranceOnset(
        t_c=last["t_c"], t_c_error=e_t, kappa3=last["kappa3"], kappa3_error=e_k, met=met,
        status=last["status"], grids=tuple(grids), **common,
    )  # fmt: skip
