"""The generalised-alpha method in space and time (section 3).

The engine integrates any first-order system on a uniform grid s_j = j ds,
j = 0..N, and time levels t_i = t_0 + i dt,

    M y_t + K y_s + F(y) + q(s, t) = 0,                                   (eq 7)

with nb_left boundary rows ``P_L y(0, t) = g_L(t)`` and nb_right rows
``P_R y(L, t) = g_R(t)``, nb_left + nb_right = number of fields.  It knows
nothing about rods: a model supplies M, K, F, dF/dy (compiled) and its scales.

Discretisation.  Substituting eq (11) into eq (10) with the parameters of
eq (13) (for which beta + gamma = 1, hence zeta = 0 in eq 12) gives, for the
cell between nodes j-1 and j,

    M [(1-a_s) abar_j + a_s abar_{j-1}]
      + K [(1-b_t)(y_j^i - y_{j-1}^i) + b_t (y_j^{i-1} - y_{j-1}^{i-1})] / ds
      + <F>_j = 0,

    abar = (1-a_t) y_t^i + a_t y_t^{i-1}
         = (1-a_t)/(g_t dt) (y^i - y^{i-1}) + [a_t - (1-a_t)(1-g_t)/g_t] y_t^{i-1},

where ``<F>_j`` is the load vector averaged over the four corners of the cell
with weights (1-b_t, b_t) x (1-b_s, b_s) -- the generalised trapezoidal rule of
eq (9), the paper's choice -- or F at the equally weighted state -- the
generalised midpoint rule.  The source q is always corner-averaged.  Note that
the spatial derivative needs no history (zeta = 0): only y_t^{i-1} is carried,
and at lambda_t = -1 its coefficient vanishes as well.

Each step is a nonlinear system for y^i at all nodes, solved by a damped Newton
method in the spirit of NLEQ1 (scaled corrections, natural monotonicity test,
damping, Jacobian reuse), on the almost-block-diagonal Jacobian (``_abd``).
"""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numba
import numpy as np

from . import _abd
from ._numba import A1, A2, A3, I1, I2, JACOBIAN_SIGNATURE, LOAD_SIGNATURE, jit

__all__ = [
    "parameters",
    "Scheme",
    "SchemeWarning",
    "System",
    "Boundary",
    "Newton",
    "ConvergenceError",
    "Run",
    "integrate",
]


# ----------------------------------------------------------------------------- eq (13)
def parameters(lam: float) -> tuple[float, float, float]:
    """alpha, beta, gamma of eq (13) for a spectral radius at infinity lambda in [-1, 0].

    lambda = -1: alpha = beta = gamma = 1/2 (no numerical damping, the paper's choice);
    lambda = 0: the high-frequency limit is annihilated (alpha = -1/2, beta = 0, gamma = 1).
    """
    lam = float(lam)
    if not (math.isfinite(lam) and -1.0 <= lam <= 0.0):
        raise ValueError(f"lambda_inf={lam!r} is outside the allowed range [-1, 0]")
    alpha = (3.0 * lam + 1.0) / (2.0 * lam - 2.0)
    beta = lam / (lam - 1.0)
    gamma = 1.0 / (1.0 - lam)
    return alpha, beta, gamma


QUADRATURES = ("trapezoidal", "midpoint")


class SchemeWarning(UserWarning):
    """A scheme setting that is allowed but known to be unsound (see the docs)."""


@dataclass(frozen=True)
class Scheme:
    """Generalised-alpha parameters in space and time and the load-vector quadrature.

    lam_s, lam_t : spectral radius at infinity in space and in time, each in [-1, 0]
        (eq 13).  The paper uses -1 for both.
    quadrature : "trapezoidal" (eq 9: average of F at the corners; the paper's)
        or "midpoint" (F at the averaged state).
    """

    lam_s: float = -1.0
    lam_t: float = -1.0
    quadrature: str = "trapezoidal"

    def __post_init__(self) -> None:
        for name in ("lam_s", "lam_t"):
            try:
                parameters(getattr(self, name))
            except ValueError as err:
                raise ValueError(f"{name}: {err}") from None
        if self.quadrature not in QUADRATURES:
            raise ValueError(f"quadrature={self.quadrature!r}; allowed: {QUADRATURES}")
        if self.lam_s != -1.0:
            warnings.warn(
                f"lam_s={self.lam_s}: with eq (13) in space the scheme is a theta-method in s "
                "that is only first order and, for the hyperbolic torsion rows, unstable "
                "(spectral radius > 1) and ill-conditioned at small Courant numbers; "
                "lam_s = -1 (the paper's choice) is the sound one",
                SchemeWarning,
                stacklevel=3,
            )

    @property
    def space(self) -> tuple[float, float, float]:
        return parameters(self.lam_s)

    @property
    def time(self) -> tuple[float, float, float]:
        return parameters(self.lam_t)

    def coefficients(self, ds: float, dt: float) -> np.ndarray:
        """Packed constants for the compiled kernels (see ``_CO_*``)."""
        a_s, b_s, _ = self.space
        a_t, b_t, g_t = self.time
        cM = (1.0 - a_t) / (g_t * dt)
        cA = a_t - (1.0 - a_t) * (1.0 - g_t) / g_t
        quad = float(QUADRATURES.index(self.quadrature))
        return np.array([cM, cA, a_s, b_s, b_t, g_t, 1.0 / ds, dt, quad])


