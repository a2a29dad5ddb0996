"""What the three engine floors of issue 34 (item 2) would need: the compiled parts'
cost per call times the counts of the fastest accurate runs, beside the floors.

    python benchmarks/floors_budget.py [--rounds 5]

For each floor -- the Fig 8 onset within 0.5 % (<= 10 ms), the 16-rate Fig 10 sweep with
each onset within 0.5 % (<= 0.3 s, one core), the same-grid Fig 8 step (half the
baseline's, which is today's engine) -- this script runs the fastest settings measured
near the accuracy (``docs/benchmarks.md``; long steps of the straight phase and N = 25
among them) with today's engine and counts their residuals (each followed by a solve,
``dyntorsion.genalpha.newton``) and factorisations (a Jacobian and a block LU each).  It
times each compiled part per call at a final state of the runs on that rod (N = 50: the
last Fig 8 setting of that size; N = 25; N = 100: the last sweep's last scene), with
today's kernels and with the block LU and explicit operators compiled for the rod's
sizes (``benchmarks/patches/abd_fixed_sizes.patch``, in a temporary worktree), in
alternating subprocesses (``--rounds``; the smallest median of each part).  From the
cheaper of the two for each part it forms

    kernels = residuals * (t_res + t_solve) + factorisations * (t_jac + t_lu)

with ``t_solve`` the explicit-operator solve and the cost of building those operators
left out: a lower bound on the compiled work of that run, with nothing for setting the
run up (timed as a one-step run), for the bookkeeping of the steps or for reading the
onset; and the same without the factorisations (``res+solve``).  The error column is each
setting's accuracy: the Fig 8 onset against the finest grid of the ``accuracy-fig08``
ladder (N = 400, dt = 0.00125 s), the sweep's largest against the N = 800 references of
the first hold-out set, all read in continuous time (read from the checkout's committed
``data/``; the patched tree, whose records are stale by design, reads none).  Whatever
beats a floor must do fewer of these operations or do them faster.  One run on a shared
machine; nothing is asserted.
"""

from __future__ import annotations

import argparse

from worktree import ROOT, checkout, run_json

PATCH = ROOT / "benchmarks" / "patches" / "abd_fixed_sizes.patch"

