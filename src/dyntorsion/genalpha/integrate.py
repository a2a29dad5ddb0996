"""The driver: validation, sources, the initial rate and the plan of the run, then chunks
of steps between checks, each taken by the stepping part (:mod:`.stepping`), kept by the
recording part (:mod:`.recording`) and followed by the stopping part's checks
(:mod:`.stopping`); the :class:`Run` they make."""

from __future__ import annotations

import time

import numpy as np

from ..model.system import Boundary, System
from .discrete import Start, setup
from .guard import check_memory, check_time, check_time_grid
from .march import StepContext, full_newton_iterations
from .newton import Newton
from .parts import Grid, Output, Problem, Stops
from .plan import Levels, Plan, RunParts, Source, gate_of, initial_rate
from .recording import Recorder
from .run import Run
from .scheme import Scheme
from .stepping import Stepper
from .stopping import CHUNK_WORK, Stopper, act_on, deferred_signals

__all__ = ["integrate", "newton_iteration_kernel"]


def _validate(system: System, grid: Grid, y0, left: Boundary, right: Boundary) -> np.ndarray:
    """The state and boundary rows against the system and the grid; y0 as an array."""
    nf = system.nf
    y0 = np.array(y0, dtype=float)
    if y0.shape != (grid.n_cells + 1, nf):
        raise ValueError(
            f"y0 has shape {y0.shape}, expected (n_cells+1, nf) = {(grid.n_cells + 1, nf)}"
        )
    if not np.all(np.isfinite(y0)):
        raise ValueError("y0 contains NaN or inf")
    if left.rows.shape[1] != nf or right.rows.shape[1] != nf or left.nb + right.nb != nf:
        raise ValueError(
            f"boundary rows: need nb_left + nb_right = {nf} rows of {nf} columns, got "
            f"{left.rows.shape} and {right.rows.shape}"
        )
    return y0


def _supports_state(scheme: Scheme, output: Output, stops: Stops) -> None:
    """A state-dependent source takes its own steps (:mod:`.state_steps`): refuse what they
    do not support, naming it."""
    unsupported = {
        "scheme.control (step-size control)": scheme.control is not None,
        "scheme.long_steps": scheme.long_steps is not None,
        "output.record": bool(output.record),
        "output.snapshots": bool(output.snapshots),
        "stops.test (the source's level_reached ends the run)": stops.test is not None,
    }
    refused = [name for name, used in unsupported.items() if used]
    if refused:
        raise ValueError(
            f"sources.state: a state-dependent source does not support {', '.join(refused)}"
        )


def integrate(
    problem: Problem,
    grid: Grid,
    *,
    scheme: Scheme = Scheme(),
    newton: Newton = Newton(),
    output: Output = Output(),
    stops: Stops = Stops(),
) -> Run:
    """Integrate ``problem`` (:class:`~.parts.Problem`: eq (7), its boundary rows, source and
    initial state) over ``grid`` (t0 to t_end) with the generalised-alpha scheme.

    Parameters
    ----------
    problem : the model, y0 (N+1, nf, finite), the boundary rows, the source and y_t0.
    grid : the nodes and time levels (:class:`~.parts.Grid`).
    scheme : eq (13)'s parameters; with ``scheme.control`` (a :class:`StepControl`) a step
        whose Newton solve fails is retried with half the step (:mod:`.control`); the fixed
        grid of dt is kept and every recorded level lies on it.  With ``scheme.long_steps``
        (a :class:`LongSteps`) the run starts with steps of a multiple of dt while the
        solution is quiet (:mod:`.long`), recording only the levels they reach.
    newton : the solve of each step (:class:`~.newton.Newton`).
    output, stops : what is kept and when the run may end early (:mod:`.parts`).

    Raises
    ------
    ValueError : y0 or the boundary rows do not fit the system and the grid.
    ConvergenceError : a step's Newton solve failed (its ``run`` holds what was computed).
    """
    system, left, right = problem.system, problem.left, problem.right
    sources, y_t0 = problem.sources, problem.y_t0
    t_start = time.perf_counter()
    y0 = _validate(system, grid, problem.y0, left, right)
    if sources.state is not None:
        _supports_state(scheme, output, stops)
    n_cells, length, dt, t_end, t0 = grid.n_cells, grid.length, grid.dt, grid.t_end, grid.t0
    record, record_every, snapshots = output.record, output.every, output.snapshots
    stop, check_every = stops.test, stops.check_every
    n1, nf = n_cells + 1, system.nf
    ds, s = grid.ds, grid.s
    n_steps = check_time_grid(dt, t_end, t0, snapshots, check_every)
    check_memory(n_steps, n1, nf, len(record or {}), len(snapshots))
    check_time(n_steps, n1, nf)
    times = t0 + dt * np.arange(n_steps + 1)
    src = Source.of(s, nf, sources.separable, sources.field)
    rate0 = initial_rate(system, y0, ds, y_t0, src, t0)
    con, work, fac = setup(system, scheme, n_cells, ds, dt, left, right, Start(y0, rate0))
    plan = Plan.of(system, grid, n_steps, output, stops)
    levels = Levels.of(times, left, right, src)
    ctx = StepContext(con, work, fac, newton.options())
    stepper = Stepper(RunParts(system, scheme, grid, left, right, levels, ctx), sources.state)
    recorder = Recorder(plan, times, y0, record_every)
    stopper = Stopper(stop, gate_of(system, stops.gate, ds, stop), plan, n_steps, work.y_old)
    stopped, failure, done = "t_end", None, 0
    bar = _progress_bar(output.progress, n_steps, n1, nf)
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
                if stepper.reason:
                    stopped = stepper.reason
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
            **(output.meta or {}),
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
        system, scheme, n_cells, length / n_cells, dt, left, right, Start(y, np.zeros_like(y))
    )
    gL, gR = left.at(np.array([dt]))[0], right.at(np.array([dt]))[0]

    def iteration(repeats: int = 1) -> float:
        return full_newton_iterations(system.F, system.dF, con, gL, gR, work, fac, repeats)

    iteration(1)
    return iteration, (work.left, work.A, work.B, work.right), work.r