@dataclass(frozen=True)
class System:
    """What the engine needs to know about a model.

    F(y, p, out) and dF(y, p, out) are compiled functions (numba) filling the
    load vector (nf,) and its Jacobian (nf, nf) for one node.  ``yscale`` and
    ``rscale`` are characteristic sizes of the fields and of the equation rows:
    they scale the Newton system and set the absolute floor of its
    convergence test.
    """

    names: tuple[str, ...]
    M: np.ndarray
    K: np.ndarray
    F: Any
    dF: Any
    params: np.ndarray
    yscale: np.ndarray
    rscale: np.ndarray

    @classmethod
    def from_model(cls, model, *, names, F, dF, params) -> System:
        """A system from a model with ``mass_matrix``, ``stiffness_matrix`` and ``scales()``."""
        ys, rs = model.scales()
        return cls(
            names=tuple(names),
            M=model.mass_matrix,
            K=model.stiffness_matrix,
            F=F,
            dF=dF,
            params=params,
            yscale=ys,
            rscale=rs,
        )

    @property
    def nf(self) -> int:
        return len(self.names)

    def index(self, name: str | int) -> int:
        if isinstance(name, int | np.integer):
            if not 0 <= name < self.nf:
                raise ValueError(f"field index {name} outside [0, {self.nf})")
            return int(name)
        try:
            return self.names.index(name)
        except ValueError:
            raise ValueError(f"unknown field {name!r}; fields are {self.names}") from None

    def load(self, y: np.ndarray) -> np.ndarray:
        """F(y) at every node of y (..., nf)."""
        y = np.ascontiguousarray(y, dtype=float)
        flat = y.reshape(-1, self.nf)
        out = np.empty_like(flat)
        for j in range(flat.shape[0]):
            self.F(flat[j], self.params, out[j])
        return out.reshape(y.shape)

    def load_jacobian(self, y: np.ndarray) -> np.ndarray:
        y = np.ascontiguousarray(y, dtype=float)
        out = np.empty((self.nf, self.nf))
        self.dF(y, self.params, out)
        return out


@dataclass(frozen=True)
class Boundary:
    """Boundary rows ``rows @ y(end, t) = values(t)`` at one end.

    ``values`` maps an array of times (n,) to an array (n, nb); a constant
    array-like is accepted for time-independent conditions.
    """

    rows: np.ndarray
    values: Callable[[np.ndarray], np.ndarray] | np.ndarray

    @classmethod
    def fields(cls, system: System, names: Sequence[str | int], values=None) -> Boundary:
        """Prescribe the listed fields (``values`` default 0)."""
        rows = np.zeros((len(names), system.nf))
        for r, name in enumerate(names):
            rows[r, system.index(name)] = 1.0
        if values is None:
            values = np.zeros(len(names))
        return cls(rows, values)

    @property
    def nb(self) -> int:
        return self.rows.shape[0]

    def at(self, t: np.ndarray) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        if callable(self.values):
            g = np.asarray(self.values(t), dtype=float)
        else:
            g = np.broadcast_to(np.asarray(self.values, dtype=float), (t.size, self.nb))
        g = np.array(np.broadcast_to(g.reshape(t.size, -1), (t.size, self.nb)), order="C")
        if not np.all(np.isfinite(g)):
            raise ValueError("boundary values are not finite")
        return g


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
    """

    tol: float = 1e-10
    max_iter: int = 30
    lam_min: float = 1e-4
    reuse: bool = True
    theta_reuse: float = 0.25
    predictor: str = "constant"

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

    def packed(self) -> np.ndarray:
        return np.array(
            [
                self.tol,
                self.max_iter,
                self.lam_min,
                self.theta_reuse,
                float(self.reuse),
                float(self.predictor == "rate"),
            ]
        )


_FAIL = {
    1: "no convergence within max_iter corrections",
    2: "damping factor fell below lam_min (no monotone decrease of the Newton correction)",
    3: "singular Jacobian",
    4: "residual is not finite",
}


class ConvergenceError(RuntimeError):
    """A time step whose Newton iteration failed.

    Attributes: ``t`` (time level being solved for), ``step`` (its index),
    ``iterations`` (corrections tried), ``residual`` (RMS scaled residual at the
    last iterate), ``reason``, and ``run``: the :class:`Run` of every step completed
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
    ):
        self.t, self.step, self.iterations, self.residual, self.reason = (
            t,
            step,
            iterations,
            residual,
            reason,
        )
        self.run = run
        super().__init__(
            f"Newton failed at t={t:.10g} (step {step}) after {iterations} iterations, "
            f"residual norm {residual:.3e}: {reason}"
        )


