"""A new distributed load in one file: a uniform lateral force per length brought in
smoothly, q(t) = q0 (1 - exp(-(t / tau)^4)) along d1, registered by its ``kind``.

It bends the untwisted rod of eq (30)'s ends (both clamped laterally) quasi-statically
into the clamped beam's deflection, whose largest value is q0 L^4 / (384 B) at
mid-span: :func:`demo` checks that, and runs the load through a Scene, the store, a small
sweep and the command line with ``--plugin``.  (An elastic foundation -k r depends on the
rod's state, which a :class:`~dyntorsion.buckling.loads.DistributedLoad` of (s, t) cannot
express: that needs state-dependent sources in the engine.)"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dyntorsion.app.cli import main
from dyntorsion.buckling.loading import Polynomial
from dyntorsion.buckling.loads import DistributedLoad
from dyntorsion.buckling.scene import Scene, simulate
from dyntorsion.buckling.seed import Perturbation
from dyntorsion.studies.sweep import run_sweep


@dataclass(frozen=True)
class SteadyWind(DistributedLoad):
    """q0 [N/m] along d1 on the whole rod, brought in over about ``tau`` [s]."""

    q0: float
    tau: float = 40.0
    kind = "steady-wind"

    def force(self, s, t, length):
        f = np.zeros((s.size, 3))
        f[:, 0] = self.q0 * -np.expm1(-((t / self.tau) ** 4))
        return f


def scene(q0: float = 1e-6, t_end: float = 120.0, n_cells: int = 20) -> Scene:
    """The untwisted rod (a zero twist history) under the wind, no seed."""
    return Scene(history=Polynomial((0.0,)), loads=(SteadyWind(q0),), seed=Perturbation(0.0),
                 n_cells=n_cells, dt=0.1, t_end=t_end)  # fmt: skip


def deflection(n_cells: int) -> float:
    """The largest lateral deflection [m] of the rod at the end of the run on n_cells."""
    sc = scene(n_cells=n_cells)
    run = simulate(sc, snapshots=[sc.t_end], progress=False)
    return float(np.max(np.abs(run.shape(sc.t_end)[1][:, 0])))


def demo(store: Path) -> dict:
    """The mid-span deflection against the beam's on 20 and 40 cells (second order in the
    cell length: Richardson's extrapolation), then store, sweep and command line."""
    sc = scene()
    coarse, fine = deflection(20), deflection(40)
    beam = 1e-6 * sc.rod.L**4 / (384 * sc.rod.B)
    table = run_sweep([scene(1e-6, 20.0), scene(2e-6, 20.0)], store, progress=False)
    record = json.loads(next(Path(store).glob(f"*-{table['key'][1]}.json")).read_text())
    back = Scene.from_params(record["params"])
    status = main([
        "buckle", "--plugin", __file__, "--load", "steady-wind:q0=2e-6", "--history", "poly:0",
        "--seed", "0", "--n-cells", "20", "--dt", "0.1", "--t-end", "20", "--store", str(store),
    ])  # fmt: skip
    return {"coarse": coarse, "fine": fine, "richardson": (4 * fine - coarse) / 3, "beam": beam, "table": table, "back": back,
            "scene": scene(2e-6, 20.0), "cli": status}  # fmt: skip
