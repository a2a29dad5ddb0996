"""Could the run have seen the instability?  A run that ends without an onset is either an
answer (the rod stayed straight) or a grid too coarse for the growth it had to show
``"unresolved"``, with the grid that would resolve it.

The growth is judged locally, as the straight rod twisted to kappa3(0, t) now: a bending
wave e^{i k s + lambda t} of the twisted, axially loaded rod (the linearised Kirchhoff
equations of section 6, isotropic, B the weaker stiffness, M = C kappa the twisting
moment, T the tension) grows at

    rho A lambda^2 = k^3 (M - B k) - T k^2,

fastest at k* (the largest root of 4 B k^2 - 3 M k + 2 T = 0).  On the clamped rod only
waves with k >= k_min, the wave number at which the static theory's critical twist is
reached (kappa_cri: lambda = 0 there), count.  The run has amplified its seed by
exp(A(t)), A(t) = int lambda dt; at the first time A reaches :data:`EFOLDS` the growth is
under way whatever the seed, and the run must resolve the fastest wave there: at least
:data:`CELLS_PER_WAVELENGTH` cells per wavelength 2 pi / k* and lambda dt at most
:data:`GROWTH_PER_STEP`.  A run that never got that far is too short, not unresolved; a
run without a seed never leaves the straight state and is an answer.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..model.rod import Rod

__all__ = ["EFOLDS", "CELLS_PER_WAVELENGTH", "GROWTH_PER_STEP", "Resolution", "growth", "judge"]

#: e-folds of linear growth after which an instability is under way, whatever the seed
EFOLDS = 5.0
#: cells per wavelength of the fastest bending wave a grid must have to resolve it
CELLS_PER_WAVELENGTH = 8
#: the largest lambda dt of a step that resolves the growth (lambda the growth rate)
GROWTH_PER_STEP = 0.5


def growth(rod: Rod, kappa: np.ndarray, tension: float | np.ndarray, k_min: float):
    """(lambda [1/s], k* [1/m]) of the fastest growing bending wave with k >= k_min at the
    twists ``kappa`` (0 where none grows)."""
    B, M = min(rod.B1, rod.B2), rod.C * np.abs(np.asarray(kappa, float))
    T = np.broadcast_to(np.asarray(tension, float), M.shape)
    with np.errstate(over="ignore", invalid="ignore"):  # a rod stiff past 1e150: inf, no growth
        k_star = (3 * M + np.sqrt(np.maximum(9 * M**2 - 32 * B * T, 0.0))) / (8 * B)
        k = np.maximum(k_star, k_min)
        lam2 = (k**3 * (M - B * k) - T * k**2) / rod.mass_per_length
    return np.sqrt(np.maximum(lam2, 0.0)), k


@dataclass(frozen=True)
class Resolution:
    """Where the growth was under way and what resolving it takes."""

    t: float  # the first time the seed has grown EFOLDS e-folds
    kappa3: float  # the end twist then [1/m]
    rate: float  # lambda then [1/s]
    wavelength: float  # 2 pi / k* [m]
    n_cells: int  # the fewest cells that resolve it
    dt: float  # the longest step that resolves it
    resolved: bool

    def message(self, n_cells: int, dt: float) -> str:
        return (
            f"unresolved: by t = {self.t:.4g} s (end twist {self.kappa3:.4g} 1/m) the seed has "
            f"grown {EFOLDS:g} e-folds at a rate {self.rate:.4g} 1/s in a bending wave "
            f"{self.wavelength:.3g} m long; seeing it needs n_cells >= {self.n_cells} and "
            f"dt <= {self.dt:.3g} s (this run: n_cells = {n_cells}, dt = {dt:.3g} s)"
        )


def judge(
    rod: Rod,
    t: np.ndarray,
    kappa3: np.ndarray,
    tension: np.ndarray,
    kappa_cri: float,
    n_cells: int,
    dt: float,
) -> Resolution | None:
    """The :class:`Resolution` of a run's growth, from its samples of time, end twist and
    tension, or None when the seed never grew :data:`EFOLDS` e-folds in the run."""
    B = min(rod.B1, rod.B2)
    k_min = rod.C * kappa_cri / B  # lambda = 0 at kappa_cri
    lam, k = growth(rod, kappa3, tension, k_min)
    grown = np.concatenate([[0.0], np.cumsum(0.5 * (lam[1:] + lam[:-1]) * np.diff(t))])
    past = np.nonzero(grown >= EFOLDS)[0]
    if past.size == 0:
        return None
    i = int(past[0])
    need_cells = math.ceil(CELLS_PER_WAVELENGTH * k[i] * rod.L / (2 * math.pi))
    need_dt = GROWTH_PER_STEP / lam[i]
    return Resolution(
        t=float(t[i]),
        kappa3=float(kappa3[i]),
        rate=float(lam[i]),
        wavelength=float(2 * math.pi / k[i]),
        n_cells=need_cells,
        dt=float(need_dt),
        resolved=n_cells >= need_cells and dt <= need_dt,
    )