# ----------------------------------------------------------------------------- kernels
# indices into the packed coefficient vector of Scheme.coefficients
_CO_CM, _CO_CA, _CO_AS, _CO_BS, _CO_BT, _CO_GT, _CO_IDS, _CO_DT, _CO_QUAD = range(9)


@jit
def _residual(F, dF, con, gL, gR, y, ws, r, want_jac):
    """Scaled residual of the step at iterate y (and F, dF where they are needed)."""
    p, M, K, P, Q, co, ys, rs, BLr, blsc, BRr, brsc = con
    Fn, dFn, c, ybo, ytmp = ws[8], ws[9], ws[11], ws[12], ws[14]
    N = y.shape[0] - 1
    nf = y.shape[1]
    nbl = BLr.shape[0]
    bs = co[_CO_BS]
    bt = co[_CO_BT]
    wn = (1.0 - bt) * (1.0 - bs)
    wp = (1.0 - bt) * bs
    trap = co[_CO_QUAD] == 0.0
    if trap:
        for j in range(N + 1):
            F(y[j], p, Fn[j])
            if want_jac:
                dF(y[j], p, dFn[j])
    else:
        for j in range(N):
            for f in range(nf):
                ytmp[f] = ybo[j, f] + wn * y[j + 1, f] + wp * y[j, f]
            F(ytmp, p, Fn[j])
            if want_jac:
                dF(ytmp, p, dFn[j])
    for rr in range(nbl):
        acc = -gL[rr]
        for f in range(nf):
            acc += BLr[rr, f] * y[0, f]
        r[rr] = acc / blsc[rr]
    for j in range(N):
        off = nbl + nf * j
        for rr in range(nf):
            acc = c[j, rr]
            for f in range(nf):
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
            acc += BRr[rr, f] * y[N, f]
        r[off + rr] = acc / brsc[rr]
    total = 0.0
    for k in range(r.shape[0]):
        total += r[k] * r[k]
    return math.sqrt(total / r.shape[0])


@jit
def _factor(con, ws, fac):
    """Assemble the scaled Jacobian from dF (left by _residual) and LU-factorise it."""
    p, M, K, P, Q, co, ys, rs, BLr, blsc, BRr, brsc = con
    dFn, Ablk, Bblk, BLs, BRs = ws[9], ws[15], ws[16], ws[17], ws[18]
    W, piv, Wl, pivl = fac[0], fac[1], fac[2], fac[3]
    N = Ablk.shape[0]
    nf = Ablk.shape[1]
    bs = co[_CO_BS]
    bt = co[_CO_BT]
    wn = (1.0 - bt) * (1.0 - bs)
    wp = (1.0 - bt) * bs
    trap = co[_CO_QUAD] == 0.0
    for j in range(N):
        jn = j + 1 if trap else j
        for rr in range(nf):
            inv = 1.0 / rs[rr]
            for f in range(nf):
                Ablk[j, rr, f] = (Q[rr, f] + wp * dFn[j, rr, f]) * ys[f] * inv
                Bblk[j, rr, f] = (P[rr, f] + wn * dFn[jn, rr, f]) * ys[f] * inv
    return _abd.factor(BLs, Ablk, Bblk, BRs, W, piv, Wl, pivl)


@jit
def _solve_neg(fac, r, x):
    """x = -J^{-1} r  (scaled unknowns)."""
    _abd.solve(fac[0], fac[1], fac[2], fac[3], fac[4], r, x)
    N1, nf = x.shape
    for j in range(N1):
        for f in range(nf):
            x[j, f] = -x[j, f]


@jit
def _norm(dx, y, ys):
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
def _axpy_scaled(y, lam, dx, ys, out):
    """out = y + lam * dx * yscale."""
    N1, nf = y.shape
    for j in range(N1):
        for f in range(nf):
            out[j, f] = y[j, f] + lam * dx[j, f] * ys[f]


