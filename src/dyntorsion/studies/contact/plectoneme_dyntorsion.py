"""PyElastica's plectoneme scene in dyntorsion: dyntorsion's half of the
side-by-side comparison, written to ``data/bench/dyntorsion_plectoneme.json``.

The scene of ``benchmarks/pyelastica_plectoneme.py`` (its constants are imported from
:mod:`.plectoneme_scene`: one place for them), in dyntorsion's terms:

* rod: L = 1 m, radius 0.025 m, E = 1e6 Pa, G = E / 1.5 (Poisson's ratio -0.25), mass
  1 kg (rho = 1 / (pi r^2 L)).  dyntorsion's rod is a Kirchhoff rod (inextensible,
  unshearable): PyElastica's axial and shear stiffnesses, E A = 1963 N and of order
  G A = 1309 N, are 4e3-6e3 times B / L^2 = 0.31 N here, so the neglected strains are
  small until the contact loads and the tight plectoneme tip (a curvature radius below the
  rod's own radius, see the page) make them matter.
* ends: rotation control (``ends="clamped-turned"``): s = 0 turned by 10 turns in 50 s at a
  constant rate and then held (:class:`~dyntorsion.buckling.turning.TurnHold`, both corners
  rounded over ``TAU`` = 0.1 s where PyElastica starts and stops the spin at once); s = L
  held in rotation and laterally, free to slide along the axis.  PyElastica turns the end
  that slides and holds the other; here the turned end is fixed in position and the far end
  slides: the two differ by a rigid translation along the axis, whose inertia and damping
  (small at these speeds) are the only difference.
* damping: PyElastica's ``AnalyticalLinearDamper`` with constant nu = 2 / (rho A) multiplies
  the velocities by exp(-nu dt) and the spins by exp(-nu dt m / J) each step: the force
  and moment per length -nu rho A v and -nu rho A w, i.e. ``viscous = viscous_moment`` =
  2 N s/m^2 and 2 N s here (:class:`~dyntorsion.beyond.contact.run.Contact`).
  (PyElastica 1.0.0 applies the damper after the boundary condition, so its turned end
  turns 0.8988 of what is asked: data/README and the Past contact page.)
* contact: dyntorsion's law (a penalty per length ``STIFFNESS`` with damping ratio 0.5,
  ``Contact``) in place of ``RodSelfContact`` (k = 1e4 N/m per element pair, nu = 10),
  with the axis beyond both ends as an obstacle (the closure of the writhe); parts of the
  rod closer along it than ``MIN_ARC`` = 1.47 D never touch, the arc RodSelfContact skips.
  (The first record, with min_arc = 3 D and k = 1e7, passed through itself at 32.3 s: the
  plectoneme's tip closed to a curvature radius of 0.30 D, its two sides less than 3 D
  apart along the rod.)
* imperfection: a point force ``SEED`` N along d1 at mid-length, for all t, in place of
  PyElastica's lateral velocity kick of 1e-4 m/s at the middle node every step of the
  twisting phase.
* time: generalised-alpha with lambda_inf = ``LAM_T`` in time, the step of each run below
  (halved where Newton fails, :mod:`dyntorsion.genalpha.state_steps`).

Every run records, every 0.1 s: link, twist and writhe (:mod:`dyntorsion.beyond.contact.
topology`), contact sites, the deepest overlap, the axial position of the sliding end, and
at the end the centreline and its plectoneme turns (:mod:`dyntorsion.beyond.contact.
plectoneme`, applied to PyElastica's final centreline too).  Written atomically after every
run; a rerun resumes when the parameters, this script and the code fingerprint of
``run_contact_scene`` are unchanged (else it starts again).

Grids (``RUNS``, the longest first): N = 200 and 150 at dt = 0.02 s, N = 100 at 0.01 and
0.02 s.  Coarser grids (N = 75 and 50) do not hold the plectoneme's tip: they stop as
under-resolved (a cell bent by more than a radian) before the twist is complete.

Run: ``python -m dyntorsion.studies.contact.plectoneme_dyntorsion [--jobs J]`` or ``make data-contact``
(each run's wall time is in the record).
"""

from __future__ import annotations

import json
import math

