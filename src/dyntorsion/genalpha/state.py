"""Sources that depend on the state: q(y) of eq (7) at the new level, inside the step.

A :class:`StateSource` (contact, a foundation) adds to each step's residual its source at
the iterate y of the new level, and to the step's Jacobian its derivative: 3 x 3 blocks
into the banded Jacobian of the nodes (:class:`StateTerms` ``nodes``, ``blocks``) and
rank-one terms U^T G for couplings beyond the band (:mod:`.low_rank`: Woodbury on the
banded factors, a sparse LU for many terms).  A step the source does not couple
(:meth:`StateSource.begin` returns None) is the engine's own Newton solve.

The stepping part :class:`StateSteps` takes the steps of a run with such a source: a step
of dt where the source couples nothing and the state is slow (:meth:`StateSource.too_fast`),
else substeps h_j = dt / (count 2^j), the longest the source allows; a failed solve is
retried one level shorter, down to ``shortest``, and the level grows back where substeps
align.  After every accepted step the source sees the two levels (:meth:`StateSource.
step_taken`) and the new level (:meth:`StateSource.level_reached`), which may end the run.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from typing import Any, NamedTuple

import numba
import numpy as np
from numba.core.types import WrapperAddressProtocol
from numba.experimental.function_type import _get_wrapper_address

from .._numba import A1, A2, JACOBIAN_SIGNATURE, LOAD_SIGNATURE, jit
from . import abd as _abd
from .discrete import CONSTANTS, WORK, EndValues, StepSource, factor, prepare_step
from .discrete import residual as _residual
from .low_rank import low_rank_solve
from .newton import NEWTON_OPTIONS, axpy_scaled, correction_norm, solve_step

__all__ = ["StateTerms", "StateSource", "Substeps", "state_newton"]


class StateTerms(NamedTuple):
    """A state-dependent source at one iterate: ``q`` (N+1, nf) at the new level and its
    Jacobian in the step's scaled rows and unknowns: the rank-one terms ``U[k] G[k]^T``
    (``U`` (k, rows), ``G`` (k, unknowns)) and the physical 3 x 3 blocks ``blocks[m]`` =
    dq/dy of the nodes ``nodes[m]``, rows ``rows`` to ``rows + 3`` and columns ``cols`` to
    ``cols + 3`` of the node's block of dF."""

    q: np.ndarray
    U: np.ndarray
    G: np.ndarray
    nodes: np.ndarray
    blocks: np.ndarray
    rows: int = 0
    cols: int = 3


class Substeps(NamedTuple):
    """How a step the source couples is split: into ``count`` substeps at first, halved
    after a failed solve down to ``shortest`` [s]."""

    count: int
    shortest: float = 1e-7


class StateSource(ABC):
    """A source of eq (7) that depends on the new level (module docstring).  ``substeps``
    splits the coupled steps; ``max_iterations`` caps their Newton iterations; ``failure``
    words the error of a step that fails at the shortest substep."""

    substeps: Substeps = Substeps(1)
    max_iterations: int = 12
    #: the reason of the error raised when a coupled step fails at the shortest substep
    failure: str = "Newton did not converge (coupled step) at the shortest substep"

    @abstractmethod
    def level(self, h: float, con) -> Any:
        """What the source keeps for steps of length ``h`` (``con``: their Constants)."""

    @abstractmethod
    def begin(self, level: Any, y_old: np.ndarray) -> Any | None:
        """The couplings of a step from the known level ``y_old``; None: none."""

    @abstractmethod
    def terms(self, step: Any, y: np.ndarray, jacobian: bool, band: bool) -> StateTerms:
        """The source at the iterate ``y`` of the step ``step`` (what :meth:`begin`
        returned), with its Jacobian when ``jacobian`` (``band``: the blocks go into the
        banded Jacobian, else into ``U``, ``G``)."""

    @abstractmethod
    def too_fast(self, h: float) -> bool:
        """Whether a step ``h`` from the last level reached is too long for the source."""

    def moved(self, y: np.ndarray) -> None:  # noqa: B027 - a hook: nothing by default
        """A step was accepted: ``y`` is the new known level."""

    def converged(self, step: Any) -> None:  # noqa: B027 - a hook: nothing by default
        """The coupled step ``step`` converged (its last :meth:`terms` are at the solution)."""

    def step_taken(self, co, h: float, old, new, q_old, q_new) -> None:  # noqa: B027
        """A step ``h`` was accepted: ``old`` and ``new`` are (y, y_t), ``q_old`` and
        ``q_new`` the source at both levels; ``co`` the step's coefficients."""

    @abstractmethod
    def level_reached(self, t: float, y: np.ndarray, h: float, check: bool) -> str | None:
        """The level ``y`` at ``t`` reached by a step ``h``; ``check``: a check level.
        A reason ends the run."""

    @abstractmethod
    def check_every(self, dt: float) -> int:
        """Every how many steps of ``dt`` a level is a check level."""


_F = numba.types.FunctionType(LOAD_SIGNATURE)
_DF = numba.types.FunctionType(JACOBIAN_SIGNATURE)
_I = numba.int64


