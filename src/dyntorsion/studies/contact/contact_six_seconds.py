"""The contact checks' scene followed toward t = 6 s on a grid that resolves it: the paper's
a = 16 rod (kappa0 = 10 1/m) past its first self-contact, through loop formation and
intertwining, with every contact check read at the end (penetration, passage, link =
twist + writhe, the energy budget as the scheme keeps it).

The done-when asks for this run at ``--fidelity quick`` (50 cells, each 20 D long): it
stops there as under-resolved before the contact (``data/contact/first_contact.json``, its
N = 50 run), so the same scene runs here on N = 800 (cells of 1.25 D) with lambda_inf = -0.8,
the scene's step 0.01 s cut to the contact's longest substep 2.5e-4 s near contact, exactly
as ``dyntorsion buckle --a 16 --kappa0 10 --contact --t-end 6 --n-cells 800 --dt 0.01
--lam-t -0.8 --json`` runs it.  Not at the paper's lambda_inf = -1: without damping in time
the step control cuts the steps near contact far shorter (to 3.3 s, 4267 contact steps
against 495, first_contact.json), many times the cost of the run at -0.8.

The run's whole result, its histories at the checks (every 0.01 s: link, twist, writhe,
contact sites, overlap, the twisting moment at s = 0, plectoneme turns) and its centreline
at ``SHOTS`` and at the end are written to ``data/contact/six_seconds.json`` as it ends
(atomically).

Run: ``python -m dyntorsion.studies.contact.contact_six_seconds`` or ``make data-contact`` (the rod passes
through itself at 3.61 s, the Past contact page; the run's wall time is in the record).
"""

from __future__ import annotations

import json

import numpy as np

from ...beyond.contact.run import Contact, ContactScene, run_contact_scene
from ...buckling.scene import Scene
from ...genalpha.scheme import Scheme
from .records import DATA, provenance, result_json, run_script, summary

A, KAPPA0, DT, T_END = 16.0, 10.0, 0.01, 6.0
RUNS = [(800, -0.8)]  # N, lambda_inf
#: times of the recorded centrelines [s] (the page's snapshots), positions to 0.1 um
SHOTS = (3.2, 3.3, 3.5, 4.0, 4.5, 5.0, 5.5, 6.0)
DIGITS = 7
OUT = DATA / "contact" / "six_seconds.json"
ROOTS = ("dyntorsion.beyond.contact.run:run_contact_scene",)


def params() -> dict:
    return {"a": A, "kappa0": KAPPA0, "dt": DT, "t_end": T_END, "runs": [list(r) for r in RUNS],
            "shots": list(SHOTS), "contact": Contact().params()}  # fmt: skip


def run(n: int, lam_t: float) -> dict:
    """The scene on N = n cells with lambda_inf = lam_t to ``T_END``: its whole result, the
    histories at the checks (with the plectoneme turns) and the centreline at ``SHOTS``
    and at the end."""
    scene = Scene(a=A, kappa0=KAPPA0, t_end=T_END, n_cells=n, dt=DT, scheme=Scheme(lam_t=lam_t))
    run = run_contact_scene(ContactScene(scene, Contact()))
    t, r = run.history["t"], run.history["r"]
    shots = {f"{ts:g}": np.round(r[int(np.argmin(np.abs(t - ts)))], DIGITS).tolist()
             for ts in SHOTS if ts <= t[-1] + 1e-9}  # fmt: skip
    return {"n_cells": n, "lam_t": lam_t, "result": json.loads(result_json(run.result())),
            "history": run.histories(plectoneme=True), "shots": shots,
            "final_centreline": np.round(r[-1], DIGITS).tolist()}  # fmt: skip


def report(row: dict) -> str:
    res = row["result"]
    return summary(f"N = {row['n_cells']}, lambda_inf {row['lam_t']}", res,
                   overlap=f"{res['max_penetration_over_D']:.4f} D",
                   energy=f"{res['energy_residual_scheme']:.2e}",
                   link_gap=f"{res['max_link_gap_turns']:.4f} turns")  # fmt: skip


def main(argv: list[str] | None = None) -> int:
    record = {"params": params(), "code": provenance(__spec__.name, ROOTS), "runs": []}
    return run_script(argv, __doc__, OUT, record, RUNS, run,
                      lambda r: (r["n_cells"], r["lam_t"]), report)  # fmt: skip


if __name__ == "__main__":
    raise SystemExit(main())
