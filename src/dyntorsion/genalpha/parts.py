"""A run's inputs: the problem, its grid, sources, output and stop tests.

The parts :func:`~.integrate.integrate` takes: what is solved (:class:`Problem`: the model,
the boundary rows and source of eq (7) and the initial state), where and when
(:class:`Grid`), the source q(s, t) of eq (7) (:class:`Sources`), what is kept
(:class:`Output`) and when a run may end before t_end (:class:`Stops`).  With the
:class:`~.scheme.Scheme` (eq 13 and its options) and the :class:`~.newton.Newton` solve
they are the whole description of a run; each part checks its own values when it is
made."""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..model.system import Boundary, System
from .guard import check_time_grid
from .watch import CompiledStop

__all__ = ["Problem", "Grid", "Sources", "Output", "Stops"]


@dataclass(frozen=True)
class Grid:
    """The space-time grid: nodes s_j = j ds, j = 0..N, ds = length / N, and time levels
    t_i = t0 + i dt up to t_end (the run takes ceil((t_end - t0) / dt) steps)."""

    n_cells: int
    length: float
    dt: float
    t_end: float
    t0: float = 0.0

    def __post_init__(self) -> None:
        n = self.n_cells
        if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < 2:
            raise ValueError(f"n_cells={n!r} must be an integer >= 2")
        length = self.length
        if not (
            isinstance(length, int | float | np.floating | np.integer)
            and math.isfinite(length)
            and length > 0
        ):
            raise ValueError(f"length={length!r} must be a finite number > 0")
        check_time_grid(self.dt, self.t_end, self.t0)
        object.__setattr__(self, "n_cells", int(n))

    @property
    def ds(self) -> float:
        return self.length / self.n_cells

    @property
    def s(self) -> np.ndarray:
        """The nodes s_j (N + 1)."""
        return np.linspace(0.0, self.length, self.n_cells + 1)


@dataclass(frozen=True)
class Sources:
    """The source q(s, t) of eq (7): ``separable`` = (q_space (N+1, nf), g) for
    q = q_space(s) g(t) (g maps an array of times to an array; None means g = 1), and/or
    ``field``, a callable (s, t) -> (N+1, nf) for a general source, and/or ``state``, a
    :class:`~.state.StateSource` whose source depends on the new level itself (solved inside
    each step, :mod:`.state_steps`)."""

    separable: tuple[np.ndarray, Callable[[np.ndarray], np.ndarray] | None] | None = None
    field: Callable[[np.ndarray, float], np.ndarray] | None = None
    state: Any = None


@dataclass(frozen=True)
class Problem:
    """Eq (7) with its data: the model ``system``, the initial state ``y0`` (N+1, nf), the
    boundary rows ``left`` at s = 0 and ``right`` at s = length (nb_left + nb_right = nf),
    the source ``sources`` and the initial rate ``y_t0``: an array (N+1, nf),
    ``"consistent"`` (from the equations, :func:`~.plan.initial_rate`) or ``"zero"``.

    At lam_t = -1 the rows without a time derivative (inextensibility) obey R^i = -R^{i-1}
    in time, so a y0 that violates their discrete form keeps an undamped (-1)^i
    oscillation that resonates with the multiplier n; pass such data through
    :func:`~.initial.consistent_initial_state` first.  The paper's straight initial states
    satisfy the discrete equations exactly."""

    system: System
    y0: np.ndarray
    left: Boundary
    right: Boundary
    sources: Sources = Sources()
    y_t0: np.ndarray | str = "consistent"


@dataclass(frozen=True)
class Output:
    """What a run keeps: ``record`` maps a name to (field, node), recorded every ``every``
    steps; the whole state at the ``snapshots`` times (nearest level); ``progress`` shows a
    bar (None: only for long runs on a terminal); ``meta`` is copied into the run."""

    record: Mapping[str, tuple[str | int, int]] | None = None
    every: int = 1
    snapshots: Sequence[float] = ()
    progress: bool | None = None
    meta: Mapping[str, Any] | None = None

    def __post_init__(self) -> None:
        if isinstance(self.every, bool) or not (isinstance(self.every, int) and self.every >= 1):
            raise ValueError(f"record_every={self.every!r} must be an integer >= 1")


@dataclass(frozen=True)
class Stops:
    """When a run ends before t_end.  ``test``: a callable (t, y) -> reason or None,
    checked every ``check_every`` steps (and at the snapshots), or a
    :class:`~.watch.CompiledStop` consulted at the same levels by the compiled march.
    ``gate`` = (fields, limit): ``test`` is known to return None at every level y with
    ``ds * sum_j norm(y_j[fields]) < limit``; until that sum reaches ``limit`` (checked after
    every step, in compiled code) it is not called and the steps run in long chunks."""

    test: Callable[[float, np.ndarray], str | None] | CompiledStop | None = None
    check_every: int | None = None
    gate: tuple[Sequence[str], float] | None = None
