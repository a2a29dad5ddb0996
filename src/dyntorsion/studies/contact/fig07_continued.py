"""The paper's Fig 7 scene followed past its first contact, written to
``data/contact/fig07_continued.json``.

The scene of Fig 7 and Fig 8 (Table 1 rod, kappa0 = 0, a = 1.6 rad/(m s), the stated seed,
clamped ends of eq 30) with the package's contact (:class:`~dyntorsion.beyond.contact.run.
Contact`, defaults: a penalty of 5e7 N/m^2 with damping ratio 0.5 on the time route of the
centreline, the axis beyond both clamps an obstacle, substeps of at most 2.5e-4 s near
contact) from rest, on the grids ``RUNS``: lambda_inf = -0.8 in time, as the runs past
contact at a = 16 (``data/contact/first_contact.json``: at the paper's -1 a third of the
contact steps' Newton solves failed there), N = 800 and 1600 (coarser grids fail the checks
within a second of the first contact: a Newton failure, the rod passing through itself,
the time route of the centreline turned away from the shape of the 12 fields),
N = 800 to 17.6 s and N = 1600 to 17.5 s, so that what the page shows can be told from the
grid's error.  The contact steps grow dearer as the loop coils; each run's wall time is in
the record.

Every run records, every ``Contact.check`` = 0.01 s: link, twist and writhe, contact sites,
the deepest overlap, the twisting moment at s = 0; and the centreline at the times ``SHOTS``
(the snapshots of the page) and at the end.  Written atomically after every run; a rerun
resumes when the parameters, this script and the code fingerprint of
``run_contact_scene`` are unchanged (else it starts again).

Run: ``python -m dyntorsion.studies.contact.fig07_continued [--jobs J]``.
"""

from __future__ import annotations

import json

import numpy as np

from ...beyond.contact.run import Contact, ContactScene, run_contact_scene
from ...buckling.scene import Scene
from ...genalpha.scheme import Scheme
from .records import DATA, provenance, result_json, run_script, summary

A, KAPPA0 = 1.6, 0.0
#: the scene's step away from contact [s] (the substeps near it: Contact.max_step)
DT = 0.01
#: (cells, lambda_inf in time, end [s]) of each run
RUNS = [(800, -0.8, 17.6), (1600, -0.8, 17.5)]
#: times of the recorded centrelines [s] (the page's snapshots), positions to 0.1 um
SHOTS = tuple(float(t) for t in np.round(np.arange(16.9, 17.6 + 1e-9, 0.05), 2))
DIGITS = 7
OUT = DATA / "contact" / "fig07_continued.json"
ROOTS = ("dyntorsion.beyond.contact.run:run_contact_scene",)


def contact_scene(n: int, lam_t: float, t_end: float) -> ContactScene:
    scene = Scene(a=A, kappa0=KAPPA0, n_cells=n, dt=DT, t_end=t_end,
                  scheme=Scheme(lam_t=lam_t))  # fmt: skip
    return ContactScene(scene, Contact())


def params() -> dict:
    return {"a": A, "kappa0": KAPPA0, "dt": DT,
            "runs": [list(r) for r in RUNS], "shots": list(SHOTS),
            "key": contact_scene(*RUNS[0]).params()}  # fmt: skip


def one(n: int, lam_t: float, t_end: float) -> dict:
    run = run_contact_scene(contact_scene(n, lam_t, t_end))
    res = json.loads(result_json(run.result()))
    h = run.history
    t = h["t"]
    shots = {f"{ts:g}": np.round(h["r"][int(np.argmin(np.abs(t - ts)))], DIGITS).tolist()
             for ts in SHOTS if ts <= t[-1] + 1e-9}  # fmt: skip
    return {
        "n_cells": n, "lam_t": lam_t, "t_end": t_end, "result": res,
        "history": run.histories(),
        "shots": shots,
        "final_centreline": np.round(h["r"][-1], DIGITS).tolist(),
    }  # fmt: skip


def report(row: dict) -> str:
    res = row["result"]
    return summary(f"N = {row['n_cells']}, lambda_t = {row['lam_t']:g}", res,
                   first_contact=f"{res['first_contact_t']}", link=f"{res['link_turns']:.3f}",
                   writhe=f"{res['writhe_turns']:.3f}", sites=f"{res['max_contact_sites']}")  # fmt: skip


def main(argv: list[str] | None = None) -> int:
    record = {"params": params(), "code": provenance(__spec__.name, ROOTS), "runs": []}
    return run_script(argv, __doc__, OUT, record, RUNS, one,
                      lambda r: (r["n_cells"], r["lam_t"], r["t_end"]), report)  # fmt: skip


if __name__ == "__main__":
    raise SystemExit(main())
