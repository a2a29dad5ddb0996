"""The initial state as a choice (issue 35, item 6).  Section 6 starts the rod
unstressed, y(s, 0) = 0, so with kappa0 = 10 the end twist jumps to kappa0 at t = 0;
section 5 pretwists the rod by C h(0) (eq 23: kappa(s, 0) = h(0)).  The replication
pretwists uniformly (:mod:`dyntorsion.buckling.simulation`: k3 = kappa3(0, 0) along the
rod).  Three starts of the Fig 10 ramp kappa3(0, t) = kappa0 + a t:

* ``"pretwisted"``: the rod twisted uniformly by kappa0 at rest (the map's scenes);
* ``"step"``: the rod unstressed, the end twist kappa0 + a t for t > 0 (a jump of
  kappa0 at the end, section 6 read literally);
* ``"smooth ramp"``: the rod unstressed, the end twist kappa0 S(t / tau) + a t with S
  the C2 smooth step x^3 (10 - 15 x + 6 x^2) over :data:`TAU` (a short ramp to kappa0,
  as section 5 smooths the twist release).

Each start is a :class:`~dyntorsion.buckling.loading.Custom` history of the scene
(``"pretwisted"`` is the paper's ramp), so its records are keyed like any other.
"""

from __future__ import annotations

import numpy as np

from ..buckling.loading import Custom, History, Ramp

__all__ = ["STARTS", "TAU", "step_start", "smooth_start", "history"]

#: the starts of the rod, in the order of the tables
STARTS: tuple[str, ...] = ("pretwisted", "step", "smooth ramp")
#: the time [s] of the smooth ramp to kappa0: two periods of the first torsional mode
#: (2 x 4 L / c = 0.139 s for the paper's rod)
TAU = 0.14


def step_start(t: np.ndarray, kappa0: float, a: float) -> np.ndarray:
    """kappa3(0, t) = kappa0 + a t for t > 0, 0 at t = 0 (the unstressed rod)."""
    return np.where(t > 0.0, kappa0 + a * t, 0.0)


def smooth_start(t: np.ndarray, kappa0: float, a: float, tau: float) -> np.ndarray:
    """kappa3(0, t) = kappa0 S(t / tau) + a t, S(x) = x^3 (10 - 15 x + 6 x^2) on [0, 1]
    and 1 beyond (C2: the end twist and its first two rates start from the unstressed
    rod's)."""
    x = np.clip(t / tau, 0.0, 1.0)
    return kappa0 * x**3 * (10.0 - 15.0 * x + 6.0 * x**2) + a * t


def history(start: str, a: float, kappa0: float) -> History:
    """The end-twist history of ``start`` (:data:`STARTS`) for the ramp kappa0 + a t."""
    if start == "pretwisted":
        return Ramp(a=a, kappa0=kappa0)
    if start == "step":
        return Custom("step start", step_start, {"kappa0": kappa0, "a": a})
    if start == "smooth ramp":
        return Custom("smooth start", smooth_start, {"kappa0": kappa0, "a": a, "tau": TAU})
    raise ValueError(f"start={start!r}; allowed: {', '.join(STARTS)}")
