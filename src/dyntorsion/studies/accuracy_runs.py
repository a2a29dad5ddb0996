"""The runs of the page "Accuracy and cost" as records: the fidelity presets' wave solves,
the fast routes to the Fig 8 onset and their wall times, long steps on three Fig 10
scenes, the fast onset estimate of every cached sweep scene, the paced Fig 10 sweep and
one ``--rtol`` run.

Records of kind ``accuracy-runs`` (one per fidelity level, cached in ``data/``, ``make
data-studies``) hold the page's tables, so that the page reads them.  The wall times in
them are measurements made as the record was computed (one process): the page shows them
as the record's.  Errors against values the page reads from other records (the ladders'
Richardson extrapolation, the cached sweeps) are left to the page: the record keeps the
raw onsets.
"""

from __future__ import annotations

import statistics
import time
from dataclasses import replace
from typing import Any

from ..beyond.predictions import estimate
from ..buckling import detect_onset, simulate
from ..buckling.scene import Scene, run_scene
from ..genalpha import LongSteps, Newton, Scheme
from ..model.rod import Rod
from ..store.results import json_ready
from ..waves import LinearLoading, SmoothRelease, solve
from . import fidelity
from . import presets as P
from . import tolerance as TOL
from . import wave_convergence as WC
from .page_records import level_loader, main_by_level

__all__ = ["KIND", "params", "study", "load"]

KIND = "accuracy-runs"

#: the Fig 8 scene of the fast routes and the settings (kappa0 = 0, a = 1.6, N = 50)
FIG8: dict[str, Any] = {"a": 1.6, "kappa0": 0.0, "n_cells": 50, "t_end": 18.0}
#: the fast routes: label -> time step [s]; Newton tolerance 1e-6, until the first peak
ROUTES: dict[str, float] = {
    "samples, N = 50, Δt = 0.05 s": 0.05,
    "continuous, N = 50, Δt = 0.15 s": 0.15,
}
#: the timed settings: label -> time step [s], Newton tolerance (None: the default), until
SETTINGS: dict[str, tuple[float, float | None, str]] = {
    "Δt = 0.02 s, to t = 18 s": (0.02, None, "contact"),
    "Δt = 0.02 s, until the first peak": (0.02, None, "first-peak"),
    "Δt = 0.05 s, Newton tol 10⁻⁶, until the first peak": (0.05, 1e-6, "first-peak"),
}
ROUTE_TOL = 1e-6
#: runs of each setting; the table keeps the median wall time
REPEATS = 5
#: the long steps' scenes: the slowest, the tenth and the fastest Fig 10 rate, kappa0 = 10
LONG_RATES = (P.FIG10_RATES[0], P.FIG10_RATES[9], P.FIG10_RATES[-1])
#: the wave scenes of the presets table: fidelity scene -> (time read [s], error norm)
WAVES: dict[str, tuple[float, str]] = {"waves": (0.04, "max"), "waves-incompatible": (0.01, "L1")}
#: the linear loading of Figs 3 and 4: rate [1/(m s)], initial twist [1/m]
LOADING = (0.1, 0.0)
#: the sweeps whose scenes the fast onset estimate is timed on
ESTIMATED = ("fig10", "fig10-tiny-seed", "imperfection")
PACED = "fig10-paced"
#: the ``--rtol`` run: the Fig 8 scene at 0.5 %, read off the samples
RTOL_RUN: dict[str, Any] = {"a": 1.6, "kappa0": 0.0, "rtol": 0.005, "reading": "samples"}


def params(level: str) -> dict[str, Any]:
    """The record's key at fidelity ``level``: the long steps' grid (the level's buckling
    grid) and everything else the runs depend on, the same at every level."""
    level = fidelity.check_level(level)
    grid = fidelity.get("buckling", level)
    return {
        "level": level,
        "fig8": dict(FIG8),
        "routes": {"dt": dict(ROUTES), "newton_tol": ROUTE_TOL},
        "settings": {k: list(v) for k, v in SETTINGS.items()},
        "repeats": REPEATS,
        "long_steps": {"rates": list(LONG_RATES), "kappa0": 10.0, "grid": [grid.n_cells, grid.dt]},
        "waves": {
            scene: {
                "t": t,
                "norm": norm,
                "grids": {lvl: fidelity.get(scene, lvl).solve_kwargs() for lvl in fidelity.LEVELS},
            }
            for scene, (t, norm) in WAVES.items()
        },
        "release": [WC.PARAMS["kappa0"], WC.PARAMS["rate"]],
        "loading": list(LOADING),
        "estimated": list(ESTIMATED),
        "paced": PACED,
        "rtol_run": dict(RTOL_RUN),
    }


