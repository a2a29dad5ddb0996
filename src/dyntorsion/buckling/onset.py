"""The onset of buckling (section 6): the critical time t_c and twist kappa3 from a
straight line fitted to the initial dramatic variation of u3(L, t) and extrapolated
back to u3 = 0, with the uncertainty of that rule, and what a run's onset means
(:func:`classify_onset`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from ..model.rod import Rod
    from .run import BucklingRun

__all__ = [
    "WINDOW",
    "Onset",
    "check_window",
    "STATUSES",
    "PEAK_FALL",
    "reference_level",
    "classify_onset",
    "first_peak",
    "detect_onset",
    "continuous_window_fit",
]

#: the default onset window: the straight line through the samples of |u3(L, t)| between
#: 10 % and 50 % of its first peak, extrapolated back to the axis
WINDOW: tuple[float, float] = (0.1, 0.5)

#: a running maximum of ``|u3(L, t)|`` is the first peak once U falls below this fraction
#: of it (so the small torsional-wave ripples on the rise do not count as a peak)
PEAK_FALL = 0.7


def reference_level(rod: Rod) -> float:
    """u_ref = L / T0 [m/s] (T0 = L^2 sqrt(rho A / B), B = min(B1, B2), the bending time scale): the level of
    ``|u3(L, t)|`` at which the rise to the onset starts, far above the prebuckling level
    and far below the first peak (0.023 m/s for Table 1)."""
    return rod.L / rod.T0


@dataclass(frozen=True)
class Onset:
    """Critical time and twist from the linear fit of u3(L, t) (section 6); the same
    window read in continuous time (:func:`continuous_window_fit`) in ``t_c_continuous``
    and ``kappa3_continuous`` (nan where the rise holds too few samples for it)."""

    t_c: float
    kappa3: float
    uncertainty_t: float
    uncertainty_kappa3: float
    slope: float
    intercept: float
    window: tuple[float, float]
    variations: dict[tuple[float, float], float]
    t_ref: float = math.nan
    u_ref: float = math.nan
    t_c_continuous: float = math.nan
    kappa3_continuous: float = math.nan


def check_window(window, variations=()) -> None:
    """Refuse an onset window (or a variation) that is not two finite fractions
    0 < lo < hi < 1 of the first peak of ``|u3(L, t)|``."""
    for name, w in (("window", window), *(("variations", v) for v in variations)):
        try:
            lo, hi = (float(v) for v in w)
        except (TypeError, ValueError):
            raise ValueError(f"{name}={w!r} must be a pair (lo, hi) with 0 < lo < hi < 1") from None
        if not 0 < lo < hi < 1:
            raise ValueError(f"{name}={tuple(w)!r} must satisfy 0 < lo < hi < 1")


#: what an onset record says happened (:func:`classify_onset`)
STATUSES = ("buckled", "forced", "unclassified", "unresolved", "no-onset", "failed")


def classify_onset(run: BucklingRun, onset: Onset | None, kappa_cri: float | None) -> str:
    """What the run shows: ``"buckled"`` (an onset after the end twist has passed the
    static critical twist ``kappa_cri``), ``"forced"`` (an onset before t = 0 or before
    ``|kappa3(0, t)|`` reaches kappa_cri: the seed bent the rod, not the instability),
    ``"no-onset"`` (the run ended, at t_end or self-contact, without one) or ``"failed"``
    (a Newton failure ended it without one); :func:`~dyntorsion.buckling.scene.run_scene`
    turns a ``"no-onset"`` whose grid could not resolve the growth into ``"unresolved"``
    (:mod:`~dyntorsion.buckling.resolution`).  With ``kappa_cri=None`` (no static theory
    for the scene) an onset at t_c >= 0 is ``"unclassified"``: without kappa_cri nothing
    tells an instability from a rod bent by its seed, so such a run never says buckled."""
    if onset is None:
        return "failed" if run.stopped.startswith("failed") else "no-onset"
    if onset.t_c < run.t[0]:
        return "forced"
    if kappa_cri is None:
        return "unclassified"
    upto = np.abs(run.kappa3_left[run.t <= onset.t_c])
    passed = max(float(upto.max(initial=0.0)), abs(float(run.end_twist(onset.t_c))))
    return "buckled" if passed >= kappa_cri else "forced"


def first_peak(U: np.ndarray, i_start: int) -> int:
    """The sample of the first peak of ``U = |u3(L, t)|`` after ``i_start``: the running
    maximum at the first later sample where U has fallen below :data:`PEAK_FALL` (0.7) of
    it (so the small torsional-wave ripples on the rise do not count as a peak), or the
    largest sample."""
    running = np.maximum.accumulate(U[i_start:])
    drop = np.nonzero(U[i_start:] < PEAK_FALL * running)[0]
    end = i_start + (int(drop[0]) if drop.size else U.size - i_start)
    return i_start + int(np.argmax(U[i_start:end]))


def _after_long_steps(run: BucklingRun, t_first: float, what: str) -> None:
    """The onset reads samples from t_first on: they must lie past the long steps of
    ``Scheme(long_steps=...)``, which record only their own, sparse, levels."""
    long = getattr(getattr(run, "run", None), "meta", {}).get("long_steps")
    if long and long["steps"] and long["until"] > t_first:
        raise ValueError(
            f"the long steps lasted until t = {long['until']:.6g} s, past t = {t_first:.6g} s "
            f"where {what}: lower LongSteps.limit so that the onset is read from samples at dt"
        )


def least_squares_line(t: np.ndarray, u: np.ndarray) -> tuple[float, float]:
    """(slope, intercept) of the least-squares line through (t, u), from correctly rounded
    sums (``math.fsum``) of the centred data: the same numbers on every machine (a BLAS
    or SIMD summation order that depends on the CPU moved the onset's last digits)."""
    n = len(t)
    t_mean, u_mean = math.fsum(t) / n, math.fsum(u) / n
    dt, du = np.asarray(t) - t_mean, np.asarray(u) - u_mean
    slope = math.fsum(dt * du) / math.fsum(dt * dt)
    return slope, u_mean - slope * t_mean


def _piece(t: np.ndarray, y: np.ndarray, k: int) -> tuple[float, tuple[float, ...]]:
    """The cubic through the samples k-1 .. k+2, the interpolant of the interval
    [t_k, t_k+1]: (t_k, (c0, c1, c2, c3)) with p = c0 + c1 x + c2 x^2 + c3 x^3 in
    x = t - t_k (Lagrange's form expanded; local, in Python floats, so the same on every
    machine)."""
    t0 = float(t[k])
    xs = [float(t[k - 1 + i]) - t0 for i in range(4)]
    c = [0.0, 0.0, 0.0, 0.0]
    for i in range(4):
        a, b, d = (xs[j] for j in range(4) if j != i)
        w = float(y[k - 1 + i]) / ((xs[i] - a) * (xs[i] - b) * (xs[i] - d))
        c[3] += w
        c[2] -= w * (a + b + d)
        c[1] += w * (a * b + a * d + b * d)
        c[0] -= w * a * b * d
    return t0, tuple(c)


def _value(c: tuple[float, ...], x: float) -> float:
    return ((c[3] * x + c[2]) * x + c[1]) * x + c[0]


def _crossing(c: tuple[float, ...], level: float, a: float, b: float) -> float:
    """The x in [a, b] where the cubic c reaches ``level`` from below (bisection to
    round-off; c(a) < level <= c(b))."""
    while True:
        m = 0.5 * (a + b)
        if m <= a or m >= b:
            return m
        if _value(c, m) >= level:
            b = m
        else:
            a = m


def _maximum(c: tuple[float, ...], h: float) -> float:
    """The largest value of the cubic c on [0, h]: at an end or where c' = 0."""
    xs = [0.0, h]
    qa, qb, qc = 3.0 * c[3], 2.0 * c[2], c[1]
    if qa == 0.0:
        if qb != 0.0:
            xs.append(-qc / qb)
    else:
        disc = qb * qb - 4.0 * qa * qc
        if disc >= 0.0:
            q = -0.5 * (qb + math.copysign(math.sqrt(disc), qb))
            xs += [q / qa] + ([qc / q] if q != 0.0 else [])
    return max(_value(c, x) for x in xs if 0.0 <= x <= h)


#: 4-point Gauss-Legendre nodes and weights on [0, 1], exact for the quartic t y(t) of a
#: cubic piece, from their closed forms (correctly rounded square roots: no LAPACK, the
#: same bits on every machine)
_GL_A, _GL_B = (math.sqrt(3 / 7 + s * 2 / 7 * math.sqrt(6 / 5)) for s in (-1.0, 1.0))
_GL_X = [0.5 * (1.0 - _GL_B), 0.5 * (1.0 - _GL_A), 0.5 * (1.0 + _GL_A), 0.5 * (1.0 + _GL_B)]
_GL_W = [
    w / 72 for w in (18 - math.sqrt(30), 18 + math.sqrt(30), 18 + math.sqrt(30), 18 - math.sqrt(30))
]


def continuous_window_fit(
    t: np.ndarray, y: np.ndarray, i_peak: int, lo: float, hi: float
) -> tuple[float, float]:
    """(t_c, slope) of the window rule read in continuous time: ``y`` (the signed
    ``u3(L, t)``, rising to its first peak at sample ``i_peak``) interpolated by piecewise
    cubics through each interval's four neighbouring samples; the peak is the largest
    value of the cubics of the two intervals beside the sample peak, the window's ends the
    times where the interpolant first reaches ``lo`` and ``hi`` of it (a record that ends
    at or just after its largest sample, at self-contact, keeps that sample as the peak, as
    the sample rule does), and the line the
    least squares fit to the interpolant over that interval, an integral (Gauss-Legendre,
    exact on each cubic piece, sums correctly rounded), extrapolated to y = 0.  The sample
    rule (:func:`detect_onset`) takes the samples whose values lie in the window, so its
    ends move by up to a step and t_c by a fraction of one: first order in dt, and a
    jump whenever a sample enters or leaves; this reading moves continuously with the
    samples and inherits the scheme's order.  Raises ``ValueError`` where the rise holds
    too few samples for the cubics (two before the window)."""
    n = t.size
    if np.any(np.diff(t) <= 0):
        raise ValueError("the sample times must increase")
    if not 2 <= i_peak <= n - 1:
        raise ValueError("the first peak lies too close to the record's start for cubics")
    pieces = [k for k in (i_peak - 1, i_peak) if k <= n - 3]  # none where the record ends at it
    peak = float(y[i_peak])
    for k in pieces:
        peak = max(peak, _maximum(_piece(t, y, k)[1], float(t[k + 1] - t[k])))
    ends = []
    for frac in (lo, hi):
        level = frac * peak
        j = int(np.argmax(y[: i_peak + 1] >= level))
        if j < 2 or j > n - 2:
            raise ValueError(
                f"the window's end at {frac:g} of the peak is too close to the record's start"
            )
        t0, c = _piece(t, y, j - 1)
        ends.append(t0 + _crossing(c, level, 0.0, float(t[j] - t[j - 1])))
    t0, t1 = ends
    if not t1 > t0:
        raise ValueError("the continuous window is empty")
    knots = [t0, *t[(t > t0) & (t < t1)].tolist(), t1]
    W, T, Y = [], [], []
    for a, b in zip(knots[:-1], knots[1:], strict=True):
        k = min(max(int(np.searchsorted(t, a, side="right")) - 1, 1), n - 3)
        tk, c = _piece(t, y, k)
        for x, w in zip(_GL_X, _GL_W, strict=True):
            tx = a + (b - a) * x
            W.append((b - a) * w)
            T.append(tx)
            Y.append(_value(c, tx - tk))
    w = math.fsum(W)
    t_mean, y_mean = (
        math.fsum(w_ * t_ for w_, t_ in zip(W, T, strict=True)) / w,
        math.fsum(w_ * y_ for w_, y_ in zip(W, Y, strict=True)) / w,
    )
    sxy = math.fsum(w_ * (t_ - t_mean) * (y_ - y_mean) for w_, t_, y_ in zip(W, T, Y, strict=True))
    sxx = math.fsum(w_ * (t_ - t_mean) ** 2 for w_, t_ in zip(W, T, strict=True))
    slope = sxy / sxx
    return t_mean - y_mean / slope, slope


def detect_onset(
    run: BucklingRun,
    window: tuple[float, float] = WINDOW,
    variations: Sequence[tuple[float, float]] = ((0.05, 0.3), (0.2, 0.7)),
    u_ref: float | None = None,
) -> Onset:
    """Fit a straight line to the initial dramatic variation of u3(L, t), extrapolate
    to u3 = 0: t_c and the end twist kappa3 = kappa3(0, t_c) of the run's history
    (kappa0 + a t_c for the paper's ramp).

    Window rule (deterministic): ``U = |u3(L, t)|``.  The rise starts when U first
    exceeds ``u_ref`` (default L / T0, T0 = L^2 sqrt(rho A / min(B1, B2)) the bending time
    scale: 0.023 m/s for Table 1, far above the prebuckling level and far below
    the first peak); its peak U_peak is the running maximum of U at the first
    later sample where U has fallen below :data:`PEAK_FALL` (0.7) of that running
    maximum (so the small torsional-wave ripples on the rise do not count as a peak).  The fit
    uses the samples from the first time U exceeds ``window[0] * U_peak`` to the
    first time it exceeds ``window[1] * U_peak``.  The same fit with each of
    ``variations`` gives the method's uncertainty: the largest ``|t_c - t_c(variation)|``.

    ``t_ref`` is the time at which U first reaches ``u_ref`` (linear interpolation
    between samples): the level a linear theory can be compared with (see
    :mod:`dyntorsion.beyond.linear_stability`), where ``t_c`` is an extrapolation from the
    nonlinear rise.
    """
    check_window(window, variations)
    t, u = np.asarray(run.t), np.asarray(run.u3_end)
    U = np.abs(u)
    if not np.any(U > 0):
        raise ValueError("u3(L, t) is identically zero: the rod never left the straight state")
    if u_ref is None:
        u_ref = reference_level(run.rod)
    above = np.nonzero(U >= u_ref)[0]
    if above.size == 0:
        if run.stopped.startswith("failed"):
            advice = (
                f"the run ended on a Newton failure at t = {run.t[-1]:.6g} s before buckling "
                "(refine dt or change the Newton options; a longer t_end does not help)"
            )
        elif run.stopped != "t_end":
            advice = f"the run stopped before buckling ({run.stopped})"
        else:
            advice = "the run ends before buckling; increase t_end"
        raise ValueError(f"|u3(L, t)| never reaches u_ref = {u_ref:.3g} m/s: {advice}")
    i_start = int(above[0])
    _after_long_steps(run, t[max(i_start - 1, 0)], "|u3(L, t)| reaches u_ref")
    if i_start == 0:
        t_ref = float(t[0])
    else:
        u0, u1 = U[i_start - 1], U[i_start]
        t_ref = float(t[i_start - 1] + (u_ref - u0) / (u1 - u0) * (t[i_start] - t[i_start - 1]))
    i_peak = first_peak(U, i_start)
    U_peak, sign = U[i_peak], np.sign(u[i_peak])

    def fit(lo: float, hi: float):
        if not 0 < lo < hi < 1:
            raise ValueError(f"window=({lo}, {hi}) must satisfy 0 < lo < hi < 1")
        head = U[: i_peak + 1]
        i0 = int(np.argmax(head >= lo * U_peak))
        i1 = int(np.argmax(head >= hi * U_peak))
        if i1 - i0 < 2:
            raise ValueError(
                f"window=({lo}, {hi}) holds fewer than 3 samples: refine dt or widen the window"
            )
        _after_long_steps(run, t[i0], f"the fit window ({lo}, {hi}) starts")
        slope, intercept = least_squares_line(t[i0 : i1 + 1], sign * U[i0 : i1 + 1])
        return -intercept / slope, slope * sign, intercept * sign

    t_c, slope, intercept = fit(*window)
    var = {tuple(v): fit(*v)[0] for v in variations}
    unc = max((abs(v - t_c) for v in var.values()), default=0.0)
    a = run.history.rate if run.history is not None else None

    def twist(time: float) -> float:
        return float(run.end_twist(time))

    kappa3 = twist(t_c)
    try:
        t_cont = continuous_window_fit(t, sign * u, i_peak, *window)[0]
    except (ValueError, FloatingPointError, ZeroDivisionError):
        t_cont = math.nan
    if a is not None:
        unc_k = abs(a) * unc
    else:
        unc_k = max((abs(run.end_twist(v) - kappa3) for v in var.values()), default=0.0)
    return Onset(
        t_c=float(t_c),
        kappa3=float(kappa3),
        uncertainty_t=float(unc),
        uncertainty_kappa3=float(unc_k),
        slope=float(slope),
        intercept=float(intercept),
        window=tuple(window),
        variations={k: float(v) for k, v in var.items()},
        t_ref=t_ref,
        u_ref=float(u_ref),
        t_c_continuous=float(t_cont),
        kappa3_continuous=twist(t_cont) if math.isfinite(t_cont) else math.nan,
    )
