"""The march of a contact scene with the contact inside the implicit step
(:mod:`.implicit`): the engine's kernels of one step (:mod:`dyntorsion.genalpha.discrete`:
the fixed part of the step, residual, banded Jacobian and LU; :mod:`~dyntorsion.genalpha.newton`:
the compiled Newton solve) driven step by step from here, so the engine's own march and
every scene without contact are untouched.

Each step: the candidate pairs from the known level (:func:`.implicit.candidates`); none:
the engine's compiled Newton solve of the step (:func:`~dyntorsion.genalpha.newton.solve_step`,
the same as a scene without contact, with its retry from the other predictor); some: a
full Newton solve with the contact's source and Jacobian columns (Woodbury on the banded
factors) at every iteration.  Between steps the same bookkeeping as the lagged route
(:class:`.run._Between`: rebuild, law on the rebuilt shape for the reported overlap,
energy budget with the source the step used, topology), so both routes report alike.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numba
import numpy as np

from ..._numba import A1, A2, JACOBIAN_SIGNATURE, LOAD_SIGNATURE, jit
from ...buckling.stops import STRAIGHT
from ...genalpha import abd as _abd
from ...genalpha.discrete import CONSTANTS, WORK, factor, prepare_step, residual, setup
from ...genalpha.newton import (
    NEWTON_OPTIONS,
    ConvergenceError,
    _axpy_scaled,
    _norm,
    solve_step,
)
from ...genalpha.plan import Source as EngineSource
from ...genalpha.plan import initial_rate
from .implicit import (
    NO_PAIRS,
    StepParams,
    add_to_residual,
    candidates,
    contact_source,
    woodbury_solve,
)

__all__ = ["Marched", "march_implicit"]


_F = numba.types.FunctionType(LOAD_SIGNATURE)
_DF = numba.types.FunctionType(JACOBIAN_SIGNATURE)
_I = numba.int64


@jit(signature=numba.void(_F, CONSTANTS, WORK, A2, A2, A2))
def _prepare(F, con, w, qs, q_old, q_new):
    """The fixed part of the step (the engine's prepare_step; sources q_seed and the
    contact's at the old level and, with q_new = 0, none at the new one)."""
    prepare_step(F, con, w, qs, 1.0, 1.0, q_old, q_new, True)


@jit(signature=numba.types.Tuple((numba.float64, _I))(_F, _DF, CONSTANTS, A1, A1, WORK, _abd.FACTORS))
def _residual_factor(F, dF, con, gL, gR, w, fac):
    """The residual w.r at w.y (its RMS) and the LU factors of the banded Jacobian (the
    column of a zero pivot, or -1)."""
    res = residual(F, dF, con, gL, gR, w.y, w, w.r, True)
    return res, factor(con, w, fac)


@jit(signature=_I(_F, _DF, CONSTANTS, A1, A1, WORK, _abd.FACTORS, NEWTON_OPTIONS))
def _free_newton(F, dF, con, gL, gR, w, fac, opts):
    """The engine's Newton solve of a step without contact; its status."""
    return solve_step(F, dF, con, gL, gR, w, fac, opts).status


@dataclass
class Marched:
    """What :func:`march_implicit` returns: the last level, the steps taken, how it ended,
    and the cost (steps with contact, their Newton iterations and wall time)."""

    y: np.ndarray
    t_final: float
    steps: int
    stopped: str
    contact_steps: int = 0
    contact_iterations: int = 0
    contact_seconds: float = 0.0
    free_seconds: float = 0.0
    largest_predicted_overlap: float = 0.0


def _contact_newton(system, con, w, fac, gL, gR, sp, pairs, R, V_old, weights, opts):
    """Full Newton for the step with the contact's source (module docstring); returns
    (converged, iterations, the contact's :class:`~.implicit.Source` at the solution)."""
    nf, nbl = system.nf, con.left_rows.shape[0]
    ys, rs = con.yscale, con.rscale
    y, r, dx = w.y, w.r, w.dx
    lam_prev = 1.0
    for it in range(1, opts.max_iter + 1):
        res, pivot = _residual_factor(system.F, system.dF, con, gL, gR, w, fac)
        src = contact_source(sp, pairs, R, V_old, y[:, 0:3], weights, nf, nbl, rs, ys)
        add_to_residual(r, src.q, sp, nf, nbl, rs)
        if not math.isfinite(res) or pivot >= 0:
            w.factored[0] = 0
            return False, it, src
        w.factored[0] = 1
        woodbury_solve(fac, r, src.C, src.cols, dx)
        nd = _norm(dx, y, ys)
        if not math.isfinite(nd):
            return False, it, src
        lam = 1.0 if nd < 1.0 else max(0.1, 1.0 / nd)  # keep a first far correction sane
        _axpy_scaled(y, lam, dx, ys, y)
        if nd <= opts.tol and lam == 1.0 and lam_prev == 1.0:
            src = contact_source(sp, pairs, R, V_old, y[:, 0:3], weights, nf, nbl, rs, ys, False)
            return True, it, src
        lam_prev = lam
    return False, opts.max_iter, src


def march_implicit(between, system, scheme, newton, grid, y0, left, right, q_seed) -> Marched:
    """March ``grid`` from y0 with the contact implicit (module docstring); ``between`` is
    the run's :class:`.run._Between`, consulted after every step."""
    n1, nf, dt, ds = y0.shape[0], system.nf, grid.dt, grid.ds
    n_steps = int(math.ceil((grid.t_end - grid.t0) / dt - 1e-9))
    times = grid.t0 + dt * np.arange(n_steps + 1)
    src0 = EngineSource.of(grid.s, nf, (q_seed, None), None)
    rate0 = initial_rate(system, y0, ds, "consistent", src0, grid.t0)
    con, w, fac = setup(system, scheme, n1 - 1, ds, dt, left, right, y0, rate0)
    opts = newton.options()
    retry = opts._replace(reuse=False, rate_predictor=not opts.rate_predictor)
    gLs, gRs = left.at(times), right.at(times)
    co = con.co
    sp = StepParams(between.law, dt, co.g_t, co.b_t, co.b_s)
    weights, recon = between.weights, between.recon
    q_seed = np.ascontiguousarray(q_seed, float)
    q_old = np.zeros((n1, nf))
    zeros = np.zeros((n1, nf))
    out = Marched(y0, float(times[0]), 0, "t_end")
    for k in range(n_steps):
        tick = time.perf_counter()
        _prepare(system.F, con, w, q_seed, q_old, zeros)
        V_old = recon.velocities(w.y_old)
        near = NO_PAIRS  # no part can reach another while the rod is nearly straight
        if between.ds * np.sum(np.hypot(w.y_old[:, 6], w.y_old[:, 7])) >= STRAIGHT:
            near = candidates(sp.law, recon.r, V_old, dt, between.c.fixtures)
        gL, gR = gLs[k + 1], gRs[k + 1]
        w.y[:, :] = w.y_old
        q_new, ok = zeros, True
        if near.nodes.shape[0] == 0:
            if _free_newton(system.F, system.dF, con, gL, gR, w, fac, opts) != 0:
                w.y[:, :] = w.y_old + dt * w.rate_old
                w.factored[0] = 0
                ok = _free_newton(system.F, system.dF, con, gL, gR, w, fac, retry) == 0
            out.free_seconds += time.perf_counter() - tick
        else:
            ok, its, src = _contact_newton(
                system, con, w, fac, gL, gR, sp, near, recon.R, V_old, weights, opts
            )
            q_new = src.q
            out.contact_steps += 1
            out.contact_iterations += its
            out.largest_predicted_overlap = max(out.largest_predicted_overlap, src.overlap)
            out.contact_seconds += time.perf_counter() - tick
        if not ok:
            err = ConvergenceError(float(times[k + 1]), k + 1, opts.max_iter, float("nan"),
                                   "Newton did not converge (implicit contact step)")  # fmt: skip
            out.stopped = f"failed: {err}"
            break
        # eq (11): the new rate from the new level
        g_t = co.g_t
        w.rate_old[:, :] = (w.y - w.y_old) / (g_t * dt) - (1.0 - g_t) / g_t * w.rate_old
        w.y_old[:, :] = w.y
        q_old = q_new
        between.pending = q_new
        out.y, out.t_final, out.steps = w.y_old.copy(), float(times[k + 1]), k + 1
        reason = between(float(times[k + 1]), w.y_old)
        if reason:
            out.stopped = reason
            break
    return out
