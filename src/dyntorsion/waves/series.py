"""The exact series of section 5: eqs (25), (27) and (29), with their truncation bounds,
in NumPy and in mpmath (``precise=True``)."""

from __future__ import annotations

import functools
import math

import mpmath
import numpy as np

from ..genalpha.guard import BudgetError
from . import reference
from .checks import (
    DEFAULT_TOL_DUHAMEL,
    DEFAULT_TOL_PRECISE,
    MAX_DUHAMEL_WORK,
    MAX_TERMS,
    MAX_TERMS_DUHAMEL,
    MP_TERM_S,
    Series,
    check_mp_budget,
    checked_grid,
    checked_scale,
    chunked_sum,
    finite_number,
    mp_array,
    sqrt_lambda,
    term_count,
)
from .transitions import DEFAULT_TRANSITION, Transition


def linear_loading_bound(terms: int, s=None, t=None, *, a: float, c: float, L: float):
    """Bound on the truncation error of eq (25) after ``terms`` terms.

    Uniform: sum_{n>N} 2|a|/(L c lambda_n) <= 4 |a| L / (c pi^2 (2N - 1)).
    Pointwise (given s, t): sin(c k t) sin(k s) = [cos((2n-1) th-) - cos((2n-1) th+)] / 2,
    th+- = pi (ct +- s) / (2L); partial sums of cos((2n-1) th) are bounded by
    1/|sin th| (Abel summation), so |tail| <= 8 |a| L / (c pi^2 (2N+1)^2) (1/|sin th+| + 1/|sin th-|).
    The smaller of the two is returned.
    """
    uniform = 4 * abs(a) * L / (c * math.pi**2 * (2 * terms - 1))
    if s is None or t is None:
        return uniform
    s, t = np.broadcast_arrays(np.asarray(s, float), np.asarray(t, float))
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        inv = sum(1.0 / np.abs(np.sin(np.pi * (c * t + sign * s) / (2 * L))) for sign in (1, -1))
        point = 8 * abs(a) * L / (c * math.pi**2 * (2 * terms + 1) ** 2) * inv
    return np.minimum(uniform, np.where(np.isfinite(inv), point, np.inf))


def linear_loading_exact(
    s,
    t,
    *,
    a: float,
    kappa0: float = 0.0,
    c: float,
    L: float,
    series: Series = Series(),
) -> np.ndarray:
    """Eq (25): kappa(s, t) for kappa(0, t) = kappa0 + a t, kappa_s(L, t) = 0 (eq 23).

        kappa = kappa0 + a t - sum_n 2a / (L c lambda_n) sin(c sqrt(lambda_n) t) sin(sqrt(lambda_n) s)

    ``series`` (:class:`Series`) says how it is summed: ``series.terms`` fixes the
    number of terms; otherwise enough are taken for the bound
    :func:`linear_loading_bound` (pointwise where it is smaller) to be below
    ``series.tol``.  ``series.precise`` sums in mpmath at ``series.digits`` digits and
    returns an object array of mpf: without ``series.terms`` the whole series, in closed
    form by Legendre's chi function (:mod:`.reference`; the tolerance is then met to
    working precision); it refuses (:class:`BudgetError`) work estimated above
    ``series.budget`` seconds.
    """
    c, L = checked_scale("c", c), checked_scale("L", L)
    a, kappa0 = finite_number("a", a), finite_number("kappa0", kappa0)
    s, t = checked_grid(s, t, L)

    def needed(tol):
        uniform = math.ceil((4 * abs(a) * L / (c * math.pi**2 * tol) + 1) / 2)
        with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
            inv = (
                max(
                    float(np.max(1.0 / np.abs(np.sin(np.pi * (c * t + sign * s) / (2 * L)))))
                    for sign in (1, -1)
                )
                * 2
            )
        root = math.sqrt(8 * abs(a) * L * inv / (c * math.pi**2 * tol)) if inv < math.inf else inv
        return min(uniform, math.ceil((root - 1) / 2) if math.isfinite(root) else uniform)

    if series.precise and series.terms is None:  # the whole series, summed in closed form
        check_mp_budget(4 * s.size, reference.POLYLOG_S, series, "pass fewer points")
        return mp_array(
            lambda si, ti: reference.linear_loading_sum(
                si, ti, a=mpmath.mpf(a), kappa0=mpmath.mpf(kappa0), c=mpmath.mpf(c), L=mpmath.mpf(L)
            ),
            s,
            t,
            series.digits,
        )
    n_terms = term_count(series, needed)
    if series.precise:
        check_mp_budget(n_terms * s.size, MP_TERM_S, series, "pass fewer points or terms")

        def point(si, ti):
            mL, mc, ma = mpmath.mpf(L), mpmath.mpf(c), mpmath.mpf(a)
            total = mpmath.mpf(kappa0) + ma * ti
            for n in range(1, n_terms + 1):
                k = (2 * n - 1) * mpmath.pi / (2 * mL)
                total -= 2 * ma / (mL * mc * k**2) * mpmath.sin(mc * k * ti) * mpmath.sin(k * si)
            return total

        return mp_array(point, s, t, series.digits)

    def term(n):
        k = sqrt_lambda(n, L)
        return 2 * a / (L * c * k**2) * np.sin(c * k * t) * np.sin(k * s)

    return kappa0 + a * t - chunked_sum(n_terms, term, s.shape)


