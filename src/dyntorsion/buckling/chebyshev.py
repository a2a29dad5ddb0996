"""Static stability by Chebyshev collocation (section 6, eqs 31-32): an independent check
of :func:`~dyntorsion.buckling.statics.critical_twist` for isotropic rods, the smallest
twisting moment M at which B w'''' - i M w''' - T w'' = 0 has a nontrivial solution."""

from __future__ import annotations

import numpy as np
import scipy.linalg

from ..model.rod import Rod
from .statics import STATIC_ENDS, checked_tension

__all__ = ["critical_twist_numerical"]


def _cheb(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Chebyshev points on [-1, 1] (descending) and the differentiation matrix (Trefethen)."""
    x = np.cos(np.pi * np.arange(n + 1) / n)
    c = np.r_[2.0, np.ones(n - 1), 2.0] * (-1.0) ** np.arange(n + 1)
    X = np.tile(x, (n + 1, 1)).T
    dX = X - X.T
    D = np.outer(c, 1.0 / c) / (dX + np.eye(n + 1))
    D -= np.diag(D.sum(axis=1))
    return x, D


def critical_twist_numerical(
    rod: Rod, n: int = 28, tension: float = 0.0, ends: str = "clamped"
) -> float:
    """Independent check of :func:`critical_twist` for isotropic rods: the smallest M at
    which B w'''' - i M w''' - T w'' = 0 (w = x + i y the lateral displacement) has a
    nontrivial solution, by Chebyshev collocation (a generalised eigenproblem in M).

    Clamped: w = w' = 0 at both ends.  Pinned (axial torque): w = 0 and
    i B w'' + M w' = 0 (the end moment along the fixed axis).  ``n`` + 1 points: the
    truncation error is spectrally small by n = 20, while the round-off of the fourth
    derivative matrix grows like n^8 eps, so the default n = 28 is near the best
    (about 1e-11 clamped, 2e-10 pinned, relative to the closed forms)."""
    T = checked_tension(rod, tension, ends)
    if not rod.isotropic:
        raise ValueError(
            "critical_twist_numerical covers isotropic sections (B1 = B2); for B1 != B2 "
            "use critical_twist_transfer"
        )
    B = rod.B1
    _, D = _cheb(n)
    D = D * (-2.0 / rod.L)  # s = L (1 - x) / 2: node 0 is s = 0, node n is s = L
    D2, D3, D4 = D @ D, D @ D @ D, D @ D @ D @ D
    I = np.eye(n + 1)
    A = (B * D4 - T * D2).astype(complex)
    Bm = 1j * D3
    rows = [0, n, 1, n - 1]  # replace two rows at each end by the boundary conditions
    if STATIC_ENDS[ends].tangent_held:
        bc_a = [I[0], I[n], D[0], D[n]]
        bc_b = [0 * I[0]] * 4
    else:
        bc_a = [I[0], I[n], 1j * B * D2[0], 1j * B * D2[n]]
        bc_b = [0 * I[0], 0 * I[0], -D[0], -D[n]]
    for r, a_row, b_row in zip(rows, bc_a, bc_b, strict=True):
        A[r] = a_row
        Bm[r] = b_row
    vals = scipy.linalg.eigvals(A, Bm)
    vals = vals[np.isfinite(vals)]
    real = vals[(np.abs(vals.imag) < 1e-6 * np.abs(vals)) & (np.abs(vals.real) > 0)]
    return float(np.min(np.abs(real.real))) / rod.C
