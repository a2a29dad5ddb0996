"""The block LU with its sizes as compile-time constants (issue 34, item 2): measured, not
adopted, ready to adopt.

    python benchmarks/bench_fixed_sizes.py [--rounds 5]

``benchmarks/patches/abd_fixed_sizes.patch`` calls the block elimination of
:func:`dyntorsion.genalpha.abd.factor` and the explicit operators of
:func:`~dyntorsion.genalpha.abd.explicit` with the Cosserat rod's sizes (12 fields, 6 of
them given at the twisted end) as constants, in a branch beside the general call: the same
code, so the same operations in the same order, but the compiler unrolls and vectorises
the loops.  This script checks out this commit twice into temporary git worktrees, applies
the patch to one, and

* checks that both give the same numbers to the last bit: the final state and t_c of the
  Fig 8 scene (N = 50, dt = 0.02 s, to 18 s), the fast route (N = 50, dt = 0.15 s, tol
  1e-6, until the first peak, read in continuous time) and the a = 16 scene with a
  clamped-free end (N = 100, dt = 0.005 s, to 3 s);
* times the same-grid Fig 8 step and the fast route in alternating subprocesses
  (``--rounds`` of each; the smallest median of each tree), so both see the machine's
  load swing alike.

Nothing is asserted.  Not adopted because any edit of the engine's code makes every cached
record stale (``dyntorsion.store.fingerprint``): adopting it means rerunning them all,
2.3 CPU-hours of scene records by the wall times they keep and several more of contact
and benchmark records, for the same numbers.
"""

from __future__ import annotations

import argparse

from worktree import ROOT, checkout, run_json

PATCH = ROOT / "benchmarks" / "patches" / "abd_fixed_sizes.patch"

RUN = """
import sys; sys.path.insert(0, sys.argv[1])
import json, time, statistics, hashlib
from dyntorsion import buckling as b
from dyntorsion.genalpha import Newton
b.simulate(Scene(a=1.6, n_cells=10, dt=0.05, t_end=0.2, kappa0=0.0))
digest = lambda y: hashlib.sha256(y.tobytes()).hexdigest()[:16]
fast = dict(a=1.6, kappa0=0.0, n_cells=50, dt=0.15, t_end=18.0, newton=Newton(tol=1e-6))
fast_onset = lambda: b.detect_onset(b.simulate(Scene(until="first-peak", **fast)))
same = lambda: b.simulate(Scene(a=1.6, n_cells=50, dt=0.02, t_end=18.0, kappa0=0.0), stop_at_contact=False)
def med(f, n):
    out = []
    for _ in range(n):
        t = time.perf_counter(); f(); out.append(time.perf_counter() - t)
    return statistics.median(out)
if sys.argv[2] == "check":
    r8 = b.simulate(Scene(a=1.6, n_cells=50, dt=0.02, t_end=18.0, kappa0=0.0))
    r16 = b.simulate(Scene(a=16.0, kappa0=10.0, n_cells=100, dt=0.005, t_end=3.0, ends="clamped-free"))
    on = fast_onset()
    print(json.dumps({"fig8": [digest(r8.run.y), b.detect_onset(r8).t_c],
                      "fast": [on.t_c, on.t_c_continuous, on.kappa3_continuous],
                      "a16_clamped_free": [digest(r16.run.y), r16.run.steps]}))
else:
    same(); fast_onset()
    print(json.dumps({"step_us": 1e6 * med(same, 5) / 900, "fast_ms": 1e3 * med(fast_onset, 9)}))
"""


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--rounds", type=int, default=5, help="alternating timing rounds")
    args = p.parse_args()
    with checkout() as today, checkout(patch=PATCH) as fixed:
        trees = {"today": today, "fixed sizes": fixed}
        checks = {k: run_json(RUN, wt / "src", "check") for k, wt in trees.items()}
        best = {k: {"step_us": float("inf"), "fast_ms": float("inf")} for k in trees}
        for _ in range(args.rounds):
            for k, wt in trees.items():
                for key, v in run_json(RUN, wt / "src", "time").items():
                    best[k][key] = min(best[k][key], v)
    same = checks["today"] == checks["fixed sizes"]
    print(f"the same numbers to the last bit: {'yes' if same else 'NO'}")
    for k, v in checks["today"].items():
        print(
            f"  {k}: {v}"
            + ("" if checks["fixed sizes"][k] == v else f" vs {checks['fixed sizes'][k]}")
        )
    print(f"smallest medians of {args.rounds} alternating rounds:")
    for key, label in (("step_us", "same-grid Fig 8 step [us]"), ("fast_ms", "fast route [ms]")):
        a, c = best["today"][key], best["fixed sizes"][key]
        print(f"  {label:28s} today {a:8.2f}  fixed sizes {c:8.2f}  ratio {c / a:.2f}")


if __name__ == "__main__":
    main()
