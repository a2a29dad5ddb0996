"""Where the time of the Fig 8 scene goes (issue 16): N = 50, dt = 0.02 s, to t = 18 s.

    python benchmarks/profile_fig08.py [--tol 1e-10] [--stop correction|contraction]

Times the whole ``simulate`` + ``detect_onset``, the compiled march alone (no checks
between chunks), and each compiled part at the state of the last level (residual without
and with the Jacobian, block LU, the explicit operators of the factors, solve), and
multiplies the part costs by the counts of the run (the explicit operators by the number
of factorisations: an upper bound, factors used at most ``EXPLICIT_AFTER`` times never
build them).  Medians; nothing is asserted.

Where the time went (issue 34, item 2; a quiet moment of the shared machine, the Fig 8
scene at tol 1e-10): residual 6 us, solve 10 us (18 by substitution), block LU 144 us,
explicit operators 160 us a call; 5.9 residuals and solves a step and 168 factorisations
in 900 steps, so about 100 us a step in the simplified Newton iterations and 55 us in
factorisations.  The straight phase (t < 10 s) factorises 6 times in 500 steps and spends
its time in 4.7 iterations a step: the first correction (scaled norm 0.1 to 7, the
torsional waves) leaves about 1e-5, and the factors of an older Jacobian contract that
by about 0.1 a correction to tol (``tests/test_newton_counts.py``).  Tried and dropped
(no fewer corrections): extrapolating the last three levels as the predictor (5.68 a
step against 5.65: the spin w3 and the lateral fields are not smooth in time at this dt,
the torsional waves alternate), a secant (Anderson(1)) step in the simplified iteration
(5.54), and building the explicit operators after 20 solves instead of 4 (3 % less by the
counts here, about 13 % at dt = 0.05 s and tol 1e-6; not resolvable on the loaded machine,
not adopted).
Anderson acceleration with a secant memory, an adaptive extrapolation predictor and a
cost rule for renewing the factors: ``benchmarks/probe_newton_strategies.py`` (none pays).
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from dyntorsion import Rod
from dyntorsion import buckling as b
from dyntorsion import genalpha as ga
from dyntorsion._numba import jit
from dyntorsion.buckling.loading import EQ30
from dyntorsion.buckling.scene import Scene
from dyntorsion.genalpha.abd import EXPLICIT_AFTER, explicit, solve_lu
from dyntorsion.genalpha.discrete import factor, residual, setup, solve_neg
from dyntorsion.model.cosserat import Cosserat


@jit
def _parts(F, dF, con, gL, gR, w, fac, part, reps):
    """``reps`` calls of one compiled part: 0 residual, 1 residual + Jacobian, 2 LU, 3 solve,
    4 the explicit operators of the LU factors, 5 a solve by substitution."""
    for _ in range(reps):
        if part == 0:
            residual(F, dF, con, gL, gR, w.y, w, w.r, False)
        elif part == 1:
            residual(F, dF, con, gL, gR, w.y, w, w.r, True)
        elif part == 2:
            factor(con, w, fac)
        elif part == 4:
            explicit(fac)
        elif part == 5:
            solve_lu(fac, w.r, w.dx)
        else:
            solve_neg(fac, w.r, w.dx)


def median(f, n=5):
    out = []
    for _ in range(n):
        t = time.perf_counter()
        f()
        out.append(time.perf_counter() - t)
    return statistics.median(out)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--tol", type=float, default=1e-10)
    p.add_argument("--stop", default=None)
    args = p.parse_args()
    kw = {"tol": args.tol} | ({"stopping": args.stop} if args.stop else {})
    newton = ga.Newton(**kw)
    scene = {"a": 1.6, "kappa0": 0.0, "n_cells": 50, "dt": 0.02, "t_end": 18.0, "newton": newton}
    b.simulate(Scene(a=1.6, n_cells=10, dt=0.05, t_end=0.2, newton=newton, kappa0=0.0))
    run = b.simulate(Scene(**scene))
    onset = b.detect_onset(run)
    sim = median(lambda: b.simulate(Scene(**scene)), 9)
    chunks = median(lambda: b.simulate(Scene(**scene), stop_at_contact=False), 9)
    bare = median(lambda: b.simulate(Scene(**scene), stop_at_contact=False, check_every=900), 9)
    detect = median(lambda: b.detect_onset(run), 9)
    whole = sim + detect
    r = run.run
    n_it, n_res, n_fac = r.iterations.sum(), r.residual_evaluations.sum(), r.factorisations.sum()
    print(
        f"t_c = {onset.t_c:.6f} s, steps {r.steps}, corrections {n_it} ({n_it / r.steps:.2f}"
        f"/step), residuals {n_res} ({n_res / r.steps:.2f}/step), factorisations {n_fac}"
    )
    # the parts, at the state of the last level (a Jacobian of the bent rod)
    sysm = Cosserat(Rod.paper()).system()
    y = np.ascontiguousarray(r.y)
    n = 50
    left = ga.Boundary.fields(sysm, list(EQ30.left))
    right = ga.Boundary.fields(sysm, list(EQ30.right))
    con, w, fac = setup(sysm, ga.Scheme(), n, Rod.paper().L / n, 0.02, left, right, y, r.y_t)
    gL, gR = np.zeros(left.nb), np.zeros(right.nb)
    F, dF = sysm.F, sysm.dF
    reps = 2000

    def loop(part):
        _parts(F, dF, con, gL, gR, w, fac, part, 1)
        return median(lambda: _parts(F, dF, con, gL, gR, w, fac, part, reps)) / reps

    t_res = loop(0)
    t_jac = loop(1) - t_res
    t_lu = loop(2)
    t_exp = loop(4)
    t_sub = loop(5)
    factor(con, w, fac)
    fac.uses[0] = EXPLICIT_AFTER + 1
    explicit(fac)
    t_sol = loop(3)
    n_jac = n_fac
    parts = {
        "residual": t_res * n_res,
        "Jacobian assembly": t_jac * n_jac,
        "block LU": t_lu * n_fac,
        "explicit operators (at most)": t_exp * n_fac,
        "solve": t_sol * (n_res),
    }
    rows = [
        ("whole: simulate + detect_onset", whole),
        ("simulate", sim),
        ("the march in one chunk", bare),
    ]
    rows += [("  " + k, v) for k, v in parts.items()]
    rows += [("  the rest of the march", bare - sum(parts.values())),
             ("overhead of the 0.1 s chunks", chunks - bare), ("contact checks", sim - chunks),
             ("detect_onset", detect)]  # fmt: skip
    print(f"{'':32s} {'s':>8s} {'% of whole':>10s}")
    for k, v in rows:
        print(f"{k:32s} {v:8.4f} {100 * v / whole:10.0f}")
    print(
        f"per call (us): residual {1e6 * t_res:.1f}, Jacobian {1e6 * t_jac:.1f}, "
        f"LU {1e6 * t_lu:.1f}, explicit operators {1e6 * t_exp:.1f}, solve {1e6 * t_sol:.1f} "
        f"(by substitution {1e6 * t_sub:.1f})"
    )
    t = 0.02 * np.arange(1, r.steps + 1)
    its = np.asarray(r.iterations)[: r.steps]
    edges = [(0, 5), (5, 10), (10, 13), (13, 15), (15, 18.01)]
    print(
        "corrections per step by phase "
        + " ".join(f"[{a:g},{c:g}): {its[(t >= a) & (t < c)].mean():.2f}" for a, c in edges)
    )


if __name__ == "__main__":
    main()
