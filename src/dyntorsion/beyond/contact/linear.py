"""The linear solve of one Newton iteration of a contact step (:mod:`.implicit`): the
banded Jacobian J of the step (:mod:`dyntorsion.genalpha.abd`) plus the contact's
columns C E^T (E the columns ``cols`` of the identity),

    (J + C E^T) dx = -r.

**Woodbury** on the banded factors of J (few columns):

    (J + C E^T)^{-1} b = z - Z (I + E^T Z)^{-1} E^T z,    z = J^{-1} b,  Z = J^{-1} C,

one banded solve per column and a dense solve of the columns' size: cost ~ m N + m^3 for m
columns.  **Sparse LU** of J + C E^T assembled whole (SuperLU, :func:`scipy.sparse.linalg.
splu`, column order COLAMD, partial pivoting), for many columns: its cost hardly grows with
m, the columns touching only the rows of the cells beside the nodes in contact.  A
plectoneme of PyElastica's scene at N = 100 holds ~100 nodes in contact, 600 columns.
Both solve the same system; :func:`sparse_from` columns switch from the first to the
second.  Measured (``benchmarks/bench_contact.py``, 2026-11-26, medians, one BLAS
thread): the two cost the same at about 190, 300 and 400 columns for N = 100, 400 and
800; the sparse LU is 2-4 times faster at 768 columns and 4-20 times slower at 12-48.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse.linalg as spla

from ..._numba import jit
from ...genalpha import abd as _abd
from ...genalpha.discrete import solve_neg

__all__ = ["contact_solve", "sparse_from", "sparse_solve", "woodbury_solve"]


def sparse_from(n_cells: int) -> int:
    """The number of contact columns from which :func:`contact_solve` takes the sparse
    LU on N = ``n_cells`` (near the measured crossing, module docstring)."""
    return 150 + n_cells // 3


@jit
def _solve_columns(fac, C, Z):
    """Z[c] = J^{-1} C[c] for every column c, with the banded factors of J."""
    for c in range(C.shape[0]):
        solve_neg(fac, C[c], Z[c])
        for j in range(Z.shape[1]):
            for f in range(Z.shape[2]):
                Z[c, j, f] = -Z[c, j, f]


def woodbury_solve(fac, r, C, cols, out) -> None:
    """out = -(J + C E^T)^{-1} r, J the banded Jacobian whose factors ``fac`` hold
    (module docstring)."""
    solve_neg(fac, r, out)  # out = -J^{-1} r = z
    if cols.size == 0:
        return
    m = cols.size
    Z3 = np.empty((m,) + out.shape)
    _solve_columns(fac, C, Z3)  # Z[c] = J^{-1} C[c]
    Z = Z3.reshape(m, -1)
    z = out.ravel()
    small = np.eye(m) + Z[:, cols].T
    corr = np.linalg.solve(small, z[cols])
    out[:, :] = (z - Z.T @ corr).reshape(out.shape)


def sparse_solve(left, A, B, right, r, C, cols, out) -> None:
    """out = -(J + C E^T)^{-1} r by a sparse LU of the whole matrix, J given by its scaled
    blocks (``Work.left``, ``Work.A``, ``Work.B``, ``Work.right``)."""
    ci, ri = np.nonzero(C)
    J = _abd.to_sparse(left, A, B, right, extra=(ri, cols[ci], C[ci, ri]))
    out[:, :] = -spla.splu(J).solve(r).reshape(out.shape)


def contact_solve(w, fac, r, C, cols, out) -> None:
    """out = -(J + C E^T)^{-1} r: Woodbury below :func:`sparse_from` columns, else the
    sparse LU (module docstring)."""
    if cols.size < sparse_from(w.A.shape[0]):
        woodbury_solve(fac, r, C, cols, out)
    else:
        sparse_solve(w.left, w.A, w.B, w.right, r, C, cols, out)
