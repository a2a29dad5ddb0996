"""Bookkeeping of a run around the compiled march: records, chunk ends and sources.

What a run records and keeps, where its chunks of steps end, and its sources:
the bookkeeping of :func:`~.integrate.integrate` around the compiled march."""

from __future__ import annotations

import bisect
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from .initial import consistent_rates
from .march import NO_GATE, Forcing, Gate, StepContext, make_gate
from .watch import CompiledStop

__all__ = ["QUIET_CHUNK", "Levels", "Plan", "Source", "gate_of", "initial_rate"]

#: the longest chunk of steps marched in one compiled call while a gate is open
QUIET_CHUNK = 4096


@dataclass(frozen=True)
class Source:
    """q(s, t) = q_space(s) q_time(t) + field(s, t)  (either part may be absent)."""

    s: np.ndarray
    q_space: np.ndarray
    q_time: Callable[[np.ndarray], np.ndarray]
    field: Callable[[np.ndarray, float], np.ndarray] | None

    @classmethod
    def of(cls, s, nf, source, source_field) -> Source:
        q_space = np.zeros((s.size, nf))
        q_time: Callable[[np.ndarray], np.ndarray] = np.ones_like
        if source is not None:
            q_space = np.ascontiguousarray(source[0], dtype=float)
            if q_space.shape != (s.size, nf):
                raise ValueError(
                    f"source space part has shape {q_space.shape}, expected {(s.size, nf)}"
                )
            if source[1] is not None:
                q_time = source[1]
        return cls(s, q_space, q_time, source_field)

    def time_factor(self, tt: np.ndarray) -> np.ndarray:
        return np.array(np.broadcast_to(np.asarray(self.q_time(tt), float), tt.shape), order="C")

    def field_at(self, tt: np.ndarray) -> np.ndarray:
        if self.field is None:
            return np.zeros((0, 0, 0))
        return np.ascontiguousarray([self.field(self.s, float(ti)) for ti in tt], dtype=float)

    def at(self, t: float) -> np.ndarray:
        q = self.q_space * float(np.asarray(self.q_time(np.array([t])))[0])
        if self.field is not None:
            q = q + self.field(self.s, t)
        return q


@dataclass(frozen=True)
class Levels:
    """The time levels t_i of the fixed grid and the boundary values and source at each."""

    times: np.ndarray
    gL: np.ndarray
    gR: np.ndarray
    q_time: np.ndarray
    src: Source

    @classmethod
    def of(cls, times: np.ndarray, left, right, src: Source) -> Levels:
        return cls(times, left.at(times), right.at(times), src.time_factor(times), src)

    def forcing(self, index) -> Forcing:
        """The :class:`~.march.Forcing` of the levels ``index`` (a slice or an index array)."""
        return Forcing(
            self.gL[index],
            self.gR[index],
            self.src.q_space,
            self.q_time[index],
            self.src.field_at(self.times[index]),
        )


class RunParts(NamedTuple):
    """What the stepping parts of one run share (:mod:`.stepping`): the model ``system``,
    the ``scheme``, the ``grid``, the boundary rows ``left`` and ``right``, the boundary
    values and sources at the fixed levels ``levels`` and the step's context ``ctx``."""

    system: Any
    scheme: Any
    grid: Any
    left: Any
    right: Any
    levels: Levels
    ctx: StepContext


def initial_rate(system, y0, ds, y_t0, source: Source, t0) -> np.ndarray:
    if not isinstance(y_t0, str):
        rate0 = np.array(y_t0, dtype=float)
        if rate0.shape != y0.shape or not np.all(np.isfinite(rate0)):
            raise ValueError(f"y_t0 must be a finite array of shape {y0.shape}")
        return rate0
    if y_t0 == "zero":
        return np.zeros_like(y0)
    if y_t0 == "consistent":
        return consistent_rates(system, y0, ds, source.at(t0))
    raise ValueError(f"y_t0={y_t0!r}; allowed: an array, 'consistent', 'zero'")


@dataclass(frozen=True)
class Plan:
    """What to record and keep, where ``stop`` is due (every ``check`` steps, at the
    snapshots and at the last level) and where the chunks of steps end: at every check,
    or, for a :class:`~.watch.CompiledStop` that the march consults itself
    (``compiled``), only at the snapshots, at most :data:`QUIET_CHUNK` steps on."""

    names: tuple[str, ...]
    fields: np.ndarray
    nodes: np.ndarray
    every: int
    snap_steps: list[int]
    n_steps: int
    check: int
    compiled: bool

    @classmethod
    def of(cls, system, grid, n_steps: int, output, stops) -> Plan:
        """The plan of a run of ``system`` on the :class:`~.parts.Grid` ``grid`` in
        ``n_steps`` steps, keeping what the :class:`~.parts.Output` ``output`` asks and
        consulting the :class:`~.parts.Stops` ``stops``; a ValueError names a record node,
        snapshot or ``check_every`` out of range."""
        n1, t0, dt = grid.n_cells + 1, grid.t0, grid.dt
        record, record_every, snapshots = output.record, output.every, output.snapshots
        stop, check_every = stops.test, stops.check_every
        rec = dict(record or {})
        fields = np.array([system.index(f) for f, _ in rec.values()], dtype=np.int64)
        nodes = np.array(
            [int(n) % n1 if -n1 <= int(n) < n1 else -1 for _, n in rec.values()], dtype=np.int64
        )
        if np.any(nodes < 0):
            raise ValueError(f"record: node indices must be in [-{n1}, {n1})")
        snap_steps = sorted({int(round((ts - t0) / dt)) for ts in snapshots})
        if any(k < 0 or k > n_steps for k in snap_steps):
            t_end = t0 + n_steps * dt
            raise ValueError(f"snapshots must lie in [t0, t_end] = [{t0}, {t_end}]")
        check = n_steps if (stop is None and check_every is None) else (check_every or 100)
        if check < 1:
            raise ValueError(f"check_every={check_every!r} must be >= 1")
        return cls(
            tuple(rec), fields, nodes, record_every, snap_steps, n_steps, check,
            isinstance(stop, CompiledStop),
        )  # fmt: skip

    def due(self, k: int) -> bool:
        """Whether ``stop`` is due at level k."""
        return k % self.check == 0 or k == self.n_steps or k in self.snap_steps

    def next_end(self, k0: int, quiet: bool) -> int:
        """Where the chunk from level k0 ends: the next level where ``stop`` is due, or,
        while ``quiet`` (the gate below its limit: no check is due) or with a compiled
        stop, the next snapshot, at most :data:`QUIET_CHUNK` steps on."""
        if quiet or self.compiled:
            return min(self.landing(k0), k0 + QUIET_CHUNK)
        return min(self.landing(k0), (k0 // self.check + 1) * self.check)

    def landing(self, k0: int) -> int:
        """The next level after k0 that a run must land on: a snapshot or the last."""
        i = bisect.bisect_right(self.snap_steps, k0)
        return self.snap_steps[i] if i < len(self.snap_steps) else self.n_steps


def gate_of(system, stop_gate, ds: float, stop) -> Gate:
    """The compiled :class:`~.march.Gate` of ``integrate(stops=Stops(gate=(fields, limit)))``."""
    if stop_gate is None or stop is None:
        return NO_GATE
    names, limit = stop_gate
    if not (isinstance(limit, int | float) and limit > 0):
        raise ValueError(f"stop_gate limit={limit!r} must be a number > 0")
    fields = np.array([system.index(f) for f in names], dtype=np.int64)
    return make_gate(fields, ds, limit)
