"""PyElastica's plectoneme scene in dyntorsion within the bounds of the contact checks
(:mod:`dyntorsion.beyond.contact.checks`): written to
``data/bench/plectoneme_bounds.json``.

The scene of :mod:`.plectoneme_dyntorsion` (imported from there: the rod, the
turning and holding of the end, the damping, the seed, the contact's reach ``min_arc``),
on finer grids and with the contact ``STIFFNESS_FACTOR`` times stiffer than there.  The
side-by-side record (N <= 200, the package's default stiffness) overlaps by up to 2.2 %
of the diameter and its Lk - Tw - Wr drifts by 0.042 turns on 200 cells, against the
bounds of the contact checks, 1 % D and 0.01 turns.  The drift falls at about second order in N
(0.088 turns on 150 cells, 0.042 on 200); the overlap falls as the contact stiffens
(a penalty law's overlap goes as the load over the stiffness).  So the runs here:
N = 400 and 500 cells at dt = 0.02 s, the contact 4 times stiffer.  Each run reports
the contact checks over the whole 100 s: the largest overlap, the largest
|Lk - Tw - Wr| (a passage of the rod through itself would have ended the run), the
energy residual, and the writhe and plectoneme turns at the end.

Run: ``python -m dyntorsion.studies.contact.plectoneme_bounds [--jobs 2]`` or ``make bench-bounds``
(each run's wall time is in the record).  Resumes like the other records
(:mod:`.records`).
"""

from __future__ import annotations

import dataclasses

from ...beyond.contact.run import ContactScene
from . import plectoneme_dyntorsion as dyn
from .records import DATA, provenance, run_script, summary

#: the contact stiffness of these runs against the side-by-side record's (dyn.STIFFNESS)
STIFFNESS_FACTOR = 4.0
#: (cells, time step [s]) of each run
RUNS = [(500, 0.02), (400, 0.02)]
OUT = DATA / "bench" / "plectoneme_bounds.json"
IMPORTS = (dyn.__name__, dyn.SCENE)


def contact_scene(n: int, dt: float) -> ContactScene:
    cs = dyn.contact_scene(n, dt)
    stiffer = dataclasses.replace(cs.contact, stiffness=STIFFNESS_FACTOR * dyn.STIFFNESS)
    return ContactScene(cs.scene, stiffer)


def params() -> dict:
    return {"scene": "benchmarks/plectoneme_dyntorsion.py", "stiffness_factor": STIFFNESS_FACTOR,
            "stiffness": STIFFNESS_FACTOR * dyn.STIFFNESS, "runs": [list(r) for r in RUNS],
            "key": contact_scene(*RUNS[0]).params()}  # fmt: skip


def one(n: int, dt: float) -> dict:
    return dyn.row(contact_scene(n, dt), n, dt)


def report(row: dict) -> str:
    res = row["result"]
    return summary(f"N = {row['n_cells']}, dt = {row['dt']:g}", res,
                   overlap=f"{res['max_penetration_over_D']:.4f} D",
                   link_gap=f"{res['max_link_gap_turns']:.4f} turns",
                   energy_residual=f"{res['energy_residual']:.2e}",
                   writhe=f"{res['writhe_turns']:.3f}")  # fmt: skip


def main(argv: list[str] | None = None) -> int:
    record = {"params": params(), "code": provenance(__spec__.name, dyn.ROOTS, IMPORTS), "runs": []}
    return run_script(argv, __doc__, OUT, record, RUNS, one,
                      lambda r: (r["n_cells"], r["dt"]), report)  # fmt: skip


if __name__ == "__main__":
    raise SystemExit(main())
