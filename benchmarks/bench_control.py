"""Cost of step-size control (genalpha.StepControl) on the buckling scene.

Fig 10 scenes (kappa0 = 10, stated seed) on the standard grid N = 100, dt = 0.005 s,
with fixed steps (contact checked every 0.1 s: the default) and with control (contact
checked every step), to the end of each run.  Reports medians of three runs, the
steps taken and rejected, why each run ended, and t_c of both (identical: the runs
agree bitwise up to the first rejection, which comes after the onset).
Nothing is asserted.  Run: ``python benchmarks/bench_control.py``.
"""

from __future__ import annotations

import statistics

from dyntorsion import buckling as b
from dyntorsion.buckling.scene import Scene, simulate_scene
from dyntorsion.genalpha import Scheme, StepControl


def main() -> None:
    b.simulate(
        Scene(a=1.6, n_cells=10, dt=0.05, t_end=0.2, kappa0=0.0)
    )  # compile outside the timing
    for a in (16.0, 1.6):
        for scheme in (Scheme(), Scheme(control=StepControl())):
            walls = []
            for _ in range(3):
                run = simulate_scene(Scene(a=a, kappa0=10.0, scheme=scheme))
                walls.append(run.run.wall_time)
            ctl = run.run.meta.get("control", {})
            print(
                f"a={a:g} {'control' if scheme.control else 'fixed  '}: "
                f"{statistics.median(walls):.2f} s, {run.run.steps} levels, "
                f"{ctl.get('accepted', run.run.steps)} steps, {ctl.get('rejected', 0)} rejected, "
                f"t_c = {b.detect_onset(run).t_c:.6f} s; {run.stopped[:60]}"
            )


if __name__ == "__main__":
    main()
