"""The Fig 10 sweep in paced steps against the standard grid and the converged onset.

    python benchmarks/bench_paced.py [--jobs 2] [--store DIR]

The converged onset of each of the 16 rates is the Richardson value of the diagonal
pair (N = 100, dt = 0.005 s) and (N = 200, dt = 0.0025 s), second order in both:
t_conv = t_200 + (t_200 - t_100) / 3.  The N = 200 runs (until the first peak) take
about 25 min on one core and are kept in ``--store`` (default
``benchmarks/.paced-reference``, not committed), so a second call only reads them.
The standard sweep and the paced one are read from ``data/`` (``make data``: presets
``fig10`` and ``fig10-paced``).  Prints, per rate, the error of the standard grid,
of the paced sweep and of N = 200 against t_conv, and the paced sweep's change
against the standard grid; nothing is asserted.
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd

from dyntorsion.store.results import Store
from dyntorsion.studies import presets as P
from dyntorsion.studies import sweep as S

HERE = Path(__file__).resolve().parent


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--jobs", type=int, default=1, help="local processes for the N = 200 runs")
    p.add_argument("--store", default=str(HERE / ".paced-reference"), help="where they are kept")
    args = p.parse_args()
    fine = [replace(sc, until="first-peak", n_cells=200, dt=0.0025) for sc in P.preset("fig10")]
    t200 = S.run_sweep(fine, Store(args.store), jobs=args.jobs, progress=False)["t_c"].to_numpy()
    std = P.cached("fig10")
    paced = P.cached("fig10-paced")
    t100, tp = std["t_c"].to_numpy(), paced["t_c"].to_numpy()
    conv = t200 + (t200 - t100) / 3
    pct = lambda x: 100 * (x / conv - 1)  # noqa: E731
    table = pd.DataFrame(
        {
            "a": std["a"].round(4),
            "t_c converged [s]": conv.round(4),
            "standard [%]": pct(t100).round(3),
            "paced [%]": pct(tp).round(3),
            "N=200 [%]": pct(t200).round(3),
            "paced - standard [%]": (100 * (tp / t100 - 1)).round(3),
            "steps standard": std["steps"],
            "steps paced": paced["steps"],
        }
    )
    print(table.to_string(index=False))
    print(
        f"largest |error| against the converged onset: standard {np.abs(pct(t100)).max():.3f} %, "
        f"paced {np.abs(pct(tp)).max():.3f} %, N = 200 {np.abs(pct(t200)).max():.3f} %; "
        f"largest |paced - standard| {np.abs(100 * (tp / t100 - 1)).max():.3f} %; steps "
        f"{int(std['steps'].sum())} standard, {int(paced['steps'].sum())} paced"
    )


if __name__ == "__main__":
    main()
