"""The time march: steps of eq (10)-(12) in compiled code, then the update of eq (11)."""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np

from .._numba import (
    A1,
    A2,
    I1,
    JACOBIAN_SIGNATURE,
    LOAD_SIGNATURE,
    Indices,
    Matrix,
    Stack,
    Vector,
    jit,
    named,
)
from . import abd as _abd
from .abd import Factors
from .discrete import (
    CONSTANTS,
    WORK,
    Constants,
    EndValues,
    StepSource,
    Work,
    factor,
    prepare_step,
    residual,
    solve_neg,
)
from .newton import CONVERGED, OUTCOME, NewtonOptions, Outcome, solve_step
from .watch import STOP_SIGNATURE, Watch

__all__ = [
    "Forcing",
    "Recording",
    "Gate",
    "StepContext",
    "Halt",
    "NO_GATE",
    "make_gate",
    "norm_sum",
    "gauge",
    "closes",
    "closed",
    "march",
    "full_newton_iterations",
]


class Forcing(NamedTuple):
    """Boundary values and sources at the time levels of a chunk of steps."""

    gL: Matrix  # (n+1, nb_left)
    gR: Matrix  # (n+1, nb_right)
    q_space: Matrix  # (N+1, nf): separable source q_space(s) q_time(t)
    q_time: Vector  # (n+1,)
    q_field: Stack  # (n+1, N+1, nf) general source, or empty


class Recording(NamedTuple):
    """Which fields at which nodes to record, every how many steps, and where."""

    fields: Indices
    nodes: Indices
    every: int
    offset: int  # index of the chunk's first step in the run
    out: Matrix  # (records, fields)


class Gate(NamedTuple):
    """A chunk of steps ends early after the first level y at which
    ``weight * sum_j sqrt(sum_{f in fields} y[j, f]**2) >= limit`` (:func:`gauge`),
    or, with ``tol < inf``, at which the local error of that gauge over the step that
    reached it exceeds ``tol`` (:func:`closes`); ``limit = inf`` never ends it.
    ``state`` is the memory of the estimate: levels seen, the largest gauge, why it
    closed (0 open, 1 limit, 2 error), and the gauge at the last three levels."""

    fields: Indices
    weight: float
    limit: float
    tol: float
    state: Vector


#: the slots of :attr:`Gate.state`: levels seen, the largest gauge, why the gate closed
#: (:data:`OPEN`, :data:`AT_LIMIT`, :data:`AT_ERROR`) and the gauge at the last three levels
SEEN, LARGEST, WHY, G3, G2, G1 = range(6)
OPEN, AT_LIMIT, AT_ERROR = 0.0, 1.0, 2.0


def make_gate(fields, weight: float, limit: float, tol: float = np.inf) -> Gate:
    """A :class:`Gate` with fresh memory."""
    return Gate(np.asarray(fields, np.int64), float(weight), float(limit), float(tol), np.zeros(6))


class StepContext(NamedTuple):
    """What every step of a run uses: the constants of eqs (10)-(12) at its step size
    (``con``), the state and work arrays carried from step to step (``work``), the LU
    factors of the latest Jacobian (``fac``) and the Newton options (``opts``)."""

    con: Constants
    work: Work
    fac: Factors
    opts: NewtonOptions


class Halt(NamedTuple):
    """What may end a chunk of steps before its last level: the :class:`Gate` (consulted
    at every level) and the compiled stop test's :class:`~.watch.Watch` (at its levels)."""

    gate: Gate
    watch: Watch


FORCING = named(Forcing)
RECORDING = named(Recording)
GATE = named(Gate)
STEP_CONTEXT = named(StepContext)
HALT = named(Halt)
#: the gate that never closes a chunk early
NO_GATE = make_gate(np.zeros(0, np.int64), 0.0, np.inf)
_F = numba.types.FunctionType(LOAD_SIGNATURE)
_DF = numba.types.FunctionType(JACOBIAN_SIGNATURE)
_STOP = numba.types.FunctionType(STOP_SIGNATURE)


@jit(signature=numba.float64(A2, I1, numba.float64))
def norm_sum(y, fields, weight):
    """``weight * sum_j sqrt(sum_{f in fields} y[j, f]**2)`` at the level y."""
    total = 0.0
    for j in range(y.shape[0]):
        acc = 0.0
        for f in fields:
            acc += y[j, f] * y[j, f]
        total += math.sqrt(acc)
    return weight * total


@jit(signature=numba.float64(A2, GATE))
def gauge(y, gate):
    """The quantity the :class:`Gate` compares with its limit, at the level y."""
    return norm_sum(y, gate.fields, gate.weight)


@jit(signature=numba.boolean(A2, GATE))
def closes(y, gate):
    """Whether the level y closes ``gate``: its :func:`gauge` G reached the limit, or
    (tol < inf) the local error of the trapezoidal step h that reached it,
    ``h^3 G_ttt / 12 ~ (G^n - 3 G^{n-1} + 3 G^{n-2} - G^{n-3}) / 12``, exceeds ``tol``
    times the largest G so far: a relative error (s h)^3 / 12 for a growth e^{st},
    zero for a response quadratic in t.  Remembers G."""
    g = gauge(y, gate)
    st = gate.state
    if g >= gate.limit:
        st[WHY] = AT_LIMIT
        return True
    if not gate.tol < np.inf:
        return False
    seen = int(st[SEEN])
    st[LARGEST] = max(st[LARGEST], g)
    third_difference = g - 3.0 * st[G1] + 3.0 * st[G2] - st[G3]
    if seen >= 3 and abs(third_difference) > 12.0 * gate.tol * st[LARGEST]:
        st[WHY] = AT_ERROR
        return True
    st[G3], st[G2], st[G1] = st[G2], st[G1], g
    st[SEEN] = seen + 1
    return False


