"""Cost of the linear solve of one Newton iteration of a contact step
(:mod:`dyntorsion.genalpha.low_rank`): the Woodbury correction on the banded factors
against the sparse LU of the whole matrix, versus the number of rank-one contact terms, at
N = 100, 400 and 800 cells (the Table 1 rod, a bent state with every field nonzero).

Each term is that of a pair pressing (C5 of :mod:`dyntorsion.beyond.contact.implicit`): two
segments far apart along the rod, nonzero in the rows of the cells beside their four nodes
and in the velocities and spins of those nodes.  Both solves are timed after the banded
factorisation the Newton iteration makes anyway; the largest difference of the two
solutions relative to their size is printed.  The switch
:func:`~dyntorsion.genalpha.low_rank.sparse_from` should sit near the crossing
(printed).  Run it with one BLAS thread (``OPENBLAS_NUM_THREADS=1``) when other processes
share the cores.  Medians of repeated runs on a shared machine: compare the ratios.
Nothing is asserted.

With ``--baseline COMMIT`` it also runs a whole scene past contact with the code of this
checkout and of COMMIT (a temporary git worktree, alternating subprocesses so that both see
the same load): PyElastica's plectoneme scene (``dyntorsion.studies.contact.plectoneme_dyntorsion``'s
``contact_scene``, from this checkout in both runs) on N = 100, dt = 0.02 s to t = 30 s (first contact at 8.9 s, the plectoneme forming from
~12 s), after one run of each that compiles its kernels, and prints the seconds per contact step, the run's wall time and its writhe at the
end (the same to rounding in both).

With ``--writhe-baseline COMMIT`` it times the writhe of a coiled centreline (a helix
of 4 turns closed as the rod is, :mod:`dyntorsion.beyond.contact.topology`, computed at
every check of a run past contact) on N = 200, 800 and 1600 segments with this checkout's
kernel and COMMIT's, in alternating subprocesses, and prints both sums (the same bit for
bit since the scalar kernel: 0ef5509a is the kernel before it).

Run: ``python benchmarks/bench_contact.py [--baseline 99c8d9e] [--rounds R]
[--writhe-baseline 0ef5509a]`` (99c8d9e: the contact step before the sparse LU and the
compiled gathering).
"""

from __future__ import annotations

import argparse
import platform
import statistics
import time

import numpy as np

from dyntorsion import Rod, __version__
from dyntorsion.buckling.scene import Scene
from dyntorsion.genalpha.discrete import Start, setup
from dyntorsion.genalpha.low_rank import sparse_from, sparse_solve, woodbury_solve
from dyntorsion.genalpha.scheme import Scheme
from dyntorsion.genalpha.state import factor_jacobian, residual_jacobian
from dyntorsion.model.cosserat import Cosserat
from worktree import ROOT, checkout, run_code, run_json


def median_ms(fn, *args, repeats: int = 7) -> float:
    samples = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn(*args)
        samples.append(time.perf_counter() - t0)
    return 1e3 * statistics.median(samples)