def _fig8(p: dict[str, Any], dt: float, tol: float | None, until: str) -> Scene:
    newton = Newton() if tol is None else Newton(tol=tol)
    return Scene(**p["fig8"], dt=dt, newton=newton, until=until)


def _routes(p: dict[str, Any]) -> list[dict[str, Any]]:
    rows = []
    for label, dt in p["routes"]["dt"].items():
        run = simulate(_fig8(p, dt, p["routes"]["newton_tol"], "first-peak"))
        o = detect_onset(run)
        rows.append({
            "route": label, "dt [s]": dt, "steps": int(run.run.steps),
            "t_c [s]": o.t_c, "t_c continuous [s]": o.t_c_continuous,
        })  # fmt: skip
    return rows


def _settings(p: dict[str, Any]) -> list[dict[str, Any]]:
    # compile outside the timing
    simulate(Scene(a=1.6, kappa0=0.0, n_cells=10, dt=0.05, t_end=0.2))
    rows = []
    for label, (dt, tol, until) in p["settings"].items():
        walls = []
        for _ in range(p["repeats"]):
            start = time.perf_counter()
            run = simulate(_fig8(p, dt, tol, until))
            onset = detect_onset(run)
            walls.append(time.perf_counter() - start)
        rows.append({
            "setting (N = 50)": label, "steps": int(run.run.steps), "t_c [s]": onset.t_c,
            "wall, median [s]": statistics.median(walls),
        })  # fmt: skip
    return rows


def _long_steps(p: dict[str, Any]) -> list[dict[str, Any]]:
    q = p["long_steps"]
    n, dt = q["grid"]
    rows = []
    for a in q["rates"]:
        plain = Scene(a=a, kappa0=q["kappa0"], n_cells=n, dt=dt, until="first-peak")
        out, wall = {}, {}
        for name, scene in (
            ("dt", plain),
            ("long", replace(plain, scheme=Scheme(long_steps=LongSteps()))),
        ):
            start = time.perf_counter()
            out[name] = run_scene(scene)
            wall[name] = time.perf_counter() - start
        d, g = out["dt"], out["long"]
        rows.append({
            "a [rad/(m s)]": a, "t_c at dt [s]": d["t_c"], "t_c long [s]": g["t_c"],
            "uncertainty_t at dt [s]": d["uncertainty_t"],
            "long steps until [s]": g["long_steps"]["until"],
            "ended by": g["long_steps"]["ended"],
            "wall at dt [s]": wall["dt"], "wall long [s]": wall["long"],
        })  # fmt: skip
    return rows


def _waves(p: dict[str, Any]) -> list[dict[str, Any]]:
    rod = Rod.paper()
    problems = {
        "waves": SmoothRelease(*p["release"]),
        "waves-incompatible": LinearLoading(a=p["loading"][0], kappa0=p["loading"][1]),
    }
    # compile outside the timing
    solve(problems["waves"], rod=rod, times=[0.002], n_cells=10, dt=0.001)
    rows = []
    for scene, q in p["waves"].items():
        problem, t = problems[scene], q["t"]
        for lvl, kw in q["grids"].items():
            start = time.perf_counter()
            sol = solve(problem, rod=rod, times=[t], **kw)
            wall = time.perf_counter() - start
            err = sol.errors(problem.dalembert(sol.s, t, c=rod.c, L=rod.L)[None, :])
            rows.append({
                "scene": scene, "level": lvl, "N": kw["n_cells"], "dt [s]": kw["dt"],
                "t [s]": t, "norm": q["norm"], "error [1/m]": float(err[q["norm"]][0]),
                "wall [s]": wall,
            })  # fmt: skip
    return rows


