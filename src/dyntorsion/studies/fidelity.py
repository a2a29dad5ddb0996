"""Fidelity presets: the grid and scheme of every expensive scene, by name.

``quick`` is for CI and first looks, ``standard`` is what the figures use (the
paper's own grid for the buckling scenes), and ``fine`` gives grid-independent
headline numbers.  (``fine`` was called ``paper`` before; the old name is refused
with a message naming the new one.)  The measured error and wall
time of each preset are on the "Accuracy and cost" page of the documentation
(errors against the exact solutions for the waves, against the finest grid of a
ladder for the buckling onset).  An explicit :class:`Fidelity` is accepted
wherever a preset name is::

    from dyntorsion import buckling
    from dyntorsion.studies import fidelity
    f = fidelity.get("buckling", "quick")            # or Fidelity(n_cells=80, dt=0.004)
    run = buckling.simulate(Scene(a=1.6, t_end=30.0, **f.simulate_kwargs()))

``DYNTORSION_FIDELITY`` (environment) sets the level :func:`level` returns, so
the notebooks can be built at ``quick`` fidelity.

The presets are measured on the rod of Table 1; for another rod, ``get(scene, level,
rod)`` keeps the number of cells and scales the time step with the rod's own time
scales (:func:`time_scale`), so that a steel wire or an elliptic rod runs at every
level with the same resolution in its own units.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from typing import Any

from ..genalpha import Scheme, parameters
from ..model.rod import Rod

__all__ = ["Fidelity", "LEVELS", "PRESETS", "RENAMED", "check_level", "get", "level", "time_scale"]

#: the named levels, cheapest first
LEVELS: tuple[str, ...] = ("quick", "standard", "fine")
#: old level name -> new one
RENAMED: dict[str, str] = {"paper": "fine"}


@dataclass(frozen=True)
class Fidelity:
    """Cells along the rod, time step [s], and lambda_infinity in space and time (eq 13)."""

    n_cells: int
    dt: float
    lam_s: float = -1.0
    lam_t: float = -1.0

    def __post_init__(self) -> None:
        if not isinstance(self.n_cells, int) or self.n_cells < 2:
            raise ValueError(f"n_cells={self.n_cells!r} must be an integer >= 2")
        if not (math.isfinite(self.dt) and self.dt > 0):
            raise ValueError(f"dt={self.dt!r} must be > 0")
        for name in ("lam_s", "lam_t"):
            try:
                parameters(getattr(self, name))
            except ValueError as err:
                raise ValueError(f"{name}: {err}") from None

    def scheme(self) -> Scheme:
        return Scheme(lam_s=self.lam_s, lam_t=self.lam_t)

    def simulate_kwargs(self) -> dict[str, Any]:
        """Keywords for :func:`dyntorsion.buckling.simulation.simulate` and :class:`dyntorsion.buckling.scene.Scene`."""
        return {"n_cells": self.n_cells, "dt": self.dt, "scheme": self.scheme()}

    def solve_kwargs(self) -> dict[str, Any]:
        """Keywords for :func:`dyntorsion.waves.solve`."""
        return {"n_cells": self.n_cells, "dt": self.dt, "lam_s": self.lam_s, "lam_t": self.lam_t}

    def courant(self, c: float, length: float) -> float:
        return c * self.dt / (length / self.n_cells)


#: The Fidelity of each level for each scene family: ``waves`` is the smooth-release
#: scene (Fig 6), ``waves-incompatible`` the linear loading and instant release (Figs 3,
#: 4), whose exact solutions jump, so finer grids, and ``buckling`` Figs 7-10 and the sweeps.
PRESETS: dict[str, dict[str, Fidelity]] = {
    "waves": {
        "quick": Fidelity(50, 0.01),
        "standard": Fidelity(100, 0.005),
        "fine": Fidelity(400, 0.00125),
    },
    "waves-incompatible": {
        "quick": Fidelity(100, 0.005),
        "standard": Fidelity(500, 0.001),
        "fine": Fidelity(2000, 0.00025),
    },
    "buckling": {
        "quick": Fidelity(50, 0.01),
        "standard": Fidelity(100, 0.005),
        "fine": Fidelity(200, 0.0025),
    },
}


def level() -> str:
    """The fidelity level of this process: ``DYNTORSION_FIDELITY`` or ``"standard"``."""
    return check_level(os.environ.get("DYNTORSION_FIDELITY", "standard"), "DYNTORSION_FIDELITY")


def check_level(name: str, what: str = "fidelity") -> str:
    """``name`` if it is one of :data:`LEVELS`, else a ValueError naming ``what``."""
    if name in RENAMED:
        raise ValueError(f"{what}={name!r} was renamed: use {RENAMED[name]!r}")
    if name not in LEVELS:
        raise ValueError(f"{what}={name!r}; allowed: {', '.join(LEVELS)}")
    return name


def time_scale(scene: str, rod: Rod) -> float:
    """How much shorter (< 1) or longer the time step of ``scene`` is for ``rod`` than for
    the rod of Table 1: the torsional transit time L/c for the wave scenes (the same
    Courant number), and for buckling the smaller of the ratios of the transit time and
    of the bending time T0 (both motions resolved as well as for Table 1).  1.0 exactly
    for Table 1."""
    ref = Rod.paper()
    transit = rod.transit / ref.transit
    if scene.startswith("waves"):
        return transit
    return min(transit, rod.T0 / ref.T0)


def get(scene: str, fidelity: str | Fidelity | None = None, rod: Rod | None = None) -> Fidelity:
    """The :class:`Fidelity` of ``scene`` at a named level (default :func:`level`), or
    ``fidelity`` itself when it is already one.  With ``rod``, a named level's time step
    is scaled to that rod (:func:`time_scale`)."""
    if isinstance(fidelity, Fidelity):
        return fidelity
    if scene not in PRESETS:
        raise ValueError(f"scene={scene!r}; allowed: {', '.join(PRESETS)}")
    name = level() if fidelity is None else check_level(fidelity)
    f = PRESETS[scene][name]
    if rod is None:
        return f
    factor = time_scale(scene, rod)
    return f if factor == 1.0 else Fidelity(f.n_cells, f.dt * factor, f.lam_s, f.lam_t)
