"""Initial data: consistent rates and states satisfying the algebraic rows of eq (12)."""

from __future__ import annotations

import numpy as np

from ..model.system import System
from .newton import ConvergenceError
from .parts import Grid, Problem
from .scheme import Scheme

__all__ = ["consistent_rates", "algebraic_residual", "consistent_initial_state"]


def consistent_rates(system: System, y0: np.ndarray, ds: float, q0: np.ndarray | None = None):
    """y_t at t_0 from the equations: M y_t = -(K y_s + F(y) + q) (least squares in M).

    y_s is taken by second-order finite differences.  Fields whose rows carry no
    time derivative (zero rows of M) get the minimum-norm rate.
    """
    y_s = np.gradient(y0, ds, axis=0, edge_order=2)
    rhs = -(y_s @ system.K.T + system.load(y0))
    if q0 is not None:
        rhs -= q0
    return rhs @ np.linalg.pinv(system.M).T


def algebraic_residual(
    system: System, y: np.ndarray, ds: float, scheme: Scheme = Scheme(), q: np.ndarray | None = None
) -> np.ndarray:
    """The rows without a time derivative (zero rows of M) at one time level, per cell.

    For the Cosserat model these are the discrete inextensibility rows
    (u_j - u_{j-1})/ds + <k x u - w x d3>_j.  Returns an array (N, n_alg).
    """
    alg = np.flatnonzero(~np.any(system.M != 0, axis=1))
    _, b_s, _ = scheme.space
    y = np.asarray(y, float)
    dy = (y[1:] - y[:-1]) / ds
    if scheme.quadrature == "trapezoidal":
        Fn = system.load(y)
        Fc = (1 - b_s) * Fn[1:] + b_s * Fn[:-1]
    else:
        Fc = system.load((1 - b_s) * y[1:] + b_s * y[:-1])
    R = dy @ system.K.T + Fc
    if q is not None:
        R += (1 - b_s) * q[1:] + b_s * q[:-1]
    return R[:, alg]


def _source_at(problem: Problem, s: np.ndarray, t: float) -> np.ndarray | None:
    """q(s, t) of ``problem``'s sources at the nodes ``s`` (None: no source)."""
    sources = problem.sources
    if sources.separable is None and sources.field is None:
        return None
    q = np.zeros((s.size, problem.system.nf))
    if sources.separable is not None:
        space, g = sources.separable
        factor = 1.0 if g is None else float(np.asarray(g(np.array([t])))[0])
        q = np.asarray(space, dtype=float) * factor
    if sources.field is not None:
        q = q + sources.field(s, t)
    return q


def consistent_initial_state(
    problem: Problem,
    grid: Grid,
    *,
    scheme: Scheme = Scheme(),
    tol: float = 1e-13,
    max_iter: int = 20,
) -> np.ndarray:
    """The state nearest to ``problem.y0`` (scaled least change) that satisfies the discrete
    algebraic rows, with the problem's source, and both boundary conditions at
    ``grid.t0`` exactly (Gauss-Newton on ``grid``'s nodes); an array (N+1, nf).

    Needed for initial data that satisfy the continuous constraint only (a
    manufactured solution, a measured shape); not for the paper's straight rod.
    Raises :class:`~.newton.ConvergenceError` when ``max_iter`` iterations do not bring the
    scaled correction below ``tol``.
    """
    system, left, right, t0 = problem.system, problem.left, problem.right, grid.t0
    y0, length = problem.y0, grid.length
    q0 = _source_at(problem, grid.s, t0)
    from scipy import sparse
    from scipy.sparse.linalg import spsolve

    y = np.array(y0, dtype=float)
    n1, nf = y.shape
    n = n1 - 1
    ds = length / n
    alg = np.flatnonzero(~np.any(system.M != 0, axis=1))
    _, b_s, _ = scheme.space
    ysc = np.asarray(system.yscale, float)
    gL, gR = left.at(np.array([t0]))[0], right.at(np.array([t0]))[0]
    D = sparse.diags(np.tile(ysc, n1))
    for _ in range(max_iter):
        R = algebraic_residual(system, y, ds, scheme, q0)
        res = np.concatenate([left.rows @ y[0] - gL, R.ravel(), right.rows @ y[-1] - gR])
        rows, cols, vals = [], [], []
        nb = left.nb
        for r in range(nb):
            for f in range(nf):
                if left.rows[r, f]:
                    rows.append(r), cols.append(f), vals.append(left.rows[r, f])
        na = alg.size
        for j in range(n):
            if scheme.quadrature == "trapezoidal":
                Jn = system.load_jacobian(y[j + 1])
                Jp = system.load_jacobian(y[j])
            else:
                Jn = Jp = system.load_jacobian((1 - b_s) * y[j + 1] + b_s * y[j])
            for a, r in enumerate(alg):
                row = nb + na * j + a
                for f in range(nf):
                    vn = system.K[r, f] / ds + (1 - b_s) * Jn[r, f]
                    vp = -system.K[r, f] / ds + b_s * Jp[r, f]
                    if vn:
                        rows.append(row), cols.append(nf * (j + 1) + f), vals.append(vn)
                    if vp:
                        rows.append(row), cols.append(nf * j + f), vals.append(vp)
        base = nb + na * n
        for r in range(right.nb):
            for f in range(nf):
                if right.rows[r, f]:
                    rows.append(base + r), cols.append(nf * n + f), vals.append(right.rows[r, f])
        J = sparse.csr_matrix((vals, (rows, cols)), shape=(res.size, nf * n1)) @ D
        # minimum-norm correction in scaled unknowns: dz = -J^T (J J^T)^{-1} res
        dz = -(J.T @ spsolve((J @ J.T).tocsc(), res))
        y += (D @ dz).reshape(n1, nf)
        if np.max(np.abs(dz)) <= tol:
            return y
    raise ConvergenceError(
        t0,
        0,
        max_iter,
        float(np.max(np.abs(res))),
        "consistent initial state: Gauss-Newton did not converge",
    )