def _estimates(p: dict[str, Any]) -> list[dict[str, Any]]:
    rows = []
    for name in p["estimated"]:
        for i, sc in enumerate(P.preset(name)):
            estimate(sc)  # the models are built once per mode count: time the passage alone
            start = time.perf_counter()
            e = estimate(sc)
            rows.append({
                "sweep": name, "index": i, "a": sc.a, "seed [N/m]": sc.seed.magnitude,
                "form": sc.seed.form, "modes": e.modes, "t_ref [s]": e.t_ref,
                "estimate [s]": time.perf_counter() - start,
            })  # fmt: skip
    return rows


def _paced(name: str) -> dict[str, Any]:
    scenes = P.preset(name)  # builds the estimate's linear models outside the timing
    start = time.perf_counter()
    live = [run_scene(sc) for sc in scenes]
    wall = time.perf_counter() - start
    return {"t_c [s]": [r["t_c"] for r in live], "wall [s]": wall}


def _rtol_run(q: dict[str, Any]) -> dict[str, Any]:
    start = time.perf_counter()
    res = TOL.onset_within(Scene(a=q["a"], kappa0=q["kappa0"]), q["rtol"], reading=q["reading"])
    wall = time.perf_counter() - start
    return {
        "t_c [s]": res.t_c, "t_c error [s]": res.t_c_error, "n_cells": res.n_cells,
        "dt [s]": res.dt, "wall [s]": wall,
        "grids": [{k: g[k] for k in ("rung", "n_cells", "dt", "status", "t_c", "kappa3")}
                  for g in res.grids],
    }  # fmt: skip


def study(p: dict[str, Any]) -> dict[str, Any]:
    """The runs of :func:`params` ``p`` (JSON-ready: a non-finite number is None).

    Returns
    -------
    dict
        ``routes``: one row per fast route of the Fig 8 scene (``FIG8``, Newton tolerance
        1e-6, until the first peak): its step ``dt [s]``, ``steps``, the onset read off
        the samples ``t_c [s]`` and in continuous time ``t_c continuous [s]``.
        ``settings``: one row per timed setting: ``steps``, ``t_c [s]`` and the median
        ``wall, median [s]`` of ``repeats`` runs (simulation and onset detection).
        ``long_steps``: one row per rate ``a [rad/(m s)]``: ``t_c`` at fixed steps and
        with long steps [s], the fixed-step run's ``uncertainty_t`` [s], until when the
        long steps ran [s] and what ``ended`` them, and both runs' walls [s].
        ``waves``: one row per wave scene and level: grid, the time read ``t [s]``, the
        error ``norm`` and its value ``error [1/m]`` of kappa3 against d'Alembert, and
        the solve's ``wall [s]``.
        ``estimates``: one row per scene of the ``estimated`` sweeps (``index`` in its
        preset): rate, seed, the estimate's ``modes``, threshold time ``t_ref [s]`` and
        the time of one estimate ``estimate [s]``.
        ``paced``: the onsets ``t_c [s]`` of the paced sweep, in preset order, and the
        ``wall [s]`` of all of them.
        ``rtol_run``: the ``--rtol`` run's ``t_c [s]``, its estimated error ``t_c error
        [s]``, the grid it stopped on, its ``wall [s]`` and its ``grids`` (one row per
        rung: rung, n_cells, dt, status, t_c, kappa3).
    """
    return json_ready({
        "routes": _routes(p),
        "settings": _settings(p),
        "long_steps": _long_steps(p),
        "waves": _waves(p),
        "estimates": _estimates(p),
        "paced": _paced(p["paced"]),
        "rtol_run": _rtol_run(p["rtol_run"]),
    })  # fmt: skip


#: the record at a fidelity level (see :func:`.page_records.level_loader`)
load = level_loader(KIND, params, study)


def _summary(runs: dict[str, Any]) -> str:
    rows = ", ".join(f"{k} {len(v)} rows" for k, v in runs.items() if isinstance(v, list))
    return f"{rows}; {len(runs['paced']['t_c [s]'])} paced scenes"


if __name__ == "__main__":  # make data-studies
    main_by_level(KIND, "compute the runs of 'Accuracy and cost'", load, _summary)
