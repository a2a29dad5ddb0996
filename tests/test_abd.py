"""The almost-block-diagonal LU against dense and banded LAPACK solves."""

import numpy as np
import pytest
from scipy.linalg import solve_banded

from dyntorsion import _abd


@pytest.mark.parametrize("nf,nbl,n", [(12, 6, 1), (12, 6, 40), (2, 1, 30), (5, 2, 7), (3, 0, 4)])
def test_solve_matches_dense(rng, nf, nbl, n):
    BL = rng.normal(size=(nbl, nf))
    A = rng.normal(size=(n, nf, nf))
    B = rng.normal(size=(n, nf, nf))
    BR = rng.normal(size=(nf - nbl, nf))
    W, piv, Wl, pivl, v = _abd.allocate(n, nf, nbl)
    assert _abd.factor(BL, A, B, BR, W, piv, Wl, pivl) == -1
    rhs = rng.normal(size=nf * (n + 1))
    x = np.zeros((n + 1, nf))
    _abd.solve(W, piv, Wl, pivl, v, rhs, x)
    J = _abd.to_dense(BL, A, B, BR)
    x_ref = np.linalg.solve(J, rhs)
    assert np.max(np.abs(x.ravel() - x_ref)) <= 1e-10 * np.max(np.abs(x_ref))
    (lo, up), ab = _abd.to_banded(BL, A, B, BR)
    assert np.allclose(solve_banded((lo, up), ab, rhs), x_ref, rtol=1e-9, atol=1e-12)


def test_pivoting_is_needed_and_done(rng):
    """A zero leading entry in every block forces row interchanges."""
    nf, nbl, n = 4, 2, 5
    BL = rng.normal(size=(nbl, nf))
    BL[:, 0] = 0.0
    BL[0, 0] = 0.0
    A = rng.normal(size=(n, nf, nf))
    A[:, 0, 0] = 0.0
    B = rng.normal(size=(n, nf, nf))
    BR = rng.normal(size=(nf - nbl, nf))
    W, piv, Wl, pivl, v = _abd.allocate(n, nf, nbl)
    assert _abd.factor(BL, A, B, BR, W, piv, Wl, pivl) == -1
    assert piv[0, 0] != 0
    rhs = rng.normal(size=nf * (n + 1))
    x = np.zeros((n + 1, nf))
    _abd.solve(W, piv, Wl, pivl, v, rhs, x)
    assert np.allclose(_abd.to_dense(BL, A, B, BR) @ x.ravel(), rhs, atol=1e-10)


def test_singular_matrix_is_reported(rng):
    nf, nbl, n = 3, 1, 4
    BL = np.zeros((nbl, nf))
    A = rng.normal(size=(n, nf, nf))
    B = rng.normal(size=(n, nf, nf))
    BR = rng.normal(size=(nf - nbl, nf))
    A[0, :, 0] = 0.0  # column 0 is zero in every row: singular
    W, piv, Wl, pivl, v = _abd.allocate(n, nf, nbl)
    assert _abd.factor(BL, A, B, BR, W, piv, Wl, pivl) == 0
