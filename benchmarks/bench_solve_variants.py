"""The explicit block solve (``abd.solve_explicit``) against two cheaper-looking variants
(issue 34, item 2): measured, not adopted.

    python benchmarks/bench_solve_variants.py [--rounds 7]

At N = 50 (12 fields, 6 given at the twisted end) a solve with the explicit operators is
a correction's larger half (``benchmarks/profile_fig08.py``).  Compared here, on the
factors of a random well-conditioned staircase matrix, in alternating rounds (in each
round the median of five timings of 5000 solves; the smallest over the rounds printed):

* today's ``solve_explicit`` (sizes read from the arrays);
* the same loops with the sizes as compile-time constants (what
  ``benchmarks/patches/abd_fixed_sizes.patch`` does for the LU, which it halves); the
  result is checked to be the same to the last bit;
* today's ``solve_explicit`` compiled for operators ``HK`` and ``G`` stored in float32
  (float64 accumulators; the simplified Newton iteration uses the factors only to contract, so their rounding
  would move the converged step by no more than the tolerance; the relative difference of
  one solve is printed).

Nothing is asserted.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from dyntorsion._numba import jit
from dyntorsion.genalpha.abd import _last_node, allocate, explicit, factor, solve_explicit

N, NF, NBL = 50, 12, 6


@jit
def solve_fixed(fac, rhs, x):
    """``solve_explicit`` with m = 18, nf = 12, nbL = 6 as constants."""
    HK, G, v = fac.HK, fac.G, fac.v
    n_cells = HK.shape[0]
    out = v[18:]
    for r in range(6):
        v[r] = rhs[r]
    for b in range(n_cells):
        off = 6 + 12 * b
        for r in range(12):
            v[6 + r] = rhs[off + r]
        HKb = HK[b]
        for q in range(18):
            out[q] = 0.0
        for c in range(18):
            vc = v[c]
            for q in range(18):
                out[q] += HKb[c, q] * vc
        for q in range(12):
            x[b, q] = out[q]
        for r in range(6):
            v[r] = out[12 + r]
    _last_node(fac, rhs, x)
    for b in range(n_cells - 1, -1, -1):
        Gb, xb, xn = G[b], x[b], x[b + 1]
        for c in range(12):
            xc = xn[c]
            for q in range(12):
                xb[q] -= Gb[c, q] * xc


@jit
def _repeat(which, fac, fac32, rhs, x, n):
    for _ in range(n):
        if which == 0:
            solve_explicit(fac, rhs, x)
        elif which == 1:
            solve_fixed(fac, rhs, x)
        else:
            solve_explicit(fac32, rhs, x)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--rounds", type=int, default=7)
    args = p.parse_args()
    rng = np.random.default_rng(0)
    BL, BR = rng.standard_normal((NBL, NF)), rng.standard_normal((NF - NBL, NF))
    A = rng.standard_normal((N, NF, NF))
    B = rng.standard_normal((N, NF, NF)) + 5.0 * np.eye(NF)
    fac = allocate(N, NF, NBL)
    if factor(BL, A, B, BR, fac) >= 0:
        raise RuntimeError("singular test matrix")
    explicit(fac)
    fac32 = fac._replace(HK=fac.HK.astype(np.float32), G=fac.G.astype(np.float32))
    rhs = rng.standard_normal(NF * (N + 1))
    names = ["today's solve_explicit", "sizes as constants", "float32 operators"]
    xs = [np.zeros((N + 1, NF)) for _ in names]
    for k, x in enumerate(xs):
        _repeat(k, fac, fac32, rhs, x, 1)
    print(f"sizes as constants, the same solution to the last bit: "
          f"{'yes' if np.array_equal(xs[0], xs[1]) else 'NO'}")  # fmt: skip
    rel = np.abs(xs[2] - xs[0]).max() / np.abs(xs[0]).max()
    print(f"float32 operators, largest difference relative to the largest |x|: {rel:.1e}")
    reps = 5000
    best = [float("inf")] * len(names)
    for _ in range(args.rounds):
        for k, x in enumerate(xs):
            ts = []
            for _ in range(5):
                t = time.perf_counter()
                _repeat(k, fac, fac32, rhs, x, reps)
                ts.append((time.perf_counter() - t) / reps)
            best[k] = min(best[k], statistics.median(ts))
    for name, v in zip(names, best, strict=True):
        print(f"  {name:24s} {1e6 * v:6.2f} us a solve   ratio {v / best[0]:.2f}")


if __name__ == "__main__":
    main()
