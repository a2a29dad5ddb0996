"""The observed order of the generalised-alpha method on the smooth torsional release of
eq (28) (section 5): kappa3 at t = 0.04 s against the exact d'Alembert solution, the grid
refined in space and time together at three Courant numbers and three lambda_inf (time).

Records of kind ``wave-convergence`` (cached in ``data/``, ``make data-studies``) hold one row per
grid: its errors and the wall time of its solve, so that the Accuracy page reads the study
instead of running 45 solves.
"""

from __future__ import annotations

import time
from typing import Any

from ..model.rod import Rod
from ..store.results import Store
from ..waves import SmoothRelease, solve
from .page_records import read_or_compute

__all__ = ["KIND", "PARAMS", "convergence", "load"]

KIND = "wave-convergence"

#: the study: eq (28) with kappa0 = 10 1/m at rate 50 1/s, read at t = 0.04 s on Table 1's
#: rod; N = 25 * 2**k cells and dt = T / (m0 * 2**k) for k < ``levels``
PARAMS: dict[str, Any] = {
    "kappa0": 10.0,
    "rate": 50.0,
    "t": 0.04,
    "lam_t": [-1.0, -0.5, 0.0],
    "m0": [1, 10, 100],
    "n0": 25,
    "levels": 5,
}


def convergence(params: dict[str, Any] = PARAMS) -> dict[str, Any]:
    """Solve the release on every grid of ``params`` (:data:`PARAMS`); columns (lists of
    equal length, JSON-ready): ``lam_t``, ``courant``, ``n_cells``, ``dt`` [s], ``max_error``
    and ``l2_error`` of kappa3 [1/m] against d'Alembert, ``wall_s`` of each solve."""
    rod = Rod.paper()
    problem = SmoothRelease(params["kappa0"], params["rate"])
    t_end = params["t"]
    cols: dict[str, list] = {
        k: [] for k in ("lam_t", "courant", "n_cells", "dt", "max_error", "l2_error", "wall_s")
    }
    for lam in params["lam_t"]:
        for m0 in params["m0"]:
            for k in range(params["levels"]):
                n, dt = params["n0"] * 2**k, t_end / (m0 * 2**k)
                start = time.perf_counter()
                sol = solve(problem, rod=rod, times=[t_end], n_cells=n, dt=dt, lam_t=lam)
                wall = time.perf_counter() - start
                err = sol.errors(problem.dalembert(sol.s, t_end, c=rod.c, L=rod.L)[None, :])
                for name, value in (
                    ("lam_t", lam),
                    ("courant", rod.c * dt * n / rod.L),
                    ("n_cells", n),
                    ("dt", dt),
                    ("max_error", float(err["max"][0])),
                    ("l2_error", float(err["L2"][0])),
                    ("wall_s", wall),
                ):
                    cols[name].append(value)
    return cols


def load(
    store: Store | str | None = None,
    *,
    compute: bool = False,
    on_stale: str = "recompute",
    params: dict[str, Any] = PARAMS,
) -> dict[str, Any]:
    """The record of the study ``params`` (:data:`PARAMS`) from ``store`` (default
    data/scenes): computed when missing or stale with ``compute=True`` (a stale one refused
    with ``on_stale="error"``), refused otherwise (:class:`LookupError` naming ``make data-studies``)."""
    return read_or_compute(
        KIND, params, lambda: convergence(params), store, compute=compute, on_stale=on_stale
    )


if __name__ == "__main__":  # make data-studies
    import argparse

    from ..store.results import ON_STALE

    parser = argparse.ArgumentParser(description="compute the wave convergence study")
    parser.add_argument("--on-stale", choices=ON_STALE, default="recompute")
    args = parser.parse_args()
    rows = load(compute=True, on_stale=args.on_stale)
    print(f"{KIND}: {len(rows['n_cells'])} grids")
