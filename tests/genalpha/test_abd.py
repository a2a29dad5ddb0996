"""The almost-block-diagonal LU against dense and banded LAPACK solves."""

import numpy as np
import pytest
from scipy.linalg import solve_banded

from dyntorsion.genalpha import abd as _abd


@pytest.mark.parametrize("nf,nbl,n", [(12, 6, 1), (12, 6, 40), (2, 1, 30), (5, 2, 7), (3, 0, 4)])
def test_solve_matches_dense(rng, nf, nbl, n):
    BL = rng.normal(size=(nbl, nf))
    A = rng.normal(size=(n, nf, nf))
    B = rng.normal(size=(n, nf, nf))
    BR = rng.normal(size=(nf - nbl, nf))
    fac = _abd.allocate(n, nf, nbl)
    assert _abd.factor(BL, A, B, BR, fac) == -1
    J = _abd.to_dense(BL, A, B, BR)
    (lo, up), ab = _abd.to_banded(BL, A, B, BR)
    # the first EXPLICIT_AFTER solves substitute with the LU factors, the later ones use
    # the explicit operators built at the next: every one solves the system
    for uses in range(_abd.EXPLICIT_AFTER + 2):
        assert fac.uses[0] == uses
        rhs = rng.normal(size=nf * (n + 1))
        x = np.zeros((n + 1, nf))
        _abd.solve(fac, rhs, x)
        x_ref = np.linalg.solve(J, rhs)
        assert np.max(np.abs(x.ravel() - x_ref)) <= 1e-10 * np.max(np.abs(x_ref))
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
    fac = _abd.allocate(n, nf, nbl)
    assert _abd.factor(BL, A, B, BR, fac) == -1
    assert fac.piv[0, 0] != 0
    rhs = rng.normal(size=nf * (n + 1))
    for solve in (_abd.solve_lu, _abd.solve_explicit):
        _abd.explicit(fac)
        x = np.zeros((n + 1, nf))
        solve(fac, rhs, x)
        assert np.allclose(_abd.to_dense(BL, A, B, BR) @ x.ravel(), rhs, atol=1e-10)


def test_singular_matrix_is_reported(rng):
    nf, nbl, n = 3, 1, 4
    BL = np.zeros((nbl, nf))
    A = rng.normal(size=(n, nf, nf))
    B = rng.normal(size=(n, nf, nf))
    BR = rng.normal(size=(nf - nbl, nf))
    A[0, :, 0] = 0.0  # column 0 is zero in every row: singular
    fac = _abd.allocate(n, nf, nbl)
    assert _abd.factor(BL, A, B, BR, fac) == 0


def rod_jacobian(rng, n: int, dt: float):
    """The scaled Jacobian blocks (BL, A, B, BR) and residual of a step of dt from a bent
    state of the rod of Table 1 (kappa3 = 10 1/m plus 1e-3 of each field's scale at
    random), N = n cells."""
    from dyntorsion import Rod
    from dyntorsion import genalpha as ga
    from dyntorsion.buckling.loading import EQ30
    from dyntorsion.model.cosserat import IDX, Cosserat

    model = Cosserat(Rod())
    system = model.system()
    left = ga.Boundary.fields(system, list(EQ30.left), [0, 0, 0, 0, 0, 10.0])
    right = ga.Boundary.fields(system, list(EQ30.right))
    y = np.zeros((n + 1, 12))
    y[:, IDX["k3"]] = 10.0
    ys, _ = model.scales()
    y += 1e-3 * ys * rng.normal(size=y.shape)
    _, blocks, rhs = ga.newton_iteration_kernel(system, ga.Scheme(), n, 1.0, dt, left, right, y)
    return (*blocks, rhs.copy())


