"""The linear solve of one Newton iteration of a step with a state-dependent source
(:mod:`.state`): the banded Jacobian J of the step (:mod:`.abd`, the source's 3 x 3 blocks
included) plus its rank-one terms U^T G (for contact, :mod:`dyntorsion.beyond.contact.
implicit`'s (C5): one row of ``U`` and ``G`` for each pair pressing, and with the midpoint
quadrature of the load three for each node in contact):

    (J + U^T G) dx = -r,        U, G of shape (k, rows of the scaled residual).

**Woodbury** on the banded factors of J (few terms):

    (J + U^T G)^{-1} b = z - Z (I + G Z)^{-1} G z,    z = J^{-1} b,  Z = J^{-1} U^T,

one banded solve per term and a dense solve of size k: cost ~ k N + k^3 for k terms on N
cells.  **Sparse LU** of J + U^T G assembled whole (SuperLU, :func:`scipy.sparse.linalg.
splu`, column order COLAMD, partial pivoting), for many terms: its cost hardly grows with
k, each term touching only the rows and unknowns of the four nodes of its pair.  Both
solve the same system (to round-off); from :func:`sparse_from` terms on the second is
taken, near where the two cost the same (``benchmarks/bench_contact.py`` measures both
against the number of terms at N = 100, 400 and 800; the Benchmarks page).

All solves write ``out``, of the shape of the residual ``r`` (nodes x fields, scaled as
:func:`dyntorsion.genalpha.discrete.solve_neg` expects), and return nothing.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sps
import scipy.sparse.linalg as spla

from .._numba import jit
from . import abd as _abd
from .discrete import solve_neg

__all__ = ["low_rank_solve", "sparse_from", "sparse_solve", "woodbury_solve"]


def sparse_from(n_cells: int) -> int:
    """The number of rank-one terms from which :func:`low_rank_solve` takes the sparse LU on
    N = ``n_cells`` (near the measured crossing, module docstring)."""
    return 150 + n_cells // 3


@jit
def _solve_columns(fac, U, Z):
    """Z[c] = J^{-1} U[c] for every term c, with the banded factors of J."""
    for c in range(U.shape[0]):
        solve_neg(fac, U[c], Z[c])
        for j in range(Z.shape[1]):
            for f in range(Z.shape[2]):
                Z[c, j, f] = -Z[c, j, f]


def woodbury_solve(fac, r, U, G, out) -> None:
    """out = -(J + U^T G)^{-1} r, J the banded Jacobian whose factors ``fac`` hold
    (module docstring)."""
    solve_neg(fac, r, out)  # out = -J^{-1} r = z
    k = U.shape[0]
    if k == 0:
        return
    Z3 = np.empty((k,) + out.shape)
    _solve_columns(fac, U, Z3)  # Z[c] = J^{-1} U[c]
    Z = Z3.reshape(k, -1)
    z = out.ravel()
    corr = np.linalg.solve(np.eye(k) + G @ Z.T, G @ z)
    out[:, :] = (z - Z.T @ corr).reshape(out.shape)


def sparse_solve(left, A, B, right, r, U, G, out) -> None:
    """out = -(J + U^T G)^{-1} r by a sparse LU of the whole matrix, J given by its scaled
    blocks (``Work.left``, ``Work.A``, ``Work.B``, ``Work.right``)."""
    J = _abd.to_sparse(left, A, B, right) + sps.csc_matrix(U.T) @ sps.csr_matrix(G)
    out[:, :] = -spla.splu(sps.csc_matrix(J)).solve(r).reshape(out.shape)


def low_rank_solve(w, fac, r, U, G, out) -> None:
    """out = -(J + U^T G)^{-1} r: Woodbury below :func:`sparse_from` terms, else the sparse
    LU (module docstring)."""
    if U.shape[0] < sparse_from(w.A.shape[0]):
        woodbury_solve(fac, r, U, G, out)
    else:
        sparse_solve(w.left, w.A, w.B, w.right, r, U, G, out)
