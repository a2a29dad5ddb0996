"""Almost-block-diagonal LU for the Jacobian of one generalised-alpha step.

Rows of the global system are ordered as the discrete equations (eq 12):

    [ nbL left boundary rows        ]  act on node 0
    [ cell 1:  A_1 y_0 + B_1 y_1    ]  nf rows
    [ ...                           ]
    [ cell N:  A_N y_{N-1} + B_N y_N]
    [ nbR right boundary rows       ]  act on node N,   nbL + nbR = nf.

Gaussian elimination with partial pivoting is done one node at a time on an
(nbL + nf) x 2nf working block: the nbL rows carried over from the previous node
and the nf rows of the next cell.  The candidate pivot rows are exactly those a
banded LU (LAPACK ``gbtrf``) would search, so the pivots and the stability are the
same; the structural zeros of the band are never touched.  Cost and storage are
linear in the number of cells.

Storage: ``W[b]`` (m x 2nf, m = nbL + nf) holds the multipliers (columns 0..nf-1,
below the diagonal), the U rows of node b (rows 0..nf-1) and the carried rows
(rows nf..m-1, columns nf..2nf-1); ``piv[b]`` the row interchanges, LAPACK style.
The last node is an nf x nf dense LU in ``Wl``/``pivl``.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ._numba import A1, A2, A3, I1, I2, jit, named


class Factors(NamedTuple):
    """LU factors of the staircase matrix (see the module docstring) and a work vector."""

    W: np.ndarray
    piv: np.ndarray
    Wl: np.ndarray
    pivl: np.ndarray
    v: np.ndarray


FACTORS = named(Factors, A3, I2, A2, I1, A1)


def allocate(n_cells: int, nf: int, nbl: int) -> Factors:
    """Work arrays for :func:`factor` and :func:`solve`."""
    m = nbl + nf
    W = np.zeros((n_cells, m, 2 * nf))
    piv = np.zeros((n_cells, nf), dtype=np.int64)
    Wl = np.zeros((nf, nf))
    pivl = np.zeros(nf, dtype=np.int64)
    v = np.zeros(m)
    return Factors(W, piv, Wl, pivl, v)


@jit
def _lu_rows(Wb, piv_b, m, ncol, nelim):
    """Partial-pivot elimination of the first ``nelim`` columns of Wb[:m, :ncol].

    Returns the index (>= 0) of the first zero pivot, or -1 when all are nonzero.
    """
    for q in range(nelim):
        p = q
        best = abs(Wb[q, q])
        for r in range(q + 1, m):
            val = abs(Wb[r, q])
            if val > best:
                best = val
                p = r
        piv_b[q] = p
        if best == 0.0:
            return q
        if p != q:
            for c in range(q, ncol):
                tmp = Wb[q, c]
                Wb[q, c] = Wb[p, c]
                Wb[p, c] = tmp
        inv = 1.0 / Wb[q, q]
        for r in range(q + 1, m):
            lmul = Wb[r, q] * inv
            Wb[r, q] = lmul
            if lmul != 0.0:
                for c in range(q + 1, ncol):
                    Wb[r, c] -= lmul * Wb[q, c]
    return -1


@jit
def factor(BL, A, B, BR, W, piv, Wl, pivl):
    """LU-factorise the staircase matrix given by its blocks.

    BL (nbL, nf): left boundary rows on node 0; A[j], B[j] (nf, nf): cell j+1 on
    nodes j and j+1; BR (nbR, nf): right boundary rows on node N.
    Returns -1 on success, else the global column index of a zero pivot.
    """
    n_cells = A.shape[0]
    nf = A.shape[1]
    nbl = BL.shape[0]
    m = nbl + nf
    for b in range(n_cells):
        Wb = W[b]
        if b == 0:
            for r in range(nbl):
                for c in range(nf):
                    Wb[r, c] = BL[r, c]
        else:
            Wp = W[b - 1]
            for r in range(nbl):
                for c in range(nf):
                    Wb[r, c] = Wp[nf + r, nf + c]
        for r in range(nbl):
            for c in range(nf, 2 * nf):
                Wb[r, c] = 0.0
        for r in range(nf):
            for c in range(nf):
                Wb[nbl + r, c] = A[b, r, c]
                Wb[nbl + r, nf + c] = B[b, r, c]
        bad = _lu_rows(Wb, piv[b], m, 2 * nf, nf)
        if bad >= 0:
            return b * nf + bad
    Wp = W[n_cells - 1]
    for r in range(nbl):
        for c in range(nf):
            Wl[r, c] = Wp[nf + r, nf + c]
    for r in range(nf - nbl):
        for c in range(nf):
            Wl[nbl + r, c] = BR[r, c]
    bad = _lu_rows(Wl, pivl, nf, nf, nf)
    if bad >= 0:
        return n_cells * nf + bad
    return -1


@jit
def solve(W, piv, Wl, pivl, v, rhs, x):
    """Solve with the factors of :func:`factor`.

    rhs: flat vector in row order (length nf (N+1)); x: (N+1, nf) solution.
    ``v`` is a work vector of length nbL + nf.
    """
    n_cells, m, two_nf = W.shape
    nf = two_nf // 2
    nbl = m - nf
    for r in range(nbl):
        v[r] = rhs[r]
    for b in range(n_cells):
        Wb = W[b]
        off = nbl + nf * b
        for r in range(nf):
            v[nbl + r] = rhs[off + r]
        for q in range(nf):
            p = piv[b, q]
            if p != q:
                tmp = v[q]
                v[q] = v[p]
                v[p] = tmp
            vq = v[q]
            if vq != 0.0:
                for r in range(q + 1, m):
                    v[r] -= Wb[r, q] * vq
        for r in range(nf):
            x[b, r] = v[r]
        for r in range(nbl):
            v[r] = v[nf + r]
    off = nbl + nf * n_cells
    for r in range(nf - nbl):
        v[nbl + r] = rhs[off + r]
    for q in range(nf):
        p = pivl[q]
        if p != q:
            tmp = v[q]
            v[q] = v[p]
            v[p] = tmp
        vq = v[q]
        for r in range(q + 1, nf):
            v[r] -= Wl[r, q] * vq
    for q in range(nf - 1, -1, -1):
        acc = v[q]
        for c in range(q + 1, nf):
            acc -= Wl[q, c] * x[n_cells, c]
        x[n_cells, q] = acc / Wl[q, q]
    for b in range(n_cells - 1, -1, -1):
        Wb = W[b]
        for q in range(nf - 1, -1, -1):
            acc = x[b, q]
            for c in range(nf):
                acc -= Wb[q, nf + c] * x[b + 1, c]
            for c in range(q + 1, nf):
                acc -= Wb[q, c] * x[b, c]
            x[b, q] = acc / Wb[q, q]


def to_dense(BL, A, B, BR) -> np.ndarray:
    """The global matrix as a dense array (for tests and benchmarks)."""
    n_cells, nf, _ = A.shape
    nbl = BL.shape[0]
    n = nf * (n_cells + 1)
    J = np.zeros((n, n))
    J[:nbl, :nf] = BL
    for j in range(n_cells):
        r0 = nbl + nf * j
        J[r0 : r0 + nf, nf * j : nf * (j + 1)] = A[j]
        J[r0 : r0 + nf, nf * (j + 1) : nf * (j + 2)] = B[j]
    J[nbl + nf * n_cells :, nf * n_cells :] = BR
    return J


def to_banded(BL, A, B, BR):
    """The global matrix in ``scipy.linalg.solve_banded`` storage: (l, u), ab."""
    J = to_dense(BL, A, B, BR)
    n_cells, nf, _ = A.shape
    nbl = BL.shape[0]
    lo = nbl + nf - 1
    up = 2 * nf - nbl - 1
    n = J.shape[0]
    ab = np.zeros((lo + up + 1, n))
    for i in range(n):
        for k in range(max(0, i - lo), min(n, i + up + 1)):
            ab[up + i - k, k] = J[i, k]
    return (lo, up), ab
