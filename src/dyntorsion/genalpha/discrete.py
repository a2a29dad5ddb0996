"""One step of the scheme as a nonlinear system: residual and Jacobian of eq (10)-(12).

For the cell between nodes j-1 and j (see :mod:`dyntorsion.genalpha`) ::

    R_j = M [(1-a_s) abar_j + a_s abar_{j-1}]
          + K [(1-b_t)(y_j^i - y_{j-1}^i) + b_t (y_j^{i-1} - y_{j-1}^{i-1})] / ds
          + <F>_j + <q>_j,

    abar = c_M (y^i - y^{i-1}) + c_A y_t^{i-1}.

Everything that does not depend on y^i is collected once per step in ``c_j``
(:func:`prepare_step`), so that R_j = P y_j^i + Q y_{j-1}^i + (1-b_t) <F(y^i)>_j + c_j
with P = c_M (1-a_s) M + (1-b_t) K / ds and Q = c_M a_s M - (1-b_t) K / ds.  The rows
and unknowns are scaled by the model's ``rscale`` and ``yscale``; the boundary rows
by ``|P_L| yscale``.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .._numba import IndexMatrix, Indices, Matrix, Stack, Vector, jit, named
from ..model.system import Boundary, System
from . import abd as _abd
from .scheme import Coefficients, Scheme

__all__ = ["Constants", "Work", "Start", "constants", "setup"]


class Pattern(NamedTuple):
    """The nonzero columns of one or more nf x nf matrices, row by row: row ``rr`` has
    ``n[rr]`` of them, ``cols[rr, :n[rr]]`` in increasing order.  Sums over a row
    visit only these, in the same order as the dense sum, so the skipped terms (exact
    zeros times finite numbers) change no bit of the result."""

    cols: IndexMatrix
    n: Indices


def pattern(*mats: np.ndarray) -> Pattern:
    """The :class:`Pattern` of the union of the nonzeros of ``mats``."""
    nz = np.zeros(mats[0].shape, dtype=bool)
    for m in mats:
        nz |= np.asarray(m) != 0
    cols = np.zeros(nz.shape, dtype=np.int64)
    n = nz.sum(axis=1).astype(np.int64)
    for rr in range(nz.shape[0]):
        cols[rr, : n[rr]] = np.nonzero(nz[rr])[0]
    return Pattern(cols, n)


class Constants(NamedTuple):
    """What stays fixed during a run: the model, the scheme and the boundary rows."""

    params: Vector  # the model's parameters, passed to F and dF
    M: Matrix
    K: Matrix
    P: Matrix  # d R_j / d y_j^i without the load
    Q: Matrix  # d R_j / d y_{j-1}^i without the load
    co: Coefficients
    yscale: Vector
    rscale: Vector
    left_rows: Matrix
    left_scale: Vector
    right_rows: Matrix
    right_scale: Vector
    pq: Pattern  # where P or Q is nonzero: the residual's sums skip the exact zeros
    mk: Pattern  # where M or K is nonzero: the same for the step's fixed part c_j


class Work(NamedTuple):
    """The state carried from step to step and the work arrays of one step."""

    y_old: Matrix  # y^{i-1}  (N+1, nf)
    rate_old: Matrix  # y_t^{i-1}
    y: Matrix  # the Newton iterate for y^i
    y_trial: Matrix  # y + lam dx
    r: Vector  # scaled residual at y  (nf (N+1),)
    r_trial: Vector  # ... at y_trial
    dx: Matrix  # scaled Newton correction at y
    dx_trial: Matrix  # simplified correction at y_trial
    F: Matrix  # load vector at the nodes (trapezoidal) or the cells (midpoint)
    dF: Stack  # its Jacobian
    F_old: Matrix  # load vector at y^{i-1} (trapezoidal)
    c: Matrix  # the part of each cell's residual fixed during the step  (N, nf)
    y_bar_old: Matrix  # b_t <y^{i-1}>_j  (midpoint rule)
    z: Matrix  # -c_M y^{i-1} + c_A y_t^{i-1}
    y_tmp: Vector  # one node's state  (nf,)
    A: Stack  # scaled Jacobian blocks on node j-1  (N, nf, nf)
    B: Stack  # ... on node j
    left: Matrix  # scaled left boundary rows
    right: Matrix  # scaled right boundary rows
    factored: Indices  # [1] while LU factors of a (possibly stale) Jacobian are held


COEFFICIENTS = named(Coefficients)
PATTERN = named(Pattern)
CONSTANTS = named(Constants)
WORK = named(Work)


class StepSource(NamedTuple):
    """The source of eq (7) over one step: q = ``space`` g(t) + field, with g at the old and
    new levels (``t_old``, ``t_new``) and the field there (``field_old``, ``field_new``,
    read only with ``use_field``)."""

    space: Matrix
    t_old: float
    t_new: float
    field_old: Matrix
    field_new: Matrix
    use_field: bool


class EndValues(NamedTuple):
    """The prescribed values of the boundary rows at the new level: ``left`` (nb_left) at
    s = 0 and ``right`` (nf - nb_left) at s = L."""

    left: Vector
    right: Vector


class Start(NamedTuple):
    """The level a run starts from: the fields ``y`` and their time derivatives ``rate``,
    each (N+1, nf)."""

    y: np.ndarray
    rate: np.ndarray


def setup(
    system: System,
    scheme: Scheme,
    n_cells: int,
    ds: float,
    dt: float,
    left: Boundary,
    right: Boundary,
    start: Start,
) -> tuple[Constants, Work, _abd.Factors]:
    """Constants, work arrays and LU storage of the compiled kernels for ``system`` under
    ``scheme`` on ``n_cells`` cells of ``ds`` [m] in steps of ``dt`` [s], with the boundary
    rows ``left`` and ``right``, the work arrays holding the level ``start``."""
    y0, rate0 = start
    nf = system.nf
    ys = np.asarray(system.yscale, float)
    con = constants(system, scheme, ds, dt, left, right)
    BLr, BRr, blsc, brsc = con.left_rows, con.right_rows, con.left_scale, con.right_scale
    co = con.co
    N1 = n_cells + 1
    nq = N1 if co.trapezoidal else n_cells
    work = Work(
        y_old=y0.copy(),
        rate_old=rate0.copy(),
        y=y0.copy(),
        y_trial=y0.copy(),
        r=np.zeros(nf * N1),
        r_trial=np.zeros(nf * N1),
        dx=np.zeros((N1, nf)),
        dx_trial=np.zeros((N1, nf)),
        F=np.zeros((nq, nf)),
        dF=np.zeros((nq, nf, nf)),
        F_old=np.zeros((N1, nf)),
        c=np.zeros((n_cells, nf)),
        y_bar_old=np.zeros((n_cells, nf)),
        z=np.zeros((N1, nf)),
        y_tmp=np.zeros(nf),
        A=np.zeros((n_cells, nf, nf)),
        B=np.zeros((n_cells, nf, nf)),
        left=BLr * ys / blsc[:, None],
        right=BRr * ys / brsc[:, None],
        factored=np.zeros(1, dtype=np.int64),
    )
    return con, work, _abd.allocate(n_cells, nf, left.nb)


def constants(
    system: System, scheme: Scheme, ds: float, dt: float, left: Boundary, right: Boundary
) -> Constants:
    """The :class:`Constants` of steps of length dt on cells of length ds."""
    ys, rs = np.asarray(system.yscale, float), np.asarray(system.rscale, float)
    BLr, BRr = np.ascontiguousarray(left.rows, float), np.ascontiguousarray(right.rows, float)
    blsc = np.abs(BLr) @ ys
    brsc = np.abs(BRr) @ ys
    if np.any(blsc == 0) or np.any(brsc == 0):
        raise ValueError("a boundary row is all zeros")
    co = scheme.coefficients(ds, dt)
    P = np.ascontiguousarray(co.c_M * (1 - co.a_s) * system.M + (1 - co.b_t) / ds * system.K)
    Q = np.ascontiguousarray(co.c_M * co.a_s * system.M - (1 - co.b_t) / ds * system.K)
    return Constants(
        params=np.ascontiguousarray(system.params, float),
        M=np.ascontiguousarray(system.M, float),
        K=np.ascontiguousarray(system.K, float),
        P=P,
        Q=Q,
        co=co,
        yscale=ys,
        rscale=rs,
        left_rows=BLr,
        left_scale=blsc,
        right_rows=BRr,
        right_scale=brsc,
        pq=pattern(P, Q),
        mk=pattern(system.M, system.K),
    )


@jit
def prepare_step(F, con, w, q):
    """c_j: the part of every cell's residual fixed during the step (old level, source
    ``q``, a :class:`StepSource`)."""
    qs, qt_old, qt_new = q.space, q.t_old, q.t_new
    qf_old, qf_new, use_qf = q.field_old, q.field_new, q.use_field
    co = con.co
    yo, ao, Fo, c, ybo, z = w.y_old, w.rate_old, w.F_old, w.c, w.y_bar_old, w.z
    N = yo.shape[0] - 1
    nf = yo.shape[1]
    a_s, bs, bt, ids = co.a_s, co.b_s, co.b_t, co.inv_ds
    for j in range(N + 1):
        for f in range(nf):
            z[j, f] = -co.c_M * yo[j, f] + co.c_A * ao[j, f]
        if co.trapezoidal:
            F(yo[j], con.params, Fo[j])
    mk = con.mk
    for j in range(N):
        for rr in range(nf):
            acc = 0.0
            for k in range(mk.n[rr]):
                f = mk.cols[rr, k]
                acc += con.M[rr, f] * ((1.0 - a_s) * z[j + 1, f] + a_s * z[j, f])
                acc += bt * ids * con.K[rr, f] * (yo[j + 1, f] - yo[j, f])
            if co.trapezoidal:
                acc += bt * ((1.0 - bs) * Fo[j + 1, rr] + bs * Fo[j, rr])
            qn = qs[j + 1, rr] * qt_new
            qo = qs[j + 1, rr] * qt_old
            qnm = qs[j, rr] * qt_new
            qom = qs[j, rr] * qt_old
            if use_qf:
                qn += qf_new[j + 1, rr]
                qo += qf_old[j + 1, rr]
                qnm += qf_new[j, rr]
                qom += qf_old[j, rr]
            acc += (1.0 - bt) * ((1.0 - bs) * qn + bs * qnm) + bt * ((1.0 - bs) * qo + bs * qom)
            c[j, rr] = acc
        if not co.trapezoidal:
            for f in range(nf):
                ybo[j, f] = bt * ((1.0 - bs) * yo[j + 1, f] + bs * yo[j, f])


@jit
def residual(F, dF, con, ends, y, w, r, want_jac):
    """Scaled residual r of the step at iterate y, the boundary rows' values ``ends`` (an
    :class:`EndValues`); its RMS.  F (and dF) at the quadrature points are left in w.F
    (w.dF) for :func:`factor`."""
    gL, gR = ends.left, ends.right
    co = con.co
    Fn, dFn, c, ybo, ytmp = w.F, w.dF, w.c, w.y_bar_old, w.y_tmp
    P, Q, rs, pq = con.P, con.Q, con.rscale, con.pq
    N = y.shape[0] - 1
    nf = y.shape[1]
    nbl = con.left_rows.shape[0]
    wn = (1.0 - co.b_t) * (1.0 - co.b_s)
    wp = (1.0 - co.b_t) * co.b_s
    trap = co.trapezoidal
    if trap:
        for j in range(N + 1):
            F(y[j], con.params, Fn[j])
            if want_jac:
                dF(y[j], con.params, dFn[j])
    else:
        for j in range(N):
            for f in range(nf):
                ytmp[f] = ybo[j, f] + wn * y[j + 1, f] + wp * y[j, f]
            F(ytmp, con.params, Fn[j])
            if want_jac:
                dF(ytmp, con.params, dFn[j])
    for rr in range(nbl):
        acc = -gL[rr]
        for f in range(nf):
            acc += con.left_rows[rr, f] * y[0, f]
        r[rr] = acc / con.left_scale[rr]
    for j in range(N):
        off = nbl + nf * j
        for rr in range(nf):
            acc = c[j, rr]
            for k in range(pq.n[rr]):
                f = pq.cols[rr, k]
                acc += P[rr, f] * y[j + 1, f] + Q[rr, f] * y[j, f]
            if trap:
                acc += wn * Fn[j + 1, rr] + wp * Fn[j, rr]
            else:
                acc += Fn[j, rr]
            r[off + rr] = acc / rs[rr]
    off = nbl + nf * N
    for rr in range(nf - nbl):
        acc = -gR[rr]
        for f in range(nf):
            acc += con.right_rows[rr, f] * y[N, f]
        r[off + rr] = acc / con.right_scale[rr]
    total = 0.0
    for k in range(r.shape[0]):
        total += r[k] * r[k]
    return math.sqrt(total / r.shape[0])


@jit
def factor(con, w, fac):
    """Assemble the scaled Jacobian blocks from w.dF (left by :func:`residual`) and
    LU-factorise them.  Returns -1, or the column of a zero pivot."""
    co = con.co
    dFn, Ablk, Bblk, P, Q = w.dF, w.A, w.B, con.P, con.Q
    ys, rs = con.yscale, con.rscale
    N = Ablk.shape[0]
    nf = Ablk.shape[1]
    wn = (1.0 - co.b_t) * (1.0 - co.b_s)
    wp = (1.0 - co.b_t) * co.b_s
    for j in range(N):
        jn = j + 1 if co.trapezoidal else j
        for rr in range(nf):
            inv = 1.0 / rs[rr]
            for f in range(nf):
                Ablk[j, rr, f] = (Q[rr, f] + wp * dFn[j, rr, f]) * ys[f] * inv
                Bblk[j, rr, f] = (P[rr, f] + wn * dFn[jn, rr, f]) * ys[f] * inv
    return _abd.factor(w.left, Ablk, Bblk, w.right, fac)


@jit
def solve_neg(fac, r, x):
    """x = -J^{-1} r  (scaled unknowns)."""
    _abd.solve(fac, r, x)
    N1, nf = x.shape
    for j in range(N1):
        for f in range(nf):
            x[j, f] = -x[j, f]
