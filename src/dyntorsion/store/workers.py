"""Running cached items on workers: :func:`cached_map`, the machinery behind
:func:`~dyntorsion.studies.sweep.run_sweep` and :func:`~dyntorsion.studies.linear_predictions.predict`.

Faults it answers for:

* each finished item is written the moment it completes (a killed sweep resumes);
* two sweeps on one store share the work: an item is claimed with a lease
  (:mod:`dyntorsion.store.leases`) before it runs, and a sweep that finds an item claimed
  waits for its record instead of computing it again (and takes it over if the
  holder dies);
* an interrupt (SIGINT, or SIGTERM in the command line) keeps what finished: items
  already running are awaited and written (a second interrupt abandons them), on local
  processes and on an executor given its number of workers (the command line's dask);
* a local worker killed from outside breaks the pool: the unfinished items start again
  once in new workers;
* local worker processes die with their parent (:func:`_watch_parent`).
"""

from __future__ import annotations

import concurrent.futures as cf
import ctypes
import multiprocessing
import os
import signal
import threading
import time
from collections import deque
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, TypedDict, Unpack

from .leases import LEASE_SUFFIX, holder_of
from .results import Store, UnsavedResultError

__all__ = ["MapOptions", "DEFAULT_OPTIONS", "cached_map", "MissingResultError", "WAIT_POLL_S"]


#: how often a sweep looks for a record another sweep is computing [s]
class MapOptions(TypedDict, total=False):
    """How :func:`cached_map` runs what the store lacks (the one place these options are
    named; sweeps, predictions and the consistency map pass them on unchanged)."""

    executor: cf.Executor | None
    jobs: int
    on_stale: str
    compute: bool
    progress: bool | None
    log: Callable[[str], None] | None
    on_corrupt: str


#: the value of each :class:`MapOptions` entry a caller leaves out
DEFAULT_OPTIONS: MapOptions = {
    "executor": None,
    "jobs": 1,
    "on_stale": "recompute",
    "compute": True,
    "progress": None,
    "log": None,
    "on_corrupt": "quarantine",
}


WAIT_POLL_S = 0.5


class MissingResultError(LookupError):
    """A scene the store does not hold, asked for without computing."""


def _timed(run: Callable[[Any], dict[str, Any]], item: Any) -> tuple[dict[str, Any], float]:
    start = time.perf_counter()
    result = run(item)
    return result, time.perf_counter() - start


def _watch_parent(parent: int) -> None:
    """Worker initialiser: end this process when its parent ends, however it ends
    (SIGKILL included): the kernel's parent-death signal on Linux, and a thread that
    polls the parent id everywhere.  Interrupts are left to the parent."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass
    if os.getppid() != parent:
        os._exit(1)

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(1.0)
        os._exit(1)

    threading.Thread(target=watch, daemon=True, name="watch-parent").start()


def _local_pool(jobs: int) -> cf.ProcessPoolExecutor:
    return cf.ProcessPoolExecutor(
        max_workers=jobs,
        mp_context=multiprocessing.get_context("spawn"),
        initializer=_watch_parent,
        initargs=(os.getpid(),),
    )


def _terminate(pool: cf.ProcessPoolExecutor) -> None:
    """Stop a local pool's workers now (an abandoned sweep)."""
    for proc in list((getattr(pool, "_processes", None) or {}).values()):
        proc.terminate()
    pool.shutdown(wait=False, cancel_futures=True)


