"""The march of a contact scene with the contact inside the implicit step
(:mod:`.implicit`): the engine's kernels of one step (:mod:`dyntorsion.genalpha.discrete`:
the fixed part of the step, residual, banded Jacobian and LU; :mod:`~dyntorsion.genalpha.newton`:
the compiled Newton solve) driven step by step from here, so the engine's own march and
every scene without contact are untouched.

Each step: the candidate pairs from the known level (:func:`.implicit.candidates`); none:
the engine's compiled Newton solve of the step (:func:`~dyntorsion.genalpha.newton.solve_step`,
the same as a scene without contact, with its retry from the other predictor); some: a
full Newton solve with the contact's source and Jacobian at every iteration (the frames'
blocks of (C5) in the banded Jacobian, a rank-one term a pressing pair by :mod:`.linear`:
Woodbury on the banded factors, or a sparse LU for many pairs).  Between steps
the same bookkeeping as the lagged route (:class:`.between.Between`: rebuild, law on the
rebuilt shape for the reported overlap, energy budget with the source the step used,
topology), so both routes report alike.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any, NamedTuple

import numba
import numpy as np
from numba.core.types import WrapperAddressProtocol
from numba.experimental.function_type import _get_wrapper_address

from ..._numba import A1, A2, JACOBIAN_SIGNATURE, LOAD_SIGNATURE, jit
from ...buckling.stops import STRAIGHT
from ...genalpha import abd as _abd
from ...genalpha.discrete import (
    CONSTANTS,
    WORK,
    EndValues,
    Start,
    StepSource,
    constants,
    factor,
    prepare_step,
    residual,
    setup,
)
from ...genalpha.march import StepContext
from ...genalpha.newton import (
    NEWTON_OPTIONS,
    ConvergenceError,
    axpy_scaled,
    correction_norm,
    solve_step,
)
from ...genalpha.plan import Source as EngineSource
from ...genalpha.plan import initial_rate
from .budget import Level, Loads
from .implicit import (
    NO_PAIRS,
    Known,
    Layout,
    StepParams,
    add_blocks,
    add_to_residual,
    candidates,
    contact_source,
)
from .linear import contact_solve

__all__ = [
    "Engine",
    "Substeps",
    "Marched",
    "march_implicit",
    "residual_jacobian",
    "factor_jacobian",
]


_F = numba.types.FunctionType(LOAD_SIGNATURE)
_DF = numba.types.FunctionType(JACOBIAN_SIGNATURE)
_I = numba.int64


@jit(signature=numba.void(_F, CONSTANTS, WORK, A2, A2, A2))
def _prepare(F, con, w, qs, q_old, q_new):
    """The fixed part of the step (the engine's prepare_step; sources q_seed and the
    contact's at the old level and, with q_new = 0, none at the new one)."""
    prepare_step(F, con, w, StepSource(qs, 1.0, 1.0, q_old, q_new, True))


@jit(signature=numba.float64(_F, _DF, CONSTANTS, A1, A1, WORK))
def residual_jacobian(F, dF, con, gL, gR, w):
    """The residual w.r at w.y (its RMS) and the Jacobian of F at the quadrature points
    (w.dF), which :func:`factor_jacobian` assembles."""
    return residual(F, dF, con, EndValues(gL, gR), w.y, w, w.r, True)


@jit(signature=_I(CONSTANTS, WORK, _abd.FACTORS))
def factor_jacobian(con, w, fac):
    """The LU factors of the banded Jacobian assembled from w.dF (the column of a zero
    pivot, or -1)."""
    return factor(con, w, fac)


@jit(signature=numba.float64(_F, _DF, CONSTANTS, A1, A1, WORK))
def _residual_only(F, dF, con, gL, gR, w):
    """The residual w.r_trial at w.y_trial (its RMS)."""
    return residual(F, dF, con, EndValues(gL, gR), w.y_trial, w, w.r_trial, False)


@jit(signature=_I(_F, _DF, CONSTANTS, A1, A1, WORK, _abd.FACTORS, NEWTON_OPTIONS))
def _free_newton(F, dF, con, gL, gR, w, fac, opts):
    """The engine's Newton solve of a step without contact; its status."""
    return solve_step(F, dF, con, gL, gR, w, fac, opts).status


class _Address(WrapperAddressProtocol):
    """A compiled function handed to the kernels by its address, looked up once.

    A dispatcher passed from Python as a first-class function argument is looked up in
    LLVM's tables at every call, and the march makes several such calls a step.  Numba's
    wrapper address protocol takes the address instead; the same
    compiled code runs, so the numbers are the same."""

    def __init__(self, dispatcher, sig):
        self.dispatcher, self.sig = dispatcher, sig
        self.address = _get_wrapper_address(dispatcher, sig)

    def __wrapper_address__(self) -> int:
        return self.address

    def signature(self):
        return self.sig


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
    failed_solves: int = 0
    shortest: float = math.inf

    def cost(self, diameter: float) -> dict[str, float]:
        """What the implicit contact cost: steps with contact candidates, their Newton
        iterations, wall time per step with and without, the largest predicted overlap."""
        free = max(self.steps - self.contact_steps, 1)
        return {
            "contact_steps": self.contact_steps,
            "contact_newton_iterations": self.contact_iterations,
            "seconds_per_contact_step": self.contact_seconds / max(self.contact_steps, 1),
            "seconds_per_free_step": self.free_seconds / free,
            "largest_predicted_overlap_over_D": self.largest_predicted_overlap / diameter,
            "failed_solves_retried_shorter": self.failed_solves,
            "shortest_step": self.shortest,
        }


def _contact_newton(F, dF, ctx: StepContext, gL, gR, sp, pairs, known: Known, weights):
    """Newton for the step with the contact's source (module docstring) from ctx.work.y,
    a full Jacobian at every iteration and a backtracking on the RMS residual (halving the
    correction up to 5 times while it grows); returns (converged, iterations, the
    contact's :class:`~.implicit.Source` at the solution).  ``gL``, ``gR``: the boundary
    values at the new level; ``known``: the step's :class:`~.implicit.Known` level."""
    con, w, fac, opts = ctx
    nf, nbl = w.y.shape[1], con.left_rows.shape[0]
    ys, rs = con.yscale, con.rscale
    layout = Layout(nf, nbl, rs, ys)
    y, r, dx, yt, rt = w.y, w.r, w.dx, w.y_trial, w.r_trial

    def rms(v):
        return float(np.sqrt(np.mean(v * v)))

    band = con.co.trapezoidal  # the frames' blocks of (C5) into the nodal dF
    residual_jacobian(F, dF, con, gL, gR, w)
    for it in range(1, opts.max_iter + 1):
        src = contact_source(sp, pairs, known, y, weights, layout, True, band)
        add_to_residual(r, src.q, sp, nf, nbl, rs)
        add_blocks(src.nodes, src.turn, w.dF)
        pivot = factor_jacobian(con, w, fac)
        res = rms(r)
        if not math.isfinite(res) or pivot >= 0:
            w.factored[0] = 0
            return False, it, src
        w.factored[0] = 1
        contact_solve(w, fac, r, src.U, src.G, dx)
        nd = correction_norm(dx, y, ys)
        if not math.isfinite(nd):
            return False, it, src
        if nd <= opts.tol:
            axpy_scaled(y, 1.0, dx, ys, y)
            src = contact_source(sp, pairs, known, y, weights, layout, False)
            return True, it, src
        lam = 1.0
        for _ in range(6):
            axpy_scaled(y, lam, dx, ys, yt)
            _residual_only(F, dF, con, gL, gR, w)
            trial = contact_source(sp, pairs, known, yt, weights, layout, False)
            add_to_residual(rt, trial.q, sp, nf, nbl, rs)
            if rms(rt) < res:
                break
            lam *= 0.5
        y[:, :] = yt
        residual_jacobian(F, dF, con, gL, gR, w)
    return False, opts.max_iter, src


class _Level:
    """The constants of steps of one length h: the engine's, the law's, the boundary rows."""

    def __init__(self, system, scheme, ds, h, left, right, law, smooth):
        self.h = h
        self.con = constants(system, scheme, ds, h, left, right)
        co = self.con.co
        self.sp = StepParams(law, h, 0.5, co.b_t, co.b_s, smooth)  # C1: the time route's rule


class Engine(NamedTuple):
    """The engine a run past contact marches with: the model (``system``, a
    :class:`~dyntorsion.model.cosserat.Cosserat`), the :class:`~dyntorsion.genalpha.Scheme`
    and the :class:`~dyntorsion.genalpha.Newton` options."""

    system: Any
    scheme: Any
    newton: Any


class Substeps(NamedTuple):
    """How a step near contact is split: into ``count`` substeps at first, halved after
    a failed solve down to ``shortest`` [s]."""

    count: int
    shortest: float = 1e-7


def march_implicit(between, engine: Engine, grid, y0, left, right, q_seed,
                   substeps: Substeps) -> Marched:  # fmt: skip
    """March ``grid`` from ``y0`` (N+1, nf) with the contact implicit (module docstring),
    the :class:`Engine` ``engine``, the boundary rows ``left`` and ``right`` and the seed
    source ``q_seed`` (N+1, nf); ``between`` is the run's :class:`.between.Between`,
    consulted after every step.

    **Step control.**  A step of ``grid.dt`` near which no pair can touch and in which the
    rod moves slowly (:func:`fast`) is taken whole.  Otherwise the step is crossed by
    substeps h_j = grid.dt / (``substeps.count`` 2^j), j >= 0, the longest for which the rod
    is not fast; a step whose Newton solve fails is retried at the next shorter level (down
    to ``substeps.shortest``), and after a success the level may grow by one where the
    substeps align.
    Measured (a = 16, N = 200): in the whip the frames spin at up to ~3000 rad/s, and at
    a fixed h = 2.5e-4 s a third of the Newton solves failed in 30 iterations, most with no
    contact active (the body-frame kinematics turned by ~0.8 rad within a step)."""
    system, scheme, newton = engine
    substeps, min_step = substeps
    n1, nf, ds = y0.shape[0], system.nf, grid.ds
    n_steps = int(math.ceil((grid.t_end - grid.t0) / grid.dt - 1e-9))
    src0 = EngineSource.of(grid.s, nf, (q_seed, None), None)
    rate0 = initial_rate(system, y0, ds, "consistent", src0, grid.t0)
    _, w, fac = setup(system, scheme, n1 - 1, ds, grid.dt, left, right, Start(y0, rate0))
    whole = _Level(system, scheme, ds, grid.dt, left, right, between.law, between.c.smooth)
    h0 = grid.dt / substeps
    j_max = max(0, int(math.floor(math.log2(h0 / min_step)))) if h0 > min_step else 0
    units = substeps * 2**j_max  # the shortest substep's count in a whole step
    levels: dict[int, _Level] = {}

    def level(j: int) -> _Level:
        if j not in levels:
            levels[j] = _Level(system, scheme, ds, h0 / 2**j, left, right, between.law,
                               between.c.smooth)  # fmt: skip
        return levels[j]

    F, dF = _Address(system.F, LOAD_SIGNATURE), _Address(system.dF, JACOBIAN_SIGNATURE)
    opts = newton.options()
    retry = opts._replace(reuse=False, rate_predictor=not opts.rate_predictor)
    contact_opts = opts._replace(max_iter=min(opts.max_iter, 12))
    weights, recon = between.weights, between.recon
    q_seed = np.ascontiguousarray(q_seed, float)
    zeros = np.zeros((n1, nf))
    state = {"q_old": zeros, "level": None}
    out = Marched(y0, float(grid.t0), 0, "t_end")
    check_every = max(1, int(round(between.c.check / grid.dt)))

    seen = {"steps": -1}

    def motion() -> dict:
        """The nodes' lab velocities at the known level, their largest speed and spin:
        computed once per accepted step (the known level changes only there)."""
        if seen["steps"] != out.steps:
            V = recon.velocities(w.y_old, True)
            seen.update(steps=out.steps, V=V,
                        speed=float(np.max(np.linalg.norm(V, axis=1))),
                        spin=float(np.max(np.linalg.norm(w.y_old[:, 3:6], axis=1))))  # fmt: skip
        return seen

    def step(lv: _Level, t_new: float, near) -> bool:
        tick = time.perf_counter()
        if state["level"] is not lv:
            w.factored[0] = 0  # the factors held are of the other step length
            state["level"] = lv
        con, h = lv.con, lv.h
        _prepare(F, con, w, q_seed, state["q_old"], zeros)
        gL, gR = left.at(np.array([t_new]))[0], right.at(np.array([t_new]))[0]
        w.y[:, :] = w.y_old
        q_new, ok = zeros, True
        if near.nodes.shape[0] == 0:
            if _free_newton(F, dF, con, gL, gR, w, fac, opts) != 0:
                w.y[:, :] = w.y_old + h * w.rate_old
                w.factored[0] = 0
                ok = _free_newton(F, dF, con, gL, gR, w, fac, retry) == 0
            out.free_seconds += time.perf_counter() - tick
        else:
            R, _ = recon.frames(True)
            V_old = motion()["V"]
            w.y[:, :] = w.y_old + h * w.rate_old  # the rate predictor
            known = Known(R, V_old, np.ascontiguousarray(w.y_old[:, 3:6]))
            ctx = StepContext(con, w, fac, contact_opts)
            ok, its, src = _contact_newton(F, dF, ctx, gL, gR, lv.sp, near, known, weights)
            q_new = src.q
            out.contact_steps += 1
            out.contact_iterations += its
            if ok:
                out.largest_predicted_overlap = max(out.largest_predicted_overlap, src.overlap)
            out.contact_seconds += time.perf_counter() - tick
        if not ok:
            w.factored[0] = 0
            out.failed_solves += 1
            return False
        g_t = con.co.g_t  # eq (11): the new rate from the new level
        rate = (w.y - w.y_old) / (g_t * h) - (1.0 - g_t) / g_t * w.rate_old
        between.budget.step(
            con.co, h, Level(w.y_old, w.rate_old), Level(w.y, rate),
            Loads(q_seed, state["q_old"], q_new),
        )  # fmt: skip
        w.rate_old[:, :] = rate
        w.y_old[:, :] = w.y
        state["q_old"] = q_new
        between.pending = q_new
        out.y, out.t_final, out.steps = w.y_old.copy(), t_new, out.steps + 1
        out.shortest = min(out.shortest, h)
        return True

    def near_pairs(lv: _Level):
        if between.ds * np.sum(np.hypot(w.y_old[:, 6], w.y_old[:, 7])) < STRAIGHT:
            return NO_PAIRS  # no part can reach another while the rod is nearly straight
        return candidates(lv.sp.law, recon.frames(True)[1], motion()["V"], lv.h,
                          between.c.fixtures)  # fmt: skip

    def fast(h: float) -> bool:
        """Whether a step h moves a node more than D / 2 or turns a frame by more than
        0.1 rad (the time route's trapezoidal rule, C1, then loses the link: a = 16,
        N = 200 in whole steps of 0.01 s, Lk - Tw - Wr went from 1e-4 to 0.05 turns in the
        whip before the first contact)."""
        m = motion()
        return h * m["speed"] > 0.5 * between.rod.thickness or h * m["spin"] > 0.1

    def failed(t_new: float, h: float) -> str:
        err = ConvergenceError(t_new, out.steps + 1, opts.max_iter, float("nan"),
                               "Newton did not converge (implicit contact step) at the "
                               "shortest substep", dt=h)  # fmt: skip
        return f"failed: {err}"

    j = 0
    for k in range(n_steps):
        t0, t1 = grid.t0 + k * grid.dt, grid.t0 + (k + 1) * grid.dt
        check = (k + 1) % check_every == 0
        reason = None
        if not state["q_old"].any() and not fast(whole.h):
            near = near_pairs(whole)
            if near.nodes.shape[0] == 0 and step(whole, t1, near):
                reason = between(out.t_final, w.y_old, whole.h, check)
                if reason:
                    out.stopped = reason
                    break
                continue
        pos, grow = 0, True  # pos in units of the shortest substep
        while pos < units:
            if grow and j > 0 and pos % (units // (substeps * 2 ** (j - 1))) == 0:
                if not fast(level(j - 1).h):
                    j -= 1  # one level longer where the longer substep aligns
            while j < j_max and fast(level(j).h):
                j += 1
            lv, span = level(j), units // (substeps * 2**j)
            t_new = t1 if pos + span >= units else t0 + (pos + span) * grid.dt / units
            if not step(lv, t_new, near_pairs(lv)):
                if j >= j_max:
                    out.stopped = failed(t_new, lv.h)
                    break
                j, grow = j + 1, False
                continue
            pos, grow = pos + span, True
            reason = between(out.t_final, w.y_old, lv.h, check and pos >= units)
            if reason:
                break
        if out.stopped != "t_end":
            break
        if reason:
            out.stopped = reason
            break
    return out