# ======================================================== eq (27): instantaneous release
def instant_release_bound(terms: int, s, t, *, kappa0: float, c: float, L: float) -> np.ndarray:
    """Pointwise bound on the truncation error of eq (27) after ``terms`` terms.

    The series converges only conditionally (the solution has jumps).  Writing
    cos(c k t) cos(k s) = [cos((2n-1) th+) + cos((2n-1) th-)] / 2, th+- = pi (ct +- s) / (2L),
    and bounding the partial sums of (-1)^(n-1) cos((2n-1) th) by 1/|cos th|
    (Abel summation) gives |tail| <= 4 |kappa0| / (pi (2N+1)) (1/|cos th+| + 1/|cos th-|),
    infinite on the fronts s = +-ct (mod 2L).
    """
    s, t = np.broadcast_arrays(np.asarray(s, float), np.asarray(t, float))
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        inv = sum(1.0 / np.abs(np.cos(np.pi * (c * t + sign * s) / (2 * L))) for sign in (1, -1))
        bound = 4 * abs(kappa0) / (math.pi * (2 * terms + 1)) * inv
    return np.where(np.isfinite(inv), bound, np.inf)


def instant_release_exact(
    s,
    t,
    *,
    kappa0: float,
    c: float,
    L: float,
    series: Series = Series(),
) -> np.ndarray:
    """Eq (27): kappa(s, t) after the twist kappa0 is released at t = 0 (eq 26).

        kappa = sum_n 2 kappa0 / (L sqrt(lambda_n)) (-1)^(n-1) cos(c sqrt(lambda_n) t) cos(sqrt(lambda_n) s)

    ``series`` (:class:`Series`) says how it is summed.  Without ``series.terms`` the
    term count comes from the pointwise bound :func:`instant_release_bound` at the worst
    of the given points and ``series.tol`` (points on a front cannot be served; pass
    ``series.terms`` or use :func:`instant_release_dalembert`).  ``series.precise``
    without ``series.terms``: the whole series in mpmath, in closed form by Legendre's
    chi function (:mod:`.reference`); on a front the mean of both sides.
    """
    c, L = checked_scale("c", c), checked_scale("L", L)
    kappa0 = finite_number("kappa0", kappa0)
    s, t = checked_grid(s, t, L)

    def needed(tol):
        # bound(N) = C / (2N + 1): C = 3 bound(1)
        C = 3 * float(np.max(instant_release_bound(1, s, t, kappa0=kappa0, c=c, L=L)))
        if not math.isfinite(C):
            return MAX_TERMS + 1
        return math.ceil((C / tol - 1) / 2)

    if series.precise and series.terms is None:  # the whole series, summed in closed form
        check_mp_budget(s.size, reference.POLYLOG_S, series, "pass fewer points")
        return mp_array(
            lambda si, ti: reference.instant_release_sum(
                si, ti, kappa0=mpmath.mpf(kappa0), c=mpmath.mpf(c), L=mpmath.mpf(L)
            ),
            s,
            t,
            series.digits,
        )
    n_terms = term_count(series, needed)
    if series.precise:
        check_mp_budget(n_terms * s.size, MP_TERM_S, series, "pass fewer points or terms")

        def point(si, ti):
            mL, mc = mpmath.mpf(L), mpmath.mpf(c)
            total = mpmath.mpf(0)
            for n in range(1, n_terms + 1):
                k = (2 * n - 1) * mpmath.pi / (2 * mL)
                total += (
                    2
                    * kappa0
                    / (mL * k)
                    * (-1) ** (n - 1)
                    * mpmath.cos(mc * k * ti)
                    * mpmath.cos(k * si)
                )
            return total

        return mp_array(point, s, t, series.digits)

    def term(n):
        k = sqrt_lambda(n, L)
        sign = 1.0 - 2.0 * ((n - 1) % 2)
        return 2 * kappa0 / (L * k) * sign * np.cos(c * k * t) * np.cos(k * s)

    return chunked_sum(n_terms, term, s.shape)


