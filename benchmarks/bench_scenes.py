"""Wall time of the paper's scenes at the grids the figures use.

* Fig 8: the buckling scene (Table 1, kappa0 = 0, a = 1.6 rad/s, default seed),
  N = 100, dt = 0.005 s, to the end of the run (self-contact or the first failed
  step in the violent motion after the onset); the onset's t_c is grid independent
  to 0.04 % there (docs/figures/fig08.md).
* Fig 6: the smooth-release wave on the paper's grid and on a grid 16 times finer.
* The linear prediction of a Fig 10 scene (kappa0 = 10, a = 1.6, stated seed;
  dyntorsion.beyond.linear_stability), with and without the torsional waves, beside the
  simulated scene.

Medians of three runs, each beside a floor: the Fig 8 runs as a fraction of the simulated
time (real time), the linear predictions beside the simulation they predict; nothing is
asserted.
"""

from __future__ import annotations

import platform
import statistics
import sys
import time

from dyntorsion import __version__
from dyntorsion import buckling as b
from dyntorsion import waves as w
from dyntorsion.beyond import linear_stability as ls
from dyntorsion.buckling.scene import Scene


def main() -> None:
    print(f"dyntorsion {__version__}, Python {sys.version.split()[0]}, {platform.machine()}")
    b.simulate(
        Scene(a=1.6, n_cells=10, dt=0.05, t_end=0.2, kappa0=0.0)
    )  # compile outside the timing
    # the standard grid, and the cheapest grids within 0.5 % and 0.1 % of the
    # Richardson t_c (Accuracy and cost page, ladder `accuracy-fig08`)
    for n, dt, note in (
        (100, 0.005, "standard"),
        (50, 0.02, "within 0.5 %"),
        (100, 0.02, "within 0.1 %"),
    ):
        walls, steps = [], 0
        for _ in range(3):
            run = b.simulate(
                Scene(a=1.6, n_cells=n, dt=dt, t_end=40.0, kappa0=0.0), on_failure="return"
            )
            walls.append(run.run.wall_time)
            steps = run.run.steps
        med = statistics.median(walls)
        print(
            f"Fig 8 scene, N={n}, dt={dt} ({note}): {med:.2f} s for {steps} steps "
            f"({1e3 * med / steps:.2f} ms/step, {1e6 * med / steps / (n + 1):.1f} us per "
            f"node and step; {med / run.t[-1]:.3f} of real time), "
            f"t_c = {b.detect_onset(run).t_c:.3f} s"
        )
    for n, dt in ((100, 0.005), (1600, 0.005 / 16)):
        times = []
        for _ in range(3):
            sol = w.solve(w.SmoothRelease(10.0), n_cells=n, dt=dt, times=[0.01])
            times.append(sol.run.wall_time)
        print(
            f"Fig 6 wave, N={n}, dt={dt:g}: {1e3 * statistics.median(times):.1f} ms, "
            f"max error {sol.errors()['max'][0]:.2e}"
        )

    model = ls.LateralModel()
    sim = []
    for _ in range(3):
        run = b.simulate(Scene(a=1.6, kappa0=10.0, n_cells=100, dt=0.005, t_end=10.0))
        sim.append(run.run.wall_time)
    t_sim = statistics.median(sim)
    print(f"Fig 10 scene a=1.6 simulated to 10 s (N=100, dt=0.005): {t_sim:.2f} s")
    for waves in (False, True):
        times = []
        for _ in range(3):
            start = time.perf_counter()
            p = model.passage(1.6, 10.0, 1e-8, waves=waves)
            times.append(time.perf_counter() - start)
        print(
            f"linear prediction, 16 modes, waves={waves}: {statistics.median(times):.2f} s "
            f"({statistics.median(times) / t_sim:.2f} of the simulation; dt = "
            f"{p.params['dt']:.2g} s), t_ref = {p.t_ref:.4f} s"
        )


if __name__ == "__main__":
    main()
