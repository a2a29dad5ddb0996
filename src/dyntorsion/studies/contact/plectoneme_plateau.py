"""Does the torque of a longer ply level off at the two-ply plateau?: slow
twisting under tension on a rod 1.6 times as long as :mod:`.plectoneme_tension`'s,
written to ``data/bench/plectoneme_plateau.json``.

The section, material, tension, damping, contact and seed of ``plectoneme_tension.py``
(imported from there: one place for them; the ply theory's eps = a sqrt(T / B) = 0.1), on
a rod ``LENGTH`` = 4 m long (L sqrt(T / B) = 16) with cells of the same length
(``N_CELLS`` = 160, 0.5 D), turned at the same rate (0.05 turns/s) by ``TURNS`` = 11 turns,
about 7 past the static critical rotation, and held.  (Not longer when first
run: the package's Greenhill determinant, ``statics.greenhill_clamped``, then scanned the
critical moment up to 40 B / L only, which a clamped rod more than about 19 tension
lengths long exceeds; it now scans as far as the rod's length asks.)  On
the 2.5 m rod the plectoneme is little more than a turn long when the turning stops, and
the torque over the first turn after the jump lies 1.22 times above the two-ply plateau
(``plectoneme_tension.json``); the question here is whether a longer ply levels off at the
theory's torque.

Measured (this record; the Past contact page reads its numbers from it): no.  The jump
itself puts most of the rod into the ply, and while Lk - Tw - Wr stays within 0.05 turns
the torque rises well above the two-ply plateau as the ply grows.  Past that the ply uses
up the rod, the 0.5 D cells do not hold the compact ply and the run fails the contact
checks (Lk - Tw - Wr and the energy residual).  A plateau needs a rod many tension lengths
longer.

Every 0.1 s: the twisting moment at s = 0, link, twist, writhe, contact sites, the
overlap, the far end's axial position and the plectoneme turns of the centreline.
Written atomically when the run ends; a record whose parameters, script, the script it
imports or code fingerprint differ from today's is stale.

Run: ``python -m dyntorsion.studies.contact.plectoneme_plateau`` or ``make bench-plateau``
(the run's wall time is in the record).
"""

from __future__ import annotations

import time

from ...model.rod import Rod
from . import plectoneme_tension as pt
from .records import DATA, provenance, resume, write

LENGTH = 4.0
N_CELLS = 160
TURNS, T_TURN, T_END = 11.0, 220.0, 230.0
OUT = DATA / "bench" / "plectoneme_plateau.json"
ROOTS = ("dyntorsion.beyond.contact.run:run_contact_scene",)
IMPORTS = (pt.__name__,)


def rod() -> Rod:
    r = pt.rod()
    return Rod(E=r.E, nu=r.nu, D=r.thickness, L=LENGTH, rho=r.rho)


def theory() -> dict:
    return pt.theory(rod())


def params() -> dict:
    return {"section": "benchmarks/plectoneme_tension.py", "radius": pt.RADIUS,
            "length": LENGTH, "tension": pt.TENSION, "n_cells": N_CELLS, "dt": pt.DT,
            "lam_t": pt.LAM_T, "viscous": pt.VISCOUS, "viscous_moment": pt.VISCOUS_MOMENT,
            "stiffness": pt.STIFFNESS, "seed": pt.SEED, "turns": TURNS, "t_turn": T_TURN,
            "t_end": T_END, "tau": pt.TAU}  # fmt: skip


def curve() -> dict:
    return pt.curve_of(pt.contact_scene(rod(), N_CELLS, TURNS, T_TURN, T_END))


def main() -> int:
    record = {"params": params(), "code": provenance(__spec__.name, ROOTS, IMPORTS),
              "theory": theory()}  # fmt: skip
    record = resume(OUT, record, ("params", "code", "theory"))
    if "curve" not in record:
        tick = time.perf_counter()
        record["curve"] = curve()
        write(OUT, record)
        res = record["curve"]["result"]
        print(f"curve: {res['stopped'][:60]} at {res['t_last']} s, plectoneme "
              f"{res['plectoneme_turns']:.2f} turns ({time.perf_counter() - tick:.0f} s)")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
