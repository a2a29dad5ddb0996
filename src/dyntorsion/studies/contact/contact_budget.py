"""The energy budget as the scheme keeps it (:mod:`dyntorsion.beyond.contact.budget`) on a
small rod through contact: which part of an energy residual is the load vector's
quadrature, the scheme's damping, or the contact's work.

PyElastica's plectoneme rod (tests/studies/test_contact_runs.py) turned 3 turns in 4 s on 30
cells, a stiff penalty (k = 1e7 N/m^2), with and without viscous damping (2 N s/m^2 and
2 N s), lambda_inf = -0.8 and -1 in time, and the two quadratures of the load vector:
the trapezoidal mean of the corners (eq 9, the paper's) and the midpoint rule, where
the nonlinear terms of eq (7) do no work in the pairing and the lines close to the
Newton solve.  Each run's result (the trapezoidal budget of the nodes, the scheme's lines)
goes to ``data/contact/budget.json`` (atomically, run by run; resumed).

Run: ``python -m dyntorsion.studies.contact.contact_budget`` or ``make data-contact``.
"""

from __future__ import annotations

import argparse
import json
import math

from ...beyond.contact.run import Contact, ContactScene, run_contact_scene
from ...buckling.scene import Scene
from ...buckling.seed import Perturbation
from ...buckling.turning import TurnHold
from ...genalpha.scheme import Scheme
from ...model.rod import Rod
from .records import DATA, provenance, result_json, run_missing

N, TURNS, T_TURN, T_END, DT = 30, 3.0, 4.0, 6.0, 0.01
ROD = dict(E=1e6, nu=-0.25, D=0.05, L=1.0, rho=1.0 / (math.pi * 0.025**2))
STIFFNESS, STEP = 1e7, 0.01
RUNS = [(N, quad, visc, lam) for quad in ("midpoint", "trapezoidal") for visc in (0.0, 2.0)
        for lam in (-0.8, -1.0)]  # fmt: skip
OUT = DATA / "contact" / "budget.json"
ROOTS = ("dyntorsion.beyond.contact.run:run_contact_scene",)
KEYS = ("stopped", "t_last", "first_contact_t", "first_self_contact_t", "energy",
        "energy_residual", "energy_scheme", "energy_residual_scheme", "wall_time")  # fmt: skip


def params() -> dict:
    return {"n_cells": N, "turns": TURNS, "t_turn": T_TURN, "t_end": T_END, "dt": DT,
            "rod": ROD, "stiffness": STIFFNESS, "max_step": STEP, "runs": [list(r) for r in RUNS]}  # fmt: skip


def run(n: int, quadrature: str, viscous: float, lam_t: float) -> dict:
    sc = Scene(history=TurnHold(TURNS, T_TURN, tau=0.1), ends="clamped-turned", rod=Rod(**ROD),
               n_cells=n, dt=DT, t_end=T_END, scheme=Scheme(lam_t=lam_t, quadrature=quadrature),
               seed=Perturbation(1e-3, form="point"))  # fmt: skip
    contact = Contact(stiffness=STIFFNESS, viscous=viscous, viscous_moment=viscous, max_step=STEP)
    res = run_contact_scene(ContactScene(sc, contact)).result()
    res = json.loads(result_json({k: res[k] for k in KEYS}))
    return {"n_cells": n, "quadrature": quadrature, "viscous": viscous, "lam_t": lam_t,
            "result": res}  # fmt: skip


def report(part: str, args: tuple, row: dict) -> str:
    r = row["result"]
    return (f"{args}: {str(r['stopped'])[:40]}, residual {r['energy_residual']:.3g}, "
            f"scheme {r['energy_residual_scheme']:.3g} ({r['wall_time']:.1f} s)")  # fmt: skip


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--jobs", type=int, default=1, help="runs at once (processes)")
    jobs = ap.parse_args(argv).jobs
    record = {"params": params(), "code": provenance(__spec__.name, ROOTS), "runs": []}
    run_missing(OUT, record, {"runs": RUNS}, {"runs": run},
                {"runs": lambda r: (r["n_cells"], r["quadrature"], r["viscous"], r["lam_t"])},
                report, jobs, indent=1)  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
