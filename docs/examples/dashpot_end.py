"""A new end set in one file: eq (30)'s ends with a torsional dashpot at s = L instead of
the end held in rotation, m3(L) = C k3(L) = -c w3(L), registered by name on import.

A dashpot of c = C / c_t (c_t the torsional wave speed) matches the rod's torsional
impedance: a twist wave reaching s = L leaves no reflection, so the ramp kappa3(0, t) = a t
on the unstressed rod arrives at s = L as kappa3(L, t) = a (t - L / c_t) and stays so.
The set declares no static critical twist (the refusal names it).  (A torsional spring
acts on the end's angle, which is no field of the rod's first-order system: it is not a
linear relation between the fields at the end, so a dashpot is the example.)"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from dyntorsion.app.cli import main
from dyntorsion.buckling.scene import Scene, simulate
from dyntorsion.model.ends import EQ30, Ends, Relation, register
from dyntorsion.model.rod import Rod
from dyntorsion.studies.sweep import run_sweep

ROD = Rod()
#: k3 + w3 / c_t = 0 at s = L: the matched dashpot, c = C / c_t
DASHPOT = register(
    Ends(
        "clamped-dashpot",
        EQ30.left,
        ("w1", "w2", "k3", "u1", "u2", "n3"),
        "eq (30) with a torsional dashpot of the rod's own impedance at s = L",
        relations=(Relation("right", "k3", (("w3", 1.0 / ROD.c),)),),
    )
)


def scene(a: float = 1.0, t_end: float = 0.06) -> Scene:
    """The ramp a t from the unstressed straight rod (kappa0 = 0, no seed) at the
    dashpot ends."""
    return Scene(a=a, kappa0=0.0, ends="clamped-dashpot", seed=0.0, n_cells=50, dt=1e-4,
                 t_end=t_end)  # fmt: skip


def demo(store: Path) -> dict:
    """The far end's twist against the unreflected wave, then store, sweep and CLI."""
    sc = scene()
    run = simulate(sc, progress=False)
    late = run.t > 1.5 * sc.rod.L / sc.rod.c
    wave = sc.a * (run.t[late] - sc.rod.L / sc.rod.c)
    error = float(np.max(np.abs(run.kappa3_right[late] - wave)) / np.max(wave))
    table = run_sweep([scene(1.0, 0.004), scene(2.0, 0.004)], store, progress=False)
    record = json.loads(next(Path(store).glob(f"*-{table['key'][0]}.json")).read_text())
    back = Scene.from_params(record["params"])
    status = main([
        "buckle", "--plugin", __file__, "--ends", "clamped-dashpot", "--a", "1", "--seed", "0",
        "--n-cells", "50", "--dt", "1e-4", "--t-end", "0.004", "--store", str(store),
    ])  # fmt: skip
    return {"error": error, "table": table, "back": back, "scene": scene(1.0, 0.004),
            "cli": status, "refused": _refusal(sc)}  # fmt: skip


def _refusal(sc: Scene) -> str:
    try:
        sc.kappa_cri()
    except ValueError as err:
        return str(err)
    return ""
