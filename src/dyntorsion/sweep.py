"""Sweeps of the buckling scene over loading rates (section 6, Fig 10), cached in ``data/``.

A :class:`~dyntorsion.scene.Scene` is everything one buckling run and its onset depend
on; :func:`~dyntorsion.scene.run_scene` computes it (both re-exported here);
:func:`run_sweep` runs a list of scenes on any
:class:`concurrent.futures.Executor`, writes each finished scene to a
:class:`~dyntorsion.results.Store` at once, and skips scenes the store already
holds, so a killed sweep resumes where it stopped.

The presets (:data:`PRESETS`) are the sweeps behind Fig 10 and the direct runs
of Figs 8 and 9 that the fitted law is checked against; ``make data`` computes
them all.
"""

from __future__ import annotations

import concurrent.futures as cf
import math
import os
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any

import pandas as pd

from .buckling import Perturbation
from .genalpha import Newton, StepControl
from .results import Store, digest
from .rod import Rod
from .scene import Scene, paper_law, run_scene, simulate_scene
from .statics import critical_twist, euler_load
from .workers import MissingResultError, cached_map

__all__ = [
    "Scene",
    "run_scene",
    "run_sweep",
    "simulate_scene",
    "cached_map",
    "MissingResultError",
    "KIND",
    "DATA",
    "default_store",
    "FIG10_RATES",
    "SEEDS",
    "PRESETS",
    "preset",
    "cached",
    "paper_law",
]

KIND = "buckling-onset"

#: the source tree's data folder (``data/scenes``)
DATA = Path(__file__).resolve().parents[2] / "data" / "scenes"


def default_store() -> Path:
    """The store used when none is given: ``$DYNTORSION_DATA`` if set, else :data:`DATA`."""
    env = os.environ.get("DYNTORSION_DATA")
    return Path(env) if env else DATA


def _row(scene: Scene, record: dict[str, Any], cached: bool) -> dict[str, Any]:
    res = record["result"]
    family = {k: v for k, v in record["params"].items() if k not in ("t_end", "dt")}
    family["history"] = {k: v for k, v in family["history"].items() if k != "a"}
    return {
        "a": scene.twist.rate,
        "kappa0": scene.twist.kappa0,
        "rho": scene.rod.rho,
        "rod": scene.rod.describe(),
        "tension": scene.tension.T,
        "ends": scene.ends.name,
        "seed": scene.seed.magnitude,
        "seed_form": scene.seed.form,
        "n_cells": scene.n_cells,
        "dt": scene.dt,
        "status": res.get("status") or _legacy_status(scene, res),
        "t_c": res["t_c"],
        "kappa3": res["kappa3"],
        "t_ref": res.get("t_ref"),
        "uncertainty_t": res["uncertainty_t"],
        "uncertainty_kappa3": res["uncertainty_kappa3"],
        "onset_error": res.get("onset_error"),
        "stopped": res["stopped"],
        "steps": res["steps"],
        "wall_time_s": record["provenance"].get("wall_time_s"),
        "key": record["key"],
        "family": digest(family)[:12],
        "cached": cached,
    }


def _legacy_status(scene: Scene, res: Mapping[str, Any]) -> str:
    """The status of a record written before records carried one (read with
    ``on_stale="accept"``): from its t_c and kappa3 alone."""
    if res["t_c"] is None:
        return "failed" if res["stopped"].startswith("failed") else "no-onset"
    try:
        kc = scene.kappa_cri()
    except ValueError:
        kc = -math.inf
    return "buckled" if res["t_c"] >= 0 and abs(res["kappa3"]) >= kc else "forced"


def run_sweep(
    scenes: Sequence[Scene],
    store: Store | str | Path | None = None,
    *,
    executor: cf.Executor | None = None,
    jobs: int = 1,
    on_stale: str = "recompute",
    compute: bool = True,
    progress: bool | None = None,
    log: Callable[[str], None] | None = None,
) -> pd.DataFrame:
    """Run (or read back) a sweep; one table row per scene, in the given order.

    Scenes that differ only in the loading rate and the time step share a ``family``
    (a hash of their other parameters): one rate sweep, ready for
    :func:`~dyntorsion.delay_law.fit_power_law`, also when the step follows the rate
    (:mod:`~dyntorsion.pacing`); a family holding one rate at two steps is two sweeps
    (``dyntorsion fit`` splits it by the step).

    Scenes already in ``store`` (default :func:`default_store`: ``$DYNTORSION_DATA`` or :data:`DATA`) are read, not recomputed;
    the others run on ``executor`` (any :class:`concurrent.futures.Executor`, for
    example ``dask.distributed.Client.get_executor()``), or on ``jobs`` local
    processes (``jobs=1``: in this process).  Each finished scene is written to
    the store the moment it completes, so an interrupted sweep loses at most the
    scenes that were running.  ``on_stale`` is passed to
    :meth:`~dyntorsion.results.Store.load`; ``compute=False`` only reads, and
    raises :class:`MissingResultError` for any scene the store lacks.
    """
    records = cached_map(
        scenes,
        run_scene,
        KIND,
        store,
        executor=executor,
        jobs=jobs,
        on_stale=on_stale,
        compute=compute,
        progress=progress,
        log=log,
        show="kappa3",
        command="dyntorsion sweep",
    )
    return pd.DataFrame([_row(scenes[i], *records[i]) for i in range(len(scenes))])


