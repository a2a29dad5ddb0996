"""PyElastica's plectoneme example, run as issue 33 (item 5) states it: the reference half
of the side-by-side comparison, written to ``data/bench/pyelastica_plectoneme.json``.

The scene is the one of PyElastica's ``examples/RodContactCase/RodSelfContact/
PlectonemesCase`` (read there; expressed here with the package's public API):

* rod: L = 1 m along y, radius 0.025 m, E = 1e6 Pa, G = E / 1.5, mass 1 kg, 150 elements
  (PyElastica's rod is shearable and extensible);
* the end s = 0 clamped; the end s = L turned about the axis by 10 turns in 50 s at a
  constant rate, free to slide along the axis (its lateral position held), then held
  (position and directors) for 50 s;
* a transverse velocity kick of 1e-4 m/s at the middle node at every twisting step (the
  example's imperfection);
* ``AnalyticalLinearDamper`` with damping constant 2 / (rho A); ``RodSelfContact`` with
  k = 1e4, nu = 10;
* ``PositionVerlet``, dt = 0.0025 L / 150.

Recorded every ``EVERY`` seconds: the total twist, writhe and link (PyElastica's
``compute_twist``, ``compute_writhe`` and ``compute_link``, closure "next_tangent" with
segments of 10 L, as the example), the axial position of the sliding end and the final
centreline.  The wall time is measured but is not the benchmark's comparison time (this
script may run niced beside other work): ``make bench`` times both codes in one run.

Run: ``python benchmarks/pyelastica_plectoneme.py [--t-end T]`` with PyElastica installed
(``pip install -e '.[bench]'``; about an hour for the full 100 s on one core).
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import platform
import tempfile
import time
from importlib.metadata import version
from pathlib import Path

import numpy as np

from dyntorsion.studies.contact.plectoneme_scene import (
    LENGTH,
    MASS,
    N_ELEM,
    RADIUS,
    SHEAR,
    T_HOLD,
    T_TWIST,
    TURNS,
    E,
)  # fmt: skip
from dyntorsion.studies.contact.records import DATA

DT = 0.0025 * LENGTH / N_ELEM
KICK = 1e-4
CONTACT_K, CONTACT_NU = 1e4, 10.0
EVERY = 0.1
#: a partial record (``complete: false``) is written every SAVE_EVERY simulated seconds
SAVE_EVERY = 5.0
OUT = DATA / "bench" / "pyelastica_plectoneme.json"


def params(t_end: float) -> dict:
    return {
        "turns": TURNS, "t_twist": T_TWIST, "t_hold": T_HOLD, "t_end": t_end,
        "length": LENGTH, "radius": RADIUS, "mass": MASS, "E": E, "G": SHEAR,
        "n_elem": N_ELEM, "dt": DT, "kick": KICK, "contact_k": CONTACT_K,
        "contact_nu": CONTACT_NU, "damping": "AnalyticalLinearDamper 2/(rho A)",
        "record_every": EVERY,
    }  # fmt: skip


def run(t_end: float, on_partial=None) -> dict:
    import elastica as ea
    from elastica._rotations import _get_rotation_matrix

    class Case(ea.BaseSystemCollection, ea.Constraints, ea.Contact, ea.CallBacks, ea.Damping):
        pass

    area = np.pi * RADIUS**2
    rho = MASS / (area * LENGTH)
    sim = Case()
    axis = np.array([0.0, 1.0, 0.0])
    rod = ea.CosseratRod.straight_rod(
        N_ELEM, np.zeros(3), axis, np.array([0.0, 0.0, 1.0]), LENGTH, RADIUS, rho,
        youngs_modulus=E, shear_modulus=SHEAR,
    )  # fmt: skip
    rod.velocity_collection[2, N_ELEM // 2] -= KICK
    sim.append(rod)
    sim.dampen(rod).using(
        ea.AnalyticalLinearDamper, damping_constant=2.0 / rho / area, time_step=DT
    )

    class TwistThenHold(ea.ConstraintBase):
        """The example's end conditions: s = 0 clamped; s = L turned at a constant rate
        about the axis, sliding along it, for T_TWIST, then held."""

        def __init__(self, p_start, p_end, d_start, d_end, **kwargs):
            super().__init__(**kwargs)
            theta = 2.0 * np.pi * TURNS
            local = d_end @ (-(p_end - p_start) / np.linalg.norm(p_end - p_start))
            local /= np.linalg.norm(local)
            self.final = _get_rotation_matrix(-theta, local.reshape(3, 1)).reshape(3, 3) @ d_end
            self.spin = theta / T_TWIST * local
            self.p0, self.d0 = p_start.copy(), d_start.copy()

        def constrain_values(self, system, time):
            if time > T_TWIST:
                system.position_collection[..., 0] = self.p0
                system.position_collection[0, -1] = 0.0
                system.position_collection[2, -1] = 0.0
                system.director_collection[..., 0] = self.d0
                system.director_collection[..., -1] = self.final

        def constrain_rates(self, system, time):
            system.velocity_collection[..., 0] = 0.0
            system.omega_collection[..., 0] = 0.0
            if time > T_TWIST:
                system.velocity_collection[..., -1] = 0.0
                system.omega_collection[..., -1] = 0.0
            else:
                system.velocity_collection[0, -1] = 0.0
                system.velocity_collection[2, -1] = 0.0
                system.omega_collection[..., -1] = -self.spin
                system.velocity_collection[2, N_ELEM // 2] -= KICK

    sim.constrain(rod).using(
        TwistThenHold, constrained_position_idx=(0, -1), constrained_director_idx=(0, -1)
    )
    sim.detect_contact_between(rod, rod).using(ea.RodSelfContact, k=CONTACT_K, nu=CONTACT_NU)
    sim.finalize()

    steps = int(round(t_end / DT))
    every = int(round(EVERY / DT))
    save_every = int(round(SAVE_EVERY / DT))
    times, pos, dirs, rad = [], [], [], []
    stepper, t = ea.PositionVerlet(), 0.0
    start = time.perf_counter()
    for i in range(steps + 1):
        if i % every == 0:
            times.append(t)
            pos.append(rod.position_collection.copy())
            dirs.append(rod.director_collection.copy())
            rad.append(rod.radius.copy())
        if on_partial is not None and i % save_every == 0 and 0 < i < steps:
            on_partial(_histories(ea, times, pos, dirs, rad, i, time.perf_counter() - start))
        if i < steps:
            t = stepper.step(sim, t, DT)
    return _histories(ea, times, pos, dirs, rad, steps, time.perf_counter() - start)


def _histories(ea, times, pos, dirs, rad, steps: int, wall: float) -> dict:
    """Twist, writhe and link (PyElastica's functions, as its example) of the recorded
    states, the sliding end's axial position and the last centreline."""
    pos, dirs, rad = np.array(pos), np.array(dirs), np.array(rad)
    twist, _ = ea.compute_twist(pos, dirs[:, 0, :, :])
    writhe = ea.compute_writhe(pos, 10 * LENGTH, "next_tangent")
    link = ea.compute_link(pos, dirs[:, 0, :, :], rad, 10 * LENGTH, "next_tangent")
    return {
        "t": list(times),
        "twist_turns": np.asarray(twist).tolist(),
        "writhe_turns": np.asarray(writhe).tolist(),
        "link_turns": np.asarray(link).tolist(),
        "end_axial_position": pos[:, 1, -1].tolist(),
        "final_centreline": pos[-1].T.tolist(),
        "steps": steps,
        "wall_seconds": wall,
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--t-end", type=float, default=T_TWIST + T_HOLD)
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args(argv)

    def write(result: dict, complete: bool) -> None:
        record = {
            "params": params(args.t_end),
            "code": {
                "pyelastica": version("pyelastica"),
                "numpy": np.__version__,
                "script_sha256": hashlib.sha256(Path(__file__).read_bytes()).hexdigest(),
                "machine": f"{platform.machine()} {platform.processor()}".strip(),
            },
            "complete": complete,
            "result": result,
        }
        args.out.parent.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile("w", dir=args.out.parent, delete=False) as f:
            json.dump(record, f)
        os.replace(f.name, args.out)

    result = run(args.t_end, on_partial=lambda r: write(r, False))
    write(result, True)
    r = result
    print(
        f"PyElastica plectoneme case to {args.t_end:g} s: {r['steps']} steps in "
        f"{r['wall_seconds']:.0f} s; end: twist {r['twist_turns'][-1]:.3f}, writhe "
        f"{r['writhe_turns'][-1]:.3f}, link {r['link_turns'][-1]:.3f} turns -> {args.out}"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