def cached_map(
    items: Sequence[Any],
    run: Callable[[Any], dict[str, Any]],
    kind: str,
    store: Store | str | Path | None = None,
    *,
    show: str | None = None,
    command: str = "dyntorsion sweep",
    **options: Unpack[MapOptions],
) -> list[tuple[dict[str, Any], bool]]:
    """(record, cached) for each item, in order.

    Each item has ``params()`` (the cache key, with ``kind``) and ``label()``;
    ``run(item)`` (a module-level function, so processes can receive it) returns the
    JSON-ready result.  Records in ``store`` (default
    :func:`~dyntorsion.store.location.default_store`) are read; the others run on ``executor``,
    or on ``jobs`` local processes (``jobs=1``: here), each claimed by a lease first
    (with an ``executor``, ``jobs`` > 1 is how many items it runs at once -- its workers:
    then an interrupt awaits and keeps every item submitted; ``jobs=1`` submits all)
    and written the moment it finishes.  ``show`` names a result entry for the log
    line; ``command`` is the one the missing-result error recommends; ``options`` are the
    :class:`MapOptions` (defaults :data:`DEFAULT_OPTIONS`).
    """
    from .location import checkout, default_store

    unknown = set(options) - set(DEFAULT_OPTIONS)
    if unknown:
        raise TypeError(
            f"cached_map: unknown option(s) {sorted(unknown)}; allowed: {sorted(DEFAULT_OPTIONS)}"
        )
    opts = {**DEFAULT_OPTIONS, **options}
    executor, jobs, on_stale, on_corrupt = (
        opts["executor"], opts["jobs"], opts["on_stale"], opts["on_corrupt"]
    )  # fmt: skip
    compute, progress, log = opts["compute"], opts["progress"], opts["log"]

    if not isinstance(store, Store):
        store = Store(default_store() if store is None else store)
    if not isinstance(jobs, int) or isinstance(jobs, bool) or jobs < 1:
        raise ValueError(f"jobs={jobs!r} must be an integer >= 1")
    say = log or (lambda msg: None)
    records: dict[int, tuple[dict[str, Any], bool]] = {}
    todo: list[int] = []
    for i, item in enumerate(items):
        rec = store.load(kind, item.params(), on_stale=on_stale, on_corrupt=on_corrupt, say=log)
        if rec is None:
            if store.path(kind, item.params()).exists():
                say(f"stale, recomputing: {item.label()}")
            todo.append(i)
        else:
            records[i] = (rec, True)
    if todo and not compute:
        missing = "\n  ".join(items[i].label() for i in todo)
        raise MissingResultError(
            f"{len(todo)} {kind} record(s) are not in {store.root}:\n  {missing}\n"
            f"compute them with `{command}`"
            + (" (or `make data-studies` in the checkout)" if checkout() is not None else "")
        )
    if todo:
        for path in store.clean():
            say(f"removed a leftover of a killed writer: {path.name}")
        sweep = _Sweep(items, run, kind, store, records, say, show, on_stale)
        sweep.go(todo, executor, jobs, progress)
    return [records[i] for i in range(len(items))]