# ----------------------------------------------------------------- presets
#: 16 loading rates, 1.6 x 10^(k/6) for k = -9..6: 0.0506 to 16 rad/(m s), 2.5 decades
FIG10_RATES: tuple[float, ...] = tuple(float(1.6 * 10 ** (k / 6)) for k in range(-9, 7))

#: the seed stated in section 6 (1e-8 N, read as N/m along the rod) and the seed
#: that reproduces the onset times of Figs 8 and 9 (see the Fig 8 page)
SEEDS: dict[str, Perturbation] = {"stated": Perturbation(1e-8), "tiny": Perturbation(1e-17)}


def _fig10(seed: str, rates: Iterable[float] = FIG10_RATES, **grid: Any) -> list[Scene]:
    return [Scene(a=a, kappa0=10.0, seed=SEEDS[seed], **grid) for a in rates]


def _fig10_paced() -> list[Scene]:
    """The Fig 10 sweep in paced steps (:func:`~dyntorsion.pacing.paced`), until the
    first peak: the fast setting of the delay law."""
    from .pacing import paced

    return [paced(replace(sc, until="first-peak")) for sc in _fig10("stated")]


def _fig08_09(seed: str) -> list[Scene]:
    return [
        Scene(a=1.6, kappa0=0.0, rod=Rod(rho=rho), seed=SEEDS[seed]) for rho in (1500.0, 5000.0)
    ]


def _grid(seed: str) -> list[Scene]:
    ends = (FIG10_RATES[0], 1.6, FIG10_RATES[-1])
    return [
        sc for n, dt in ((50, 0.01), (200, 0.0025)) for sc in _fig10(seed, ends, n_cells=n, dt=dt)
    ]


#: the grid ladder of the accuracy-and-cost page: N x dt, Courant number 28.9 on the diagonal
LADDER_N: tuple[int, ...] = (25, 50, 100, 200, 400)
LADDER_DT: tuple[float, ...] = (0.02, 0.01, 0.005, 0.0025, 0.00125)
#: Newton tolerances of the sensitivity study
NEWTON_TOLS: tuple[float, ...] = (1e-3, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12)


def _ladder(a: float, kappa0: float) -> list[Scene]:
    return [Scene(a=a, kappa0=kappa0, n_cells=n, dt=dt) for n in LADDER_N for dt in LADDER_DT]


#: the seeds of the Fig 8 page: uniform magnitudes [N/m], then point forces of 1e-8 N
FIG08_SEEDS: tuple[Perturbation, ...] = (
    *(Perturbation(m) for m in (1e-6, 1e-8, 1e-10, 1e-12, 1e-14, 1e-16, 1e-17)),
    *(Perturbation(1e-8, "point", x) for x in (0.5, 0.1, 0.9)),
)


def _fig08_seeds() -> list[Scene]:
    return [Scene(a=1.6, kappa0=0.0, seed=seed) for seed in FIG08_SEEDS]


#: imperfection sensitivity ("Why is buckling delayed?"): three rates, uniform seeds
#: 1e-12..1e-4 N/m, point seeds of 1e-8 N at three places, and no seed at all
IMPERFECTION_RATES: tuple[float, ...] = (0.2, 1.6, 12.8)
IMPERFECTION_SEEDS: tuple[Perturbation, ...] = (
    *(Perturbation(10.0**k) for k in range(-12, -3)),
    *(Perturbation(1e-8, "point", x) for x in (0.1, 0.5, 0.9)),
    Perturbation(0.0),
)


def _imperfection() -> list[Scene]:
    return [Scene(a=a, kappa0=10.0, seed=p) for a in IMPERFECTION_RATES for p in IMPERFECTION_SEEDS]


