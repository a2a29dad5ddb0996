"""The runs of the page "After the onset" as records: step-size control against fixed
steps, the rod at self-contact on refined grids, and the energy balance along the whip.

Records of kind ``after-onset`` (one per fidelity level, cached in ``data/``, ``make
data``) hold the page's three tables, one row per run, so that the page reads them.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..buckling import detect_onset, simulate
from ..buckling.postbuckling import contact_measures, energy_balance
from ..buckling.scene import Scene, simulate_scene
from ..genalpha import Scheme, StepControl
from ..store.results import json_ready
from . import fidelity
from .page_records import level_loader, main_by_level
from .presets import FIG10_RATES, SEEDS

__all__ = ["KIND", "RATES", "params", "study", "load"]

KIND = "after-onset"

#: the two Fig 10 rates of the page (the fastest and the fourth fastest)
RATES = (FIG10_RATES[-1], FIG10_RATES[-4])
CONTROL = Scheme(control=StepControl())
#: the energy balance's run ends here [s]
ENERGY_T_END = 4.0


def params(level: str) -> dict[str, Any]:
    """The record's key at fidelity ``level``: the rates, the page's grid and the contact
    grids (the finest only above ``quick``)."""
    grid = fidelity.get("buckling", level)
    grids = [(100, 0.005), (200, 0.0025)] + ([(400, 0.00125)] if level != "quick" else [])
    return {
        "level": level,
        "rates": list(RATES),
        "grid": [grid.n_cells, grid.dt],
        "contact_grids": [list(g) for g in grids],
        "energy_t_end": ENERGY_T_END,
    }


def _control(n_cells: int, dt: float) -> list[dict[str, Any]]:
    rows = []
    for a in RATES:
        base = dict(a=a, kappa0=10.0, seed=SEEDS["stated"], n_cells=n_cells, dt=dt)
        fixed = simulate_scene(Scene(**base))
        ctl = simulate_scene(Scene(**base, scheme=CONTROL))
        rows.append({
            "a [rad/(m s)]": a,
            "t_c fixed [s]": detect_onset(fixed).t_c,
            "t_c control [s]": detect_onset(ctl).t_c,
            "fixed steps end": fixed.stopped.split(" (")[0],
            "control ends": ctl.stopped.split(" (")[0],
            "rejected": ctl.run.meta["control"]["rejected"],
        })  # fmt: skip
    return rows


def _contact(grids: list[list]) -> list[dict[str, Any]]:
    rows = []
    for a in RATES:
        for n, dt in grids:
            run = simulate_scene(
                Scene(a=a, kappa0=10.0, seed=SEEDS["stated"], n_cells=n, dt=dt, scheme=CONTROL)
            )
            m = contact_measures(run)
            rows.append({
                "a": a, "N": n, "Δt [s]": dt, "t_contact [s]": m.t_contact,
                "t_contact - t_c [s]": m.time_to_contact, "κ3(0) [1/m]": m.twist,
                "max curvature [1/m]": m.max_curvature, "half-energy width / L": m.width,
            })  # fmt: skip
    return rows


def _energy(n_cells: int, dt: float, t_end: float) -> list[dict[str, Any]]:
    rows = []
    for quadrature in ("trapezoidal", "midpoint"):
        scheme = Scheme(quadrature=quadrature, control=StepControl())
        run = simulate(
            Scene(a=RATES[0], kappa0=10.0, n_cells=n_cells, dt=dt, t_end=t_end, scheme=scheme),
            snapshots=np.arange(0.0, t_end + dt / 2, dt), on_failure="return",
        )  # fmt: skip
        eb = energy_balance(run)
        pre = eb.t <= detect_onset(run).t_c
        rows.append({
            "quadrature": quadrature,
            "end": run.stopped.split(" (")[0],
            "W at the end [J]": eb.W[-1],
            "max |E-E0-W| / W before onset": np.max(np.abs(eb.defect[pre])) / eb.W[-1],
            "max |E-E0-W| / W after onset": np.max(np.abs(eb.defect[~pre])) / eb.W[-1],
        })  # fmt: skip
    return rows


def study(p: dict[str, Any]) -> dict[str, Any]:
    """The three tables of :func:`params` ``p``: ``control``, ``contact``, ``energy``
    (lists of rows, JSON-ready: a non-finite number is None)."""
    n, dt = p["grid"]
    return json_ready({
        "control": _control(n, dt),
        "contact": _contact(p["contact_grids"]),
        "energy": _energy(n, dt, p["energy_t_end"]),
    })  # fmt: skip


#: the record at a fidelity level (see :func:`.page_records.level_loader`)
load = level_loader(KIND, params, study)


if __name__ == "__main__":  # make data-studies
    main_by_level(
        KIND,
        "compute the runs of 'After the onset'",
        load,
        lambda tables: ", ".join(f"{k} {len(v)} rows" for k, v in tables.items()),
    )
