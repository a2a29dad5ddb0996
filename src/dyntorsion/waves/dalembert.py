"""Closed-form d'Alembert solutions of the three problems of section 5 (travelling
fronts with their reflections): an independent check of the series."""

from __future__ import annotations

import mpmath
import numpy as np

from ..genalpha.guard import BudgetError
from .checks import MAX_IMAGES, checked_grid, checked_scale, finite_number
from .transitions import DEFAULT_TRANSITION, Transition


def _images(t, s, c, L, disturbance, from_left: bool, n_max: int | None = None):
    """Sum of travelling images of a boundary disturbance phi (phi = 0 for t <= 0).

    from_left (Dirichlet at 0, Neumann at L):  sum_k (-1)^k [phi(t - (2kL + s)/c) + phi(t - (2(k+1)L - s)/c)]
    from the right (Neumann at 0, Dirichlet at L): sum_k (-1)^k [phi(t - ((2k+1)L - s)/c) + phi(t - ((2k+1)L + s)/c)]
    """
    t = np.asarray(t, float)
    k_max = int(np.max(c * t / (2 * L))) + 1 if n_max is None else n_max
    if (k_max + 1) * max(1, t.size) > MAX_IMAGES:
        raise BudgetError(
            f"t={np.max(t):.4g} s (the latest time) is {k_max} wave transits 2L/c: {k_max + 1} images x "
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


def _images_mp(s, t, c, L, disturbance, from_left: bool, digits: int, period=None):
    """:func:`_images` in mpmath, point by point (object array of mpf): the check of the
    mpmath series (``Series(precise=True)``).  ``period``: t is first reduced modulo it (in mpmath);
    ``disturbance(tau, period_shift)`` gets the retarded time and the subtracted multiple."""
    if not (isinstance(digits, int | np.integer) and digits >= 5):
        raise ValueError(f"digits={digits!r} must be an integer >= 5 or None")
    k_max = int(np.max(c * (t if period is None else np.minimum(t, period)) / (2 * L))) + 1
    if (k_max + 1) * max(1, t.size) > MAX_IMAGES:
        raise BudgetError(
            f"t={np.max(t):.4g} s (the latest time) is {k_max} wave transits 2L/c: {k_max + 1} images x "
            f"{t.size} points exceeds {MAX_IMAGES:.3g}; pass earlier times or fewer points"
        )
    out = np.empty(np.broadcast(s, t).shape, dtype=object)
    with mpmath.workdps(digits + 10):
        mc, mL = mpmath.mpf(c), mpmath.mpf(L)
        for idx in np.ndindex(out.shape):
            ms, mt = mpmath.mpf(float(s[idx])), mpmath.mpf(float(t[idx]))
            shift = mpmath.mpf(0)
            if period is not None:
                P = 4 * mL / mc
                shift = mpmath.floor(mt / P) * P
                mt -= shift
            total = mpmath.mpf(0)
            for k in range(int(mt * mc / (2 * mL)) + 2):
                if from_left:
                    d1, d2 = 2 * k * mL + ms, 2 * (k + 1) * mL - ms
                else:
                    d1, d2 = (2 * k + 1) * mL - ms, (2 * k + 1) * mL + ms
                total += (-1) ** k * (disturbance(mt - d1 / mc) + disturbance(mt - d2 / mc))
            out[idx] = (total, shift)
    return out


def linear_loading_dalembert(
    s,
    t,
    *,
    a: float,
    kappa0: float = 0.0,
    c: float,
    L: float,
    digits: int | None = None,
):
    """Closed form of eq (23) with h = kappa0 + a t: kappa0 plus travelling ramps a (t - d/c)_+
    with reflections (same sign at the free end s = L, opposite at the driven end s = 0).
    ``digits`` (an integer >= 5): in mpmath at that many digits (object array of mpf);
    None: NumPy float64."""
    c, L = checked_scale("c", c), checked_scale("L", L)
    a, kappa0 = finite_number("a", a), finite_number("kappa0", kappa0)
    s, t = checked_grid(s, t, L)
    if digits is not None:
        ma = mpmath.mpf(a)
        parts = _images_mp(s, t, c, L, lambda tau: ma * max(tau, 0), True, digits, period=4 * L / c)
        return _finish(parts, lambda v, shift: kappa0 + ma * shift + v, digits)
    # kappa - a t has the period 4L/c of eq (25): evaluate within one period
    t_r = np.mod(t, 4 * L / c)
    ramp = lambda tau: a * np.maximum(tau, 0.0)  # noqa: E731
    return kappa0 + a * (t - t_r) + _images(t_r, s, c, L, ramp, from_left=True)


def instant_release_dalembert(
    s, t, *, kappa0: float, c: float, L: float, digits: int | None = None
):
    """Closed form of eq (26): kappa0 minus travelling steps; on a front the mean of both sides.
    ``digits`` (an integer >= 5): in mpmath at that many digits (object array of mpf);
    None: NumPy float64."""
    c, L = checked_scale("c", c), checked_scale("L", L)
    kappa0 = finite_number("kappa0", kappa0)
    s, t = checked_grid(s, t, L)
    if digits is not None:
        mk = mpmath.mpf(kappa0)

        def step(tau):
            return -mk if tau > 0 else (-mk / 2 if tau == 0 else 0)

        parts = _images_mp(s, t, c, L, step, False, digits, period=4 * L / c)
        return _finish(parts, lambda v, shift: mk + v, digits)
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
    digits: int | None = None,
):
    """Closed form of eq (28): kappa0 + travelling copies of kappa0 (f(rate t) - 1).
    ``digits`` (an integer >= 5): in mpmath at that many digits (object array of mpf);
    None: NumPy float64."""
    c, L = checked_scale("c", c), checked_scale("L", L)
    s, t = checked_grid(s, t, L)
    if digits is not None:
        mk, mr = mpmath.mpf(kappa0), mpmath.mpf(rate)
        parts = _images_mp(s, t, c, L, lambda tau: mk * (f.mp(mr * tau) - 1), False, digits)
        return _finish(parts, lambda v, shift: mk + v, digits)
    return kappa0 + _images(t, s, c, L, lambda tau: kappa0 * (f(rate * tau) - 1.0), from_left=False)


def _finish(parts, combine, digits):
    out = np.empty(parts.shape, dtype=object)
    with mpmath.workdps(digits):
        for idx in np.ndindex(parts.shape):
            out[idx] = +combine(*parts[idx])
    return out
