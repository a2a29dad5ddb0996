"""Closed-form d'Alembert solutions of the three problems of section 5 (travelling
fronts with their reflections): an independent check of the series."""

from __future__ import annotations

import numpy as np

from ..genalpha.guard import BudgetError
from .checks import MAX_IMAGES, _finite, _grid, _scale
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
