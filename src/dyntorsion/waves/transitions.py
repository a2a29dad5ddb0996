"""The smooth transition functions f of the smooth release (eq 28, Fig 5)."""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Sequence

import mpmath
import numpy as np
from scipy.special import expit


class Transition:
    """A release profile f(x): f = 1 for x <= 0, falling to 0; C-infinity for x > 0.

    ``f(x, k)`` is the k-th derivative, vectorised in NumPy; ``f.mp(x, k)`` the
    same for one mpmath number.  For x < 0 the profile is held at f = 1 (the
    twist before the release starts), so ``f(rate * t)`` is the boundary value
    for all t and the d'Alembert solutions can evaluate it at retarded times.
    """

    name = "transition"
    #: highest derivative available
    max_order = 4

    @property
    def taylor_order(self) -> int:
        """Highest order :meth:`mp_taylor` and :meth:`abs_derivative_integrals` serve."""
        return self.max_order

    def __call__(self, x, k: int = 0) -> np.ndarray:
        self._check_order(k)
        x = np.asarray(x, dtype=float)
        out = np.full(x.shape, 1.0 if k == 0 else 0.0)
        pos = x > 0
        if np.any(pos):
            out[pos] = self._positive(x[pos], k)
        return out

    def mp(self, x, k: int = 0):
        self._check_order(k)
        x = mpmath.mpf(x)
        if x <= 0:
            return mpmath.mpf(1 if k == 0 else 0)
        return self._positive_mp(x, k)

    def derivatives_at_zero(self, orders: int = 5) -> list[float]:
        """f^(k)(0+) for k = 0 .. orders-1 (the compatibility data of section 5)."""
        with mpmath.workdps(60):
            eps = mpmath.mpf(10) ** -40
            return [
                float(self.mp(eps, k)) if k <= self.max_order else math.nan for k in range(orders)
            ]

    def mp_taylor(self, x, order: int) -> list:
        """[f^(k)(x) / k! for k = 0 .. order] at one mpmath point x, order <= ``taylor_order``;
        at x = 0 the limits from the right (the release's), for x < 0 the held f = 1."""
        if not (isinstance(order, int | np.integer) and 0 <= order <= self.taylor_order):
            raise ValueError(
                f"order={order!r} must be an integer in [0, {self.taylor_order}] for {self.name}"
            )
        x = mpmath.mpf(x)
        if x < 0:
            return [mpmath.mpf(1)] + [mpmath.mpf(0)] * order
        return [self._positive_mp(x, k) / mpmath.factorial(k) for k in range(order + 1)]

    def abs_derivative_integrals(self, x_end: float, order: int, points: int = 801) -> np.ndarray:
        """Estimates of int_0^x_end |f^(k)(x)| dx, k = 0 .. order <= ``taylor_order``
        (trapezoid on ``points`` nodes, times 1.25): the remainder bound of eq (29)'s
        expansion by parts."""
        xs = np.linspace(0.0, x_end, points)
        vals = np.array([np.abs(self(xs, k)) for k in range(order + 1)])
        return 1.25 * np.trapezoid(vals, xs, axis=1)

    def negligible_beyond(self, digits: int) -> float:
        """An X with int_X^inf |f''(x)| dx <= 10^-digits (inf: unknown); eq (29)'s
        Duhamel integrals stop there."""
        return math.inf

    def _check_order(self, k: int) -> None:
        if not (isinstance(k, int | np.integer) and 0 <= k <= self.max_order):
            raise ValueError(
                f"derivative order k={k!r} must be an integer in [0, "
                f"{self.max_order}] for {self.name}"
            )

    def _positive(self, x: np.ndarray, k: int) -> np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError

    def _positive_mp(self, x, k: int):  # pragma: no cover - abstract
        raise NotImplementedError


def _poly_derivatives(order: int, inner: np.polynomial.Polynomial) -> list:
    """P_k with d^k/dx^k exp(q(x)) = P_k(x) exp(q(x)), P_0 = 1, P_{k+1} = P_k' + q' P_k."""
    q1 = inner.deriv()
    polys = [np.polynomial.Polynomial([1.0])]
    for _ in range(order):
        polys.append(polys[-1].deriv() + q1 * polys[-1])
    return polys