#: mechanisms ("Why is buckling delayed?"): the gyroscopic term off, the bending rotary
#: inertia scaled by 0.1 and 10 (torsional wave speed unchanged), and the rotating-frame
#: transport term rho A (w x u) off (not a physical model: a probe of the spin coupling of
#: the lateral motion), at the three rates
MECHANISMS: dict[str, dict[str, Any]] = {
    "gyroscopic term off": {"terms": (("gyro", 0.0),)},
    "rotary inertia x 0.1": {"rotary_inertia_scale": 0.1},
    "rotary inertia x 10": {"rotary_inertia_scale": 10.0},
    "rotating-frame transport off": {"terms": (("wxu", 0.0),)},
}


def _mechanisms() -> list[Scene]:
    return [Scene(a=a, kappa0=10.0, **kw) for a in IMPERFECTION_RATES for kw in MECHANISMS.values()]


#: the delay law under an axial load ("Tension and compression" page): loads as fractions
#: of the clamped Euler load 4 pi^2 B / L^2, every third Fig 10 rate, the stated seed,
#: and the pretwist at the paper's ratio kappa0 / kappa_cri = 10 / 11.2335 of each load
TENSION_FRACTIONS: tuple[float, ...] = (-0.5, -0.25, 0.0, 0.5, 1.0)
TENSION_RATES: tuple[float, ...] = FIG10_RATES[::3]


def tension_scenes(fraction: float, rates: Iterable[float] = TENSION_RATES) -> list[Scene]:
    """The rate sweep at axial load ``fraction`` x the clamped Euler load (Table 1 rod)."""
    rod = Rod()
    T = fraction * euler_load(rod, "clamped")
    kappa0 = 10.0 if T == 0.0 else 10.0 * critical_twist(rod, T) / critical_twist(rod)
    return [Scene(a=a, kappa0=kappa0, tension=T, seed=SEEDS["stated"]) for a in rates]


def _newton(a: float, kappa0: float, seed: str = "stated") -> list[Scene]:
    return [
        Scene(a=a, kappa0=kappa0, seed=SEEDS[seed], newton=Newton(tol=tol)) for tol in NEWTON_TOLS
    ]


#: name -> function returning the scenes; ``make data`` runs them all
PRESETS: dict[str, Callable[[], list[Scene]]] = {
    "fig10": lambda: _fig10("stated"),
    "fig10-tiny-seed": lambda: _fig10("tiny"),
    "fig10-paced": _fig10_paced,
    "fig08-09": lambda: _fig08_09("stated"),
    "fig08-09-tiny-seed": lambda: _fig08_09("tiny"),
    "fig10-grid": lambda: _grid("stated"),
    "fig10-grid-tiny-seed": lambda: _grid("tiny"),
    "accuracy-fig08": lambda: _ladder(1.6, 0.0),
    "accuracy-fast": lambda: _ladder(16.0, 10.0),
    "newton-fig08": lambda: _newton(1.6, 0.0),
    "newton-fast": lambda: _newton(16.0, 10.0),
    "newton-fast-tiny-seed": lambda: _newton(16.0, 10.0, "tiny"),
    "fig08-seeds": _fig08_seeds,
    "imperfection": _imperfection,
    "mechanisms": _mechanisms,
    "tension": lambda: [sc for f in TENSION_FRACTIONS for sc in tension_scenes(f)],
}


def cached(name: str, store: Store | str | Path | None = None) -> pd.DataFrame:
    """The table of a named preset read from ``store`` (default :func:`default_store`: ``$DYNTORSION_DATA`` or :data:`DATA`), computing
    nothing: a missing scene raises :class:`MissingResultError`, a stale one
    :class:`~dyntorsion.results.StaleResultError`, each asking for ``make data``."""
    return run_sweep(preset(name), store, compute=False, on_stale="error", progress=False)


#: the step-size control every preset runs with (issue 15): identical to fixed steps
#: until the first rejected step, so the onsets do not move, and the runs go on past the
#: post-buckling whip to self-contact or t_end instead of stopping on a Newton failure
PRESET_CONTROL = StepControl()


def preset(name: str) -> list[Scene]:
    """The scenes of a named sweep (see :data:`PRESETS`), each with the step-size
    control :data:`PRESET_CONTROL`."""
    if name not in PRESETS:
        raise ValueError(f"preset={name!r}; allowed: {', '.join(PRESETS)}")
    return [
        replace(sc, scheme=replace(sc.scheme, control=PRESET_CONTROL)) for sc in PRESETS[name]()
    ]