RUN = r"""
import sys; sys.path.insert(0, sys.argv[1]); sys.path.insert(0, sys.argv[2])
import json, statistics, time
from dataclasses import replace
import numpy as np
from dyntorsion import Rod, buckling as b, genalpha as ga
from dyntorsion.beyond.predictions import estimate
from dyntorsion.buckling.loading import EQ30
from dyntorsion.buckling.scene import run_scene, simulate_scene
from dyntorsion.genalpha.abd import EXPLICIT_AFTER, explicit
from dyntorsion.genalpha.discrete import factor, setup
from dyntorsion.model.cosserat import Cosserat
from dyntorsion.studies import presets as P
from dyntorsion.studies.pacing import paced
from dyntorsion.studies.sweep import run_sweep
from profile_fig08 import _parts

def med(f, n):
    out = []
    for _ in range(n):
        t = time.perf_counter(); f(); out.append(time.perf_counter() - t)
    return statistics.median(out)

def counts(r):
    long = r.meta.get("long_steps") or {"steps": 0, "factor": 1}  # r.steps counts those in dt
    return {"steps": int(r.steps) - long["steps"] * (long["factor"] - 1),
            "res": int(r.residual_evaluations.sum()),
            "it": int(r.iterations.sum()), "fac": int(r.factorisations.sum())}

def parts(run, n, dt):
    sysm = Cosserat(Rod.paper()).system()
    left = ga.Boundary.fields(sysm, list(EQ30.left))
    right = ga.Boundary.fields(sysm, list(EQ30.right))
    con, w, fac = setup(sysm, ga.Scheme(), n, Rod.paper().L / n, dt, left, right,
                        np.ascontiguousarray(run.y), run.y_t)
    gL, gR = np.zeros(left.nb), np.zeros(right.nb)
    reps = 2000 if n <= 50 else 1000
    def loop(part):
        _parts(sysm.F, sysm.dF, con, gL, gR, w, fac, part, 1)
        return 1e6 * med(lambda: _parts(sysm.F, sysm.dF, con, gL, gR, w, fac, part, reps), 5) / reps
    t = {"res": loop(0)}
    t["jac"] = max(0.0, loop(1) - t["res"])
    t["lu"], t["exp"] = loop(2), loop(4)
    factor(con, w, fac); fac.uses[0] = EXPLICIT_AFTER + 1; explicit(fac)
    t["solve"] = loop(3)
    return t

fast = dict(a=1.6, kappa0=0.0, n_cells=50, dt=0.15, t_end=18.0, until="first-peak")
tol6 = dict(tol=1e-6)
half = dict(tol=1e-6, theta_reuse=0.5)
fig8 = {  # name: (cells, Newton options, long steps of the straight phase)
    "fig8, theta 0.25": (50, tol6, None),
    "fig8, theta 0.5": (50, half, None),
    "fig8, long x4, theta 0.5": (50, half, ga.LongSteps(factor=4)),
    "fig8, long x16, theta 0.25": (50, tol6, ga.LongSteps(factor=16)),
    "fig8, long x16, theta 0.5": (50, half, ga.LongSteps(factor=16)),
    "fig8, N = 25, theta 0.25": (25, tol6, None),
}
sweeps = {  # name: (Newton options, long steps, paced steps)
    "sweep, theta 0.25": ({}, None, 96),
    "sweep, theta 0.5": ({"theta_reuse": 0.5}, None, 96),
    "sweep, long x4, theta 0.5": ({"theta_reuse": 0.5}, ga.LongSteps(factor=4), 96),
    "sweep, 64 steps, theta 0.5": ({"theta_reuse": 0.5}, None, 64),
}
same = dict(a=1.6, kappa0=0.0, n_cells=50, dt=0.02, t_end=18.0)

def fig8_run(n, nw, long):
    return b.simulate(Scene(**fast | {"n_cells": n}, newton=ga.Newton(**nw), scheme=ga.Scheme(long_steps=long)))

def sweep(nw, long, steps):
    return [paced(replace(sc, until="first-peak", newton=replace(sc.newton, **nw),
                          scheme=replace(sc.scheme, long_steps=long)), steps=steps)
            for sc in P.preset("fig10")]

timing = sys.argv[3] == "time"  # else the parts only (the patched tree: its records are stale)
b.simulate(Scene(a=1.6, n_cells=10, dt=0.05, t_end=0.2, kappa0=0.0))
if timing:  # the converged onsets, read in continuous time
    ladder = P.cached("accuracy-fig08")
    ref8 = float(ladder[(ladder.n_cells == 400) & (ladder.dt == 0.00125)].t_c_continuous.iloc[0])
    tab = run_sweep(P.reference_scenes(("tolerance-holdout",))[:16], compute=False,
                    on_stale="error", progress=False)
    assert list(tab.a) == [sc.a for sc in P.preset("fig10")], "the references' rates"
    refs = tab.t_c_continuous.to_numpy()
out = {"runs": {}, "parts": {}, "ms": {}}
last = {}  # a final state of each rod's runs: where the parts are timed
for name, (n, nw, long) in fig8.items():
    r = fig8_run(n, nw, long)
    out["runs"][name] = counts(r.run) | {"cells": n}
    last[n] = (r.run, fast["dt"])
    if timing:
        out["runs"][name]["err %"] = 100 * abs(b.detect_onset(r).t_c_continuous / ref8 - 1)
for name, (nw, long, steps) in sweeps.items():
    scs = sweep(nw, long, steps)
    runs = [simulate_scene(sc).run for sc in scs]
    out["runs"][name] = {k: sum(counts(x)[k] for x in runs) for k in ("steps", "res", "it", "fac")}
    out["runs"][name]["cells"] = scs[-1].n_cells
    last[scs[-1].n_cells] = (runs[-1], scs[-1].dt)
    if timing:
        t_c = [run_scene(sc)["t_c_continuous"] for sc in scs]
        out["runs"][name]["err %"] = max(100 * abs(c / ref - 1) for c, ref in zip(t_c, refs))
out["runs"]["fig8 same grid"] = counts(b.simulate(Scene(**same), stop_at_contact=False).run) | {"cells": 50}
for n, (run, dt) in last.items():
    out["parts"][str(n)] = parts(run, n, dt)
if timing:
    one = dict(fast, t_end=0.15, newton=ga.Newton(tol=1e-6))
    out["ms"]["setup"] = 1e3 * med(lambda: b.simulate(Scene(**one)), 9)
    for name, (n, nw, long) in fig8.items():
        out["ms"][name] = 1e3 * med(lambda: b.detect_onset(fig8_run(n, nw, long)), 9)
    for name, (nw, long, steps) in sweeps.items():
        out["ms"][name] = 1e3 * med(lambda: [run_scene(sc) for sc in sweep(nw, long, steps)], 1)
    out["ms"]["fig8 same grid"] = 1e3 * med(lambda: b.simulate(Scene(**same), stop_at_contact=False), 1)
    out["ms"]["estimates"] = 1e3 * med(lambda: [estimate(sc) for sc in P.preset("fig10")], 3)
print(json.dumps(out))
"""