@jit
def _newton(F, dF, con, gL, gR, ws, fac, nt, state, info):
    """Damped Newton solve of one step; the predictor is in ws[2] on entry.

    state[0] == 1 means factors of a (possibly stale) Jacobian are available.
    info <- [status, corrections, residual evaluations, factorisations, residual].
    Returns the status (0 = converged, see _FAIL).
    """
    ys = con[6]
    y, yt, r, rt, dx, dxb = ws[2], ws[3], ws[4], ws[5], ws[6], ws[7]
    tol = nt[0]
    maxit = int(nt[1])
    lam_min = nt[2]
    theta_max = nt[3]
    reuse = nt[4] > 0.0
    nres = 0
    nfact = 0
    have = state[0] == 1 and reuse
    res = _residual(F, dF, con, gL, gR, y, ws, r, not have)
    nres += 1
    if not math.isfinite(res):
        info[0], info[1], info[2], info[3], info[4] = 4.0, 0.0, nres, nfact, res
        return 4
    fresh = False
    if not have:
        if _factor(con, ws, fac) >= 0:
            info[0], info[1], info[2], info[3], info[4] = 3.0, 0.0, nres, nfact, res
            state[0] = 0
            return 3
        nfact += 1
        fresh = True
        state[0] = 1
    _solve_neg(fac, r, dx)
    lam = 1.0
    for it in range(maxit):
        nd = _norm(dx, y, ys)
        if not math.isfinite(nd):
            info[0], info[1], info[2], info[3], info[4] = 4.0, it, nres, nfact, res
            return 4
        if nd <= tol:
            _axpy_scaled(y, 1.0, dx, ys, y)
            info[0], info[1], info[2], info[3], info[4] = 0.0, it + 1, nres, nfact, res
            return 0
        while True:
            _axpy_scaled(y, lam, dx, ys, yt)
            rest = _residual(F, dF, con, gL, gR, yt, ws, rt, False)
            nres += 1
            ndb = np.inf
            if math.isfinite(rest):
                _solve_neg(fac, rt, dxb)
                ndb = _norm(dxb, yt, ys)
            theta = ndb / nd
            if theta <= 1.0 - 0.25 * lam or ndb <= tol:
                break
            if not fresh:
                res = _residual(F, dF, con, gL, gR, y, ws, r, True)
                nres += 1
                if _factor(con, ws, fac) >= 0:
                    info[0], info[1], info[2], info[3], info[4] = 3.0, it, nres, nfact, res
                    state[0] = 0
                    return 3
                nfact += 1
                fresh = True
                _solve_neg(fac, r, dx)
                nd = _norm(dx, y, ys)
                lam = 1.0
                if nd <= tol:
                    _axpy_scaled(y, 1.0, dx, ys, y)
                    info[0], info[1], info[2], info[3], info[4] = 0.0, it + 1, nres, nfact, res
                    return 0
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
            if lam < lam_min:
                info[0], info[1], info[2], info[3], info[4] = 2.0, it + 1, nres, nfact, rest
                return 2
        y[:, :] = yt
        r[:] = rt
        res = rest
        if ndb <= tol:
            _axpy_scaled(y, 1.0, dxb, ys, y)
            info[0], info[1], info[2], info[3], info[4] = 0.0, it + 2, nres, nfact, res
            return 0
        if lam == 1.0 and theta <= theta_max and reuse:
            dx[:, :] = dxb
            fresh = False
        else:
            res = _residual(F, dF, con, gL, gR, y, ws, r, True)
            nres += 1
            if _factor(con, ws, fac) >= 0:
                info[0], info[1], info[2], info[3], info[4] = 3.0, it + 1, nres, nfact, res
                state[0] = 0
                return 3
            nfact += 1
            fresh = True
            _solve_neg(fac, r, dx)
        lam = min(1.0, 4.0 * lam)
    info[0], info[1], info[2], info[3], info[4] = 1.0, maxit, nres, nfact, res
    return 1


@jit
def _prepare_step(F, con, ws, qs, qt_old, qt_new, qf_old, qf_new, use_qf):
    """Constant (old-level) part of every cell's residual, and the predictor."""
    p, M, K, P, Q, co, ys, rs, BLr, blsc, BRr, brsc = con
    yo, ao = ws[0], ws[1]
    Fo, c, ybo, z = ws[10], ws[11], ws[12], ws[13]
    N = yo.shape[0] - 1
    nf = yo.shape[1]
    cM = co[_CO_CM]
    cA = co[_CO_CA]
    a_s = co[_CO_AS]
    bs = co[_CO_BS]
    bt = co[_CO_BT]
    ids = co[_CO_IDS]
    trap = co[_CO_QUAD] == 0.0
    for j in range(N + 1):
        for f in range(nf):
            z[j, f] = -cM * yo[j, f] + cA * ao[j, f]
        if trap:
            F(yo[j], p, Fo[j])
    for j in range(N):
        for rr in range(nf):
            acc = 0.0
            for f in range(nf):
                acc += M[rr, f] * ((1.0 - a_s) * z[j + 1, f] + a_s * z[j, f])
                acc += bt * ids * K[rr, f] * (yo[j + 1, f] - yo[j, f])
            if trap:
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
        if not trap:
            for f in range(nf):
                ybo[j, f] = bt * ((1.0 - bs) * yo[j + 1, f] + bs * yo[j, f])


_CON = numba.types.Tuple((A1, A2, A2, A2, A2, A1, A1, A1, A2, A1, A2, A1))
_WS = numba.types.Tuple(
    (A2, A2, A2, A2, A1, A1, A2, A2, A2, A3, A2, A2, A2, A2, A1, A3, A3, A2, A2)
)
_FAC = numba.types.Tuple((A3, I2, A2, I1, A1))
_MARCH_SIGNATURE = numba.types.int64(
    numba.types.FunctionType(LOAD_SIGNATURE),
    numba.types.FunctionType(JACOBIAN_SIGNATURE),
    _CON,
    A2,
    A2,
    A2,
    A1,
    A3,
    _WS,
    _FAC,
    A1,
    I1,
    I1,
    I1,
    numba.types.int64,
    numba.types.int64,
    A2,
    A2,
    A1,
)