# ============================================================ eq (29): smooth release
def _duhamel_np(t: float, n_terms: int, f: Transition, rate: float, c: float, L: float):
    """I_n(t) = int_0^t f''(rate tau) sin(c sqrt(lambda_n) (t - tau)) dtau, n = 1..N,
    by composite Gauss-Legendre (20 points per panel, a panel per half period of
    the fastest mode and per 0.05 of x = rate tau)."""
    omega = c * sqrt_lambda(np.arange(1, n_terms + 1), L)
    if t == 0.0:
        return np.zeros(n_terms)
    panels = int(max(4, math.ceil(omega[-1] * t / math.pi), math.ceil(rate * t / 0.05)))
    if 20.0 * panels > MAX_DUHAMEL_WORK / 100 or 20.0 * panels * n_terms > MAX_DUHAMEL_WORK:
        raise BudgetError(
            f"t={t:.4g} s: the Duhamel integrals need {panels:.3g} panels x {n_terms} terms "
            f"(> {MAX_DUHAMEL_WORK:.3g} evaluations); pass earlier times, fewer series.terms or a "
            "looser series.tol (or use smooth_release_dalembert)"
        )
    xg, wg = np.polynomial.legendre.leggauss(20)
    edges = np.linspace(0.0, t, panels + 1)
    h = np.diff(edges)[:, None]
    tau = (edges[:-1, None] + 0.5 * h * (xg[None, :] + 1)).ravel()
    w = (0.5 * h * wg[None, :]).ravel()
    g = f(rate * tau, 2) * w
    out = np.empty(n_terms)
    chunk = max(1, 4_000_000 // tau.size)
    for i in range(0, n_terms, chunk):
        out[i : i + chunk] = np.sin(np.outer(omega[i : i + chunk], t - tau)) @ g
    return out


def smooth_release_bound(
    terms: int,
    t,
    *,
    kappa0: float,
    c: float,
    L: float,
    rate: float = 50.0,
    f: Transition = DEFAULT_TRANSITION,
) -> np.ndarray:
    """Bound on the truncation error of eq (29) after ``terms`` terms, uniform in s.

    Integrating I_n by parts once,
    |I_n(t)| <= (|f''(rate t)| + |f''(0)| + int_0^{rate t} |f'''(x)| dx) / omega_n = B(t) / omega_n,
    so the terms fall like n^-3 and
    |tail| <= 2 rate^2 |kappa0| B(t) / (L c^2) (2L/pi)^3 / (4 (2N - 1)^2).
    """
    t = np.atleast_1d(np.asarray(t, dtype=float))
    xg, wg = np.polynomial.legendre.leggauss(40)
    out = []
    for tt in t.ravel():
        x_end = rate * tt
        edges = np.linspace(0.0, x_end, 201)
        h = np.diff(edges)[:, None]
        xq = (edges[:-1, None] + 0.5 * h * (xg + 1)).ravel()
        wq = (0.5 * h * wg).ravel()
        B = (
            (
                abs(float(f(x_end, 2)))
                + abs(float(f(np.nextafter(0.0, 1.0), 2)))
                + float(np.sum(np.abs(f(xq, 3)) * wq))
            )
            if x_end > 0
            else 0.0
        )
        out.append(
            2
            * rate**2
            * abs(kappa0)
            * B
            / (L * c**2)
            * (2 * L / math.pi) ** 3
            / (4 * (2 * terms - 1) ** 2)
        )
    return np.array(out).reshape(t.shape)


def smooth_release_exact(
    s,
    t,
    *,
    kappa0: float,
    c: float,
    L: float,
    rate: float = 50.0,
    f: Transition = DEFAULT_TRANSITION,
    series: Series = Series(),
) -> np.ndarray:
    """Eq (29): kappa(s, t) for kappa(L, t) = kappa0 f(rate t), kappa_s(0, t) = 0 (eq 28).

        kappa = kappa0 f(rate t) + int_0^t eta dtau,
        eta = sum_n (-1)^n 2 rate^2 kappa0 / (L c lambda_n) f''(rate tau) sin(c sqrt(lambda_n)(t - tau)) cos(sqrt(lambda_n) s)

    (for rate = 50 the factor 2 rate^2 is the paper's 5000).  The Duhamel
    integrals are evaluated by composite Gauss-Legendre quadrature, not by a Riemann
    sum.  ``series`` (:class:`Series`) says how it is summed.  NumPy: without
    ``series.terms`` the term count comes from :func:`smooth_release_bound` (needs f''')
    and ``series.tol`` (default DEFAULT_TOL_DUHAMEL: each term costs a quadrature).
    ``series.precise`` without ``series.terms``: the whole series in mpmath to
    ``series.tol`` (default DEFAULT_TOL_PRECISE), the first N integrals by one shared
    rule and the rest by an expansion by parts with a bounded remainder
    (:mod:`.reference`); with ``series.terms`` the first that many terms.  It refuses
    (:class:`BudgetError`) work estimated above ``series.budget`` seconds, saying what
    would make it possible.
    """
    c, L = checked_scale("c", c), checked_scale("L", L)
    rate = checked_scale("rate", rate)
    kappa0 = finite_number("kappa0", kappa0)
    if not isinstance(f, Transition):
        raise ValueError(f"f={f!r} must be a Transition (ExpQuartic, FlatBlend, CustomTransition)")
    s, t = checked_grid(s, t, L)

    def needed(tol):
        if f.max_order < 3:
            raise ValueError(f"{f.name}: a tolerance needs f'''; pass series.terms")
        worst = float(
            np.max(smooth_release_bound(1, np.unique(t), kappa0=kappa0, c=c, L=L, rate=rate, f=f))
        )
        return math.ceil((math.sqrt(worst / tol) + 1) / 2)

    if series.precise:
        return _smooth_release_precise(s, t, reference.Release(c, L, rate, kappa0, f), series)
    n_terms = term_count(series, needed, DEFAULT_TOL_DUHAMEL, MAX_TERMS_DUHAMEL)
    coef_n = np.arange(1, n_terms + 1)
    k = sqrt_lambda(coef_n, L)
    sign = np.where(coef_n % 2 == 0, 1.0, -1.0)
    amp = sign * 2 * rate**2 * kappa0 / (L * c * k**2)
    s1, t1 = s.ravel(), t.ravel()
    out = np.array(kappa0 * f(rate * t1, 0), dtype=float)
    for ti in np.unique(t1):
        mask = t1 == ti
        In = _duhamel_np(float(ti), n_terms, f, rate, c, L)
        out[mask] += np.cos(np.outer(s1[mask], k)) @ (amp * In)
    return out.reshape(s.shape)


def _smooth_release_precise(s, t, release: reference.Release, series: Series) -> np.ndarray:
    """Eq (29) in mpmath: the first N terms exactly, the rest by the expansion by parts
    (:mod:`.reference`), to ``series.tol`` (default DEFAULT_TOL_PRECISE, or
    10^-(digits - 5) if that is larger: no more than the precision can hold);
    ``series.terms`` truncates."""
    digits, budget, tol = series.digits, series.budget, series.tol
    if tol is None:
        tol = max(DEFAULT_TOL_PRECISE, 10.0 ** -(digits - 5))
    times = np.unique(t)
    with mpmath.workdps(digits + 10):
        plan = reference.smooth_release_plan(
            times, s.size, release, tol=tol, digits=digits, terms=series.terms
        )
        if budget is not None and plan.seconds > budget:
            replan = functools.partial(
                reference.smooth_release_plan, times, s.size, release, digits=digits
            )
            raise BudgetError(reference.refusal(plan, replan, release, tol, budget, series.terms))
        out = reference.smooth_release_sums(s, t, release, plan=plan)
    with mpmath.workdps(digits):
        return np.vectorize(lambda v: +v, otypes=[object])(out)
