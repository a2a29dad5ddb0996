"""The mpmath references of eqs (25), (27) and (29) at any parameters: whole series, not truncations.

Every series of section 5 is a sum over the odd j = 2n - 1 of e^(i j psi) / j^q times a
smooth factor.  Its whole sum is Legendre's chi function

    chi_q(w) = sum_{j odd} w^j / j^q = (Li_q(w) - Li_q(-w)) / 2,   |w| = 1,

which mpmath's polylog evaluates at any precision; the tail after N terms is chi_q minus
the first N terms.  (The d'Alembert image sums of :mod:`.dalembert` are the independent
check.)

* Eq (25): sin(c k t) sin(k s) = [cos(j th-) - cos(j th+)] / 2, th+- = pi (ct +- s) / (2L), so
  kappa = kappa0 + a t - 4 a L / (c pi^2) Re[chi_2(e^(i th-)) - chi_2(e^(i th+))].
* Eq (27): (-1)^(n-1) cos(j th) = sin(j (th + pi/2)), so
  kappa = 2 kappa0 / pi Im[chi_1(e^(i (th+ + pi/2))) + chi_1(e^(i (th- + pi/2)))].
* Eq (29): kappa = kappa0 f(rate t) + sum_n (-1)^n alpha / j^2 I_n cos(j sigma),
  alpha = 8 rate^2 kappa0 L / (c pi^2), sigma = pi s / (2L), omega_n = j Omega, Omega = pi c / (2L),
  I_n = Im[e^(i omega_n t) G(omega_n)], G(omega) = int_0^T g(tau) e^(-i omega tau) dtau,
  g(tau) = f''(rate tau), T = min(t, X / rate) with X past which int |f''| < 10^-(digits+5).
  The first N of the G(omega_n) come from one Gauss-Legendre rule shared by all n (the
  frequencies are equally spaced, so e^(-i omega_n tau) is a recurrence in n, in fixed point);
  the rest from M terms of the expansion by parts
      G(omega) = sum_{m<M} [g^(m)(0+) - g^(m)(T) e^(-i omega T)] / (i omega)^(m+1) + R_M,
      |R_M| <= int_0^T |g^(M)| / omega^M,
  whose sums over n > N are chi-function tails.  N and M are chosen for the bound
  |alpha| int_0^T |g^(M)| / Omega^M sum_{n>N} j^-(M+2) <= tol / 2 at the least estimated cost.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import mpmath
import numpy as np
from mpmath.calculus.quadrature import GaussLegendre
from mpmath.libmp import to_fixed

from ..genalpha.guard import BudgetError
from .transitions import Transition

#: the highest order M of the expansion by parts of eq (29)'s Duhamel integrals
MAX_ORDER = 40
#: Gauss-Legendre nodes per panel (degree 4 of mpmath's rule: 3 * 2^3)
NODES_PER_PANEL = 24
#: cost (s, measured on a 2-core 2026 machine at 35 digits): one node of the shared rule per
#: term, one polylog, one term of a partial sum at one point
QUAD_UNIT_S, POLYLOG_S, TERM_UNIT_S = 4e-6, 0.04, 2e-5


def chi(q: int, psi):
    """chi_q(e^(i psi)) = sum_{j odd} e^(i j psi) / j^q (q >= 2; q = 1 see :func:`chi1_imag`)."""
    w = mpmath.expj(psi)
    return (mpmath.polylog(q, w) - mpmath.polylog(q, -w)) / 2


def chi1_imag(psi):
    """Im chi_1(e^(i psi)) = sum_{j odd} sin(j psi) / j = (arg(1 + w) - arg(1 - w)) / 2:
    +-pi/4, and 0 (the mean) where w = +-1."""
    w = mpmath.expj(psi)
    return (mpmath.arg(1 + w) - mpmath.arg(1 - w)) / 2


def odd_tails(qs, psi, skip: int) -> dict:
    """{q: sum_{n > skip} e^(i j psi) / j^q} for the orders qs >= 2, j = 2n - 1: chi_q minus
    the first terms, at a precision raised by the q log10(2 skip + 1) digits they cancel
    (the tail is ~(2 skip + 1)^-q of chi_q ~ 1)."""
    extra = int(max(qs) * math.log10(2 * skip + 1)) + 5 if skip else 0
    with mpmath.extradps(extra):
        psi = +psi
        out = {q: chi(q, psi) for q in qs}
        if skip:
            e = mpmath.expj(psi)
            e2, z = e * e, e
            for n in range(1, skip + 1):
                j = mpmath.mpf(2 * n - 1)
                for q in qs:
                    out[q] -= z / j**q
                z *= e2
    return {q: +v for q, v in out.items()}


def linear_loading_sum(s, t, *, a, kappa0, c, L):
    """Eq (25) summed whole at one point (mpmath numbers)."""
    th_m, th_p = (mpmath.pi * (c * t + sign * s) / (2 * L) for sign in (-1, 1))
    return kappa0 + a * t - 4 * a * L / (c * mpmath.pi**2) * mpmath.re(chi(2, th_m) - chi(2, th_p))


def instant_release_sum(s, t, *, kappa0, c, L):
    """Eq (27) summed whole at one point: the mean of both sides on a front."""
    half = mpmath.pi / 2
    ths = (mpmath.pi * (c * t + sign * s) / (2 * L) for sign in (-1, 1))
    return 2 * kappa0 / mpmath.pi * sum(chi1_imag(th + half) for th in ths)


# ============================================================ eq (29)
class Release(NamedTuple):
    """The smooth release of eq (29): wave speed ``c`` [m/s], length ``L`` [m], release
    rate ``rate`` [1/s], initial twist ``kappa0`` [1/m] and the :class:`Transition` ``f``."""

    c: float
    L: float
    rate: float
    kappa0: float
    f: Transition


class SmoothPlan(NamedTuple):
    """How eq (29) is summed: N exact terms, M orders of the tail, the rule, the cost."""

    terms: int  # N
    order: int  # M (0: no tail, a truncation after N terms)
    x_end: float  # X: the Duhamel integrals stop at tau = min(t, X / rate)
    panels: int  # Gauss-Legendre panels of the largest rule
    bound: float  # bound on the error of the tail expansion (0 without a tail)
    seconds: float  # estimated cost


def _log_abs_integrals(f: Transition, x_end: float, rate: float, orders: int) -> np.ndarray:
    """log of int_0^T |g^(M)| = rate^(M-1) int_0^(rate T) |f^(M+2)|, M = 0..orders (estimates)."""
    with np.errstate(divide="ignore"):
        base = np.log(f.abs_derivative_integrals(x_end, orders + 2)[2:])
    return base + (np.arange(orders + 1) - 1) * math.log(rate)


def _tail_terms(tol: float, log_C: float, M: int) -> int:
    """Least N with C [(2N+1)^-(M+2) + (2N+1)^-(M+1) / (2 (M+1))] <= tol (C = e^log_C)."""

    def log_bound(N):
        x = 2 * N + 1
        return log_C + math.log(x ** -(M + 2) + x ** -(M + 1) / (2 * (M + 1)))

    lo, hi = 0, 1
    while log_bound(hi) > math.log(tol):
        lo, hi = hi, hi * 2
        if hi > 10**12:
            return hi
    while hi - lo > 1:
        mid = (lo + hi) // 2
        lo, hi = (lo, mid) if log_bound(mid) <= math.log(tol) else (mid, hi)
    return max(hi, 1)


def _panels(N: int, Omega: float, T: float, rate: float) -> int:
    """Panels of the shared rule: one per period of the fastest mode and per 0.1 of x = rate tau."""
    return int(
        max(4, math.ceil((2 * N - 1) * Omega * T / (2 * math.pi)), math.ceil(rate * T / 0.1))
    )


def smooth_release_plan(
    times, n_points: int, release: Release, *, tol, digits, terms=None
) -> SmoothPlan:
    """Choose N and M for eq (29) of the :class:`Release` ``release`` at the given
    distinct times, ``n_points`` points each (see the module docstring)."""
    c, L, rate, kappa0, f = release
    Omega = math.pi * c / (2 * L)
    X = f.negligible_beyond(digits + 5)
    Ts = tuple(min(float(t), X / rate) for t in times)
    distinct = sorted(set(Ts))
    scale = max(1.0, digits / 35)
    top = min(MAX_ORDER, f.taylor_order - 2)
    with mpmath.workdps(20):  # which orders of the expansion are not zero at tau = 0+
        nonzero0 = np.cumsum([v != 0 for v in f.mp_taylor(0, top + 2)[2:]]) if top >= 1 else []
    during = any(0 < T == float(t) for T, t in zip(Ts, times, strict=True))

    def cost(N, M):
        quad = sum(N * NODES_PER_PANEL * _panels(N, Omega, T, rate) for T in distinct)
        polylogs = n_points * 4 * (nonzero0[M - 1] + (M if during else 0)) if M else 0
        terms_s = n_points * N * (M + 2) * TERM_UNIT_S
        return (quad * QUAD_UNIT_S + polylogs * POLYLOG_S + terms_s) * scale

    if terms is not None:
        N = int(terms)
        return SmoothPlan(N, 0, X, _panels(N, Omega, max(Ts), rate), 0.0, cost(N, 0))
    alpha = 8 * rate**2 * abs(kappa0) * L / (c * math.pi**2)
    if alpha == 0:
        return SmoothPlan(1, 0, X, _panels(1, Omega, max(Ts), rate), 0.0, cost(1, 0))
    if top < 1:
        raise ValueError(f"{f.name}: a tolerance needs f'''; pass series.terms")
    log_J = _log_abs_integrals(f, rate * max(Ts), rate, top)
    best = None
    for M in range(1, top + 1):
        if not np.isfinite(log_J[M]):
            log_C = -math.inf
            N = 1
        else:
            log_C = math.log(alpha) + log_J[M] - M * math.log(Omega)
            N = _tail_terms(tol / 2, log_C, M)
        if N > 10**9:
            continue
        x = 2 * N + 1
        bound = math.exp(log_C) * (x ** -(M + 2) + x ** -(M + 1) / (2 * (M + 1)))
        plan = SmoothPlan(N, M, X, _panels(N, Omega, max(Ts), rate), bound, cost(N, M))
        if best is None or plan.seconds < best.seconds:
            best = plan
    if best is None:
        raise BudgetError(
            f"eq (29): no expansion order <= {top} meets tol={tol:g} with fewer than 1e9 terms; "
            "loosen tol, give the transition derivatives of higher order (taylor_order), or use "
            "smooth_release_dalembert"
        )
    return best


def refusal(plan: SmoothPlan, replan, release: Release, tol, budget, terms) -> str:
    """The budget error of eq (29): the plan's cost, and what would make it possible
    (``replan(tol=...)`` the plan at another tolerance; ``tol``, ``budget`` and ``terms``
    the fields of the caller's :class:`~dyntorsion.waves.checks.Series`)."""
    c, L, rate, _, f = release
    Omega = math.pi * c / (2 * L)
    fits = None
    if terms is None:
        fits = next((x for x in (tol * 10.0**k for k in range(1, 13))
                     if replan(tol=x).seconds <= budget), None)  # fmt: skip
    why = (
        f"the exact terms must reach frequencies well above the release's (rate / Omega = "
        f"{rate / Omega:.3g}, Omega = pi c / (2L) = {Omega:.3g} 1/s)"
    )
    if not math.isfinite(plan.x_end):
        why += (
            f"; {f.name} has no known support, so the Duhamel integrals run to t: "
            "negligible_beyond(digits) on the transition would end them where f'' vanishes"
        )
    if plan.order and plan.order >= f.taylor_order - 2:
        why += (
            f", and {f.name} gives derivatives only to order {f.taylor_order}: a transition "
            "with derivatives of higher order (taylor_order, mp_taylor, "
            "abs_derivative_integrals) would allow a higher-order tail and far fewer terms"
        )
    return (
        f"series.precise=True: eq (29) needs {plan.terms} exact terms on a rule of "
        f"{plan.panels * NODES_PER_PANEL} nodes and {plan.order} orders of the tail, an "
        f"estimated {plan.seconds:.3g} s (> series.budget={budget:g} s): {why}. "
        + (f"series.tol={fits:g} fits the budget; " if fits else "")
        + "pass fewer distinct times or points, raise series.budget (None: no limit), use "
        "series.precise=False, or use smooth_release_dalembert(digits=...)"
    )


def _shared_fourier(f: Transition, rate, Omega, T, N: int, panels: int) -> list:
    """G(omega_n) = int_0^T f''(rate tau) e^(-i omega_n tau) dtau, n = 1..N, omega_n = (2n-1) Omega:
    one composite Gauss-Legendre rule; e^(-i omega_n tau) by the recurrence
    e^(-i omega_(n+1) tau) = e^(-i omega_n tau) e^(-2 i Omega tau), in fixed point."""
    if T == 0:
        return [mpmath.mpc(0)] * N
    bits = mpmath.mp.prec + 2 * max(8, int(math.log2(N + 1)) + 4)
    nodes = GaussLegendre(mpmath.mp).calc_nodes(4, mpmath.mp.prec)
    h = T / panels
    cols: list[list[int]] = [[], [], [], [], []]  # w g, Re v, Im v, Re z, Im z
    for p in range(panels):
        mid = (p + mpmath.mpf(0.5)) * h
        for x, wt in nodes:
            tau = mid + h / 2 * x
            v = mpmath.expj(-Omega * tau)
            z = v * v
            vals = (h / 2 * wt * f.mp(rate * tau, 2), v.real, v.imag, z.real, z.imag)
            for col, val in zip(cols, vals, strict=True):
                col.append(to_fixed(val._mpf_, bits))
    wg, vr, vi, zr, zi = (np.array(col, dtype=object) for col in cols)
    zs, zd = zr + zi, zi - zr
    out = []
    for _ in range(N):
        re, im = int((wg * vr).sum()), int((wg * vi).sum())
        out.append(mpmath.mpc(mpmath.ldexp(re, -2 * bits), mpmath.ldexp(im, -2 * bits)))
        k1 = zr * (vr + vi)  # (vr + i vi)(zr + i zi) with three products
        vr, vi = (k1 - vi * zs) >> bits, (k1 + vr * zd) >> bits
    return out


def smooth_release_sums(s, t, release: Release, *, plan: SmoothPlan) -> np.ndarray:
    """Eq (29) of the :class:`Release` ``release`` at the points (s, t) (float arrays) by
    ``plan``: object array of mpf."""
    c, L, rate, kappa0, f = release
    mc, mL, mr, mk = (mpmath.mpf(v) for v in (c, L, rate, kappa0))
    Omega = mpmath.pi * mc / (2 * mL)
    alpha = 8 * mr**2 * mk * mL / (mc * mpmath.pi**2)
    N, M = plan.terms, plan.order
    out = np.empty(s.shape, dtype=object)
    fourier: dict = {}
    per_time: dict = {}
    for idx in np.ndindex(s.shape):
        ti = float(t[idx])
        if ti not in per_time:
            mt = mpmath.mpf(ti)
            T = min(mt, plan.x_end / mr) if math.isfinite(plan.x_end) else mt
            key = T
            if key not in fourier:
                panels = _panels(N, float(Omega), float(T), rate)
                fourier[key] = _shared_fourier(f, mr, Omega, T, N, panels)
            In = [
                mpmath.im(mpmath.expj((2 * n - 1) * Omega * mt) * G)
                for n, G in enumerate(fourier[key], 1)
            ]
            a0 = f.mp_taylor(0, M + 2) if M else []
            aT = f.mp_taylor(mr * T, M + 2) if M else []
            G0 = [mr**m * a0[m + 2] * mpmath.factorial(m + 2) for m in range(M)]
            GT = [mr**m * aT[m + 2] * mpmath.factorial(m + 2) for m in range(M)]
            per_time[ti] = (mt, T, In, G0, GT)
        mt, T, In, G0, GT = per_time[ti]
        sigma = mpmath.pi * mpmath.mpf(float(s[idx])) / (2 * mL)
        total = mk * f.mp(mr * mt, 0)
        for n, I_n in enumerate(In, 1):
            j = 2 * n - 1
            total += (-1) ** n * alpha / j**2 * I_n * mpmath.cos(j * sigma)
        total += mpmath.im(_expansion_tail(G0, GT, alpha, Omega, mt, T, sigma, N, plan.bound))
        out[idx] = total
    return out


def _expansion_tail(G0, GT, alpha, Omega, t, T, sigma, N, bound):
    """sum_{n>N} (-1)^n alpha / j^2 cos(j sigma) e^(i omega_n t) [M-term expansion of G(omega_n)]
    (complex; its imaginary part is the tail of eq 29).  Orders whose whole contribution is
    below bound / (10 M) are skipped (exactly zero ones always)."""
    half = mpmath.pi / 2
    total = mpmath.mpc(0)
    M = len(G0)
    for m in range(M):
        q = m + 3
        size = abs(alpha) / Omega ** (m + 1) * 2 * (2 * N + 1) ** (1 - q) / (q - 1)
        pref = 1j * alpha / (2 * (1j) ** (m + 1) * Omega ** (m + 1))
        for G, phase in ((G0[m], Omega * t), (-GT[m], Omega * (t - T))):
            if G == 0 or abs(G) * size < bound / (10 * M):
                continue
            tails = (
                odd_tails([q], phase + sigma + half, N)[q]
                + odd_tails([q], phase - sigma + half, N)[q]
            )
            total += pref * G * tails
    return total