class ExpQuartic(Transition):
    """f(x) = exp(-x^4): the default smoothing function (Fig 5).

    It meets everything the paper states about its f (reference [13] is not
    available): f(0) = 1, f'(0) = f''(0) = f'''(0) = 0, f''''(0) = -24, C-infinity,
    and kappa0 f(50 t) has fallen to 1/e at t = 0.02 s ("a release within
    approximately 0.02 s").
    """

    name = "exp(-x^4)"
    #: :meth:`mp_taylor` and :meth:`abs_derivative_integrals` serve any order
    taylor_order = 10**6

    def __init__(self) -> None:
        self._polys = _poly_derivatives(self.max_order, np.polynomial.Polynomial([0, 0, 0, 0, -1]))
        self._int_coef = [[int(c) for c in p.coef[::-1]] for p in self._polys]

    def _positive(self, x, k):
        return self._polys[k](x) * np.exp(-(x**4))

    def _positive_mp(self, x, k):
        total = mpmath.mpf(0)
        for c in self._int_coef[k]:  # Horner, exact integer coefficients
            total = total * x + c
        return total * mpmath.exp(-(x**4))

    def mp_taylor(self, x, order: int) -> list:
        """Taylor coefficients a_k = f^(k)(x) / k! of exp(-x^4) at x, any order, exactly:
        exp(-(x + h)^4) = exp(-x^4) exp(p(h)), p(h) = -(4x^3 h + 6x^2 h^2 + 4x h^3 + h^4), and
        E = exp(p) obeys E' = p' E, i.e. (k+1) e_{k+1} = sum_i i p_i e_{k+1-i}."""
        if not (isinstance(order, int | np.integer) and order >= 0):
            raise ValueError(f"order={order!r} must be an integer >= 0")
        x = mpmath.mpf(x)
        if x < 0:
            return [mpmath.mpf(1)] + [mpmath.mpf(0)] * order
        p = [0, -4 * x**3, -6 * x**2, -4 * x, -1]
        e = [mpmath.mpf(1)]
        for k in range(order):
            e.append(sum(i * p[i] * e[k + 1 - i] for i in range(1, 5) if k + 1 - i >= 0) / (k + 1))
        scale = mpmath.exp(-(x**4))
        return [v * scale for v in e]

    def abs_derivative_integrals(self, x_end: float, order: int, points: int = 2001) -> np.ndarray:
        """As :meth:`Transition.abs_derivative_integrals`, with the Taylor recurrence of
        :meth:`mp_taylor` vectorised in floats (the terms p_1 e_k dominate: no cancellation)."""
        x = np.linspace(0.0, x_end, points)
        p = [None, -4 * x**3, -6 * x**2, -4 * x, -np.ones_like(x)]
        e = [np.ones_like(x)]
        for k in range(order):
            e.append(sum(i * p[i] * e[k + 1 - i] for i in range(1, 5) if k + 1 - i >= 0) / (k + 1))
        vals = np.abs(np.array(e)) * np.exp(-(x**4))
        vals *= np.array([float(math.factorial(k)) for k in range(order + 1)])[:, None]
        return 1.25 * np.trapezoid(vals, x, axis=1)

    def negligible_beyond(self, digits: int) -> float:
        """X with int_X^inf |f''| <= 8 X^3 exp(-X^4) <= 10^-digits (X >= 2: |f''| <= 16 x^6
        e^(-x^4) and x^6 e^(-x^4 / 2) falls, so the integral is below 16 X^6 e^(-X^4/2)
        int_X^inf (x/X)^3 e^(-x^4/2) dx = 8 X^3 e^(-X^4))."""
        X = 2.0
        while math.log(8 * X**3) - X**4 > -digits * math.log(10):
            X += 0.01
        return X