from ...beyond.contact.plectoneme import plectoneme_turns
from ...beyond.contact.run import Contact, ContactScene, run_contact_scene
from ...buckling.scene import Scene
from ...buckling.seed import Perturbation
from ...buckling.turning import TurnHold
from ...genalpha.scheme import Scheme
from ...model.rod import Rod
from .plectoneme_scene import LENGTH, MASS, N_ELEM, RADIUS, SHEAR, T_HOLD, T_TWIST, TURNS, E
from .records import DATA, provenance, result_json, run_script, summary

T_END = T_TWIST + T_HOLD
TAU = 0.1
#: PyElastica's damper, nu = 2 / (rho A) [1/s], as a force and moment per length (docstring)
VISCOUS = 2.0
#: the package's default contact stiffness [N/m^2] (an overlap of 0.6 % D measured at N = 50
#: where 1e7 gave 2.5 %)
STIFFNESS = Contact().stiffness
#: RodSelfContact never lets elements fewer than 1 + ceil(0.8 pi r n / L) apart touch (11 of
#: its 150 elements, 0.073 m): the same arc, in diameters, is the contact's ``min_arc``
MIN_ARC = (1 + math.ceil(0.8 * math.pi * RADIUS * N_ELEM / LENGTH)) * LENGTH / N_ELEM / (2 * RADIUS)
SEED = 1e-3
LAM_T = -0.8
CHECK = 0.1
#: (cells, time step [s]) of each run
RUNS = [(200, 0.02), (150, 0.02), (100, 0.01), (100, 0.02)]
OUT = DATA / "bench" / "dyntorsion_plectoneme.json"
ROOTS = ("dyntorsion.beyond.contact.run:run_contact_scene",)
#: the module of the scene's numbers, which the records of this scene name among their imports
SCENE = "dyntorsion.studies.contact.plectoneme_scene"


def rod() -> Rod:
    return Rod(E=E, nu=E / (2.0 * SHEAR) - 1.0, D=2.0 * RADIUS, L=LENGTH,
               rho=MASS / (math.pi * RADIUS**2 * LENGTH))  # fmt: skip


def contact_scene(n: int, dt: float) -> ContactScene:
    scene = Scene(
        history=TurnHold(TURNS, T_TWIST, tau=TAU), ends="clamped-turned", rod=rod(), n_cells=n,
        dt=dt, t_end=T_END, scheme=Scheme(lam_t=LAM_T), seed=Perturbation(SEED, form="point"),
    )  # fmt: skip
    contact = Contact(stiffness=STIFFNESS, viscous=VISCOUS, viscous_moment=VISCOUS,
                      max_step=dt, check=CHECK, min_arc=MIN_ARC)  # fmt: skip
    return ContactScene(scene, contact)


def params() -> dict:
    return {"turns": TURNS, "t_turn": T_TWIST, "t_hold": T_HOLD, "tau": TAU,
            "rod": rod().params(), "viscous": VISCOUS, "stiffness": STIFFNESS, "min_arc": MIN_ARC, "seed": SEED,
            "lam_t": LAM_T, "check": CHECK, "runs": [list(r) for r in RUNS],
            "key": contact_scene(*RUNS[0]).params()}  # fmt: skip


def row(cs: ContactScene, n: int, dt: float) -> dict:
    """Run ``cs`` (``n`` cells, step ``dt``) and keep its result, histories, last
    centreline and the plectoneme turns of it."""
    run = run_contact_scene(cs)
    r_final = run.history["r"][-1]
    return {
        "n_cells": n, "dt": dt, "result": json.loads(result_json(run.result())),
        "history": run.histories(), "final_centreline": r_final.tolist(),
        "plectoneme": plectoneme_turns(r_final, 2.0 * RADIUS)._asdict(),
    }  # fmt: skip


def one(n: int, dt: float) -> dict:
    return row(contact_scene(n, dt), n, dt)


def report(row: dict) -> str:
    res = row["result"]
    return summary(f"N = {row['n_cells']}, dt = {row['dt']:g}", res,
                   link=f"{res['link_turns']:.3f}", twist=f"{res['twist_turns']:.3f}",
                   writhe=f"{res['writhe_turns']:.3f}",
                   plectoneme=f"{row['plectoneme']['turns']:.2f} turns")  # fmt: skip


def main(argv: list[str] | None = None) -> int:
    record = {"params": params(), "code": provenance(__spec__.name, ROOTS, (SCENE,)), "runs": []}
    return run_script(argv, __doc__, OUT, record, RUNS, one,
                      lambda r: (r["n_cells"], r["dt"]), report)  # fmt: skip


if __name__ == "__main__":
    raise SystemExit(main())
