"""Slow twisting under tension (the quasi-static limit): the peak torque
against the package's static critical twist, the torque plateau of the plectoneme against
the two-ply theory (:mod:`dyntorsion.beyond.ply`), and the torque-rotation curve with its
jump; written to ``data/bench/plectoneme_tension.json``.

The rod: the section of PyElastica's plectoneme example (radius a = 0.025 m, E = 1 MPa,
G = E / 1.5, 1 kg/m), ``LENGTH`` = 2.5 m long (L / a = 100), under a tension ``TENSION`` at
the far end, which slides along the axis; s = 0 is turned (rotation control,
:class:`~dyntorsion.buckling.turning.TurnHold`).  The tension is chosen so that the ply
theory's small parameter eps = a sqrt(T / B) is 0.1 (the finite-radius correction eps /
sqrt(6) = 4 %) and the rod is ten tension lengths long (L sqrt(T / B) = 10: the clamped
critical torque within 5 % of the infinite rod's 2 sqrt(B T)).  The rod's velocity is
damped as in the PyElastica scene (2 N s/m^2 per length) so that it settles between events;
its spin only lightly, ``VISCOUS_MOMENT`` = 0.05 N s per length: the twist then evens out
along the rod in L^2 / (C / 0.05) = 0.8 s and the viscous torque at the turned end is
~0.02 N m.  Measured on earlier runs of this script: a spin damping of 2 N s (the PyElastica
scene's) made the twist diffuse in 30 s and added ~0.4 N m of viscous torque (0.56 N m
against the elastic 0.16 N m at 0.155 turns); none let the torsional waves ring and the
frames' time route drift (its tangent by 0.49 rad), so that the energy budget failed (a
residual of 154 %, the contact dashpots taking 198 J against 25 J of work at the ends).

Two parts:

* ``bracket`` (no contact, the engine alone): turn to ``F`` x the static critical rotation
  Theta_c = kappa_cri(T) L (``statics.critical_twist``) in ``T_BRACKET`` s and hold to
  ``T_HOLD`` s.  Below Theta_c the rod must stay straight, above it must buckle: the
  static critical torque C kappa_cri(T) bracketed by the dynamic code.  (A ramp through the
  critical twist at any finite rate buckles late, the paper's delayed instability; the
  hold removes the rate.)
* ``curve`` (past contact): turn by ``TURNS`` in ``T_TURN`` s, hold to ``T_END``; every
  0.1 s the twisting moment at s = 0, link, twist, writhe, contact sites, the far end's
  axial position and the plectoneme turns of the centreline.  Its peak comes after
  Theta_c (delayed, as above), then the jump, then the plateau.

Written atomically after each part; a rerun keeps parts whose parameters, script and code
fingerprint are unchanged.  Run: ``python -m dyntorsion.studies.contact.plectoneme_tension``.
"""

from __future__ import annotations

import json
import math
import time

import numpy as np

from ...beyond.contact.run import Contact, ContactScene, run_contact_scene
from ...beyond.ply import ply, ply_torque_leading
from ...buckling import simulate
from ...buckling.scene import Scene
from ...buckling.seed import Perturbation
from ...buckling.statics import critical_twist
from ...buckling.turning import TurnHold
from ...genalpha.scheme import Scheme
from ...model.rod import Rod
from .records import DATA, provenance, result_json, resume, write

RADIUS, E, LENGTH = 0.025, 1e6, 2.5
TENSION = 5.0
N_CELLS, DT, LAM_T = 100, 0.02, -0.8
VISCOUS, VISCOUS_MOMENT, STIFFNESS, SEED = 2.0, 0.05, 1e7, 1e-3
F = (0.98, 0.99, 1.01, 1.02)
T_BRACKET, T_HOLD, N_BRACKET = 30.0, 300.0, 100
TURNS, T_TURN, T_END, TAU = 4.5, 90.0, 100.0, 1.0
OUT = DATA / "bench" / "plectoneme_tension.json"
ROOTS = ("dyntorsion.beyond.contact.run:run_contact_scene", "dyntorsion.buckling:simulate")


def rod() -> Rod:
    return Rod(E=E, nu=-0.25, D=2 * RADIUS, L=LENGTH, rho=1.0 / (math.pi * RADIUS**2))


def seed() -> Perturbation:
    return Perturbation(SEED, form="point")


