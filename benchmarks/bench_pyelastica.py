"""Side by side with PyElastica: the same fast buckling scene in both codes.

The scene: Table 1 rod, pretwisted kappa0 = 10 1/m, end twist rate a = 16 rad/(m s)
(the fast scene of the Accuracy and cost page; the paper's Fig 8 scene, 20 s of
simulated time, is long for an explicit code), seed force 1e-8 N/m along d1.
Onset t_c by the same method (``dyntorsion.buckling.onset.detect_onset``) on the same
trace, u3 at s = L.  Each code runs on a ladder of resolutions; the converged value
is its finest run; the report gives the cheapest run within 1 % of it.

How the scene is expressed in PyElastica (``pyelastica`` on the package index):

* rod: ``CosseratRod.straight_rod`` along z, E, rho, D, L of Table 1 and
  ``shear_modulus`` = G = E / (2 (1 + nu)), so the twist stiffness is G J exactly as
  in the paper.  PyElastica's rod is shearable and extensible: shear stiffness
  (27/28) G A and axial stiffness E A.  Against the bending stiffness these are
  G A L^2 / (E I) = 6e6 times stiffer, the Kirchhoff limit for all practical
  purposes; ``SHEAR_FACTOR`` multiplies the shear stiffness further (kept at 1,
  so the explicit step is not shortened for nothing).
* left end, eq (30): position fixed and rotation about x and y fixed
  (``GeneralConstraint``, rotational selector (T, T, F)); the prescribed twist
  kappa3(0, t) = kappa0 + a t is imposed as the end moment it implies,
  m3 = G J (kappa0 + a t), a torque about d3 on the first element.  In the
  continuum problem the two are the same condition; discretely they differ by the
  half-element in which PyElastica applies the torque.
* right end: rotation fixed, lateral position fixed, axial sliding free
  (``GeneralConstraint``, translational selector (T, T, F)).
* initial state: the straight rod with its directors turned by kappa0 s about z
  (pretwisted, stress free in bending), at rest.
* seed: 1e-8 N/m along each element's current d1, lumped to the nodes.
* time stepping: ``PositionVerlet`` (explicit, symplectic), dt = DT = 4e-6 s at every
  resolution (the shear-rotation mode of an element limits it, not the element length);
  no damping (the paper has none).  No self-contact: runs end at a fixed time past
  the onset.

Run: ``python benchmarks/bench_pyelastica.py`` (needs ``pip install -e '.[bench]'``).
"""

from __future__ import annotations

import platform
import sys
import time
from types import SimpleNamespace

import numba
import numpy as np

from dyntorsion import Rod, __version__
from dyntorsion import buckling as b
from dyntorsion.buckling.scene import Scene

A_RATE, KAPPA0, SEED = 16.0, 10.0, 1e-8
SHEAR_FACTOR = 1.0
#: PositionVerlet step [s].  The explicit limit is set by the shear-rotation mode of an
#: element, omega = sqrt((27/28) G A / (rho I)) = 2.3e5 rad/s for Table 1 whatever the
#: element length, so dt < 2 / omega = 8.8e-6 s; half of that:
DT = 4e-6
#: |u3(L)| above this (m/s, ten times the largest physical velocity of the scene) or
#: non-finite counts as a numerical blow-up; the trace before it is kept
U_BLOWUP = 10.0
T_END = 3.3  # s; the onset is near 2.7 s, the first peak of |u3(L)| before 3.1 s


@numba.njit(cache=True)
def _seed_forces(forces, directors, node_length, q):
    """q N/m along d1, d1 of the node's neighbouring elements averaged (lab frame)."""
    n = directors.shape[2]
    for j in range(n + 1):
        for i in range(3):
            if j == 0:
                d = directors[0, i, 0]
            elif j == n:
                d = directors[0, i, n - 1]
            else:
                d = 0.5 * (directors[0, i, j - 1] + directors[0, i, j])
            forces[i, j] += q * node_length[j] * d


def elastica_run(
    n_elements: int, rod: Rod = Rod(), t_end: float = T_END, dt: float = DT, record_every: int = 250
):
    try:
        import elastica as ea
    except ImportError:
        raise SystemExit(
            "bench_pyelastica needs PyElastica: pip install 'dyntorsion[bench]'"
        ) from None

    class Scene(ea.BaseSystemCollection, ea.Constraints, ea.Forcing, ea.CallBacks):
        pass

    sim = Scene()
    cr = ea.CosseratRod.straight_rod(
        n_elements,
        np.zeros(3),
        np.array([0.0, 0.0, 1.0]),
        np.array([1.0, 0.0, 0.0]),
        rod.L,
        rod.D / 2,
        rod.rho,
        youngs_modulus=rod.E,
        shear_modulus=rod.G,
    )
    cr.shear_matrix[0, 0, :] *= SHEAR_FACTOR
    cr.shear_matrix[1, 1, :] *= SHEAR_FACTOR
    s_mid = (np.arange(n_elements) + 0.5) * rod.L / n_elements
    for k, phi in enumerate(KAPPA0 * s_mid):  # pretwist: turn d1, d2 about z
        c, s = np.cos(phi), np.sin(phi)
        cr.director_collection[0, :, k] = [c, s, 0.0]
        cr.director_collection[1, :, k] = [-s, c, 0.0]
    sim.append(cr)
    sim.constrain(cr).using(
        ea.GeneralConstraint,
        constrained_position_idx=(0,),
        constrained_director_idx=(0,),
        translational_constraint_selector=np.array([True, True, True]),
        rotational_constraint_selector=np.array([True, True, False]),
    )
    sim.constrain(cr).using(
        ea.GeneralConstraint,
        constrained_position_idx=(-1,),
        constrained_director_idx=(-1,),
        translational_constraint_selector=np.array([True, True, False]),
        rotational_constraint_selector=np.array([True, True, True]),
    )

    class EndTwistAndSeed(ea.NoForces):
        """m3 = G J (kappa0 + a t) on the first element; SEED N/m along d1 (compiled)."""

        def __init__(self):
            super().__init__()
            self.node_length = np.full(n_elements + 1, rod.L / n_elements)
            self.node_length[[0, -1]] *= 0.5

        def apply_torques(self, system, time=0.0):
            system.external_torques[2, 0] += rod.C * (KAPPA0 + A_RATE * time)

        def apply_forces(self, system, time=0.0):
            _seed_forces(system.external_forces, system.director_collection, self.node_length, SEED)

    sim.add_forcing_to(cr).using(EndTwistAndSeed)
    trace = {"t": [], "u3": []}

    class Record(ea.CallBackBaseClass):
        def make_callback(self, system, time, current_step):
            if current_step % record_every == 0:
                trace["t"].append(time)
                trace["u3"].append(system.velocity_collection[2, -1])

    sim.collect_diagnostics(cr).using(Record)
    sim.finalize()
    steps = int(round(t_end / dt))
    record_every = max(1, int(round(record_every * DT / dt)))
    start = time.perf_counter()
    ea.integrate(ea.PositionVerlet(), sim, t_end, steps, progress_bar=False)
    wall = time.perf_counter() - start
    run = SimpleNamespace(
        t=np.array(trace["t"]),
        u3_end=np.array(trace["u3"]),
        rod=rod,
        params={"a": A_RATE, "kappa0": KAPPA0},
        history=None,  # the ramp: detect_onset takes kappa0 + a t_c
    )
    return run, wall, steps


