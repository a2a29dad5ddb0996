"""The damped Newton solve of one step (NLEQ1-like: scaled corrections, natural
monotonicity test, damping, reuse of the Jacobian's LU factors, and a stopping test
on the correction or on the contraction of the iteration)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import IntEnum
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from .._numba import jit, named
from .discrete import EndValues, factor, residual, solve_neg

if TYPE_CHECKING:
    from .run import Run

__all__ = [
    "Newton",
    "NewtonOptions",
    "Status",
    "Outcome",
    "CONVERGED",
    "ConvergenceError",
    "correction_norm",
    "axpy_scaled",
]


class Status(IntEnum):
    """How the Newton solve of a step ended."""

    CONVERGED = 0
    MAX_ITER = 1
    DAMPING = 2
    SINGULAR = 3
    NOT_FINITE = 4


REASONS = {
    Status.MAX_ITER: "no convergence within max_iter corrections",
    Status.DAMPING: "damping factor fell below lam_min "
    "(no monotone decrease of the Newton correction)",
    Status.SINGULAR: "singular Jacobian",
    Status.NOT_FINITE: "residual is not finite",
}

# plain ints for the compiled code
_CONVERGED, _MAX_ITER, _DAMPING, _SINGULAR, _NOT_FINITE = (int(s) for s in Status)
#: :attr:`Status.CONVERGED` as the plain int the compiled code of other modules compares
CONVERGED = _CONVERGED


class NewtonOptions(NamedTuple):
    """:class:`Newton` for the compiled kernels."""

    tol: float
    max_iter: int
    lam_min: float
    theta_reuse: float
    reuse: bool
    rate_predictor: bool
    contraction: bool


class Outcome(NamedTuple):
    """The result of the Newton solve of one step (``status`` is a :class:`Status`)."""

    status: int
    corrections: int
    residual_evaluations: int
    factorisations: int
    residual: float


NEWTON_OPTIONS = named(NewtonOptions)
OUTCOME = named(Outcome)


@dataclass(frozen=True)
class Newton:
    """Options of the damped Newton solve of each step (NLEQ1-like).

    Parameters
    ----------
    tol
        Scaled correction norm at which a step is converged: the RMS over all
        unknowns of ``abs(dy) / max(abs(y), yscale)``.
    max_iter
        Corrections allowed per step.
    lam_min
        Smallest damping factor before giving up.
    reuse
        Keep the LU factors of the Jacobian while the simplified Newton iteration
        contracts by at least ``theta_reuse`` per iteration (within a step and
        across steps); False refactors at every iteration.
    theta_reuse
        Contraction factor below which the factors are kept.
    predictor
        ``"constant"`` (the previous level, default) or ``"rate"`` (y + dt y_t of
        the previous level).  At lam_t = -1 the trapezoidal rates alternate in
        sign after any incompatibility of initial and boundary data (the ramp
        of eq 30 has one), and the rate predictor then starts Newton so far off
        that it fails; the constant predictor does not.
    stopping
        When a step is converged.  ``"contraction"`` is the default: it saves about
        one correction in eight on the Fig 8 scene and moves t_c by orders of
        magnitude less than the onset uncertainty (``benchmarks/bench_targets.py``
        prints both tests side by side).
        ``"correction"``: when a Newton correction,
        computed from the residual at the current iterate, is at most ``tol``
        (it is then applied), so a step pays one residual and one solve after its
        last significant correction.  ``"contraction"`` (Deuflhard, *Newton Methods
        for Nonlinear Problems*, sec. 2.1; Hairer and Wanner, *Solving ODEs II*,
        sec. IV.8): with the contraction rate ``theta_k = ||dx_k|| / ||dx_{k-1}||`` of two
        undamped corrections, the error left after applying dx_k is estimated as
        ``theta_k / (1 - theta_k) ||dx_k||`` and the step stops when that is at most
        ``tol``; on the first correction of a step, after a damped one, or when
        theta_k >= 1 it falls back to the ``"correction"`` test.  The rate is the
        larger of the last two (theta = max(theta_k, theta_{k-1})), so the test
        needs two undamped rates: a first correction far from the solution can
        make the first rate alone tiny and the estimate too small by orders of
        magnitude (tests/genalpha/test_newton_stopping.py has such a step).
    """

    tol: float = 1e-10
    max_iter: int = 30
    lam_min: float = 1e-4
    reuse: bool = True
    theta_reuse: float = 0.25
    predictor: str = "constant"
    stopping: str = "contraction"

    def __post_init__(self) -> None:
        if not (math.isfinite(self.tol) and 0 < self.tol < 1):
            raise ValueError(f"Newton tol={self.tol!r} must be in (0, 1)")
        if not (isinstance(self.max_iter, int) and self.max_iter >= 1):
            raise ValueError(f"Newton max_iter={self.max_iter!r} must be an integer >= 1")
        if not (0 < self.lam_min <= 1):
            raise ValueError(f"Newton lam_min={self.lam_min!r} must be in (0, 1]")
        if not (0 < self.theta_reuse < 1):
            raise ValueError(f"Newton theta_reuse={self.theta_reuse!r} must be in (0, 1)")
        if self.predictor not in ("rate", "constant"):
            raise ValueError(f"Newton predictor={self.predictor!r}; allowed: 'rate', 'constant'")
        if self.stopping not in ("correction", "contraction"):
            raise ValueError(
                f"Newton stopping={self.stopping!r}; allowed: 'correction', 'contraction'"
            )

    def options(self) -> NewtonOptions:
        return NewtonOptions(
            tol=float(self.tol),
            max_iter=int(self.max_iter),
            lam_min=float(self.lam_min),
            theta_reuse=float(self.theta_reuse),
            reuse=bool(self.reuse),
            rate_predictor=self.predictor == "rate",
            contraction=self.stopping == "contraction",
        )


class ConvergenceError(RuntimeError):
    """A time step whose Newton iteration failed.

    Attributes: ``t`` (time level being solved for), ``step`` (its index),
    ``iterations`` (corrections tried), ``residual`` (RMS scaled residual at the
    last iterate), ``reason``, ``dt`` (the step that failed, when step-size control
    was on; else None), and ``run``: the :class:`Run` of every step completed
    before the failure (set by :func:`integrate`; nothing computed is lost).
    """

    def __init__(
        self,
        t: float,
        step: int,
        iterations: int,
        residual: float,
        reason: str,
        run: Run | None = None,
        dt: float | None = None,
    ):
        self.t, self.step, self.iterations, self.residual, self.reason = (
            t,
            step,
            iterations,
            residual,
            reason,
        )
        self.run, self.dt = run, dt
        at = "" if dt is None else f" with dt={dt:.4g}"
        super().__init__(
            f"Newton failed at t={t:.10g} (step {step}){at} after {iterations} iterations, "
            f"residual norm {residual:.3e}: {reason}"
        )


# ----------------------------------------------------------------------------- kernels
@jit
def correction_norm(dx, y, ys):
    """RMS of the correction relative to max(|y|, yscale)  (dx in scaled units)."""
    N1, nf = dx.shape
    acc = 0.0
    for j in range(N1):
        for f in range(nf):
            sc = max(abs(y[j, f]), ys[f])
            d = dx[j, f] * ys[f] / sc
            acc += d * d
    return math.sqrt(acc / (N1 * nf))


@jit
def axpy_scaled(y, lam, dx, ys, out):
    """out = y + lam * dx * yscale."""
    N1, nf = y.shape
    for j in range(N1):
        for f in range(nf):
            out[j, f] = y[j, f] + lam * dx[j, f] * ys[f]


@jit
def _refactor(F, dF, con, gL, gR, w, fac):
    """Residual, Jacobian and its LU factors at w.y, and the Newton correction w.dx.

    Returns (RMS residual, status): CONVERGED when the factors are fresh."""
    res = residual(F, dF, con, EndValues(gL, gR), w.y, w, w.r, True)
    if not math.isfinite(res):
        return res, _NOT_FINITE
    if factor(con, w, fac) >= 0:
        w.factored[0] = 0
        return res, _SINGULAR
    w.factored[0] = 1
    solve_neg(fac, w.r, w.dx)
    return res, _CONVERGED


@jit
def _small(ndb, theta, theta_prev, lam, tol, contraction):
    """The stopping test of :class:`Newton` for the correction of norm ndb that
    followed one with contraction rate theta taken with damping lam; theta_prev is the
    rate before (inf if there was none or it was damped)."""
    if ndb <= tol:
        return True
    rate = max(theta, theta_prev)
    if contraction and lam == 1.0 and rate < 1.0:
        return rate / (1.0 - rate) * ndb <= tol
    return False


@jit
def solve_step(F, dF, con, gL, gR, w, fac, opts):
    """Damped Newton solve of one step for w.y (the predictor on entry).

    Keeps the factors of w.factored across calls while ``opts.reuse``.
    Returns an :class:`Outcome`.
    """
    ys = con.yscale
    y, yt, r, rt, dx, dxb = w.y, w.y_trial, w.r, w.r_trial, w.dx, w.dx_trial
    tol = opts.tol
    nres = 1
    nfact = 0
    fresh = False
    if w.factored[0] == 1 and opts.reuse:
        res = residual(F, dF, con, EndValues(gL, gR), y, w, r, False)
        if not math.isfinite(res):
            return Outcome(_NOT_FINITE, 0, nres, nfact, res)
        solve_neg(fac, r, dx)
    else:
        res, status = _refactor(F, dF, con, gL, gR, w, fac)
        if status != _CONVERGED:
            return Outcome(status, 0, nres, nfact, res)
        nfact += 1
        fresh = True
    lam = 1.0
    theta_prev = np.inf
    carried = -1.0  # the norm of dx at y when the last iteration left them (else -1)
    for it in range(opts.max_iter):
        nd = carried if carried >= 0.0 else correction_norm(dx, y, ys)
        carried = -1.0
        if not math.isfinite(nd):
            return Outcome(_NOT_FINITE, it, nres, nfact, res)
        if nd <= tol:
            axpy_scaled(y, 1.0, dx, ys, y)
            return Outcome(_CONVERGED, it + 1, nres, nfact, res)
        while True:
            axpy_scaled(y, lam, dx, ys, yt)
            rest = residual(F, dF, con, EndValues(gL, gR), yt, w, rt, False)
            nres += 1
            ndb = np.inf
            if math.isfinite(rest):
                solve_neg(fac, rt, dxb)
                ndb = correction_norm(dxb, yt, ys)
            theta = ndb / nd
            done = _small(ndb, theta, theta_prev, lam, tol, opts.contraction)
            if theta <= 1.0 - 0.25 * lam or done:
                break
            if not fresh:
                # a stale Jacobian did not contract: refactorise at y and start over
                res, status = _refactor(F, dF, con, gL, gR, w, fac)
                nres += 1
                if status != _CONVERGED:
                    return Outcome(status, it, nres, nfact, res)
                nfact += 1
                fresh = True
                nd = correction_norm(dx, y, ys)
                lam = 1.0
                if nd <= tol:
                    axpy_scaled(y, 1.0, dx, ys, y)
                    return Outcome(_CONVERGED, it + 1, nres, nfact, res)
                continue
            # NLEQ1's estimate of the damping factor from the simplified correction
            if math.isfinite(ndb):
                acc = 0.0
                N1, nf = dx.shape
                for j in range(N1):
                    for f in range(nf):
                        sc = max(abs(yt[j, f]), ys[f])
                        d = (dxb[j, f] - (1.0 - lam) * dx[j, f]) * ys[f] / sc
                        acc += d * d
                h = 2.0 * math.sqrt(acc / (N1 * nf)) / (lam * lam * nd)
                lam_new = min(0.5 * lam, 1.0 / h) if h > 0.0 else 0.5 * lam
            else:
                lam_new = 0.1 * lam
            lam = max(lam_new, 0.1 * lam)
            if lam < opts.lam_min:
                return Outcome(_DAMPING, it + 1, nres, nfact, rest)
        theta_prev = theta if lam == 1.0 else np.inf
        y[:, :] = yt
        r[:] = rt
        res = rest
        if done:
            axpy_scaled(y, 1.0, dxb, ys, y)
            return Outcome(_CONVERGED, it + 2, nres, nfact, res)
        if lam == 1.0 and theta <= opts.theta_reuse and opts.reuse:
            dx[:, :] = dxb
            carried = ndb
            fresh = False
        else:
            res, status = _refactor(F, dF, con, gL, gR, w, fac)
            nres += 1
            if status != _CONVERGED:
                return Outcome(status, it + 1, nres, nfact, res)
            nfact += 1
            fresh = True
        lam = min(1.0, 4.0 * lam)
    return Outcome(_MAX_ITER, opts.max_iter, nres, nfact, res)