def closed(gate: Gate) -> bool:
    """Whether :func:`closes` has closed ``gate`` at some level."""
    return gate.state[WHY] != OPEN


@jit(
    signature=numba.types.Tuple((numba.int64, OUTCOME))(
        _F, _DF, _STOP, STEP_CONTEXT, FORCING, RECORDING, HALT, A2,
    )
)  # fmt: skip
def march(F, dF, test, ctx, forcing, rec, halt, stats):
    """Advance len(forcing.gL) - 1 steps from ctx.work.y_old, ctx.work.rate_old.

    ``F``, ``dF``: the model's load vector and its Jacobian (compiled); ``ctx``: the
    :class:`StepContext`; ``forcing``: the boundary values and sources at the chunk's
    levels; ``rec``: what to record where.  ``stats[k]`` <- corrections, residual
    evaluations, factorisations, residual and retries of step k.  Returns the number of
    steps completed and the last :class:`Outcome`.  Fewer steps than asked: a failure,
    or, with a converged outcome, ``halt.gate`` closed the chunk after its last completed
    step (it is consulted at every level, the last one too: ``gate.state[WHY]`` says), or
    ``test(y, halt.watch)`` (a :class:`~.watch.Watch`, consulted at its levels
    ``rec.offset + k + 1``) said stop.
    """
    # the step's constants, state and work arrays, LU factors, Newton options
    con, w, fac, opts = ctx.con, ctx.work, ctx.fac, ctx.opts
    gate, watch = halt.gate, halt.watch
    co = con.co
    yo, ao, y = w.y_old, w.rate_old, w.y
    N1, nf = yo.shape
    dt, g_t = co.dt, co.g_t
    rate = opts.rate_predictor
    qs, qt, qf = forcing.q_space, forcing.q_time, forcing.q_field
    use_qf = qf.shape[0] > 0
    nsteps = forcing.gL.shape[0] - 1
    nrec = 0
    retry = NewtonOptions(
        opts.tol, opts.max_iter, opts.lam_min, opts.theta_reuse, False, rate, opts.contraction
    )
    out = Outcome(CONVERGED, 0, 0, 0, 0.0)
    for k in range(nsteps):
        if use_qf:
            prepare_step(F, con, w, StepSource(qs, qt[k], qt[k + 1], qf[k], qf[k + 1], True))
        else:
            prepare_step(F, con, w, StepSource(qs, qt[k], qt[k + 1], qs, qs, False))
        for j in range(N1):
            for f in range(nf):
                y[j, f] = yo[j, f] + dt * ao[j, f] if rate else yo[j, f]
        gL, gR = forcing.gL[k + 1], forcing.gR[k + 1]
        out = solve_step(F, dF, con, gL, gR, w, fac, opts)
        stats[k, 0] = out.corrections
        stats[k, 1] = out.residual_evaluations
        stats[k, 2] = out.factorisations
        stats[k, 3] = out.residual
        if out.status != CONVERGED:
            # one retry: the other predictor, a fresh Jacobian at every iteration
            for j in range(N1):
                for f in range(nf):
                    y[j, f] = yo[j, f] if rate else yo[j, f] + dt * ao[j, f]
            w.factored[0] = 0
            out = solve_step(F, dF, con, gL, gR, w, fac, retry)
            stats[k, 0] += out.corrections
            stats[k, 1] += out.residual_evaluations
            stats[k, 2] += out.factorisations
            stats[k, 3] = out.residual
            stats[k, 4] = 1.0
            if out.status != CONVERGED:
                return k, out
        # eq (11): the new rate from the new level
        for j in range(N1):
            for f in range(nf):
                ao[j, f] = (y[j, f] - yo[j, f]) / (g_t * dt) - (1.0 - g_t) / g_t * ao[j, f]
                yo[j, f] = y[j, f]
        if (rec.offset + k + 1) % rec.every == 0:
            for m in range(rec.fields.shape[0]):
                rec.out[nrec, m] = yo[rec.nodes[m], rec.fields[m]]
            nrec += 1
        if gate.limit < np.inf and closes(yo, gate):
            return k + 1, out
        level = rec.offset + k + 1
        if watch.every > 0 and level % watch.every == 0 and level < watch.until:
            if test(yo, watch):
                return k + 1, out
    return nsteps, out


@jit(signature=numba.float64(_F, _DF, CONSTANTS, A1, A1, WORK, _abd.FACTORS, numba.int64))
def full_newton_iterations(F, dF, con, gL, gR, w, fac, repeats):
    """``repeats`` full Newton iterations at w.y: residual, Jacobian, LU, solve."""
    res = 0.0
    for _ in range(repeats):
        res = residual(F, dF, con, EndValues(gL, gR), w.y, w, w.r, True)
        factor(con, w, fac)
        solve_neg(fac, w.r, w.dx)
    return res