@jit(signature=_MARCH_SIGNATURE)
def _march(
    F,
    dF,
    con,
    gL,
    gR,
    qs,
    qt,
    qf,
    ws,
    fac,
    nt,
    state,
    rec_f,
    rec_n,
    rec_every,
    k_offset,
    rec_out,
    stats,
    info,
):
    """Advance len(gL) - 1 steps.  Returns the number of steps completed."""
    co = con[5]
    yo, ao, y = ws[0], ws[1], ws[2]
    N1, nf = yo.shape
    dt = co[_CO_DT]
    g_t = co[_CO_GT]
    rate = nt[5] > 0.0
    use_qf = qf.shape[0] > 0
    nsteps = gL.shape[0] - 1
    nrec = 0
    nt_retry = nt.copy()
    nt_retry[4] = 0.0
    for k in range(nsteps):
        if use_qf:
            _prepare_step(F, con, ws, qs, qt[k], qt[k + 1], qf[k], qf[k + 1], True)
        else:
            _prepare_step(F, con, ws, qs, qt[k], qt[k + 1], qs, qs, False)
        for j in range(N1):
            for f in range(nf):
                y[j, f] = yo[j, f] + dt * ao[j, f] if rate else yo[j, f]
        status = _newton(F, dF, con, gL[k + 1], gR[k + 1], ws, fac, nt, state, info)
        stats[k, 0] = info[1]
        stats[k, 1] = info[2]
        stats[k, 2] = info[3]
        stats[k, 3] = info[4]
        if status != 0:
            # one retry: the other predictor, a fresh Jacobian at every iteration
            for j in range(N1):
                for f in range(nf):
                    y[j, f] = yo[j, f] if rate else yo[j, f] + dt * ao[j, f]
            state[0] = 0
            status = _newton(F, dF, con, gL[k + 1], gR[k + 1], ws, fac, nt_retry, state, info)
            stats[k, 0] += info[1]
            stats[k, 1] += info[2]
            stats[k, 2] += info[3]
            stats[k, 3] = info[4]
            stats[k, 4] = 1.0
            if status != 0:
                return k
        for j in range(N1):
            for f in range(nf):
                ao[j, f] = (y[j, f] - yo[j, f]) / (g_t * dt) - (1.0 - g_t) / g_t * ao[j, f]
                yo[j, f] = y[j, f]
        if (k_offset + k + 1) % rec_every == 0:
            for m in range(rec_f.shape[0]):
                rec_out[nrec, m] = yo[rec_n[m], rec_f[m]]
            nrec += 1
    return nsteps


# ----------------------------------------------------------------------------- driver
@dataclass
class Run:
    """The outcome of :func:`integrate`.

    Attributes
    ----------
    t
        Times at which the traces were recorded (t_0 first).
    traces
        Name -> array over ``t`` (the recorded fields at their nodes).
    snapshot_times, snapshots
        Whole fields (n_snap, N+1, nf) at chosen times.
    iterations, residual_evaluations, factorisations
        Newton statistics per step.
    retries
        1 for a step whose first Newton solve failed and was retried (from the
        other predictor, refactorising at every iteration), else 0.
    y, y_t
        The state and its time derivative at the last completed level.
    stopped
        Why the run ended (``"t_end"`` or the reason returned by ``stop``).
    """

    s: np.ndarray
    t: np.ndarray
    traces: dict[str, np.ndarray]
    snapshot_times: np.ndarray
    snapshots: np.ndarray
    iterations: np.ndarray
    residual_evaluations: np.ndarray
    factorisations: np.ndarray
    residuals: np.ndarray
    retries: np.ndarray
    y: np.ndarray
    y_t: np.ndarray
    t_final: float
    steps: int
    wall_time: float
    stopped: str
    names: tuple[str, ...]
    meta: dict[str, Any] = field(default_factory=dict)

    def __getitem__(self, name: str) -> np.ndarray:
        return self.traces[name]

    def snapshot(self, t: float) -> np.ndarray:
        """Whole state at the snapshot time nearest to t."""
        if len(self.snapshot_times) == 0:
            raise ValueError("this run recorded no snapshots")
        return self.snapshots[int(np.argmin(np.abs(self.snapshot_times - t)))]

    def field(self, name: str, t: float) -> np.ndarray:
        return self.snapshot(t)[:, self.names.index(name)]


def _check_positive(name: str, value: float) -> None:
    if not (
        isinstance(value, int | float | np.floating | np.integer)
        and math.isfinite(value)
        and value > 0
    ):
        raise ValueError(f"{name}={value!r} must be a finite number > 0")


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