def test_explicit_operators_on_the_rod_jacobian(rng):
    """On the Jacobian of a step of the rod (bent, every field nonzero; its U blocks have
    condition numbers up to about 1e4), the explicit operators solve like the LU
    substitution, to rounding, and a new factorisation makes the next solve substitute
    again (operators of stale factors are never used)."""
    n = 60
    BL, A, B, BR, _ = rod_jacobian(rng, n, 0.005)
    fac = _abd.allocate(n, 12, BL.shape[0])
    assert _abd.factor(BL, A, B, BR, fac) == -1
    _abd.explicit(fac)
    J = _abd.to_dense(BL, A, B, BR)
    for _ in range(3):
        rhs = rng.normal(size=12 * (n + 1))
        x_lu, x_ex = np.zeros((n + 1, 12)), np.zeros((n + 1, 12))
        _abd.solve_lu(fac, rhs, x_lu)
        _abd.solve_explicit(fac, rhs, x_ex)
        scale = np.max(np.abs(x_lu))
        assert 0 < np.max(np.abs(x_ex - x_lu)) <= 1e-11 * scale  # different sums, same solve
        assert np.max(np.abs(J @ x_ex.ravel() - rhs)) <= 1e-9 * np.max(np.abs(rhs))
    # after a refactorisation of another matrix the next solves are the LU's, and then
    # the operators are rebuilt from the new factors
    B2 = B + 0.1 * rng.normal(size=B.shape)
    assert _abd.factor(BL, A, B2, BR, fac) == -1
    J2 = _abd.to_dense(BL, A, B2, BR)
    for uses in range(_abd.EXPLICIT_AFTER + 2):
        assert fac.uses[0] == uses
        rhs = rng.normal(size=12 * (n + 1))
        x = np.zeros((n + 1, 12))
        _abd.solve(fac, rhs, x)
        assert np.allclose(x.ravel(), np.linalg.solve(J2, rhs), rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("dt", [1e-7, 100.0])
def test_explicit_operators_at_extreme_steps(rng, dt):
    """At a tiny step the U blocks of the rod's Jacobian have condition numbers near 1e13
    (N = 100, dt = 1e-7 s), at a huge one near 1: the explicit solve stays within 1e-7
    of the LU substitution (measured 1.6e-10 and 4e-15), far inside what a simplified
    Newton correction needs."""
    n = 100
    BL, A, B, BR, rhs = rod_jacobian(rng, n, dt)
    fac = _abd.allocate(n, 12, BL.shape[0])
    assert _abd.factor(BL, A, B, BR, fac) == -1
    _abd.explicit(fac)
    x_lu, x_ex = np.zeros((n + 1, 12)), np.zeros((n + 1, 12))
    _abd.solve_lu(fac, rhs, x_lu)
    _abd.solve_explicit(fac, rhs, x_ex)
    assert np.max(np.abs(x_ex - x_lu)) <= 1e-7 * np.max(np.abs(x_lu))


@pytest.mark.parametrize("nf,nbl,n", [(12, 6, 1), (12, 6, 9), (5, 2, 7), (3, 0, 4)])
def test_sparse_form_is_the_dense_form(rng, nf, nbl, n):
    """to_sparse holds the blocks where to_dense puts them, and adds the extra entries
    (summed where they meet a block's entry, placed where they do not)."""
    BL = rng.normal(size=(nbl, nf))
    A = rng.normal(size=(n, nf, nf))
    B = rng.normal(size=(n, nf, nf))
    BR = rng.normal(size=(nf - nbl, nf))
    J = _abd.to_dense(BL, A, B, BR)
    assert np.array_equal(_abd.to_sparse(BL, A, B, BR).toarray(), J)
    size = nf * (n + 1)
    rows, cols = rng.integers(0, size, 30), rng.integers(0, size, 30)
    keep = np.unique(rows * size + cols, return_index=True)[1]
    rows, cols, vals = rows[keep], cols[keep], rng.normal(size=keep.size)
    J[rows, cols] += vals
    assert np.array_equal(_abd.to_sparse(BL, A, B, BR, extra=(rows, cols, vals)).toarray(), J)
    assert _abd.sparse_pattern(n, nf, nbl)[0].size == _abd.to_sparse(BL, A, B, BR).nnz