def dyntorsion_run(n_cells: int, dt: float):
    start = time.perf_counter()
    run = b.simulate(
        Scene(a=A_RATE, kappa0=KAPPA0, n_cells=n_cells, dt=dt, t_end=T_END, seed=SEED),
        on_failure="return",
        progress=False,
    )
    return run, time.perf_counter() - start, run.t.size - 1


def ladder(name, runs):
    rows = []
    for label, (run, wall, steps) in runs:
        bad = np.nonzero(~(np.abs(run.u3_end) <= U_BLOWUP))[0]
        if bad.size:  # keep what came before, as dyntorsion's on_failure="return" does
            print(
                f"  {name} {label}: the run blew up (|u3| > {U_BLOWUP} m/s or non-finite) "
                f"at t = {run.t[bad[0]]:.3f} s"
            )
            run = SimpleNamespace(
                t=run.t[: bad[0]],
                u3_end=run.u3_end[: bad[0]],
                rod=run.rod,
                scene=run.scene,
                history=None,
            )
        U = np.abs(run.u3_end)
        i_peak = int(np.argmax(U)) if U.size else 0
        if bad.size and not np.any(U[i_peak:] < 0.7 * U[i_peak]):
            tc = float("nan")  # the largest |u3| is the blow-up itself, not a buckling peak
            print(f"  {name} {label}: blew up before the first peak of |u3|: no onset")
        else:
            try:
                tc = b.detect_onset(run).t_c
            except ValueError as err:
                tc = float("nan")
                print(f"  {name} {label}: no onset ({err})")
        rows.append((label, tc, wall, steps))
    ref = [tc for _, tc, _, _ in rows if np.isfinite(tc)][-1]  # the finest with an onset
    print(f"{name}: converged (finest run with an onset) t_c = {ref:.4f} s")
    best = None
    for label, tc, wall, steps in rows:
        err = abs(tc / ref - 1)
        print(
            f"  {label:>22}: t_c = {tc:.4f} s ({100 * err:.3f} %), {steps} steps, "
            f"{wall:.2f} s wall ({1e6 * wall / steps:.1f} us/step)"
        )
        if best is None and err < 0.01:  # NaN compares False
            best = (label, tc, wall)
    return ref, best


def main() -> None:
    from importlib.metadata import version

    print(
        f"dyntorsion {__version__}, PyElastica {version('pyelastica')}, "
        f"Python {sys.version.split()[0]}, {platform.machine()}"
    )
    print(f"PositionVerlet dt = {DT:g} s; dyntorsion: best of 3 runs, PyElastica: one run")
    print(f"scene: kappa0 = {KAPPA0}, a = {A_RATE}, seed {SEED} N/m along d1, t_end = {T_END} s")
    elastica_run(10, t_end=0.01)  # compile both codes outside the timing
    dyntorsion_run(10, 0.05)
    ours = [
        (f"N={n}, dt={dt:g}", min((dyntorsion_run(n, dt) for _ in range(3)), key=lambda r: r[1]))
        for n, dt in ((25, 0.01), (50, 0.005), (100, 0.0025), (200, 0.00125))
    ]
    theirs = [
        (f"n={n}, dt={dt:g}", elastica_run(n, dt=dt))
        for n, dt in ((25, DT), (50, DT), (100, DT), (200, DT), (400, DT), (400, DT / 2))
    ]
    ref_o, best_o = ladder("dyntorsion", ours)
    ref_e, best_e = ladder("PyElastica", theirs)
    print(
        f"converged onsets differ by {100 * (ref_e / ref_o - 1):+.2f} % (PyElastica vs dyntorsion)"
    )
    if best_o and best_e:
        print(
            f"cheapest within 1 %: dyntorsion {best_o[0]} {best_o[2]:.2f} s, PyElastica "
            f"{best_e[0]} {best_e[2]:.2f} s: ratio {best_e[2] / best_o[2]:.0f}x"
        )


if __name__ == "__main__":
    main()
