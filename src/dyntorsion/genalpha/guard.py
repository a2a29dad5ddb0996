"""Checks before a run starts: the time grid and the memory and time it will need.

Checks made before a run starts: the time grid (dt, t_end, snapshots, check
interval) and the memory the run will allocate, so bad input is refused with its name
and allowed range before anything is computed."""

from __future__ import annotations

import math
import os
import sys
from collections.abc import Sequence

import numpy as np

__all__ = [
    "BudgetError",
    "StepLongerThanRunError",
    "real",
    "check_time_grid",
    "check_memory",
    "available_memory",
    "run_bytes",
    "MEMORY_FRACTION",
]

#: a run may allocate at most this fraction of the memory available when it starts
MEMORY_FRACTION = 0.5
#: the smallest time step (the step's coefficients scale like 1/dt^2)
DT_MIN = 1e-15


class BudgetError(ValueError):
    """A computation refused before it starts because its estimated work or memory
    exceeds the budget; the message gives the estimate and how to lower it."""


class StepLongerThanRunError(ValueError):
    """A time step longer than the whole run (dt > t_end - t0): refused before a step."""


def _real(value) -> bool:
    return isinstance(value, int | float | np.integer | np.floating) and not isinstance(value, bool)


def real(name: str, value, unit: str = "") -> float:
    """``value`` as a float, or a TypeError (not a real number) or ValueError (not
    finite) naming ``name``."""
    if not _real(value):
        raise TypeError(
            f"{name}={value!r} must be a finite real number{unit}, not {type(value).__name__}"
        )
    if not math.isfinite(value):
        raise ValueError(f"{name}={value!r} must be a finite real number{unit}")
    return float(value)


def check_time_grid(
    dt, t_end, t0: float = 0.0, snapshots: Sequence[float] = (), check_every=None
) -> int:
    """The number of steps ceil((t_end - t0) / dt), after checking that dt and t_end are
    finite numbers with 0 < dt <= t_end - t0, the snapshot times finite and in
    [t0, t_end], and ``check_every`` None or an integer >= 1."""
    if not (_real(dt) and math.isfinite(dt) and dt >= DT_MIN):
        raise ValueError(f"dt={dt!r} must be a finite number >= {DT_MIN:g} s")
    if not (_real(t0) and math.isfinite(t0)):
        raise ValueError(f"t0={t0!r} must be a finite number [s]")
    if not (_real(t_end) and math.isfinite(t_end) and t_end > t0):
        raise ValueError(f"t_end={t_end!r} must be a finite number > t0={t0!r} [s]")
    dt, t_end, t0 = float(dt), float(t_end), float(t0)
    if dt > t_end - t0:
        raise StepLongerThanRunError(
            f"dt={dt!r} exceeds the run's length t_end - t0 = {t_end - t0!r}: allowed 0 < dt <= "
            "t_end - t0 (the run would step past t_end)"
        )
    try:
        snaps = np.asarray(list(snapshots), dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"snapshots={snapshots!r} must be a sequence of times [s]") from None
    if check_every is not None and not (
        isinstance(check_every, int | np.integer)
        and not isinstance(check_every, bool)
        and check_every >= 1
    ):
        raise ValueError(f"check_every={check_every!r} must be None or an integer >= 1")
    steps = (t_end - t0) / dt
    if steps > 2**53:
        raise ValueError(
            f"dt={dt!r} and t_end={t_end!r} make {steps:.3g} steps (more than 2^53): raise dt"
        )
    n_steps = max(1, int(math.ceil(steps * (1.0 - 1e-12))))
    if snaps.size:
        k = np.round((snaps - t0) / dt) if np.all(np.isfinite(snaps)) else np.array([-1.0])
        if k.min() < 0 or k.max() > n_steps:
            raise ValueError(
                f"snapshots={snaps.tolist()!r} must be finite times in [t0, t_end] = "
                f"[{t0}, {t_end}] (each is taken at the nearest time level)"
            )
    return n_steps