def kernels_ms(c: dict, t: dict, factorisations: bool = True) -> float:
    """The lower bound of the module docstring, in ms (without the factorisations' part
    when ``factorisations`` is false: residuals and solves alone)."""
    fac = c["fac"] * (t["jac"] + t["lu"]) if factorisations else 0.0
    return 1e-3 * (c["res"] * (t["res"] + t["solve"]) + fac)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--rounds", type=int, default=5, help="alternating rounds")
    args = p.parse_args()
    with checkout() as today, checkout(patch=PATCH) as fixed:
        trees = {"today": today, "fixed sizes": fixed}
        parts: dict[str, dict[str, dict[str, float]]] = {k: {} for k in trees}
        wall: dict[str, float] = {}
        runs: dict[str, dict] = {}
        for _ in range(args.rounds):
            for k, wt in trees.items():
                got = run_json(
                    RUN, wt / "src", wt / "benchmarks", "time" if k == "today" else "parts"
                )
                runs = got["runs"] if k == "today" else runs  # the counts: the same each round
                for n, t in got["parts"].items():
                    parts[k][n] = {q: min(parts[k].get(n, t)[q], t[q]) for q in t}
                for name, ms in got["ms"].items():
                    wall[name] = min(wall.get(name, ms), ms)
    cheap = {n: {q: min(parts[k][n][q] for k in trees) for q in parts["today"][n]}
             for n in parts["today"]}  # fmt: skip
    print(f"smallest of {args.rounds} alternating rounds (each a median of repeated calls):")
    for n in sorted(parts["today"], key=int):
        print(f"parts per call at N = {n} (us):")
        for k in trees:
            print(f"  {k:12s} " + "  ".join(f"{q} {v:6.1f}" for q, v in parts[k][n].items()))
    print(
        f"setting a run up (one step, N = 50): {wall['setup']:.1f} ms; the 16 fast "
        f"estimates that pace the sweep (inside its wall time): {wall['estimates']:.0f} ms"
    )
    print(f"{'run':28s} {'N':>4s} {'steps':>6s} {'res':>6s} {'LU':>5s} {'wall ms':>8s} "
          f"{'kernels ms':>10s} {'res+solve':>9s} {'floor ms':>8s} {'error %':>7s}")  # fmt: skip
    for name, c in runs.items():
        floor = 300.0 if "sweep" in name else float("nan") if "same" in name else 10.0
        t = cheap[str(c["cells"])]
        print(f"{name:28s} {c['cells']:4d} {c['steps']:6d} {c['res']:6d} {c['fac']:5d} "
              f"{wall[name]:8.1f} {kernels_ms(c, t):10.1f} {kernels_ms(c, t, False):9.1f} "
              f"{floor:8.1f} {c.get('err %', float('nan')):7.3f}")  # fmt: skip
    same = runs["fig8 same grid"]
    step, bound = (
        1e3 * wall["fig8 same grid"] / same["steps"],
        1e3 * kernels_ms(same, cheap["50"]) / same["steps"],
    )
    print(
        f"same-grid Fig 8 step: {step:.0f} us today, kernels alone at least {bound:.0f} us "
        f"({bound / step:.2f} of it; the floor: half the baseline's, which is today's engine)"
    )


if __name__ == "__main__":
    main()
