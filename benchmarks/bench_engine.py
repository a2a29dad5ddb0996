"""Cost of the generalised-alpha engine versus the number of cells (12-field model).

For N = 50 ... 800 it times, on the Fig 8 rod with kappa0 = 10 and a small bent
state (every field nonzero):

* one full Newton iteration: residual + Jacobian assembly + block LU + solve;
* a bare ``scipy.linalg.solve_banded`` (LAPACK gbsv) of the same matrix and
  right-hand side, for reference (it does only the LU and the solve);
* one time step of the buckling scene, as the solver runs it (Jacobian reuse);
* the parts of the linear algebra: the block LU, the explicit block operators built
  from it (``_abd.explicit``), and one solve by substitution with the LU factors
  against one with the operators (what each reuse of kept factors costs).

Timings are medians of repeated runs on a shared machine: compare the ratios,
not the absolute numbers.  Nothing here is asserted.
"""

from __future__ import annotations

import platform
import statistics
import sys
import time

import numpy as np
from scipy.linalg import solve_banded

from dyntorsion import Rod, __version__
from dyntorsion import genalpha as ga
from dyntorsion.buckling.loading import EQ30
from dyntorsion.genalpha import abd as _abd
from dyntorsion.model.cosserat import IDX, Cosserat


def median_time(fn, repeats: int, inner: int) -> float:
    """Median over ``repeats`` of the mean time of ``inner`` calls."""
    samples = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        for _ in range(inner):
            fn()
        samples.append((time.perf_counter() - t0) / inner)
    return statistics.median(samples)


def scene(n: int):
    model = Cosserat(Rod())
    system = model.system()
    kappa0, a = 10.0, 1.6
    left = ga.Boundary(
        ga.Boundary.fields(system, list(EQ30.left)).rows,
        lambda t: np.outer(kappa0 + a * t, [0, 0, 0, 0, 0, 1.0]),
    )
    right = ga.Boundary.fields(system, list(EQ30.right))
    y = np.zeros((n + 1, 12))
    y[:, IDX["k3"]] = kappa0
    return model, system, left, right, y


def main() -> None:
    rng = np.random.default_rng(0)
    print(f"dyntorsion {__version__}, Python {sys.version.split()[0]}, {platform.machine()}")
    print("N      t_iter[us]  t_band[us]  iter/band  t_step[us]  us/node/iter  steps/s")
    dt = 1e-3
    for n in (50, 100, 200, 400, 800):
        model, system, left, right, y = scene(n)
        ys, _ = model.scales()
        y_bent = y + 1e-3 * ys * rng.normal(size=y.shape)
        iteration, blocks, rhs = ga.newton_iteration_kernel(
            system, ga.Scheme(), n, 1.0, dt, left, right, y_bent
        )
        inner = max(1, 4000 // n)
        t_iter = median_time(lambda inner=inner, it=iteration: it(inner), 7, 1) / inner
        (lo, up), ab = _abd.to_banded(*blocks)
        b = rhs.copy()
        t_band = median_time(
            lambda ab=ab, b=b, lo=lo, up=up: solve_banded((lo, up), ab, b), 7, inner
        )
        # one step of the real scene (includes Jacobian reuse and the step set-up)
        f = np.zeros((n + 1, 3))
        f[:, 0] = 1e-8
        steps = 400
        run = ga.integrate(
            ga.Problem(
                system,
                y,
                left,
                right,
                sources=ga.Sources(separable=(model.external_force(f), None)),
            ),
            ga.Grid(n_cells=n, length=1.0, dt=dt, t_end=steps * dt),
            output=ga.Output(record={"u3": ("u3", -1)}),
        )
        t_step = run.wall_time / run.steps
        print(
            f"{n:<6d} {1e6 * t_iter:10.1f}  {1e6 * t_band:10.1f}  {t_iter / t_band:9.2f}"
            f"  {1e6 * t_step:10.1f}  {1e6 * t_iter / (n + 1):12.3f}  {1 / t_step:7.0f}"
        )

    print()
    print("N      factor[us]  operators[us]  solve LU[us]  solve explicit[us]  ratio")
    for n in (50, 100, 200, 400, 800):
        model, system, left, right, y = scene(n)
        ys, _ = model.scales()
        y_bent = y + 1e-3 * ys * rng.normal(size=y.shape)
        _, (BL, A, B, BR), rhs = ga.newton_iteration_kernel(
            system, ga.Scheme(), n, 1.0, dt, left, right, y_bent
        )
        fac = _abd.allocate(n, system.nf, BL.shape[0])
        x = np.zeros((n + 1, system.nf))
        inner = max(1, 4000 // n)
        blocks = (BL, A, B, BR)
        t_fac = median_time(lambda b=blocks, f=fac: _abd.factor(*b, f), 7, inner)
        t_ops = median_time(lambda f=fac: _abd.explicit(f), 7, inner)
        t_lu = median_time(lambda f=fac, r=rhs, x=x: _abd.solve_lu(f, r, x), 7, 4 * inner)
        t_ex = median_time(lambda f=fac, r=rhs, x=x: _abd.solve_explicit(f, r, x), 7, 4 * inner)
        print(
            f"{n:<6d} {1e6 * t_fac:10.1f}  {1e6 * t_ops:13.1f}  {1e6 * t_lu:12.1f}"
            f"  {1e6 * t_ex:18.1f}  {t_lu / t_ex:5.2f}"
        )


if __name__ == "__main__":
    main()
