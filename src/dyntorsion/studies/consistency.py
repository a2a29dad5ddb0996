"""The consistency map's scenes: which of the paper's unstated choices -- the
seed (size and form), the onset rule, the rates of Fig 10 -- reproduce which of its
dynamic claims.  The claims and the fits are in :mod:`dyntorsion.studies.claims`.

Every scene is simulated once and read with every onset rule of
:mod:`dyntorsion.buckling.onset_rules` (records of kind ``onset-rules``), so the rule costs
nothing.  Three sets, each a named preset (``python -m dyntorsion.studies.consistency``, run by
``make data-studies``):

* ``map``: the rate ladder :data:`LADDER` (0.01 to 50 rad/(m s), kappa0 = 10, as
  Fig 10) x the seeds :data:`MAP_SEEDS` (1e-20 to 1e-6, uniform [N/m] and point [N] at
  mid-span) at the map grid :data:`MAP_GRID` (N = 50: the cheapest level of the model
  whose error is measured, by the ``confirm`` set, against the standard grid);
* ``direct``: the Fig 8 and Fig 9 scenes (kappa0 = 0, a = 1.6, rho = 1500 and 5000)
  with every seed of the map at the standard grid :data:`CONFIRM_GRID`;
* ``confirm``: the ladder at the standard grid for the seeds :data:`CONFIRM_SEEDS`,
  the best cells of the map (a test checks they still are).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import Any

import pandas as pd

from ..buckling.onset_rules import KIND, RULES, run_rules
from ..buckling.scene import Scene
from ..buckling.seed import Perturbation
from ..model.rod import Rod
from ..store.results import Store
from ..store.workers import cached_map
from .presets import PRESET_CONTROL

__all__ = [
    "LADDER",
    "MAP_SEEDS",
    "MAP_GRID",
    "CONFIRM_GRID",
    "CONFIRM_SEEDS",
    "PRESETS",
    "grid_dt",
    "scenes",
    "table",
]

#: the rate ladder [rad/(m s)]: 1-2-5 steps over 3.7 decades, wider than Fig 10's rates
LADDER: tuple[float, ...] = (0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0)
#: the seed magnitudes of the map, every second decade
MAP_MAGNITUDES: tuple[float, ...] = tuple(10.0**k for k in range(-20, -5, 2))
#: the seeds: uniform (N/m along the rod) and point (N at mid-span), both along d1
MAP_SEEDS: tuple[Perturbation, ...] = (
    *(Perturbation(m) for m in MAP_MAGNITUDES),
    *(Perturbation(m, "point", 0.5) for m in MAP_MAGNITUDES),
)
#: (N, the largest dt [s], the largest twist increment a dt [1/m] per step)
MAP_GRID: tuple[int, float, float] = (50, 0.01, 0.1)
#: the standard grid that confirms a map cell and runs the direct Fig 8 and 9 scenes:
#: (N, the largest dt [s], the largest twist increment a dt [1/m] per step)
CONFIRM_GRID: tuple[int, float, float] = (100, 0.005, 0.05)
#: the seeds confirmed at the standard grid: the two map seeds around the closest cell's
#: seed (:func:`dyntorsion.studies.claims.closest`: 1.1e-16 N/m uniform; a test checks it)
CONFIRM_SEEDS: tuple[Perturbation, ...] = (Perturbation(1e-16), Perturbation(1e-14))


def grid_dt(a: float, grid: tuple[int, float, float]) -> float:
    """The step of ``grid`` at loading rate ``a``: the largest dt, shortened so that the
    twist grows by at most the grid's increment per step (the fast rates' short rise
    needs samples for the window rules)."""
    _, dt, dk = grid
    return float(min(dt, dk / a))


def _scene(a: float, kappa0: float, seed: Perturbation, grid, rho: float = 1500.0) -> Scene:
    sc = Scene(
        a=a,
        kappa0=kappa0,
        rod=Rod(rho=rho),
        seed=seed,
        n_cells=grid[0],
        dt=grid_dt(a, grid),
        until="first-peak",
    )
    return replace(sc, scheme=replace(sc.scheme, control=PRESET_CONTROL))


def _ladder(seeds, grid) -> list[Scene]:
    return [_scene(a, 10.0, p, grid) for p in seeds for a in LADDER]


def _direct() -> list[Scene]:
    return [_scene(1.6, 0.0, p, CONFIRM_GRID, rho) for p in MAP_SEEDS for rho in (1500.0, 5000.0)]


#: name -> the scenes of the set
PRESETS: dict[str, Callable[[], list[Scene]]] = {
    "map": lambda: _ladder(MAP_SEEDS, MAP_GRID),
    "direct": _direct,
    "confirm": lambda: _ladder(CONFIRM_SEEDS, CONFIRM_GRID),
}


def scenes(name: str) -> list[Scene]:
    """The scenes of the named set (:data:`PRESETS`)."""
    if name not in PRESETS:
        raise ValueError(f"preset={name!r}; allowed: {', '.join(PRESETS)}")
    return PRESETS[name]()


def _rows(scene: Scene, record: dict[str, Any]) -> list[dict[str, Any]]:
    res = record["result"]
    base = {
        "a": scene.a,
        "kappa0": scene.kappa0,
        "rho": scene.rod.rho,
        "seed": scene.seed.magnitude,
        "form": scene.seed.form,
        "n_cells": scene.n_cells,
        "dt": scene.dt,
        "status": res["status"],
    }
    rules = res.get("rules") or {}
    return [
        base
        | {
            "rule": rule,
            "t_c": rules.get(rule, {}).get("t_c", math.nan),
            "kappa3": rules.get(rule, {}).get("kappa3", math.nan),
        }
        for rule in RULES
    ]


def table(
    name: str,
    store: Store | str | Path | None = None,
    *,
    compute: bool = False,
    on_stale: str = "recompute",
    jobs: int = 1,
    progress: bool | None = False,
) -> pd.DataFrame:
    """One row per scene of the named set and onset rule (columns ``a, kappa0, rho, seed,
    form, n_cells, dt, status, rule, t_c, kappa3``), read from ``store``; with
    ``compute=True`` missing or stale scenes are simulated on ``jobs`` processes (a stale
    one refused instead with ``on_stale="error"``)."""
    scs = scenes(name)
    records = cached_map(
        scs,
        run_rules,
        KIND,
        store,
        jobs=jobs,
        on_stale=on_stale if compute else "error",
        compute=compute,
        progress=progress,
        command="python -m dyntorsion.studies.consistency",
    )
    return pd.DataFrame(
        [row for sc, (rec, _) in zip(scs, records, strict=True) for row in _rows(sc, rec)]
    )


if __name__ == "__main__":  # make data-studies
    import argparse

    from ..store.results import ON_STALE

    parser = argparse.ArgumentParser(description="compute the consistency map's scenes")
    parser.add_argument("--jobs", type=int, default=1)
    parser.add_argument("--on-stale", choices=ON_STALE, default="recompute")
    args = parser.parse_args()
    for name in PRESETS:
        df = table(name, compute=True, on_stale=args.on_stale, jobs=args.jobs, progress=None)
        print(f"{name}: {len(df) // len(RULES)} scenes")