class _Sweep:
    """The items still to compute: claimed, run, written; or awaited from another sweep."""

    def __init__(self, items, run, kind, store, records, say, show, on_stale) -> None:
        self.items, self.run, self.kind, self.store = items, run, kind, store
        self.records, self.say, self.show, self.on_stale = records, say, show, on_stale
        self.leases: dict[int, Any] = {}
        self.announced: set[int] = set()
        self.bar = None

    def finish(self, i: int, result: dict[str, Any], wall: float) -> None:
        tail = f" -> {self.show} = {result[self.show]}" if self.show else ""
        try:
            path = self.store.save(self.kind, self.items[i].params(), result, wall_time=wall)
        except OSError as err:  # the disk filled during the run: say what was computed
            lost = UnsavedResultError(
                err.errno, f"{err.strerror}; computed, not kept: {self.items[i].label()}{tail}",
                err.filename,
            )  # fmt: skip
            lost.result = result
            raise lost from err
        self.records[i] = (self.store.read(path), False)
        self.release(i)
        self.say(f"done in {wall:.1f} s: {self.items[i].label()}{tail}")
        if self.bar is not None:
            self.bar.update()

    def release(self, i: int) -> None:
        lease = self.leases.pop(i, None)
        if lease is not None:
            lease.release()

    def claim(self, i: int) -> bool:
        """True if this sweep is to compute item i now; False if another sweep holds it
        (or has just written it: then its record is taken)."""
        params = self.items[i].params()
        lease = self.store.lease(self.kind, params)
        if lease is None:
            if i not in self.announced:  # once: what it waits for, held by whom since when
                self.announced.add(i)
                held = Path(f"{self.store.path(self.kind, params)}{LEASE_SUFFIX}")
                self.say(f"waiting for {self.items[i].label()}: held by {holder_of(held)}")
            return False
        rec = self.store.load(self.kind, params, on_stale=self.on_stale, on_corrupt="error")
        if rec is not None:  # written by the other sweep meanwhile
            lease.release()
            self.records[i] = (rec, True)
            if self.bar is not None:
                self.bar.update()
            return False
        self.leases[i] = lease
        return True

    def poll(self, waiting: deque) -> None:
        """Take the records other sweeps have written; claim those they abandoned."""
        for _ in range(len(waiting)):
            i = waiting.popleft()
            rec = self.store.load(
                self.kind, self.items[i].params(), on_stale=self.on_stale, on_corrupt="error"
            )
            if rec is not None:
                self.records[i] = (rec, True)
                if self.bar is not None:
                    self.bar.update()
            else:
                waiting.append(i)

    def go(self, todo: list[int], executor, jobs: int, progress: bool | None) -> None:
        if progress or progress is None:
            from tqdm.auto import tqdm

            self.bar = tqdm(
                total=len(todo), unit="scene", disable=None if progress is None else False
            )
        try:
            if executor is None and jobs == 1:
                self.serial(todo)
            else:
                self.parallel(todo, executor, jobs)
        finally:
            for i in list(self.leases):
                self.release(i)
            if self.bar is not None:
                self.bar.close()

    def serial(self, todo: list[int]) -> None:
        pending, waiting = deque(todo), deque()
        while pending or waiting:
            if not pending:
                time.sleep(WAIT_POLL_S)
                self.poll(waiting)
                pending.extend(waiting)
                waiting.clear()
                continue
            i = pending.popleft()
            if i in self.records:
                continue
            if not self.claim(i):
                if i not in self.records:
                    waiting.append(i)
                continue
            self.finish(i, *_timed(self.run, self.items[i]))

    def parallel(self, todo: list[int], executor, jobs: int) -> None:
        """Run ``todo`` on ``executor`` (``jobs`` at a time; 1: all submitted at once) or
        on ``jobs`` local processes; a local worker killed from outside (the operating
        system out of memory, a kill) breaks the pool: the finished items are written and
        the unfinished ones start again once in new workers."""
        if executor is not None:
            return self.submit(todo, executor, jobs, own=False)
        for attempt in (1, 2):
            try:
                return self.submit(todo, _local_pool(jobs), jobs, own=True)
            except cf.BrokenExecutor as err:
                lost = [i for i in todo if i not in self.records]
                for i in lost:
                    self.release(i)
                what = f"{len(lost)} unfinished item(s)"
                if attempt == 2:
                    raise cf.BrokenExecutor(
                        f"a worker process died twice (killed by the system: out of memory?); "
                        f"the finished items are in {self.store.root}, {what} are not; rerun "
                        "with fewer --jobs"
                    ) from err
                self.say(f"a worker process died (killed by the system?): {what} start again")
                todo = lost
        return None

    def submit(self, todo: list[int], pool, jobs: int, own: bool) -> None:
        capacity = jobs if own or jobs > 1 else len(todo)
        pending, waiting = deque(todo), deque()
        futures: dict[cf.Future, int] = {}
        try:
            while pending or waiting or futures:
                while pending and len(futures) < capacity:
                    i = pending.popleft()
                    if i in self.records:
                        continue
                    if self.claim(i):
                        futures[pool.submit(_timed, self.run, self.items[i])] = i
                    elif i not in self.records:
                        waiting.append(i)
                if futures:
                    done, _ = cf.wait(futures, timeout=WAIT_POLL_S, return_when=cf.FIRST_COMPLETED)
                    for fut in done:
                        self.finish(futures.pop(fut), *fut.result())
                elif waiting:
                    time.sleep(WAIT_POLL_S)
                if waiting:
                    self.poll(waiting)
                    if not pending and len(futures) < capacity:
                        pending.extend(waiting)
                        waiting.clear()
        except KeyboardInterrupt:
            # a foreign executor bounded to its workers runs every item submitted; its
            # futures may not say so (dask's stay pending), and cancelling would stop them
            self.keep_running(futures, pool if own else None, cancel=own or jobs == 1)
            raise
        except BaseException:
            self.keep_done(futures)
            if own:
                _terminate(pool)
            raise
        finally:
            if own:
                pool.shutdown(wait=True, cancel_futures=True)

    def keep_done(self, futures: dict[cf.Future, int]) -> None:
        """On an error or termination: write the items that have finished, cancel the rest."""
        for fut, i in futures.items():
            if not fut.cancel() and fut.done() and fut.exception() is None:
                self.finish(i, *fut.result())

    def keep_running(self, futures: dict[cf.Future, int], pool, cancel: bool = True) -> None:
        """On an interrupt: cancel what has not started (``cancel``; else every future is
        taken as running), await and write what runs; a second interrupt abandons those
        (and stops local workers)."""
        for fut in futures if cancel else ():
            fut.cancel()
        running = {f: i for f, i in futures.items() if not f.cancelled()}
        if running:
            self.say(
                f"interrupted: finishing the {len(running)} running item(s) to keep them; "
                "interrupt again to abandon them"
            )
        try:
            for fut in cf.as_completed(running):
                if fut.exception() is None:
                    self.finish(running[fut], *fut.result())
        except KeyboardInterrupt:
            self.say("abandoned the running item(s)")
            if pool is not None:
                _terminate(pool)
