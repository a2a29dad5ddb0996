"""What a first run waits for: the kernels' compilation, at the package's level and at numba's.

    python benchmarks/bench_compile.py [--out data/bench/compile.json]

Each setting runs in a fresh process with an empty kernel cache:

* ``package``: as shipped (``dyntorsion._numba.KERNEL_OPT`` and numba's generic message for
  a slice of the wrong shape, set only while the package's kernels compile);
* ``numba``: numba's own level (3) and messages (the package's compile listener removed).

For each: the wall time of the README's first command (``buckle --fidelity quick``, the
kernels it needs compiled on the way), then the median of three warm runs of the Fig 8
scene at the standard grid, with its t_c and kappa3 (the two settings must agree to the
last bit).  The Benchmarks page reads the record.  Nothing here is asserted.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from bench_today import machine
from dyntorsion.studies.contact.records import write
from worktree import ROOT

CHILD = r"""
import contextlib, io, json, statistics, sys, time
if sys.argv[1] == "numba":
    from numba.core import event
    import dyntorsion._numba as n
    for listener in list(event._registered["numba:compile"]):
        if isinstance(listener, n._KernelCompilation):
            event.unregister("numba:compile", listener)
from dyntorsion.app.cli import main
from dyntorsion.buckling.scene import Scene, run_scene
start = time.perf_counter()
with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
    main(["buckle", "--a", "16", "--kappa0", "10", "--fidelity", "quick"])
first = time.perf_counter() - start
scene = Scene(a=1.6, kappa0=0.0, n_cells=100, dt=0.005, t_end=30.0)
run_scene(scene)
walls = []
for _ in range(3):
    t = time.perf_counter()
    res = run_scene(scene)
    walls.append(time.perf_counter() - t)
print(json.dumps({"first_quick_buckle_s": first, "fig8_standard_s": statistics.median(walls),
                  "t_c": repr(res["t_c"]), "kappa3": repr(res["kappa3"])}))
"""

SETTINGS = ("package", "numba")


def run(setting: str) -> dict:
    """One setting in a fresh process with an empty kernel cache."""
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache}
        env.pop("NUMBA_OPT", None)
        out = subprocess.run(
            [sys.executable, "-c", CHILD, setting],
            env=env, capture_output=True, text=True, check=True,
        )  # fmt: skip
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", type=Path, default=ROOT / "data" / "bench" / "compile.json")
    args = p.parse_args()
    from dyntorsion import __version__
    from dyntorsion._numba import KERNEL_OPT

    results = {s: run(s) for s in SETTINGS}
    same = len({(r["t_c"], r["kappa3"]) for r in results.values()}) == 1
    import datetime as dt

    record = {
        "date": dt.datetime.now(dt.UTC).isoformat(timespec="seconds"),
        "machine": machine(),
        "dyntorsion": __version__,
        "kernel_opt": KERNEL_OPT,
        "same_numbers": same,
        "results": results,
    }
    write(args.out, record, indent=1)
    for s, r in results.items():
        print(f"{s:8s} first quick buckle {r['first_quick_buckle_s']:6.1f} s, "
              f"Fig 8 standard warm {r['fig8_standard_s']:.3f} s, t_c {r['t_c']}")  # fmt: skip
    ratio = results["numba"]["first_quick_buckle_s"] / results["package"]["first_quick_buckle_s"]
    print(f"first run: numba's settings take {ratio:.2f} times the package's; same numbers: {same}")
    print(f"written: {args.out}")


if __name__ == "__main__":
    main()
