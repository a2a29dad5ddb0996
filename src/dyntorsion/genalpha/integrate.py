"""The driver: validation, sources, the initial rate and the plan of the run, then chunks
of steps between checks, each taken by the stepping part (:mod:`.stepping`), kept by the
recording part (:mod:`.recording`) and followed by the stopping part's checks
(:mod:`.stopping`); the :class:`Run` they make."""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from ..model.system import Boundary, System
from .discrete import setup
from .guard import check_memory, check_time, check_time_grid
from .march import full_newton_iterations
from .newton import Newton
from .plan import Levels, Plan, Source, gate_of, initial_rate
from .recording import Recorder
from .run import Run
from .scheme import Scheme
from .stepping import Stepper
from .stopping import CHUNK_WORK, Stopper, act_on, deferred_signals
from .watch import CompiledStop

__all__ = ["integrate", "newton_iteration_kernel"]


def _check_positive(name: str, value: float) -> None:
    if not (
        isinstance(value, int | float | np.floating | np.integer)
        and math.isfinite(value)
        and value > 0
    ):
        raise ValueError(f"{name}={value!r} must be a finite number > 0")


def _validate(system, n_cells, length, dt, t_end, t0, record_every, y0, left, right):
    """The arguments of :func:`integrate` that need no other context; y0 as an array."""
    if not isinstance(n_cells, int | np.integer) or n_cells < 2:
        raise ValueError(f"n_cells={n_cells!r} must be an integer >= 2")
    _check_positive("length", length)
    check_time_grid(dt, t_end, t0)
    if not (isinstance(record_every, int) and record_every >= 1):
        raise ValueError(f"record_every={record_every!r} must be an integer >= 1")
    nf = system.nf
    y0 = np.array(y0, dtype=float)
    if y0.shape != (n_cells + 1, nf):
        raise ValueError(f"y0 has shape {y0.shape}, expected (n_cells+1, nf) = {(n_cells + 1, nf)}")
    if not np.all(np.isfinite(y0)):
        raise ValueError("y0 contains NaN or inf")
    if left.rows.shape[1] != nf or right.rows.shape[1] != nf or left.nb + right.nb != nf:
        raise ValueError(
            f"boundary rows: need nb_left + nb_right = {nf} rows of {nf} columns, got "
            f"{left.rows.shape} and {right.rows.shape}"
        )
    return y0


