"""Cost of the linear solve of one Newton iteration of a contact step
(:mod:`dyntorsion.beyond.contact.linear`): the Woodbury correction on the banded factors
against the sparse LU of the whole matrix, versus the number of contact columns, at
N = 100, 400 and 800 cells (the Table 1 rod, a bent state with every field nonzero).

The contact columns are those of m nodes in contact, 6 each (velocity and spin), each
column nonzero in the rows of the two cells beside the node and beside a partner node
far along the rod, as :func:`dyntorsion.beyond.contact.implicit.contact_source` makes
them.  Both solves are timed after the banded factorisation the Newton iteration makes
anyway (``_residual_factor``); the largest difference of the two solutions relative to
their size is printed.  The switch :func:`~dyntorsion.beyond.contact.linear.sparse_from`
should sit near the crossing (printed).  Run it with one BLAS thread
(``OPENBLAS_NUM_THREADS=1``) when other processes share the cores.  Medians of repeated runs on a shared machine: compare the
ratios.  Nothing is asserted.

Run: ``python benchmarks/bench_contact.py``.
"""

from __future__ import annotations

import platform
import statistics
import time

import numpy as np

from dyntorsion import Rod, __version__
from dyntorsion.beyond.contact.linear import sparse_from, sparse_solve, woodbury_solve
from dyntorsion.beyond.contact.marching import _residual_factor
from dyntorsion.buckling.scene import Scene
from dyntorsion.genalpha.discrete import setup
from dyntorsion.genalpha.scheme import Scheme
from dyntorsion.model.cosserat import Cosserat


def median_ms(fn, *args, repeats: int = 7) -> float:
    samples = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn(*args)
        samples.append(time.perf_counter() - t0)
    return 1e3 * statistics.median(samples)


def case(n: int, m: int, rng):
    """The factored step matrix of N = n and the columns of m nodes in contact."""
    rod = Rod.paper()
    system = Cosserat(rod).system()
    nf = system.nf
    scene = Scene(a=16.0, kappa0=10.0, n_cells=n, dt=0.01)
    left, right = scene.ends.rows(system, scene.twist, scene.tension)
    y0 = np.zeros((n + 1, nf))
    y0[:, system.index("k3")] = 10.0
    con, w, fac = setup(system, Scheme(), n, rod.L / n, 2.5e-4, left, right, y0, 0 * y0)
    w.y[:, :] = y0 + 1e-3 * rng.normal(size=y0.shape)
    gL, gR = left.at(np.array([2.5e-4]))[0], right.at(np.array([2.5e-4]))[0]
    _residual_factor(system.F, system.dF, con, gL, gR, w, fac)
    nbl = con.left_rows.shape[0]
    nodes = np.sort(rng.choice(np.arange(1, n), size=m, replace=False))
    partner = np.roll(nodes, m // 2)
    C = np.zeros((6 * m, nf * (n + 1)))
    for k, (a, b) in enumerate(zip(nodes, partner, strict=True)):
        for node in (a, b):
            for cell in (node - 1, node):
                if 0 <= cell < n:
                    rows = nbl + nf * cell + np.arange(3)
                    C[6 * k : 6 * k + 6][:, rows] = 1e-2 * rng.normal(size=(6, 3))
    cols = (nf * nodes[:, None] + np.arange(6)[None, :]).ravel()
    return w, fac, C, cols


def main() -> int:
    print(f"dyntorsion {__version__}, python {platform.python_version()}, the sparse LU from "
          f"{sparse_from(100)} / {sparse_from(400)} / {sparse_from(800)} columns at N = 100 / 400 / 800")  # fmt: skip
    print(f"{'N':>5} {'nodes':>6} {'columns':>8} {'Woodbury [ms]':>14} {'sparse LU [ms]':>15} "
          f"{'ratio':>6} {'rel. diff':>10}")  # fmt: skip
    rng = np.random.default_rng(1)
    for n in (100, 400, 800):
        for m in (2, 4, 8, 16, 32, 64, 128):
            if m > n // 2:
                continue
            w, fac, C, cols = case(n, m, rng)
            r = w.r.copy()
            a, b = np.empty_like(w.y), np.empty_like(w.y)
            woodbury_solve(fac, r, C, cols, a)  # compile
            sparse_solve(w.left, w.A, w.B, w.right, r, C, cols, b)
            diff = float(np.abs(a - b).max() / np.abs(a).max())
            tw = median_ms(woodbury_solve, fac, r, C, cols, a)
            ts = median_ms(sparse_solve, w.left, w.A, w.B, w.right, r, C, cols, b)
            print(f"{n:>5} {m:>6} {cols.size:>8} {tw:>14.2f} {ts:>15.2f} {tw / ts:>6.2f} "
                  f"{diff:>10.1e}", flush=True)  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
