"""Convergence in N and in the step of the first self-contact of the paper's a = 16 scene
past the onset, with the implicit contact of
:mod:`dyntorsion.beyond.contact`: each grid run from rest to ``T_END`` (just past the
first contact), and the time of first contact, Lk - Tw - Wr at its largest, the largest
bending within a cell and the energy residual written to
``data/contact/first_contact.json`` (atomically, after every run: an interrupted sweep
resumes where it stopped when the parameters, the script and the code fingerprint of the
contact runs are unchanged).

Grids: N = 50 (the "quick" grid), 100, 200, 400, 800 at the default longest substep near contact (2.5e-4 s),
and at N = 400 the longest substep halved twice.  The scene's step is 0.01 s throughout
(at a = 16 the driven end turns 0.16 rad in it, so every step is crossed in substeps:
the step that matters is the substep).

Past the first contact (``PAST``): N = 200 at the paper's lambda_inf = -1 and N = 400 with
lambda_inf = -0.8 in time, each to a few tenths of a second past it; then the two
centrelines the contact can act on (``Contact.route``: the time route left to run, or
anchored on the shape of the 12 fields after every step) side by side at N = 400 and 800,
lambda_inf = -0.8, to t = 3.3 s, and the time route at N = 800 with lambda_inf = -0.9 and
-1 (how much of the energy residual is the scheme's damping).  Their whole results
(energy budget, drifts of the centreline, cost) are kept.

Run: ``python -m dyntorsion.studies.contact.contact_convergence [--jobs J]`` (about 1.5 h on one core before the
sparse contact solve of :mod:`dyntorsion.genalpha.low_rank`).
"""

from __future__ import annotations

import argparse
import json

from ...beyond.contact.run import Contact, ContactScene, run_contact_scene
from ...buckling.scene import Scene
from ...genalpha.scheme import Scheme
from .records import DATA, provenance, result_json, run_missing

A, KAPPA0, DT, T_END = 16.0, 10.0, 0.01, 3.2
GRIDS = [(50, 2.5e-4), (100, 2.5e-4), (200, 2.5e-4), (400, 2.5e-4), (800, 2.5e-4), (400, 1.25e-4),
         (400, 6.25e-5)]  # fmt: skip
PAST = [(200, -1.0, 3.3, "time"), (400, -0.8, 3.45, "time"), (400, -0.8, 3.3, "time"),
        (400, -0.8, 3.3, "anchored"), (800, -0.8, 3.3, "time"), (800, -0.8, 3.3, "anchored"),
        (800, -0.9, 3.3, "time"), (800, -1.0, 3.3, "time")]  # N, lambda_inf, end time, route  # fmt: skip
OUT = DATA / "contact" / "first_contact.json"
KEYS = ("first_contact_t", "first_self_contact_t", "first_fixture_contact_t", "max_link_gap_turns", "max_cell_bend", "energy_residual",
        "max_penetration_over_D", "stopped", "wall_time")  # fmt: skip


def params() -> dict:
    return {"a": A, "kappa0": KAPPA0, "dt": DT, "t_end": T_END,
            "grids": [list(g) for g in GRIDS], "past": [list(p) for p in PAST],
            "contact": Contact().params()}  # fmt: skip


#: where the runs' computation starts: the record carries the fingerprint of every package
#: definition reachable from here (:mod:`dyntorsion.store.fingerprint`)
ROOTS = ("dyntorsion.beyond.contact.run:run_contact_scene",)


def grid_run(n: int, step: float) -> dict:
    """The run from rest to ``T_END`` on N = n with the longest substep ``step``."""
    scene = Scene(a=A, kappa0=KAPPA0, t_end=T_END, n_cells=n, dt=DT)
    res = run_contact_scene(ContactScene(scene, Contact(max_step=step))).result()
    return json.loads(result_json({"n_cells": n, "max_step": step, **{k: res[k] for k in KEYS}}))


def past_run(n: int, lam_t: float, t_end: float, route: str) -> dict:
    """The run past the first contact to ``t_end`` (its whole result)."""
    scene = Scene(a=A, kappa0=KAPPA0, t_end=t_end, n_cells=n, dt=DT,
                  scheme=Scheme(lam_t=lam_t))  # fmt: skip
    res = run_contact_scene(ContactScene(scene, Contact(route=route))).result()
    res = json.loads(result_json(res))  # numpy scalars as Python ones, NaN as null
    return {"n_cells": n, "lam_t": lam_t, "t_end": t_end, "route": route, "result": res}


def report(part: str, args: tuple, row: dict) -> str:
    res = row if part == "runs" else row["result"]
    return (
        f"{part} {args}: {str(res['stopped'])[:60]}, first contact "
        f"{res['first_contact_t']} s ({res['wall_time']:.0f} s)"
    )


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--jobs", type=int, default=1, help="runs at once (processes)")
    jobs = ap.parse_args(argv).jobs
    record = {"params": params(), "code": provenance(__spec__.name, ROOTS), "runs": [], "past": []}
    run_missing(OUT, record, {"runs": GRIDS, "past": PAST}, {"runs": grid_run, "past": past_run},
                {"runs": lambda r: (r["n_cells"], r["max_step"]),
                 "past": lambda r: (r["n_cells"], r["lam_t"], r["t_end"], r["route"])},
                report, jobs, indent=1)  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
