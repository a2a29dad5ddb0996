"""Input checks, term counts and work budgets of the exact series (section 5)."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import mpmath
import numpy as np

from ..genalpha.guard import BudgetError

FIELDS = ("k3", "w3")
#: largest number of series terms a tolerance may ask for
MAX_TERMS = 200_000
#: the same for eq (29) (the work grows like the square of the term count)
MAX_TERMS_DUHAMEL = 20_000
#: default tolerance on the series truncation bound of eqs (25) and (27)
DEFAULT_TOL = 1e-10
#: default tolerance for eq (29), whose every term is a Duhamel integral
DEFAULT_TOL_DUHAMEL = 1e-6
#: default tolerance of the whole-series mpmath references (``precise=True`` without ``terms``)
DEFAULT_TOL_PRECISE = 1e-20
#: default working precision (decimal digits) of the mpmath references
DEFAULT_DIGITS = 35
#: the mpmath references refuse work estimated above this many seconds (:attr:`Series.budget`)
MP_BUDGET_S = 60.0
#: cost at 35 digits (measured on a 2-core 2026 machine) of one series term at one point
#: (scaled by digits / 35 above 35)
MP_TERM_S = 3e-5
#: the closed forms refuse more travelling images x points than this
MAX_IMAGES = 2_000_000
#: the NumPy Duhamel integrals of eq (29) refuse more evaluations than this per time
#: (and more than 1/100 of it quadrature nodes, which are held in memory)
MAX_DUHAMEL_WORK = 2e8


def positive_number(name: str, value) -> float:
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


def checked_scale(name: str, value) -> float:
    v = positive_number(name, value)
    if not SCALES[0] <= v <= SCALES[1]:
        raise ValueError(f"{name}={value!r} must lie in the range [{SCALES[0]:g}, {SCALES[1]:g}]")
    return v


def finite_number(name: str, value) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name}={value!r} must be a finite number") from None
    if not (math.isfinite(v) and abs(v) <= MAGNITUDE):
        raise ValueError(f"{name}={value!r} must be a finite number of size <= {MAGNITUDE:g}")
    return v


@dataclass(frozen=True)
class Series:
    """How an exact series of section 5 (eqs 25, 27, 29) is summed.

    Parameters
    ----------
    terms : int >= 1 or None
        Number of terms; None: as many as ``tol`` needs (NumPy) or the whole series
        (``precise=True``).
    tol : float > 0 or None
        Tolerance on the truncation bound; None: :data:`DEFAULT_TOL` (eqs 25, 27),
        :data:`DEFAULT_TOL_DUHAMEL` (eq 29) or, with ``precise=True``,
        :data:`DEFAULT_TOL_PRECISE`.  Ignored when ``terms`` is given.
    precise : bool
        Sum in mpmath at ``digits`` decimal digits and return an object array of mpf;
        False: NumPy float64.
    digits : int >= 5
        Working precision of ``precise=True``.
    budget : float > 0 or None
        ``precise=True`` refuses (:class:`~dyntorsion.genalpha.guard.BudgetError`) work
        estimated above this many seconds; None: no limit.

    Raises
    ------
    ValueError
        A field out of its range, named as ``series.<field>``.
    """

    terms: int | None = None
    tol: float | None = None
    precise: bool = False
    digits: int = DEFAULT_DIGITS
    budget: float | None = MP_BUDGET_S

    def __post_init__(self) -> None:
        terms, digits = self.terms, self.digits
        if terms is not None:
            if isinstance(terms, bool) or not (isinstance(terms, int | np.integer) and terms >= 1):
                raise ValueError(f"series.terms={terms!r} must be an integer >= 1 or None")
            object.__setattr__(self, "terms", int(terms))
        if self.tol is not None:
            object.__setattr__(self, "tol", positive_number("series.tol", self.tol))
        if not isinstance(self.precise, bool | np.bool_):
            raise ValueError(f"series.precise={self.precise!r} must be True or False")
        object.__setattr__(self, "precise", bool(self.precise))
        if isinstance(digits, bool) or not (isinstance(digits, int | np.integer) and digits >= 5):
            raise ValueError(f"series.digits={digits!r} must be an integer >= 5")
        object.__setattr__(self, "digits", int(digits))
        if self.budget is not None:
            object.__setattr__(self, "budget", positive_number("series.budget", self.budget))


def checked_grid(s, t, L):
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


def term_count(
    series: Series,
    needed: Callable[[float], int],
    default_tol: float = DEFAULT_TOL,
    max_terms: int = MAX_TERMS,
) -> int:
    """Term count of ``series``: its ``terms``, or ``needed(tol)`` for its tolerance on the
    truncation bound (``default_tol`` when it has none); more than ``max_terms`` is refused."""
    if series.terms is not None:
        return series.terms
    tol = default_tol if series.tol is None else series.tol
    n = needed(tol)
    if n > max_terms:
        raise ValueError(
            f"series.tol={tol:g} needs {n} series terms (> {max_terms}); loosen series.tol, "
            "pass series.terms, or use the d'Alembert solution"
        )
    return max(int(n), 1)


def sqrt_lambda(n, L: float):
    """sqrt(lambda_n) = (2n - 1) pi / (2L), n = 1, 2, ..."""
    return (2 * np.asarray(n) - 1) * np.pi / (2 * L)


def chunked_sum(n_terms: int, term: Callable[[np.ndarray], np.ndarray], shape) -> np.ndarray:
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


def check_mp_budget(units: float, unit_s: float, series: Series, lower: str) -> None:
    """Refuse (:class:`BudgetError`) an mpmath evaluation of ``units`` evaluations of
    ``unit_s`` seconds each (at 35 digits) whose estimated time exceeds ``series.budget``
    seconds (None: no limit)."""
    if series.budget is None:
        return
    estimate = units * unit_s * max(1.0, series.digits / DEFAULT_DIGITS)
    if estimate > series.budget:
        raise BudgetError(
            f"series.precise=True: about {units:.3g} mpmath evaluations, an estimated {estimate:.3g} s "
            f"(> series.budget={series.budget:g} s); {lower}, use series.precise=False, or raise "
            "series.budget (None: no limit)"
        )


def mp_array(fn, s, t, digits: int) -> np.ndarray:
    with mpmath.workdps(digits):
        vals = [
            fn(mpmath.mpf(float(si)), mpmath.mpf(float(ti)))
            for si, ti in zip(s.ravel(), t.ravel(), strict=True)
        ]
    return np.array(vals, dtype=object).reshape(s.shape)