def integrate(
    system: System,
    *,
    n_cells: int,
    length: float,
    dt: float,
    t_end: float,
    y0: np.ndarray,
    left: Boundary,
    right: Boundary,
    scheme: Scheme = Scheme(),
    t0: float = 0.0,
    y_t0: np.ndarray | str = "consistent",
    source: tuple[np.ndarray, Callable[[np.ndarray], np.ndarray] | None] | None = None,
    source_field: Callable[[np.ndarray, float], np.ndarray] | None = None,
    record: Mapping[str, tuple[str | int, int]] | None = None,
    record_every: int = 1,
    snapshots: Sequence[float] = (),
    newton: Newton = Newton(),
    stop: Callable[[float, np.ndarray], str | None] | CompiledStop | None = None,
    check_every: int | None = None,
    stop_gate: tuple[Sequence[str], float] | None = None,
    progress: bool | None = None,
    meta: Mapping[str, Any] | None = None,
) -> Run:
    """Integrate ``system`` from t0 to t_end with the generalised-alpha scheme.

    Parameters
    ----------
    n_cells : number of cells N >= 2 (nodes s_j = j * length / N).
    dt : time step > 0; the run takes ceil((t_end - t0) / dt) steps.
    y0 : initial state (N+1, nf), finite.  At lam_t = -1 the rows without a time
        derivative (inextensibility) obey R^i = -R^{i-1} in time, so a y0 that
        violates their discrete form keeps an undamped (-1)^i oscillation that
        resonates with the multiplier n; pass such data through
        :func:`consistent_initial_state` first.  The paper's straight initial
        states satisfy the discrete equations exactly.
    left, right : boundary rows at s = 0 and s = length (nb_left + nb_right = nf).
    y_t0 : initial time derivative (N+1, nf), or "consistent" (from the equations,
        see :func:`consistent_rates`), or "zero".  Irrelevant at lam_t = -1.
    source : (q_space (N+1, nf), g) for a separable source q(s, t) = q_space(s) g(t)
        (g maps an array of times to an array; None means g = 1).
    source_field : callable (s, t) -> (N+1, nf) for a general source.
    record : name -> (field, node) recorded every ``record_every`` steps.
    snapshots : times at which the whole state is kept (nearest time level).
    scheme : with ``scheme.control`` (a :class:`StepControl`) a step whose Newton solve
        fails is retried with half the step (:mod:`.control`); the fixed grid of dt
        is kept and every recorded level lies on it.  With ``scheme.long_steps`` (a
        :class:`LongSteps`) the run starts with steps of a multiple of dt while the
        solution is quiet (:mod:`.long`), recording only the levels they reach.
    stop : callable (t, y) -> reason or None, checked every ``check_every`` steps (and
        at the snapshots), or a :class:`~.watch.CompiledStop` consulted at the same
        levels by the compiled march itself.
    stop_gate : (fields, limit): ``stop`` is known to return None at every level y
        with ``ds * sum_j norm(y_j[fields]) < limit`` (the Euclidean norm over the
        fields), so until the first level at which that sum reaches ``limit`` (checked
        after every step, in compiled code) it is not called and the steps run in long
        chunks; from then on as without the gate.  Same levels, same calls of ``stop``
        where they can matter, less overhead.
    progress : show a progress bar (None: only for long runs on a terminal).
    """
    t_start = time.perf_counter()
    y0 = _validate(system, n_cells, length, dt, t_end, t0, record_every, y0, left, right)
    n_cells = int(n_cells)
    n1, nf = n_cells + 1, system.nf
    ds = length / n_cells
    s = np.linspace(0.0, length, n1)
    n_steps = check_time_grid(dt, t_end, t0, snapshots, check_every)
    check_memory(n_steps, n1, nf, len(record or {}), len(snapshots))
    check_time(n_steps, n1, nf)
    times = t0 + dt * np.arange(n_steps + 1)
    src = Source.of(s, nf, source, source_field)
    rate0 = initial_rate(system, y0, ds, y_t0, src, t0)
    con, work, fac = setup(system, scheme, n_cells, ds, dt, left, right, y0, rate0)
    plan = Plan.of(system, n1, n_steps, t0, dt, record, record_every, snapshots, stop, check_every)
    levels = Levels.of(times, left, right, src)
    ctx = (con, work, fac, newton.options())
    stepper = Stepper(system, scheme, ds, dt, left, right, levels, ctx, t0)
    recorder = Recorder(plan, times, y0, record_every)
    stopper = Stopper(stop, gate_of(system, stop_gate, ds, stop), plan, n_steps, work.y_old)
    stopped, failure, done = "t_end", None, 0
    bar = _progress_bar(progress, n_steps, n1, nf)
    cap = max(1, CHUNK_WORK // (n1 * nf))  # steps a chunk may take before Python sees a signal
    with deferred_signals() as caught:
        try:
            k0 = 0
            while k0 < n_steps:
                k1, in_long = stepper.end(k0, plan.next_end(k0, stopper.quiet), plan)
                k1 = k1 if in_long else min(k1, k0 + cap)
                stats = recorder.stats[k0:k1]
                watched = stopper.watched(in_long)
                if in_long:
                    completed = stepper.long_chunk(k0, k1, plan, stats, recorder.t, recorder.values)
                    failure = None
                else:
                    rec, steps = recorder.buffer(k0, k1)
                    gate, watch = stopper.for_chunk()
                    completed, failure = stepper.chunk(
                        k0, k1, rec, stats, gate, stopper.test, watch, times
                    )
                    recorder.keep(rec, steps, k0 + completed, t0, dt)
                done = k0 + completed
                act_on(caught)
                if failure is not None:
                    stopped = f"failed: {failure}"
                    break
                if bar is not None:
                    bar.update(completed)
                k0 = done
                recorder.level(done, work.y_old)
                reason = stopper.after(done, k1, in_long, watched, float(times[done]), work.y_old)
                if reason:
                    stopped = reason
                    break
        finally:
            if bar is not None:
                bar.close()
    t_rec, traces = recorder.traces()
    snapshot_times, snapshots = recorder.whole_states(n1, nf)
    st = recorder.stats[:done]
    result = Run(
        s=s,
        t=t_rec,
        traces=traces,
        snapshot_times=snapshot_times,
        snapshots=snapshots,
        iterations=st[:, 0].astype(int),
        residual_evaluations=st[:, 1].astype(int),
        factorisations=st[:, 2].astype(int),
        residuals=st[:, 3].copy(),
        retries=st[:, 4].astype(int),
        y=work.y_old.copy(),
        y_t=work.rate_old.copy(),
        t_final=float(times[done]),
        steps=done,
        wall_time=time.perf_counter() - t_start,
        stopped=stopped,
        names=system.names,
        substeps=stepper.substeps(done),
        rejections=stepper.rejections,
        meta={
            "n_cells": n_cells,
            "length": length,
            "dt": dt,
            "t0": t0,
            "t_end": t_end,
            "scheme": scheme.params(),
            **stepper.summary(done),
            "newton": newton.__dict__.copy(),
            **(meta or {}),
        },
    )
    if failure is not None:
        failure.run = result
        raise failure
    return result


def _progress_bar(progress: bool | None, n_steps: int, n1: int, nf: int):
    """A progress bar (None: only for long runs on a terminal), or None."""
    if progress is None:
        progress = n_steps * n1 * nf > 5e7
    if not progress:
        return None
    from tqdm.auto import tqdm

    return tqdm(total=n_steps, unit="step", disable=None, leave=False)


def newton_iteration_kernel(
    system: System,
    scheme: Scheme,
    n_cells: int,
    length: float,
    dt: float,
    left: Boundary,
    right: Boundary,
    y: np.ndarray,
):
    """A callable ``f(repeats)`` doing that many full Newton iterations of a step from
    state y inside compiled code, and the step's scaled Jacobian blocks and
    right-hand side (for benchmarks against LAPACK)."""
    y = np.ascontiguousarray(y, float)
    con, work, fac = setup(
        system, scheme, n_cells, length / n_cells, dt, left, right, y, np.zeros_like(y)
    )
    gL, gR = left.at(np.array([dt]))[0], right.at(np.array([dt]))[0]

    def iteration(repeats: int = 1) -> float:
        return full_newton_iterations(system.F, system.dF, con, gL, gR, work, fac, repeats)

    iteration(1)
    return iteration, (work.left, work.A, work.B, work.right), work.r
