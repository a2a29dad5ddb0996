"""Prebuckling torsional waves (section 5).

While the rod is straight only kappa = k3 and omega = w3 are nonzero and eq (6)
reduces to the reduced moment balance and the reduced compatibility equation

    rho J omega_t = G J kappa_s,      kappa_t = omega_s,                (eq 22)

i.e. the wave equation kappa_tt = c^2 kappa_ss with c = sqrt(G / rho).  This
module holds

* the 2-field model :class:`Torsion` for the generalised-alpha engine ("model
  only what a scene requires");
* the three initial-boundary-value problems of the section -- linear loading
  (eq 23, solution eq 25), instantaneous release (eq 26, solution eq 27) and
  smooth release (eq 28, solution eq 29) -- as :class:`LinearLoading`,
  :class:`InstantRelease`, :class:`SmoothRelease`;
* their exact series in NumPy (vectorised) and in mpmath (``precise=True``),
  with a term count or a tolerance on a rigorous truncation bound;
* their closed-form d'Alembert solutions (travelling fronts with reflections),
  an independent check of the series;
* the smooth transition functions f of Fig 5 (:class:`ExpQuartic`, the default,
  and the fully flat :class:`FlatBlend`);
* :func:`solve`, which runs a problem on the engine.

Eigenvalues of all three problems: sqrt(lambda_n) = (2n - 1) pi / (2L).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import mpmath
import numpy as np
from scipy.special import expit

from ._numba import jacobian_kernel, load_kernel
from .genalpha import Boundary, Newton, Run, Scheme, System, integrate
from .genalpha.guard import BudgetError
from .rod import Rod

FIELDS = ("k3", "w3")
#: largest number of series terms a tolerance may ask for
MAX_TERMS = 200_000
#: the same for eq (29) (the work grows like the square of the term count)
MAX_TERMS_DUHAMEL = 20_000
#: default tolerance on the series truncation bound of eqs (25) and (27)
DEFAULT_TOL = 1e-10
#: default tolerance for eq (29), whose every term is a Duhamel integral
DEFAULT_TOL_DUHAMEL = 1e-6
#: default working precision (decimal digits) of the mpmath references
DEFAULT_DIGITS = 35
#: the mpmath references refuse work estimated above this many seconds (``budget=``)
MP_BUDGET_S = 60.0
#: cost at 35 digits (measured on a 2-core 2026 machine): one series term at one point,
#: one Gauss-Legendre panel of a Duhamel integral (scaled by digits / 35 above 35)
MP_TERM_S, MP_PANEL_S = 3e-5, 2.5e-3
#: the closed forms refuse more travelling images x points than this
MAX_IMAGES = 2_000_000
#: the NumPy Duhamel integrals of eq (29) refuse more evaluations than this per time
#: (and more than 1/100 of it quadrature nodes, which are held in memory)
MAX_DUHAMEL_WORK = 2e8


# ============================================================================ the model
@load_kernel
def _no_load(y, p, out):
    out[0] = 0.0
    out[1] = 0.0


@jacobian_kernel
def _no_load_jacobian(y, p, out):
    out[:, :] = 0.0


@dataclass(frozen=True)
class Torsion:
    """The reduced torsion model of eq (22) for a rod: y = (kappa, omega).

    Rows:  rho J omega_t - C kappa_s = 0   and   kappa_t - omega_s = 0.
    """

    rod: Rod = field(default_factory=Rod)

    @property
    def mass_matrix(self) -> np.ndarray:
        return np.array([[0.0, self.rod.rotary_inertia[2]], [1.0, 0.0]])

    @property
    def stiffness_matrix(self) -> np.ndarray:
        return np.array([[-self.rod.C, 0.0], [0.0, -1.0]])

    def scales(self) -> tuple[np.ndarray, np.ndarray]:
        r = self.rod
        ys = np.array([1.0 / r.L, r.c / r.L])
        rs = np.array([r.C / r.L**2, r.c / r.L**2])
        return ys, rs

    def system(self) -> System:
        return System.from_model(
            self, names=FIELDS, F=_no_load, dF=_no_load_jacobian, params=np.zeros(1)
        )

    def energy(self, y: np.ndarray, ds: float) -> float:
        """Discrete energy of the box scheme: sum over cells of ds (rhoJ wbar^2 + C kbar^2)/2.

        Bars are cell averages of the two nodes; for lam_s = lam_t = -1 this is
        exactly conserved when no work crosses the ends.
        """
        ybar = 0.5 * (y[1:] + y[:-1])
        r = self.rod
        return float(
            0.5 * ds * np.sum(r.rotary_inertia[2] * ybar[:, 1] ** 2 + r.C * ybar[:, 0] ** 2)
        )


# ===================================================================== transitions (Fig 5)
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


# ============================================================================ validation
def _positive_number(name: str, value) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name}={value!r} must be a finite number > 0") from None
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{name}={value!r} must be a finite number > 0")
    return v


#: the range of the scales c, L and rate, and the bound on |a|, |kappa0| and t, within
#: which the formulas stay inside floating point
SCALES, MAGNITUDE = (1e-60, 1e60), 1e100


def _scale(name: str, value) -> float:
    v = _positive_number(name, value)
    if not SCALES[0] <= v <= SCALES[1]:
        raise ValueError(f"{name}={value!r} must lie in the range [{SCALES[0]:g}, {SCALES[1]:g}]")
    return v


def _finite(name: str, value) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name}={value!r} must be a finite number") from None
    if not (math.isfinite(v) and abs(v) <= MAGNITUDE):
        raise ValueError(f"{name}={value!r} must be a finite number of size <= {MAGNITUDE:g}")
    return v


def _grid(s, t, L):
    try:
        s = np.asarray(s, dtype=float)
        t = np.asarray(t, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"s={s!r} and t={t!r} must be numbers or arrays of numbers") from None
    if not (np.all(np.isfinite(s)) and np.all(np.isfinite(t))):
        raise ValueError("s and t must be finite")
    if np.any(t > MAGNITUDE):
        raise ValueError(f"t must be <= {MAGNITUDE:g}; got max(t) = {t.max()}")
    if np.any(s < 0) or np.any(s > L * (1 + 1e-12)):
        raise ValueError(f"s must lie in [0, L] = [0, {L}]; got [{s.min()}, {s.max()}]")
    if np.any(t < 0):
        raise ValueError(f"t must be >= 0; got min(t) = {t.min()}")
    return np.broadcast_arrays(s, t)


def _terms(
    terms,
    tol,
    needed: Callable[[float], int],
    default_tol: float = DEFAULT_TOL,
    max_terms: int = MAX_TERMS,
) -> int:
    """Term count from ``terms`` or from the tolerance on the truncation bound."""
    if terms is not None:
        if not (isinstance(terms, int | np.integer) and terms >= 1):
            raise ValueError(f"terms={terms!r} must be an integer >= 1")
        return int(terms)
    tol = default_tol if tol is None else _positive_number("tol", tol)
    n = needed(tol)
    if n > max_terms:
        raise ValueError(
            f"tol={tol:g} needs {n} series terms (> {max_terms}); loosen tol, "
            "pass terms=..., or use the d'Alembert solution"
        )
    return max(int(n), 1)


def sqrt_lambda(n, L: float):
    """sqrt(lambda_n) = (2n - 1) pi / (2L), n = 1, 2, ..."""
    return (2 * np.asarray(n) - 1) * np.pi / (2 * L)


def _chunked_sum(n_terms: int, term: Callable[[np.ndarray], np.ndarray], shape) -> np.ndarray:
    """sum_{n=1}^{n_terms} term(n) with n along a leading axis, in chunks (bounded memory)."""
    out = np.zeros(shape)
    size = max(1, int(np.prod(shape)))
    chunk = max(1, min(n_terms, 4_000_000 // size))
    for n0 in range(1, n_terms + 1, chunk):
        n = np.arange(n0, min(n0 + chunk, n_terms + 1), dtype=float).reshape(
            (-1,) + (1,) * len(shape)
        )
        out += term(n).sum(axis=0)
    return out


def _mp_budget(units: float, unit_s: float, digits: int, budget, lower: str) -> None:
    """Refuse (:class:`BudgetError`) an mpmath evaluation whose estimated time exceeds
    ``budget`` seconds (None: no limit)."""
    if not (isinstance(digits, int | np.integer) and digits >= 5):
        raise ValueError(f"digits={digits!r} must be an integer >= 5")
    if budget is None:
        return
    budget = _positive_number("budget", budget)
    estimate = units * unit_s * max(1.0, digits / DEFAULT_DIGITS)
    if estimate > budget:
        raise BudgetError(
            f"precise=True: about {units:.3g} mpmath evaluations, an estimated {estimate:.3g} s "
            f"(> budget={budget:g} s); {lower}, use precise=False, or raise budget= (None: no limit)"
        )


def _mp_array(fn, s, t, digits: int) -> np.ndarray:
    with mpmath.workdps(digits):
        vals = [
            fn(mpmath.mpf(float(si)), mpmath.mpf(float(ti)))
            for si, ti in zip(s.ravel(), t.ravel(), strict=True)
        ]
    return np.array(vals, dtype=object).reshape(s.shape)


# ============================================================== eq (25): linear loading
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
    terms: int | None = None,
    tol: float | None = None,
    precise: bool = False,
    digits: int = DEFAULT_DIGITS,
    budget: float | None = MP_BUDGET_S,
) -> np.ndarray:
    """Eq (25): kappa(s, t) for kappa(0, t) = kappa0 + a t, kappa_s(L, t) = 0 (eq 23).

        kappa = kappa0 + a t - sum_n 2a / (L c lambda_n) sin(c sqrt(lambda_n) t) sin(sqrt(lambda_n) s)

    ``terms`` fixes the number of terms; otherwise enough are taken for the
    bound :func:`linear_loading_bound` (pointwise where it is smaller) to be below
    ``tol``.
    ``precise=True`` sums in mpmath at ``digits`` digits and returns an object
    array of mpf; it refuses (:class:`BudgetError`) work estimated above ``budget``
    seconds.
    """
    c, L = _scale("c", c), _scale("L", L)
    a, kappa0 = _finite("a", a), _finite("kappa0", kappa0)
    s, t = _grid(s, t, L)

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

    n_terms = _terms(terms, tol, needed)
    if precise:
        _mp_budget(n_terms * s.size, MP_TERM_S, digits, budget, "pass fewer points or terms")

        def point(si, ti):
            mL, mc, ma = mpmath.mpf(L), mpmath.mpf(c), mpmath.mpf(a)
            total = mpmath.mpf(kappa0) + ma * ti
            for n in range(1, n_terms + 1):
                k = (2 * n - 1) * mpmath.pi / (2 * mL)
                total -= 2 * ma / (mL * mc * k**2) * mpmath.sin(mc * k * ti) * mpmath.sin(k * si)
            return total

        return _mp_array(point, s, t, digits)

    def term(n):
        k = sqrt_lambda(n, L)
        return 2 * a / (L * c * k**2) * np.sin(c * k * t) * np.sin(k * s)

    return kappa0 + a * t - _chunked_sum(n_terms, term, s.shape)


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
    terms: int | None = None,
    tol: float | None = None,
    precise: bool = False,
    digits: int = DEFAULT_DIGITS,
    budget: float | None = MP_BUDGET_S,
) -> np.ndarray:
    """Eq (27): kappa(s, t) after the twist kappa0 is released at t = 0 (eq 26).

        kappa = sum_n 2 kappa0 / (L sqrt(lambda_n)) (-1)^(n-1) cos(c sqrt(lambda_n) t) cos(sqrt(lambda_n) s)

    With ``tol`` the term count comes from the pointwise bound
    :func:`instant_release_bound` at the worst of the given points (points on a
    front cannot be served; pass ``terms`` or use :func:`instant_release_dalembert`).
    """
    c, L = _scale("c", c), _scale("L", L)
    kappa0 = _finite("kappa0", kappa0)
    s, t = _grid(s, t, L)

    def needed(tol):
        # bound(N) = C / (2N + 1): C = 3 bound(1)
        C = 3 * float(np.max(instant_release_bound(1, s, t, kappa0=kappa0, c=c, L=L)))
        if not math.isfinite(C):
            return MAX_TERMS + 1
        return math.ceil((C / tol - 1) / 2)

    n_terms = _terms(terms, tol, needed)
    if precise:
        _mp_budget(n_terms * s.size, MP_TERM_S, digits, budget, "pass fewer points or terms")

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

        return _mp_array(point, s, t, digits)

    def term(n):
        k = sqrt_lambda(n, L)
        sign = 1.0 - 2.0 * ((n - 1) % 2)
        return 2 * kappa0 / (L * k) * sign * np.cos(c * k * t) * np.cos(k * s)

    return _chunked_sum(n_terms, term, s.shape)


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
            f"(> {MAX_DUHAMEL_WORK:.3g} evaluations); pass earlier times, fewer terms or a "
            "looser tol (or use smooth_release_dalembert)"
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


def _duhamel_pieces(t: float, n: int, rate: float, c: float, L: float) -> int:
    """Panels of the mpmath Duhamel integral of term n: one per period, per 0.2 of x."""
    omega = c * (2 * n - 1) * math.pi / (2 * L)
    return int(max(2, math.ceil(omega * t / (2 * math.pi)), math.ceil(rate * t / 0.2)))


def _duhamel_mp(t, n: int, f: Transition, rate, c, L):
    omega = c * (2 * n - 1) * mpmath.pi / (2 * L)
    if t == 0:
        return mpmath.mpf(0)
    pieces = _duhamel_pieces(float(t), n, float(rate), float(c), float(L))
    return mpmath.quad(
        lambda tau: f.mp(rate * tau, 2) * mpmath.sin(omega * (t - tau)),
        mpmath.linspace(0, t, pieces + 1),
        method="gauss-legendre",
    )


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
    terms: int | None = None,
    tol: float | None = None,
    precise: bool = False,
    digits: int = DEFAULT_DIGITS,
    budget: float | None = MP_BUDGET_S,
) -> np.ndarray:
    """Eq (29): kappa(s, t) for kappa(L, t) = kappa0 f(rate t), kappa_s(0, t) = 0 (eq 28).

        kappa = kappa0 f(rate t) + int_0^t eta dtau,
        eta = sum_n (-1)^n 2 rate^2 kappa0 / (L c lambda_n) f''(rate tau) sin(c sqrt(lambda_n)(t - tau)) cos(sqrt(lambda_n) s)

    (for rate = 50 the factor 2 rate^2 is the paper's 5000).  The Duhamel
    integrals are evaluated by composite Gauss-Legendre quadrature (NumPy) or
    mpmath's Gauss-Legendre on one panel per period (``precise=True``), not by a
    Riemann sum.  With ``tol`` (default 1e-6: each term costs a quadrature) the
    term count comes from :func:`smooth_release_bound` (needs f''').  ``precise=True``
    refuses (:class:`BudgetError`) work estimated above ``budget`` seconds: each term at
    each distinct time is a quadrature over :func:`_duhamel_pieces` panels.
    """
    c, L = _scale("c", c), _scale("L", L)
    rate = _scale("rate", rate)
    kappa0 = _finite("kappa0", kappa0)
    if not isinstance(f, Transition):
        raise ValueError(f"f={f!r} must be a Transition (ExpQuartic, FlatBlend, CustomTransition)")
    s, t = _grid(s, t, L)

    def needed(tol):
        if f.max_order < 3:
            raise ValueError(f"{f.name}: a tolerance needs f'''; pass terms=...")
        worst = float(
            np.max(smooth_release_bound(1, np.unique(t), kappa0=kappa0, c=c, L=L, rate=rate, f=f))
        )
        return math.ceil((math.sqrt(worst / tol) + 1) / 2)

    n_terms = _terms(terms, tol, needed, DEFAULT_TOL_DUHAMEL, MAX_TERMS_DUHAMEL)
    coef_n = np.arange(1, n_terms + 1)
    if precise:
        panels = sum(
            _duhamel_pieces(float(ti), int(n), rate, c, L) for ti in np.unique(t) for n in coef_n
        )
        _mp_budget(
            panels + n_terms * s.size,
            MP_PANEL_S,
            digits,
            budget,
            "pass fewer distinct times, fewer terms or a looser tol",
        )
        with mpmath.workdps(digits):
            mL, mc, mr, mk = (mpmath.mpf(v) for v in (L, c, rate, kappa0))
            cache: dict[float, list] = {}
            out = np.empty(s.shape, dtype=object)
            for idx in np.ndindex(s.shape):
                ti = float(t[idx])
                if ti not in cache:
                    mt = mpmath.mpf(ti)
                    cache[ti] = [_duhamel_mp(mt, int(n), f, mr, mc, mL) for n in coef_n]
                mt, ms = mpmath.mpf(ti), mpmath.mpf(float(s[idx]))
                total = mk * f.mp(mr * mt, 0)
                for n, In in zip(coef_n, cache[ti], strict=True):
                    k = (2 * int(n) - 1) * mpmath.pi / (2 * mL)
                    total += (
                        (-1) ** int(n) * 2 * mr**2 * mk / (mL * mc * k**2) * In * mpmath.cos(k * ms)
                    )
                out[idx] = total
            return out

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


# ========================================================= closed-form d'Alembert solutions
def _images(t, s, c, L, disturbance, from_left: bool, n_max: int | None = None):
    """Sum of travelling images of a boundary disturbance phi (phi = 0 for t <= 0).

    from_left (Dirichlet at 0, Neumann at L):  sum_k (-1)^k [phi(t - (2kL + s)/c) + phi(t - (2(k+1)L - s)/c)]
    from the right (Neumann at 0, Dirichlet at L): sum_k (-1)^k [phi(t - ((2k+1)L - s)/c) + phi(t - ((2k+1)L + s)/c)]
    """
    t = np.asarray(t, float)
    k_max = int(np.max(c * t / (2 * L))) + 1 if n_max is None else n_max
    if (k_max + 1) * max(1, t.size) > MAX_IMAGES:
        raise BudgetError(
            f"t up to {np.max(t):.4g} s is {k_max} wave transits 2L/c: {k_max + 1} images x "
            f"{t.size} points exceeds {MAX_IMAGES:.3g}; pass earlier times or fewer points"
        )
    out = np.zeros(np.broadcast(s, t).shape)
    for k in range(k_max + 1):
        if from_left:
            d1, d2 = 2 * k * L + s, 2 * (k + 1) * L - s
        else:
            d1, d2 = (2 * k + 1) * L - s, (2 * k + 1) * L + s
        out += (-1) ** k * (disturbance(t - d1 / c) + disturbance(t - d2 / c))
    return out


def linear_loading_dalembert(s, t, *, a: float, kappa0: float = 0.0, c: float, L: float):
    """Closed form of eq (23) with h = kappa0 + a t: kappa0 plus travelling ramps a (t - d/c)_+
    with reflections (same sign at the free end s = L, opposite at the driven end s = 0)."""
    c, L = _scale("c", c), _scale("L", L)
    a, kappa0 = _finite("a", a), _finite("kappa0", kappa0)
    s, t = _grid(s, t, L)
    # kappa - a t has the period 4L/c of eq (25): evaluate within one period
    t_r = np.mod(t, 4 * L / c)
    ramp = lambda tau: a * np.maximum(tau, 0.0)  # noqa: E731
    return kappa0 + a * (t - t_r) + _images(t_r, s, c, L, ramp, from_left=True)


def instant_release_dalembert(s, t, *, kappa0: float, c: float, L: float):
    """Closed form of eq (26): kappa0 minus travelling steps; on a front the mean of both sides."""
    c, L = _scale("c", c), _scale("L", L)
    kappa0 = _finite("kappa0", kappa0)
    s, t = _grid(s, t, L)
    step = lambda tau: -kappa0 * np.heaviside(tau, 0.5)  # noqa: E731
    # periodic in t with the period 4L/c of eq (27)
    return kappa0 + _images(np.mod(t, 4 * L / c), s, c, L, step, from_left=False)


def smooth_release_dalembert(
    s,
    t,
    *,
    kappa0: float,
    c: float,
    L: float,
    rate: float = 50.0,
    f: Transition = DEFAULT_TRANSITION,
):
    """Closed form of eq (28): kappa0 + travelling copies of kappa0 (f(rate t) - 1)."""
    c, L = _scale("c", c), _scale("L", L)
    s, t = _grid(s, t, L)
    return kappa0 + _images(t, s, c, L, lambda tau: kappa0 * (f(rate * tau) - 1.0), from_left=False)


# ===================================================================== the three problems
@dataclass(frozen=True)
class LinearLoading:
    """Eq (23): kappa(0, t) = kappa0 + a t, omega(L, t) = 0; kappa = kappa0, omega = 0 at t = 0."""

    a: float
    kappa0: float = 0.0

    def boundaries(self, system: System) -> tuple[Boundary, Boundary]:
        left = Boundary.fields(system, ["k3"], lambda t: (self.kappa0 + self.a * t)[:, None])
        return left, Boundary.fields(system, ["w3"])

    def exact(self, s, t, *, c, L, **kw):
        return linear_loading_exact(s, t, a=self.a, kappa0=self.kappa0, c=c, L=L, **kw)

    def dalembert(self, s, t, *, c, L):
        return linear_loading_dalembert(s, t, a=self.a, kappa0=self.kappa0, c=c, L=L)


@dataclass(frozen=True)
class InstantRelease:
    """Eq (26): omega(0, t) = 0 (kappa_s = 0), kappa(L, t) = 0 for t > 0; kappa = kappa0 at t = 0."""

    kappa0: float

    def boundaries(self, system: System) -> tuple[Boundary, Boundary]:
        return Boundary.fields(system, ["w3"]), Boundary.fields(system, ["k3"])

    def exact(self, s, t, *, c, L, **kw):
        return instant_release_exact(s, t, kappa0=self.kappa0, c=c, L=L, **kw)

    def dalembert(self, s, t, *, c, L):
        return instant_release_dalembert(s, t, kappa0=self.kappa0, c=c, L=L)


@dataclass(frozen=True)
class SmoothRelease:
    """Eq (28): omega(0, t) = 0, kappa(L, t) = kappa0 f(rate t); kappa = kappa0 at t = 0."""

    kappa0: float
    rate: float = 50.0
    f: Transition = DEFAULT_TRANSITION

    def boundaries(self, system: System) -> tuple[Boundary, Boundary]:
        right = Boundary.fields(
            system, ["k3"], lambda t: (self.kappa0 * self.f(self.rate * t))[:, None]
        )
        return Boundary.fields(system, ["w3"]), right

    def exact(self, s, t, *, c, L, **kw):
        return smooth_release_exact(
            s, t, kappa0=self.kappa0, c=c, L=L, rate=self.rate, f=self.f, **kw
        )

    def dalembert(self, s, t, *, c, L):
        return smooth_release_dalembert(
            s, t, kappa0=self.kappa0, c=c, L=L, rate=self.rate, f=self.f
        )


Problem = LinearLoading | InstantRelease | SmoothRelease


@dataclass
class WaveSolution:
    """kappa(s, t) and omega(s, t) of a wave problem on the engine, at the requested times."""

    problem: Any
    rod: Rod
    s: np.ndarray
    t: np.ndarray
    kappa: np.ndarray
    omega: np.ndarray
    run: Run

    def exact(self, kind: str = "dalembert", **kw) -> np.ndarray:
        """The exact kappa at the same (s, t): ``"dalembert"`` (closed form) or ``"series"``."""
        ss, tt = np.meshgrid(self.s, self.t)
        if kind == "dalembert":
            return self.problem.dalembert(ss, tt, c=self.rod.c, L=self.rod.L)
        if kind == "series":
            return self.problem.exact(ss, tt, c=self.rod.c, L=self.rod.L, **kw)
        raise ValueError(f"kind={kind!r}; allowed: 'dalembert', 'series'")

    def errors(self, reference: np.ndarray | None = None) -> dict[str, np.ndarray]:
        """Max, L2 and L1 (trapezoidal in s) norms of kappa - reference, per time."""
        ref = self.exact() if reference is None else np.asarray(reference, dtype=float)
        e = self.kappa - ref
        return {
            "max": np.max(np.abs(e), axis=1),
            "L2": np.sqrt(np.trapezoid(e**2, self.s, axis=1)),
            "L1": np.trapezoid(np.abs(e), self.s, axis=1),
        }


def solve(
    problem: Problem,
    *,
    rod: Rod | None = None,
    n_cells: int,
    dt: float,
    times: Sequence[float] | float,
    lam_t: float = -1.0,
    lam_s: float = -1.0,
    quadrature: str = "trapezoidal",
    newton: Newton = Newton(),
) -> WaveSolution:
    """Run a wave problem on the generalised-alpha engine with the 2-field model.

    ``times`` must be multiples of ``dt``; the run ends at the last of them.
    """
    rod = Rod.paper() if rod is None else rod
    times_arr = np.atleast_1d(np.asarray(times, dtype=float))
    if times_arr.size == 0 or np.any(times_arr <= 0) or not np.all(np.isfinite(times_arr)):
        raise ValueError(f"times={times!r} must be finite and > 0")
    dt = _positive_number("dt", dt)
    steps = times_arr / dt
    if np.any(np.abs(steps - np.round(steps)) > 1e-9 * np.maximum(1.0, steps)):
        raise ValueError(f"times={times!r} must be multiples of dt={dt}")
    model = Torsion(rod)
    system = model.system()
    left, right = problem.boundaries(system)
    if not isinstance(n_cells, int | np.integer) or n_cells < 2:
        raise ValueError(f"n_cells={n_cells!r} must be an integer >= 2")
    y0 = np.zeros((n_cells + 1, 2))
    y0[:, 0] = problem.kappa0
    scheme = Scheme(lam_s=lam_s, lam_t=lam_t, quadrature=quadrature)
    run = integrate(
        system,
        n_cells=int(n_cells),
        length=rod.L,
        dt=dt,
        t_end=float(times_arr.max()),
        y0=y0,
        left=left,
        right=right,
        scheme=scheme,
        y_t0="zero",
        snapshots=list(times_arr),
        newton=newton,
        meta={"problem": repr(problem), "rod": rod.as_dict()},
    )
    snaps = np.array([run.snapshot(ti) for ti in times_arr])
    return WaveSolution(
        problem=problem,
        rod=rod,
        s=run.s,
        t=times_arr,
        kappa=snaps[:, :, 0],
        omega=snaps[:, :, 1],
        run=run,
    )