class FlatBlend(Transition):
    """The classic fully flat blend on [0, width]: f = 1 / (1 + exp(p(x / width))),
    p(u) = 1/(1 - u) - 1/u.

    Every derivative vanishes at x = 0 (and at x = width, where f reaches 0
    exactly), so the release is infinitely compatible with the initial state.
    """

    name = "flat blend"

    def __init__(self, width: float = 1.0) -> None:
        if not (math.isfinite(width) and width > 0):
            raise ValueError(f"width={width!r} must be a finite number > 0")
        self.width = float(width)
        self.name = f"flat blend (width {width:g})"

    @staticmethod
    def _chain(sig, tau, p, k):
        """k-th u-derivative of sigma(p(u)), sigma = 1/(1 + e^p), tau = 1 - sigma.

        Outer derivatives d^j sigma / dp^j are written with the factor sigma*tau so
        that nothing cancels near the ends; inner ones are p_j = d^j p / du^j;
        Faa di Bruno up to j = 4.
        """
        st = sig * tau
        d = tau - sig
        F1 = -st
        F2 = st * d
        F3 = st * (2 * st - d * d)
        F4 = -st * d * (8 * st - d * d)
        p1, p2, p3, p4 = p[1], p[2], p[3], p[4]
        if k == 0:
            return sig
        if k == 1:
            return F1 * p1
        if k == 2:
            return F2 * p1**2 + F1 * p2
        if k == 3:
            return F3 * p1**3 + 3 * F2 * p1 * p2 + F1 * p3
        return F4 * p1**4 + 6 * F3 * p1**2 * p2 + F2 * (3 * p2**2 + 4 * p1 * p3) + F1 * p4

    @staticmethod
    def _inner(u, one, fact):
        return [
            fact(j) / (one - u) ** (j + 1) - (-1) ** j * fact(j) / u ** (j + 1) for j in range(5)
        ]

    def _positive(self, x, k):
        u = x / self.width
        out = np.zeros_like(u)
        if k == 0:
            out[u <= 2e-3] = 1.0
        inner = (u > 2e-3) & (u < 1.0 - 2e-3)  # outside, f - {0, 1} and all derivatives < 1e-190
        ui = u[inner]
        p = self._inner(ui, 1.0, math.factorial)
        sig, tau = expit(-p[0]), expit(p[0])
        out[inner] = self._chain(sig, tau, p, k) / self.width**k
        return out

    def negligible_beyond(self, digits: int) -> float:
        """f = 0 exactly from x = width on."""
        return self.width

    #: :meth:`mp_taylor` serves this order (its recurrences cost order^2 a point)
    taylor_order = 18

    def mp_taylor(self, x, order: int) -> list:
        """As :meth:`Transition.mp_taylor`, exactly: with q = -|p| (p = p(u), u = x / width) the
        Taylor series of E = e^q obeys (k+1) e_(k+1) = sum_i i q_i e_(k+1-i) (q_i = 1/(1-u)^(i+1)
        - (-1)^i / u^(i+1) up to sign), and f = 1/(1 + E) (p <= 0) or 1 - 1/(1 + E) (p > 0)
        is a series reciprocal.  Every derivative is 0 at x = 0 and from x = width on."""
        head = super().mp_taylor(mpmath.mpf(-1), order)  # validates order
        x = mpmath.mpf(x)
        if x <= 0 or x >= self.width:
            return [mpmath.mpf(1 if x <= 0 else 0)] + head[1:]
        u = x / self.width
        p0 = 1 / (1 - u) - 1 / u
        sign = -1 if p0 > 0 else 1
        q = [sign * (1 / (1 - u) ** (i + 1) - (-1) ** i / u ** (i + 1)) for i in range(order + 1)]
        e = [mpmath.exp(q[0])]
        for k in range(order):
            e.append(sum(i * q[i] * e[k + 1 - i] for i in range(1, k + 2)) / (k + 1))
        d0 = 1 + e[0]
        r = [1 / d0]
        for k in range(1, order + 1):
            r.append(-sum(e[i] * r[k - i] for i in range(1, k + 1)) / d0)
        a = r if sign > 0 else [1 - r[0]] + [-v for v in r[1:]]
        return [v / mpmath.mpf(self.width) ** k for k, v in enumerate(a)]

    @functools.lru_cache(maxsize=32)  # noqa: B019 - a few (x_end, order) per reference
    def abs_derivative_integrals(self, x_end: float, order: int, points: int = 401) -> np.ndarray:
        """As :meth:`Transition.abs_derivative_integrals`, from :meth:`mp_taylor` (any order
        up to ``taylor_order``) at 30 digits; beyond x = width every derivative is 0.  (The
        peaks of |f^(k)| near the ends are ~ (8 k^3)^(-1/2) wide in u: 1.8 nodes at k = 18.)"""
        xs = np.linspace(0.0, min(x_end, self.width), points)
        with mpmath.workdps(30):
            vals = np.array([[float(abs(v)) for v in self.mp_taylor(x, order)] for x in xs])
        vals *= np.array([float(math.factorial(k)) for k in range(order + 1)])
        return 1.25 * np.trapezoid(vals, xs, axis=0)

    def _positive_mp(self, x, k):
        u = x / self.width
        if u >= 1:
            return mpmath.mpf(0)
        p = self._inner(u, mpmath.mpf(1), mpmath.factorial)
        sig, tau = 1 / (1 + mpmath.exp(p[0])), 1 / (1 + mpmath.exp(-p[0]))
        return self._chain(sig, tau, p, k) / mpmath.mpf(self.width) ** k


class CustomTransition(Transition):
    """A caller's f: ``numpy`` = [f, f', f'', ...] (vectorised callables for x > 0),
    optional ``mpmath`` = the same for mpmath numbers (needed for ``precise=True``).

    f'' is needed by eq (29); f''' as well to choose the term count from a tolerance.
    """

    def __init__(
        self,
        numpy: Sequence[Callable],
        mpmath_: Sequence[Callable] | None = None,
        name: str = "custom",
    ):
        if len(numpy) < 3:
            raise ValueError("numpy must list at least f, f' and f''")
        self._np = list(numpy)
        self._mp = list(mpmath_) if mpmath_ is not None else None
        self.max_order = len(self._np) - 1
        self.name = name

    def _positive(self, x, k):
        return np.asarray(self._np[k](x), dtype=float)

    def _positive_mp(self, x, k):
        if self._mp is None:
            raise ValueError(f"{self.name}: no mpmath derivatives given, precise=True unavailable")
        return self._mp[k](x)


DEFAULT_TRANSITION = ExpQuartic()


def smoothing(x) -> np.ndarray:
    """The default smooth transition f(x) = exp(-x^4) of Fig 5 (f = 1 for x <= 0)."""
    return DEFAULT_TRANSITION(x)