def available_memory() -> int | None:
    """Bytes of memory available to a new allocation (MemAvailable of /proc/meminfo,
    else the free physical pages), or None where neither is known."""
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return None


def run_bytes(n_steps: int, n_nodes: int, nf: int, n_recorded: int, n_snapshots: int) -> int:
    """What a run allocates up front and while it records, in bytes: per step its time,
    boundary data (nf rows), source factor, statistics (5) and recorded traces; per
    snapshot a whole field; the Jacobian blocks, their factors and explicit operators
    and the work arrays (about 12 nf^2 per node)."""
    per_step = 8 * (1 + nf + 1 + 5 + n_recorded)
    return int(per_step * (n_steps + 1) + 8 * n_nodes * nf * (n_snapshots + 12 * nf + 16))


def check_memory(n_steps: int, n_nodes: int, nf: int, n_recorded: int, n_snapshots: int) -> None:
    """Refuse (:class:`BudgetError` with the estimate and how to lower it) a run whose arrays
    exceed :data:`MEMORY_FRACTION` of the available memory."""
    need = run_bytes(n_steps, n_nodes, nf, n_recorded, n_snapshots)
    avail = available_memory()
    if avail is None or need <= MEMORY_FRACTION * avail:
        return
    raise BudgetError(
        f"the run needs about {need / 2**30:.3g} GiB ({n_steps} time steps x {n_nodes} nodes, "
        f"{n_snapshots} snapshots), over the limit of {MEMORY_FRACTION:.0%} of the "
        f"{avail / 2**30:.3g} GiB available: raise dt, "
        "shorten t_end, or keep fewer snapshots"
    )


#: wall time of one step per node and field [s]: about three times the cost `make bench`
#: measures (``benchmarks/bench_engine.py``, the Benchmarks page), so that step control,
#: retries and a slower machine stay under the estimate
SECONDS_PER_NODE_FIELD_STEP = 0.3e-6
#: runs estimated longer than this are announced before they start [s]
ANNOUNCE_AFTER_S = 30.0
#: the default budget of one run [s]; ``DYNTORSION_MAX_TIME`` (or the CLI's --max-time) sets it
DEFAULT_MAX_TIME_S = 6 * 3600.0


def run_seconds(n_steps: int, n_nodes: int, nf: int) -> float:
    """An upper estimate of a run's wall time from its steps and grid."""
    return SECONDS_PER_NODE_FIELD_STEP * n_steps * n_nodes * nf


def max_time() -> float:
    """The run-time budget: ``$DYNTORSION_MAX_TIME`` [s] if set, else the default."""
    raw = os.environ.get("DYNTORSION_MAX_TIME")
    if raw is None:
        return DEFAULT_MAX_TIME_S
    try:
        value = float(raw)
    except ValueError:
        value = math.nan
    if not value > 0:
        raise ValueError(f"DYNTORSION_MAX_TIME={raw!r} must be a number of seconds > 0")
    return value


def check_time(n_steps: int, n_nodes: int, nf: int, say=None) -> float:
    """Refuse (:class:`BudgetError`, with the estimate and what to change) a run estimated
    longer than :func:`max_time`; announce one longer than :data:`ANNOUNCE_AFTER_S`
    through ``say`` (default: one line on stderr).  Returns the estimate [s]."""
    need = run_seconds(n_steps, n_nodes, nf)
    budget = max_time()
    if need > budget:
        raise BudgetError(
            f"the run is estimated at {_duration(need)} ({n_steps} time steps x {n_nodes} "
            f"nodes x {nf} fields), over the budget of {_duration(budget)}: raise dt, use "
            "fewer cells, shorten t_end, or raise the budget (--max-time or DYNTORSION_MAX_TIME)"
        )
    if need > ANNOUNCE_AFTER_S:
        (say or _stderr)(
            f"dyntorsion: this run may take up to {_duration(need)} ({n_steps} steps x "
            f"{n_nodes} nodes; budget {_duration(budget)})"
        )
    return need


def _duration(seconds: float) -> str:
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


def _stderr(message: str) -> None:
    print(message, file=sys.stderr)