def case(n: int, k: int, rng):
    """The factored step matrix of N = n and k rank-one contact terms (module docstring)."""
    rod = Rod.paper()
    system = Cosserat(rod).system()
    nf = system.nf
    scene = Scene(a=16.0, kappa0=10.0, n_cells=n, dt=0.01)
    left, right = scene.ends.rows(system, scene.twist, scene.tension)
    y0 = np.zeros((n + 1, nf))
    y0[:, system.index("k3")] = 10.0
    con, w, fac = setup(system, Scheme(), n, rod.L / n, 2.5e-4, left, right, Start(y0, 0 * y0))
    w.y[:, :] = y0 + 1e-3 * rng.normal(size=y0.shape)
    gL, gR = left.at(np.array([2.5e-4]))[0], right.at(np.array([2.5e-4]))[0]
    residual_jacobian(system.F, system.dF, con, gL, gR, w)
    factor_jacobian(con, w, fac)
    nbl = con.left_rows.shape[0]
    U, G = np.zeros((k, nf * (n + 1))), np.zeros((k, nf * (n + 1)))
    for t in range(k):
        i = int(rng.integers(0, n // 2 - 1))
        j = i + n // 2
        for node in (i, i + 1, j, j + 1):
            for cell in (node - 1, node):
                if 0 <= cell < n:
                    U[t, nbl + nf * cell + np.arange(3)] = 1e-2 * rng.normal(size=3)
            G[t, nf * node + np.arange(6)] = rng.normal(size=6)
    return w, fac, U, G


#: this checkout's record modules: the scene is their ``plectoneme_dyntorsion.contact_scene``
#: in both trees (one place for it), run with the package of each
BENCH = str(ROOT / "src" / "dyntorsion" / "studies")

# The tree's package first; this checkout's studies folder searched before the tree's, so
# that the scene module is this checkout's, importing the tree's engine.  Its records
# helper (writing, provenance) is not needed and may not exist in an older tree: a stub.
SCENE = r"""
import json, pathlib, sys, time, types
sys.path[:0] = [sys.argv[1]]
import dyntorsion.studies
dyntorsion.studies.__path__.insert(0, sys.argv[2])
stub = types.ModuleType("dyntorsion.studies.contact.records")
stub.DATA = pathlib.Path(".")
stub.provenance = stub.result_json = stub.run_script = stub.summary = None
sys.modules[stub.__name__] = stub
from dyntorsion.beyond.contact.run import run_contact_scene
from dyntorsion.studies.contact.plectoneme_dyntorsion import contact_scene
t_end = float(sys.argv[3])
t0 = time.perf_counter()
res = run_contact_scene(contact_scene(100, 0.02), t_end).result()
print(json.dumps({"wall": time.perf_counter() - t0, "writhe": res["writhe_turns"],
                  "contact_step": res["implicit"]["seconds_per_contact_step"],
                  "contact_steps": res["implicit"]["contact_steps"]}))
"""


def alternate(
    baseline: str, code: str, args: list[str], rounds: int, warm: list[str] | None = None
) -> dict[str, list[dict]]:
    """``code`` run with this checkout's ``src`` and ``baseline``'s (a temporary git
    worktree) in alternating subprocesses, ``rounds`` times each, after one run of each
    with ``warm`` (compiling its kernels) when given: the JSON each printed last."""
    with checkout(baseline) as wt:
        trees = (ROOT / "src", wt / "src")
        out = {"this checkout": [], f"baseline {baseline}": []}
        for src in trees if warm is not None else ():
            run_code(code, src, *warm)
        for _ in range(max(rounds, 1)):
            for key, src in zip(out, trees, strict=True):
                out[key].append(run_json(code, src, *args))
    return out


def scene_against(baseline: str, rounds: int) -> None:
    """The plectoneme scene with this checkout's code and ``baseline``'s (module docstring)."""
    out = alternate(baseline, SCENE, [BENCH, "30"], rounds, warm=[BENCH, "9.5"])
    print("PyElastica's plectoneme scene, N = 100, dt = 0.02 s, to 30 s (medians of "
          f"{rounds} alternating runs):")  # fmt: skip
    for key, runs in out.items():
        step = statistics.median(r["contact_step"] for r in runs)
        wall = statistics.median(r["wall"] for r in runs)
        print(f"  {key:<22} {step:.4f} s a contact step ({runs[0]['contact_steps']} steps), "
              f"run {wall:.1f} s, writhe at 30 s {runs[0]['writhe']:.6f} turns")  # fmt: skip


WRITHE = r"""
import json, statistics, sys, time
sys.path.insert(0, sys.argv[1])
import numpy as np
from dyntorsion.beyond.contact.topology import closed_polygon, writhe_turns
out = {}
for n in (200, 800, 1600):
    th = np.linspace(0.0, 8 * np.pi, n + 1)
    closed = closed_polygon(np.c_[0.1 * np.cos(th) - 0.1, 0.1 * np.sin(th), 0.05 * th])
    value = writhe_turns(closed)
    times = []
    for _ in range(5):
        t0 = time.perf_counter()
        writhe_turns(closed)
        times.append(time.perf_counter() - t0)
    out[n] = [1e3 * statistics.median(times), value]
print(json.dumps(out))
"""


def writhe_against(baseline: str, rounds: int) -> None:
    """The writhe kernel of this checkout and of ``baseline`` (module docstring)."""
    out = alternate(baseline, WRITHE, [], rounds)
    print(f"The writhe of a helix of 4 turns (medians of 5 calls; {max(rounds, 1)} round(s)):")
    keys = list(out)
    for n in out[keys[0]][0]:
        ms = {k: statistics.median(r[n][0] for r in out[k]) for k in keys}
        vals = {k: out[k][0][n][1] for k in keys}
        same = "the same bit for bit" if len(set(vals.values())) == 1 else "DIFFERENT"
        print(f"  N = {n:>5}: " + ", ".join(f"{k} {ms[k]:.1f} ms" for k in keys)
              + f" (ratio {ms[keys[1]] / ms[keys[0]]:.2f}); writhe {vals[keys[0]]:.12f} turns, "
              f"{same}")  # fmt: skip


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline", help="also run a scene past contact with this commit's code")
    ap.add_argument("--rounds", type=int, default=1, help="alternating runs of each (default 1)")
    ap.add_argument("--writhe-baseline", help="also time the writhe kernel against this commit's")
    args = ap.parse_args()
    print(f"dyntorsion {__version__}, python {platform.python_version()}, the sparse LU from "
          f"{sparse_from(100)} / {sparse_from(400)} / {sparse_from(800)} terms at N = 100 / 400 / 800")  # fmt: skip
    print(f"{'N':>5} {'terms':>6} {'Woodbury [ms]':>14} {'sparse LU [ms]':>15} {'ratio':>6} "
          f"{'rel. diff':>10}")  # fmt: skip
    rng = np.random.default_rng(1)
    for n in (100, 400, 800):
        for k in (12, 48, 192, 384, 768):
            if k > 2 * n:
                continue
            w, fac, U, G = case(n, k, rng)
            r = w.r.copy()
            a, b = np.empty_like(w.y), np.empty_like(w.y)
            woodbury_solve(fac, r, U, G, a)  # compile
            sparse_solve(w.left, w.A, w.B, w.right, r, U, G, b)
            diff = float(np.abs(a - b).max() / np.abs(a).max())
            tw = median_ms(woodbury_solve, fac, r, U, G, a)
            ts = median_ms(sparse_solve, w.left, w.A, w.B, w.right, r, U, G, b)
            print(f"{n:>5} {k:>6} {tw:>14.2f} {ts:>15.2f} {tw / ts:>6.2f} {diff:>10.1e}",
                  flush=True)  # fmt: skip
    if args.baseline:
        scene_against(args.baseline, args.rounds)
    if args.writhe_baseline:
        writhe_against(args.writhe_baseline, args.rounds)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