@jit(signature=numba.void(_F, CONSTANTS, WORK, A2, A2, A2))
def prepare(F, con, w, qs, q_old, q_new):
    """The fixed part of the step with the separable source ``qs`` and the state
    source at the old level ``q_old`` and ``q_new`` at the new one."""
    prepare_step(F, con, w, StepSource(qs, 1.0, 1.0, q_old, q_new, True))


@jit(signature=numba.float64(_F, _DF, CONSTANTS, A1, A1, WORK))
def residual_jacobian(F, dF, con, gL, gR, w):
    """The residual w.r at w.y (its RMS) and the Jacobian of F at the quadrature points."""
    return _residual(F, dF, con, EndValues(gL, gR), w.y, w, w.r, True)


@jit(signature=_I(CONSTANTS, WORK, _abd.FACTORS))
def factor_jacobian(con, w, fac):
    """The LU factors of the banded Jacobian assembled from w.dF (a zero pivot's column, or -1)."""
    return factor(con, w, fac)


@jit(signature=numba.float64(_F, _DF, CONSTANTS, A1, A1, WORK))
def residual_only(F, dF, con, gL, gR, w):
    """The residual w.r_trial at w.y_trial (its RMS)."""
    return _residual(F, dF, con, EndValues(gL, gR), w.y_trial, w, w.r_trial, False)


@jit(signature=_I(_F, _DF, CONSTANTS, A1, A1, WORK, _abd.FACTORS, NEWTON_OPTIONS))
def free_newton(F, dF, con, gL, gR, w, fac, opts):
    """The engine's Newton solve of a step the source does not couple; its status."""
    return solve_step(F, dF, con, gL, gR, w, fac, opts).status


@jit
def add_blocks(nodes, blocks, rows, cols, dF):
    """dF[a][rows:rows+3, cols:cols+3] += the blocks of ``nodes``."""
    for m in range(nodes.shape[0]):
        na = nodes[m]
        for x in range(3):
            for y in range(3):
                dF[na, rows + x, cols + y] += blocks[m, x, y]


class Address(WrapperAddressProtocol):
    """A compiled function handed to the kernels by its address, looked up once (numba
    looks a dispatcher passed as a first-class function up at every call)."""

    def __init__(self, dispatcher, sig):
        self.dispatcher, self.sig = dispatcher, sig
        self.address = _get_wrapper_address(dispatcher, sig)

    def __wrapper_address__(self) -> int:
        return self.address

    def signature(self):
        return self.sig


def _rms(v) -> float:
    return float(np.sqrt(np.mean(v * v)))


def _add_to_residual(r, q, co, nbl, rscale) -> None:
    """r += the new level's source in every cell: (1 - b_t) [(1 - b_s) q_j + b_s q_{j-1}]
    / rscale (the rows of prepare_step / residual)."""
    cell = (1.0 - co.b_t) * ((1.0 - co.b_s) * q[1:] + co.b_s * q[:-1]) / rscale
    r[nbl : nbl + cell.size] += cell.ravel()


def state_newton(F, dF, ctx, gL, gR, source: StateSource, step) -> tuple[bool, int, StateTerms]:
    """Newton for a coupled step from ctx.work.y: the source's terms at every iteration, a
    full Jacobian each time, a backtracking on the RMS residual (halving the correction up
    to 5 times while it grows).  Returns (converged, iterations, the terms at the end)."""
    con, w, fac, opts = ctx
    nbl, co = con.left_rows.shape[0], con.co
    ys, rs = con.yscale, con.rscale
    y, r, dx, yt, rt = w.y, w.r, w.dx, w.y_trial, w.r_trial
    band = co.trapezoidal
    residual_jacobian(F, dF, con, gL, gR, w)
    for it in range(1, opts.max_iter + 1):
        src = source.terms(step, y, True, band)
        _add_to_residual(r, src.q, co, nbl, rs)
        add_blocks(src.nodes, src.blocks, src.rows, src.cols, w.dF)
        pivot = factor_jacobian(con, w, fac)
        res = _rms(r)
        if not math.isfinite(res) or pivot >= 0:
            w.factored[0] = 0
            return False, it, src
        w.factored[0] = 1
        low_rank_solve(w, fac, r, src.U, src.G, dx)
        nd = correction_norm(dx, y, ys)
        if not math.isfinite(nd):
            return False, it, src
        if nd <= opts.tol:
            axpy_scaled(y, 1.0, dx, ys, y)
            return True, it, source.terms(step, y, False, band)
        lam = 1.0
        for _ in range(6):
            axpy_scaled(y, lam, dx, ys, yt)
            residual_only(F, dF, con, gL, gR, w)
            trial = source.terms(step, yt, False, band)
            _add_to_residual(rt, trial.q, co, nbl, rs)
            if _rms(rt) < res:
                break
            lam *= 0.5
        y[:, :] = yt
        residual_jacobian(F, dF, con, gL, gR, w)
    return False, opts.max_iter, src
