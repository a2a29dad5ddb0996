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

Factors used more than :data:`EXPLICIT_AFTER` times are turned into explicit block
operators (:func:`explicit`, built at the next solve): the forward elimination of node b
maps the carried rows and the rows of cell b+1, v = [carried; rhs_b] (m values), to
[U_b z_b; carried'], and the back substitution is x_b = z_b - G_b x_{b+1} with
G_b = U_b^{-1} C_b (C_b the coupling of the U rows to node b+1).  ``HK[b]`` (m x m,
stored transposed: ``HK[b, c, q]`` multiplies v_c) gives [z_b; carried'] = HK_b^T v in
one product, so a solve is m^2 + nf^2 independent multiply-adds a node instead of a
chain of dependent ones: 1.6 to 1.9 times as fast at N = 50 to 800
(benchmarks/bench_engine.py), the same
solution to rounding (``tests/genalpha/test_abd.py``).  Building them costs about one
factorisation; the simplified Newton iteration reuses its factors for tens of solves,
so nearly every solve takes this path, while factors used a few times only (full
Newton, step halvings) never build them.
"""

from __future__ import annotations

from functools import cache
from typing import NamedTuple

import numpy as np
import scipy.sparse as sps

from .._numba import IndexMatrix, Indices, Matrix, Stack, Vector, jit, named


class Factors(NamedTuple):
    """LU factors of the staircase matrix, their explicit block operators and work
    (see the module docstring)."""

    W: Stack  # (N, m, 2 nf) multipliers, U rows and carried rows of each node
    piv: IndexMatrix  # (N, nf) row interchanges
    Wl: Matrix  # (nf, nf) LU of the last node
    pivl: Indices  # (nf,)
    v: Vector  # (2 m,) work
    HK: Stack  # (N, m, m) forward elimination and U_b^{-1} of each node, transposed
    G: Stack  # (N, nf, nf) U_b^{-1} C_b, transposed
    uses: Indices  # [solves since the factorisation]; HK, G valid once > EXPLICIT_AFTER


#: solves by substitution with new LU factors before their explicit operators are built
#: (:func:`solve`); 1, 4 and 8 gave the same Fig 10 sweep time within 1.2 %
EXPLICIT_AFTER = 4

FACTORS = named(Factors)


def allocate(n_cells: int, nf: int, nbl: int) -> Factors:
    """Work arrays for :func:`factor` and :func:`solve`."""
    m = nbl + nf
    return Factors(
        W=np.zeros((n_cells, m, 2 * nf)),
        piv=np.zeros((n_cells, nf), dtype=np.int64),
        Wl=np.zeros((nf, nf)),
        pivl=np.zeros(nf, dtype=np.int64),
        v=np.zeros(2 * m),
        HK=np.zeros((n_cells, m, m)),
        G=np.zeros((n_cells, nf, nf)),
        uses=np.zeros(1, dtype=np.int64),
    )


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
def factor(BL, A, B, BR, fac):
    """LU-factorise the staircase matrix given by its blocks into ``fac``.

    BL (nbL, nf): left boundary rows on node 0; A[j], B[j] (nf, nf): cell j+1 on
    nodes j and j+1; BR (nbR, nf): right boundary rows on node N.
    Returns -1 on success, else the global column index of a zero pivot.
    """
    W, piv, Wl, pivl = fac.W, fac.piv, fac.Wl, fac.pivl
    fac.uses[0] = 0
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
def solve(fac, rhs, x):
    """Solve with the factors of :func:`factor`: by substitution the first
    :data:`EXPLICIT_AFTER` times, then with the explicit operators (built at the next
    solve, :func:`explicit`).

    rhs: flat vector in row order (length nf (N+1)); x: (N+1, nf) solution.
    """
    if fac.uses[0] == EXPLICIT_AFTER:
        explicit(fac)
    if fac.uses[0] >= EXPLICIT_AFTER:
        solve_explicit(fac, rhs, x)
    else:
        solve_lu(fac, rhs, x)
    fac.uses[0] += 1


@jit
def solve_lu(fac, rhs, x):
    """Solve by forward elimination and back substitution with the LU factors."""
    W, piv, v = fac.W, fac.piv, fac.v
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
    _last_node(fac, rhs, x)
    for b in range(n_cells - 1, -1, -1):
        Wb = W[b]
        for q in range(nf - 1, -1, -1):
            acc = x[b, q]
            for c in range(nf):
                acc -= Wb[q, nf + c] * x[b + 1, c]
            for c in range(q + 1, nf):
                acc -= Wb[q, c] * x[b, c]
            x[b, q] = acc / Wb[q, q]


@jit
def _last_node(fac, rhs, x):
    """x_N from the rows carried into the last node (in ``fac.v[:nbL]``) and the right
    boundary rows, with the dense LU of the last node."""
    Wl, pivl, v = fac.Wl, fac.pivl, fac.v
    n_cells = x.shape[0] - 1
    nf = Wl.shape[0]
    nbl = fac.W.shape[1] - nf
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


@jit
def explicit(fac):
    """The explicit operators ``fac.HK``, ``fac.G`` of the LU factors (module docstring).

    For node b: T = the forward elimination applied to the identity (m x m), Z = U_b^{-1}
    by back substitution; HK[b, c, q] = (Z T)[q, c] for q < nf and T[q, c] below,
    G[b, c, q] = (Z C_b)[q, c].  About as costly as the factorisation itself."""
    W, piv, HK, G = fac.W, fac.piv, fac.HK, fac.G
    n_cells, m, two_nf = W.shape
    nf = two_nf // 2
    T = np.empty((m, m))
    Zt = np.empty((nf, nf))
    for b in range(n_cells):
        Wb = W[b]
        for i in range(m):
            for j in range(m):
                T[i, j] = 0.0
            T[i, i] = 1.0
        for q in range(nf):
            p = piv[b, q]
            if p != q:
                for j in range(m):
                    tmp = T[q, j]
                    T[q, j] = T[p, j]
                    T[p, j] = tmp
            for r in range(q + 1, m):
                lmul = Wb[r, q]
                if lmul != 0.0:
                    for j in range(m):
                        T[r, j] -= lmul * T[q, j]
        # Zt = (U_b^{-1})^T, row k holding column k of the inverse (nonzero for q <= k)
        for col in range(nf):
            for q in range(nf - 1, -1, -1):
                if q > col:
                    Zt[col, q] = 0.0
                    continue
                acc = 1.0 if q == col else 0.0
                for c in range(q + 1, col + 1):
                    acc -= Wb[q, c] * Zt[col, c]
                Zt[col, q] = acc / Wb[q, q]
        HKb, Gb = HK[b], G[b]
        for c in range(m):
            for q in range(nf):
                HKb[c, q] = 0.0
            for k in range(nf):
                tk = T[k, c]
                if tk != 0.0:
                    for q in range(k + 1):
                        HKb[c, q] += Zt[k, q] * tk
            for q in range(nf, m):
                HKb[c, q] = T[q, c]
        for c in range(nf):
            for q in range(nf):
                Gb[c, q] = 0.0
            for k in range(nf):
                ck = Wb[k, nf + c]
                if ck != 0.0:
                    for q in range(k + 1):
                        Gb[c, q] += Zt[k, q] * ck


@jit
def solve_explicit(fac, rhs, x):
    """Solve with the operators of :func:`explicit`: [x_b; carried'] = HK_b^T [carried;
    rhs_b] node by node, the last node by its LU, then x_b -= G_b^T-products back."""
    HK, G, v = fac.HK, fac.G, fac.v
    n_cells, m, _ = HK.shape
    nf = G.shape[1]
    nbl = m - nf
    out = v[m:]
    for r in range(nbl):
        v[r] = rhs[r]
    for b in range(n_cells):
        off = nbl + nf * b
        for r in range(nf):
            v[nbl + r] = rhs[off + r]
        HKb = HK[b]
        for q in range(m):
            out[q] = 0.0
        for c in range(m):
            vc = v[c]
            for q in range(m):
                out[q] += HKb[c, q] * vc
        for q in range(nf):
            x[b, q] = out[q]
        for r in range(nbl):
            v[r] = out[nf + r]
    _last_node(fac, rhs, x)
    for b in range(n_cells - 1, -1, -1):
        Gb = G[b]
        xb = x[b]
        xn = x[b + 1]
        for c in range(nf):
            xc = xn[c]
            for q in range(nf):
                xb[q] -= Gb[c, q] * xc


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


@cache
def sparse_pattern(n_cells: int, nf: int, nbl: int) -> tuple[np.ndarray, np.ndarray]:
    """Row and column indices of the entries of BL, [A_j B_j] (j = 1..N) and BR in the
    global matrix, in the order of ``np.concatenate([BL.ravel(), AB.ravel(), BR.ravel()])``
    with ``AB[j] = [A_j B_j]`` (the layout of the module docstring)."""
    f = np.arange(nf)
    rows = [np.repeat(np.arange(nbl), nf)]
    cols = [np.tile(f, nbl)]
    j = np.arange(n_cells)[:, None, None]
    rows.append(np.broadcast_to(nbl + nf * j + f[None, :, None], (n_cells, nf, 2 * nf)).ravel())
    cols.append(np.broadcast_to(nf * j + np.arange(2 * nf)[None, None, :],
                                (n_cells, nf, 2 * nf)).ravel())  # fmt: skip
    rows.append(np.repeat(nbl + nf * n_cells + np.arange(nf - nbl), nf))
    cols.append(nf * n_cells + np.tile(f, nf - nbl))
    return np.concatenate(rows), np.concatenate(cols)


def to_sparse(BL, A, B, BR, extra=None) -> sps.csc_matrix:
    """The global matrix in compressed sparse columns, plus ``extra`` = (rows, columns,
    values) of entries to add (summed where they meet the blocks' entries)."""
    n_cells, nf, _ = A.shape
    rows, cols = sparse_pattern(n_cells, nf, BL.shape[0])
    data = [BL.ravel(), np.concatenate([A, B], axis=2).ravel(), BR.ravel()]
    if extra is not None:
        rows, cols = np.concatenate([rows, extra[0]]), np.concatenate([cols, extra[1]])
        data.append(extra[2])
    n = nf * (n_cells + 1)
    return sps.csc_matrix((np.concatenate(data), (rows, cols)), shape=(n, n))