def theory(r: Rod | None = None) -> dict:
    """The static critical twist of ``r`` (default :func:`rod`) under ``TENSION``, the
    infinite rod's Greenhill moment and the two-ply plateau (:mod:`dyntorsion.beyond.ply`)."""
    r = rod() if r is None else r
    kc = critical_twist(r, TENSION)
    return {
        "kappa_cri": kc, "critical_torque": r.C * kc, "critical_turns": kc * r.L / (2 * math.pi),
        "greenhill_infinite": 2 * math.sqrt(r.B1 * TENSION), "ply": ply(TENSION, r.B1, RADIUS)._asdict(),
        "ply_leading": ply_torque_leading(TENSION, r.B1, RADIUS),
        "eps": RADIUS * math.sqrt(TENSION / r.B1), "lam": r.L * math.sqrt(TENSION / r.B1),
        "C": r.C, "B": r.B1,
    }  # fmt: skip


def params() -> dict:
    return {"radius": RADIUS, "E": E, "length": LENGTH, "tension": TENSION, "n_cells": N_CELLS,
            "dt": DT, "lam_t": LAM_T, "viscous": VISCOUS, "viscous_moment": VISCOUS_MOMENT,
            "stiffness": STIFFNESS, "seed": SEED,
            "bracket": {"F": list(F), "t_turn": T_BRACKET, "t_hold": T_HOLD, "n_cells": N_BRACKET},
            "curve": {"turns": TURNS, "t_turn": T_TURN, "t_end": T_END, "tau": TAU}}  # fmt: skip


def bracket(kc: float) -> list[dict]:
    rows = []
    for f in F:
        turns = f * kc * LENGTH / (2 * math.pi)
        run = simulate(Scene(history=TurnHold(turns, T_BRACKET, tau=2.0), ends="clamped-turned", rod=rod(), tension=TENSION, n_cells=N_BRACKET, dt=DT, t_end=T_HOLD, seed=seed(), scheme=Scheme(lam_t=LAM_T)), on_failure="return", snapshots=[T_HOLD])  # fmt: skip
        u = np.abs(run.u3_end)
        snap = run.run.snapshots
        bent = None if snap is None or len(snap) == 0 else float(np.abs(snap[-1][:, 6:8]).max())
        hold = run.t >= T_BRACKET + 4 * 2.0
        half = run.t >= 0.5 * (T_BRACKET + T_HOLD)
        rows.append({
            "F": f, "turns": turns, "stopped": run.stopped, "t_last": float(run.t[-1]),
            "max_u3_hold_first_half": float(u[hold & ~half].max()),
            "max_u3_hold_second_half": float(u[half].max()) if half.any() else None,
            "max_u3": float(u.max()), "t_max_u3": float(run.t[np.argmax(u)]),
            "end_moment_last": float(rod().C * run.kappa3_left[-1]),
            "max_bending_curvature_at_t_hold": bent,
        })  # fmt: skip
    return rows


def contact_scene(r: Rod, n_cells: int, turns: float, t_turn: float, t_end: float) -> ContactScene:
    """The rod ``r`` under ``TENSION`` turned by ``turns`` in ``t_turn`` s and held to
    ``t_end``, with this scene's grid step, damping, seed and contact."""
    scene = Scene(
        history=TurnHold(turns, t_turn, tau=TAU), ends="clamped-turned", rod=r,
        tension=TENSION, n_cells=n_cells, dt=DT, t_end=t_end, scheme=Scheme(lam_t=LAM_T),
        seed=seed(),
    )  # fmt: skip
    contact = Contact(stiffness=STIFFNESS, viscous=VISCOUS, viscous_moment=VISCOUS_MOMENT, max_step=DT,
                      check=0.1)  # fmt: skip
    return ContactScene(scene, contact)


def curve_of(cs: ContactScene) -> dict:
    """Run ``cs`` and keep its result, its histories with the plectoneme turns of every
    recorded centreline, and the last centreline."""
    run = run_contact_scene(cs)
    return {
        "result": json.loads(result_json(run.result())),
        "history": run.histories(plectoneme=True),
        "final_centreline": run.history["r"][-1].tolist(),
    }


def curve() -> dict:
    return curve_of(contact_scene(rod(), N_CELLS, TURNS, T_TURN, T_END))


def main() -> int:
    record = {"params": params(), "code": provenance(__spec__.name, ROOTS), "theory": theory()}
    record = resume(OUT, record, ("params", "code", "theory"))
    for name, part in (("bracket", lambda: bracket(record["theory"]["kappa_cri"])),
                       ("curve", curve)):  # fmt: skip
        if name in record:
            continue
        tick = time.perf_counter()
        record[name] = part()
        record[f"{name}_wall_seconds"] = time.perf_counter() - tick
        write(OUT, record)
        print(f"{name} done ({time.perf_counter() - tick:.0f} s)", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