def consistent_initial_state(
    system: System,
    y0: np.ndarray,
    *,
    length: float,
    left: Boundary,
    right: Boundary,
    scheme: Scheme = Scheme(),
    t0: float = 0.0,
    q0: np.ndarray | None = None,
    tol: float = 1e-13,
    max_iter: int = 20,
) -> np.ndarray:
    """The state nearest to y0 (scaled least change) that satisfies the discrete
    algebraic rows and both boundary conditions at t0 exactly (Gauss-Newton).

    Needed for initial data that satisfy the continuous constraint only (a
    manufactured solution, a measured shape); not for the paper's straight rod.
    """
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


def _setup(
    system: System,
    scheme: Scheme,
    n_cells: int,
    ds: float,
    dt: float,
    left: Boundary,
    right: Boundary,
    y0: np.ndarray,
    a0: np.ndarray,
):
    """Constants, work arrays and LU storage of the compiled kernels."""
    nf = system.nf
    ys, rs = np.asarray(system.yscale, float), np.asarray(system.rscale, float)
    BLr, BRr = np.ascontiguousarray(left.rows, float), np.ascontiguousarray(right.rows, float)
    blsc = np.abs(BLr) @ ys
    brsc = np.abs(BRr) @ ys
    if np.any(blsc == 0) or np.any(brsc == 0):
        raise ValueError("a boundary row is all zeros")
    co = scheme.coefficients(ds, dt)
    cM, _, a_s, _, b_t = co[:5]
    P = np.ascontiguousarray(cM * (1 - a_s) * system.M + (1 - b_t) / ds * system.K)
    Q = np.ascontiguousarray(cM * a_s * system.M - (1 - b_t) / ds * system.K)
    con = (
        np.ascontiguousarray(system.params, float),
        np.ascontiguousarray(system.M, float),
        np.ascontiguousarray(system.K, float),
        P,
        Q,
        co,
        ys,
        rs,
        BLr,
        blsc,
        BRr,
        brsc,
    )
    N1 = n_cells + 1
    nq = N1 if scheme.quadrature == "trapezoidal" else n_cells
    ws = (
        y0.copy(),
        a0.copy(),
        y0.copy(),
        y0.copy(),  # yo ao y yt
        np.zeros(nf * N1),
        np.zeros(nf * N1),  # r rt
        np.zeros((N1, nf)),
        np.zeros((N1, nf)),  # dx dxb
        np.zeros((nq, nf)),
        np.zeros((nq, nf, nf)),  # Fn dFn
        np.zeros((N1, nf)),
        np.zeros((n_cells, nf)),  # Fo c
        np.zeros((n_cells, nf)),
        np.zeros((N1, nf)),
        np.zeros(nf),  # ybo z ytmp
        np.zeros((n_cells, nf, nf)),
        np.zeros((n_cells, nf, nf)),  # Ablk Bblk
        BLr * ys / blsc[:, None],
        BRr * ys / brsc[:, None],  # scaled BC rows
    )
    fac = _abd.allocate(n_cells, nf, left.nb)
    return con, ws, fac


_ITERATION_SIGNATURE = numba.types.float64(
    numba.types.FunctionType(LOAD_SIGNATURE),
    numba.types.FunctionType(JACOBIAN_SIGNATURE),
    _CON,
    A1,
    A1,
    _WS,
    _FAC,
    numba.types.int64,
)


@jit(signature=_ITERATION_SIGNATURE)
def _full_newton_iterations(F, dF, con, gL, gR, ws, fac, repeats):
    """``repeats`` full Newton iterations at ws[2]: residual, Jacobian, LU, solve."""
    res = 0.0
    for _ in range(repeats):
        res = _residual(F, dF, con, gL, gR, ws[2], ws, ws[4], True)
        _factor(con, ws, fac)
        _solve_neg(fac, ws[4], ws[6])
    return res


def newton_iteration_kernel(
    system: System,
    scheme: Scheme,
    n_cells: int,
    length: float,
    dt: float,
    left: Boundary,
    right: Boundary,
    y: np.ndarray,
):
    """A callable ``f(repeats)`` doing that many full Newton iterations of a step from
    state y inside compiled code, and the step's scaled Jacobian blocks and
    right-hand side (for benchmarks against LAPACK)."""
    y = np.ascontiguousarray(y, float)
    con, ws, fac = _setup(
        system, scheme, n_cells, length / n_cells, dt, left, right, y, np.zeros_like(y)
    )
    gL, gR = left.at(np.array([dt]))[0], right.at(np.array([dt]))[0]

    def iteration(repeats: int = 1) -> float:
        return _full_newton_iterations(system.F, system.dF, con, gL, gR, ws, fac, repeats)

    iteration(1)
    return iteration, (ws[17], ws[15], ws[16], ws[18]), ws[4]


