"""The smooth transition functions f of the smooth release (eq 28, Fig 5)."""

from __future__ import annotations

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

    def __init__(self) -> None:
        self._polys = _poly_derivatives(self.max_order, np.polynomial.Polynomial([0, 0, 0, 0, -1]))

    def _positive(self, x, k):
        return self._polys[k](x) * np.exp(-(x**4))

    def _positive_mp(self, x, k):
        total = mpmath.mpf(0)
        for c in self._polys[k].coef[::-1]:  # Horner, exact integer coefficients
            total = total * x + int(c)
        return total * mpmath.exp(-(x**4))


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
