"""Three Newton strategies for the same-grid step (issue 34, item 2): measured, not adopted.

    python benchmarks/probe_newton_strategies.py [--timing]

``benchmarks/patches/newton_strategies.patch`` adds, behind environment switches read
when the kernels compile (each variant gets a numba cache of its own):

* ``DT_ANDERSON=m``: Anderson (type II) acceleration of the simplified Newton iteration,
  with a memory of the last m secant pairs (iterate difference, difference of the
  simplified corrections; normalised) kept across steps while the LU factors are, and
  used only once a correction is below ``DT_LINEAR`` (1e-3; the first correction of a
  step, 0.1 to 7 in the scaled norm, is far outside the linear range);
* ``DT_PRED=1``: each step's predictor is the constant, linear or quadratic
  extrapolation of the last levels, whichever was closest to the previous step's solution;
* ``DT_REFAC=K``: the factors are also renewed when the contraction rate predicts more
  than K further corrections to the tolerance (a cost rule, as RADAU5's THET).

It checks out this commit into a temporary git worktree, applies the patch and runs the
Fig 8 scene (N = 50, dt = 0.02 s, to 18 s, Newton tol 1e-10) with each variant,
printing t_c, the Newton corrections per step by phase, the factorisations and (with
``--timing``) a median wall time.  The counts do not depend on the machine's load.
Nothing is asserted.

What it found (2026-11-28, one run; t_c 14.739877 s in every variant): none pays.
Anderson with m = 2, 4, 8: 5.72, 5.50 and 5.54 corrections a step against today's 5.65
(the contraction of about 0.03-0.1 a correction after the first is not one that a memory
of a few secant pairs learns; a first version that also accelerated the first
correction of a step, with unnormalised pairs, took 6.4-7.0); the adaptive predictor 5.62
(at a Courant number c dt / ds of about 58 the torsional waves are not resolved in time,
so the levels do not extrapolate); renewing the factors by the cost rule 4.24 (K = 2) and
4.79 (K = 4) corrections a step for 376 and 268 factorisations against 168 (a
factorisation costs about seven corrections).  None comes near half the step: even full
Newton takes 3.0 to 4.3 corrections a step (``bench_targets.py``; the first correction,
0.1 to 7 in the scaled norm, leaves about 1e-5), and fresher factors cost more than the
corrections they save; halving the step needs each residual, solve and factorisation to
cost less.  The wall times (``--timing``: 159-232 ms, today's 194 ms)
are within this machine's noise.
"""

from __future__ import annotations

import argparse

from worktree import ROOT, checkout, run_json

PATCH = ROOT / "benchmarks" / "patches" / "newton_strategies.patch"

VARIANTS = {
    "today's iteration": {},
    "Anderson m=2": {"DT_ANDERSON": "2"},
    "Anderson m=4": {"DT_ANDERSON": "4"},
    "Anderson m=8": {"DT_ANDERSON": "8"},
    "adaptive predictor": {"DT_PRED": "1"},
    "refactor if > 2 left": {"DT_REFAC": "2"},
    "refactor if > 4 left": {"DT_REFAC": "4"},
}

RUN = """
import sys; sys.path.insert(0, sys.argv[1])
import json, time, statistics
import numpy as np
from dyntorsion import buckling as b
scene = dict(a=1.6, kappa0=0.0, n_cells=50, dt=0.02, t_end=18.0)
b.simulate(Scene(a=1.6, n_cells=10, dt=0.05, t_end=0.2, kappa0=0.0))
run = b.simulate(Scene(**scene))
r = run.run
t = 0.02 * np.arange(1, r.steps + 1)
phases = [(0, 5), (5, 10), (10, 13), (13, 15), (15, 18.01)]
out = {"t_c": b.detect_onset(run).t_c, "per_step": float(r.iterations.mean()),
       "phases": [float(r.iterations[(t >= a) & (t < c)].mean()) for a, c in phases],
       "lu": int(r.factorisations.sum())}
if sys.argv[2] == "1":
    ts = []
    for _ in range(5):
        s = time.perf_counter(); b.simulate(Scene(**scene)); ts.append(time.perf_counter() - s)
    out["ms"] = 1e3 * statistics.median(ts)
print(json.dumps(out))
"""


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--timing", action="store_true", help="also a median wall time")
    args = p.parse_args()
    with checkout(patch=PATCH) as wt:
        print(f"{'variant':22s} {'t_c [s]':>10s} {'corr/step':>9s}  by phase "
              f"[0,5) [5,10) [10,13) [13,15) [15,18)  {'LU':>4s}"
              + ("   ms" if args.timing else ""))  # fmt: skip
        for i, (name, env) in enumerate(VARIANTS.items()):
            env = env | {"NUMBA_CACHE_DIR": str(wt.parent / f"numba{i}")}
            o = run_json(RUN, wt / "src", "1" if args.timing else "0", env=env)
            ph = " ".join(f"{v:5.2f}" for v in o["phases"])
            ms = f" {o['ms']:6.1f}" if args.timing else ""
            print(f"{name:22s} {o['t_c']:10.6f} {o['per_step']:9.2f}  {ph:38s} {o['lu']:4d}{ms}")


if __name__ == "__main__":
    main()