def integrate(
    system: System,
    *,
    n_cells: int,
    length: float,
    dt: float,
    t_end: float,
    y0: np.ndarray,
    left: Boundary,
    right: Boundary,
    scheme: Scheme = Scheme(),
    t0: float = 0.0,
    y_t0: np.ndarray | str = "consistent",
    source: tuple[np.ndarray, Callable[[np.ndarray], np.ndarray] | None] | None = None,
    source_field: Callable[[np.ndarray, float], np.ndarray] | None = None,
    record: Mapping[str, tuple[str | int, int]] | None = None,
    record_every: int = 1,
    snapshots: Sequence[float] = (),
    newton: Newton = Newton(),
    stop: Callable[[float, np.ndarray], str | None] | None = None,
    check_every: int | None = None,
    progress: bool | None = None,
    meta: Mapping[str, Any] | None = None,
) -> Run:
    """Integrate ``system`` from t0 to t_end with the generalised-alpha scheme.

    Parameters
    ----------
    n_cells : number of cells N >= 2 (nodes s_j = j * length / N).
    dt : time step > 0; the run takes ceil((t_end - t0) / dt) steps.
    y0 : initial state (N+1, nf), finite.  At lam_t = -1 the rows without a time
        derivative (inextensibility) obey R^i = -R^{i-1} in time, so a y0 that
        violates their discrete form keeps an undamped (-1)^i oscillation that
        resonates with the multiplier n; pass such data through
        :func:`consistent_initial_state` first.  The paper's straight initial
        states satisfy the discrete equations exactly.
    left, right : boundary rows at s = 0 and s = length (nb_left + nb_right = nf).
    y_t0 : initial time derivative (N+1, nf), or "consistent" (from the equations,
        see :func:`consistent_rates`), or "zero".  Irrelevant at lam_t = -1.
    source : (q_space (N+1, nf), g) for a separable source q(s, t) = q_space(s) g(t)
        (g maps an array of times to an array; None means g = 1).
    source_field : callable (s, t) -> (N+1, nf) for a general source.
    record : name -> (field, node) recorded every ``record_every`` steps.
    snapshots : times at which the whole state is kept (nearest time level).
    stop : callable (t, y) -> reason or None, checked every ``check_every`` steps.
    progress : show a progress bar (None: only for long runs on a terminal).
    """
    t_start = time.perf_counter()
    if not isinstance(n_cells, int | np.integer) or n_cells < 2:
        raise ValueError(f"n_cells={n_cells!r} must be an integer >= 2")
    n_cells = int(n_cells)
    _check_positive("length", length)
    _check_positive("dt", dt)
    if not (math.isfinite(t_end) and math.isfinite(t0) and t_end > t0):
        raise ValueError(f"t_end={t_end!r} must be finite and > t0={t0!r}")
    if not (isinstance(record_every, int) and record_every >= 1):
        raise ValueError(f"record_every={record_every!r} must be an integer >= 1")
    nf = system.nf
    y0 = np.array(y0, dtype=float)
    if y0.shape != (n_cells + 1, nf):
        raise ValueError(f"y0 has shape {y0.shape}, expected (n_cells+1, nf) = {(n_cells + 1, nf)}")
    if not np.all(np.isfinite(y0)):
        raise ValueError("y0 contains NaN or inf")
    if left.rows.shape[1] != nf or right.rows.shape[1] != nf or left.nb + right.nb != nf:
        raise ValueError(
            f"boundary rows: need nb_left + nb_right = {nf} rows of {nf} columns, got "
            f"{left.rows.shape} and {right.rows.shape}"
        )
    ds = length / n_cells
    s = np.linspace(0.0, length, n_cells + 1)
    n_steps = max(1, int(math.ceil((t_end - t0) / dt * (1.0 - 1e-12))))
    times = t0 + dt * np.arange(n_steps + 1)

    q_space = np.zeros((n_cells + 1, nf))
    q_time: Callable[[np.ndarray], np.ndarray] = lambda tt: np.ones_like(tt)  # noqa: E731
    if source is not None:
        q_space = np.ascontiguousarray(source[0], dtype=float)
        if q_space.shape != (n_cells + 1, nf):
            raise ValueError(
                f"source space part has shape {q_space.shape}, expected {(n_cells + 1, nf)}"
            )
        if source[1] is not None:
            q_time = source[1]

    def q_full_at(tt: np.ndarray) -> np.ndarray:
        if source_field is None:
            return np.zeros((0, 0, 0))
        return np.ascontiguousarray([source_field(s, float(ti)) for ti in tt], dtype=float)

    if isinstance(y_t0, str):
        if y_t0 == "zero":
            a0 = np.zeros_like(y0)
        elif y_t0 == "consistent":
            q0 = q_space * float(np.asarray(q_time(np.array([t0])))[0])
            if source_field is not None:
                q0 = q0 + source_field(s, t0)
            a0 = consistent_rates(system, y0, ds, q0)
        else:
            raise ValueError(f"y_t0={y_t0!r}; allowed: an array, 'consistent', 'zero'")
    else:
        a0 = np.array(y_t0, dtype=float)
        if a0.shape != y0.shape or not np.all(np.isfinite(a0)):
            raise ValueError(f"y_t0 must be a finite array of shape {y0.shape}")

    con, ws, fac = _setup(system, scheme, n_cells, ds, dt, left, right, y0, a0)
    N1 = n_cells + 1
    nt = newton.packed()
    state = np.zeros(1, dtype=np.int64)

    rec = dict(record or {})
    rec_f = np.array([system.index(f) for f, _ in rec.values()], dtype=np.int64)
    rec_n = np.array(
        [int(n) % N1 if -N1 <= int(n) < N1 else -1 for _, n in rec.values()], dtype=np.int64
    )
    if np.any(rec_n < 0):
        raise ValueError(f"record: node indices must be in [-{N1}, {N1})")
    snap_steps = sorted({int(round((ts - t0) / dt)) for ts in snapshots})
    if any(k < 0 or k > n_steps for k in snap_steps):
        raise ValueError(f"snapshots must lie in [t0, t_end] = [{t0}, {t_end}]")
    check = n_steps if (stop is None and check_every is None) else (check_every or 100)
    if check < 1:
        raise ValueError(f"check_every={check_every!r} must be >= 1")
    bounds = sorted({0, n_steps, *snap_steps, *range(0, n_steps, check)})

    rec_t = [t0]
    rec_vals = [y0[rec_n, rec_f].copy()]
    snap_t, snap_y = [], []
    if 0 in snap_steps:
        snap_t.append(t0)
        snap_y.append(y0.copy())
    stats = np.zeros((n_steps, 5))
    info = np.zeros(5)
    stopped = "t_end"
    failure = None
    done = 0
    if progress is None:
        progress = n_steps * N1 * nf > 5e7
    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=n_steps, unit="step", disable=None, leave=False)
    try:
        for k0, k1 in zip(bounds[:-1], bounds[1:], strict=True):
            tt = times[k0 : k1 + 1]
            gL, gR = left.at(tt), right.at(tt)
            qt = np.array(np.broadcast_to(np.asarray(q_time(tt), float), tt.shape), order="C")
            qf = q_full_at(tt)
            first_rec = (k0 // record_every + 1) * record_every
            rec_steps = np.arange(first_rec, k1 + 1, record_every)
            rec_out = np.zeros((rec_steps.size, len(rec_f)))
            completed = _march(
                system.F,
                system.dF,
                con,
                gL,
                gR,
                q_space,
                qt,
                qf,
                ws,
                fac,
                nt,
                state,
                rec_f,
                rec_n,
                record_every,
                k0,
                rec_out,
                stats[k0:k1],
                info,
            )
            if completed < k1 - k0:
                k_fail = k0 + completed + 1
                failure = ConvergenceError(
                    float(times[k_fail]),
                    k_fail,
                    int(info[1]),
                    float(info[4]),
                    _FAIL.get(int(info[0]), "unknown")
                    + " (also after a retry from the other predictor with a fresh Jacobian)",
                )
                done = k0 + completed
                kept = rec_steps <= done
                rec_t.extend(t0 + dt * rec_steps[kept])
                rec_vals.extend(rec_out[kept])
                stopped = f"failed: {failure}"
                break
            done = k1
            rec_t.extend(t0 + dt * rec_steps)
            rec_vals.extend(rec_out)
            if bar is not None:
                bar.update(k1 - k0)
            if k1 in snap_steps:
                snap_t.append(float(times[k1]))
                snap_y.append(ws[0].copy())
            if stop is not None and k1 < n_steps:
                reason = stop(float(times[k1]), ws[0])
                if reason:
                    stopped = str(reason)
                    break
    finally:
        if bar is not None:
            bar.close()
    rv = np.array(rec_vals).reshape(len(rec_vals), len(rec_f))
    traces = {name: rv[:, m].copy() for m, name in enumerate(rec)}
    st = stats[:done]
    result = Run(
        s=s,
        t=np.array(rec_t),
        traces=traces,
        snapshot_times=np.array(snap_t),
        snapshots=np.array(snap_y) if snap_y else np.zeros((0, N1, nf)),
        iterations=st[:, 0].astype(int),
        residual_evaluations=st[:, 1].astype(int),
        factorisations=st[:, 2].astype(int),
        residuals=st[:, 3].copy(),
        retries=st[:, 4].astype(int),
        y=ws[0].copy(),
        y_t=ws[1].copy(),
        t_final=float(times[done]),
        steps=done,
        wall_time=time.perf_counter() - t_start,
        stopped=stopped,
        names=system.names,
        meta={
            "n_cells": n_cells,
            "length": length,
            "dt": dt,
            "t0": t0,
            "t_end": t_end,
            "scheme": {
                "lam_s": scheme.lam_s,
                "lam_t": scheme.lam_t,
                "quadrature": scheme.quadrature,
            },
            "newton": newton.__dict__.copy(),
            **(meta or {}),
        },
    )
    if failure is not None:
        failure.run = result
        raise failure
    return result
