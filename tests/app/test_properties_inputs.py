"""Property-based tests of the input classes of the fault probe: the ramp, polynomial and
tabulated end histories at numeric extremes agree with a direct evaluation of their formula
(mpmath, 50 digits) to a relative 1e-12; an empty or blank string for any command-line option
is refused in one line; a negative number in any notation is a value; an interrupt (SIGINT or
SIGTERM) keeps the items an executor runs.  The hand-picked probes are in
tests/app/test_faults_inputs.py."""

from __future__ import annotations

import concurrent.futures as cf
import math
import signal
import threading
import time

import mpmath as mp
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from dyntorsion.buckling.loading import Polynomial, Ramp, Tabulated
from dyntorsion.store.fingerprint import register_kind

mp.mp.dps = 50
REL = 1e-12


def _close(got: float, exact: mp.mpf, scale: mp.mpf | None = None) -> bool:
    """``got`` within REL of ``exact`` relative to ``scale`` (default |exact|: the size of
    the terms where the function crosses zero), or both below float's normal range."""
    size = abs(exact) if scale is None else max(abs(exact), abs(scale))
    if size < 1e-290:
        return abs(got) < 1e-290
    return abs(mp.mpf(got) - exact) <= REL * size


def _times(hi: float):
    return st.lists(st.floats(0.0, hi), min_size=1, max_size=8)


BIG = st.floats(1e-150, 1e150)


@given(a=BIG, kappa0=st.floats(0.0, 1e150), ts=_times(1e150))
def test_a_ramp_is_its_formula_at_any_scale(a, kappa0, ts):
    h = Ramp(a, kappa0)
    for t, got in zip(ts, h(np.array(ts)), strict=True):
        assert _close(got, mp.mpf(kappa0) + mp.mpf(a) * mp.mpf(t))


@given(c=st.lists(st.floats(0.0, 1e100), min_size=1, max_size=5), ts=_times(1e50))
def test_a_polynomial_is_its_formula_at_any_scale(c, ts):
    h = Polynomial(tuple(c))
    for t, got in zip(ts, h(np.array(ts)), strict=True):
        exact = mp.fsum(mp.mpf(ck) * mp.mpf(t) ** k for k, ck in enumerate(c))
        assert _close(got, exact)


@given(
    steps=st.lists(st.floats(1e-6, 1e6), min_size=1, max_size=6),
    kappa=st.lists(st.floats(-1e150, 1e150), min_size=7, max_size=7),
)
def test_a_table_passes_through_its_points_and_holds_after_the_last(steps, kappa):
    t = np.concatenate([[0.0], np.cumsum(steps)])
    if np.any(np.diff(t) <= 0):
        return  # a step lost to round-off: not a strictly increasing table
    k = kappa[: len(t)]
    h = Tabulated(tuple(t), tuple(k))
    got = h(np.concatenate([t, [t[-1] * 2 + 1]]))
    scale = max(map(abs, k))
    for g, want in zip(got, [*k, k[-1]], strict=True):
        assert _close(g, mp.mpf(want), scale=mp.mpf(scale) * 1e-3 if scale else None)
    assert math.isfinite(float(np.max(np.abs(got))))


# ------------------------------------------------- blank strings for any CLI option
def _valued_options() -> list[tuple[str, str]]:
    """(subcommand, option) for every option of every subcommand that takes a value."""
    from dyntorsion.app.cli import parser

    p = parser()
    sub = next(a for a in p._actions if a.dest == "command")
    return [
        (name, opt)
        for name, sp in sub.choices.items()
        for action in sp._actions
        if action.nargs != 0
        for opt in action.option_strings
        if opt.startswith("--")
    ]


BLANK = st.text(alphabet=" \t\n\r\x0b\x0c", max_size=4)


@settings(suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(where=st.sampled_from(_valued_options()), blank=BLANK, joined=st.booleans())
def test_a_blank_value_for_any_option_is_refused_naming_it(where, blank, joined, capsys):
    """``--store ''`` wrote into the working directory, ``--ellipse ''`` ran the default
    circle: an empty or blank value is refused in one line naming the option (exit 2)."""
    from dyntorsion.app.cli import main

    command, option = where
    argv = [command, f"{option}={blank}"] if joined else [command, option, blank]
    capsys.readouterr()
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"dyntorsion: error: {option}=")
    assert "is empty" in err[0]


@settings(suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(value=st.sampled_from(["-inf", "-Infinity", "-INF", "-nan", "-1e308", "-.5"]))
def test_a_negative_number_in_any_notation_is_a_value_not_an_option(value, capsys):
    """``--E -inf`` said "expected one argument" (argparse read it as an option)."""
    from dyntorsion.app.cli import main

    capsys.readouterr()
    assert main(["buckle", "--a", value]) == 2  # read, then refused: a must be > 0
    err = capsys.readouterr().err.strip()
    assert err.startswith("dyntorsion: error: a=") and "expected one argument" not in err


# --------------------------------------------------------- signals on an executor
#: a record kind of these tests' own items (their code: the sweep machinery)
ITEMS = "test-items"
register_kind(ITEMS, ("dyntorsion.store.workers:cached_map",))


class _Item:
    def __init__(self, n: int) -> None:
        self.n = n

    def params(self) -> dict:
        return {"n": self.n}

    def label(self) -> str:
        return f"item {self.n}"


def _slow(item: _Item) -> dict:
    time.sleep(0.3)
    return {"n": item.n}


class _PendingFutures(cf.Executor):
    """Runs each item on a thread, but its futures never say they run (as dask's
    executor): only the sweep's bound to the workers tells which are running."""

    def submit(self, fn, *args):
        fut = cf.Future()

        def work():
            try:
                out = fn(*args)
            except BaseException as err:  # noqa: BLE001 -- handed to the future
                if not fut.cancelled():
                    fut.set_exception(err)
            else:
                if not fut.cancelled():
                    fut.set_result(out)

        threading.Thread(target=work, daemon=True).start()
        return fut


@settings(max_examples=5, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    sig=st.sampled_from([signal.SIGINT, signal.SIGTERM]),
    delay=st.floats(0.05, 0.2),
    executor=st.sampled_from(["threads", "pending"]),
)
def test_an_interrupt_keeps_the_items_an_executor_runs(tmp_path, sig, delay, executor):
    """A dask sweep lost both running scenes on Ctrl-C (its futures stay pending, so they
    were cancelled) and SIGTERM; with the executor bounded to its workers every running
    item is awaited and written, then the interrupt goes on."""
    from dyntorsion.app.cli import _terminate  # SIGTERM as the command line raises it
    from dyntorsion.store.workers import cached_map

    store = tmp_path / f"s{time.monotonic_ns()}"
    pool = cf.ThreadPoolExecutor(2) if executor == "threads" else _PendingFutures()
    old = signal.signal(signal.SIGTERM, _terminate)
    timer = threading.Timer(delay, signal.raise_signal, args=(sig,))
    try:
        timer.start()
        with pytest.raises(KeyboardInterrupt):
            cached_map([_Item(1), _Item(2), _Item(3)], _slow, ITEMS, store,
                       executor=pool, jobs=2, progress=False)  # fmt: skip
    finally:
        timer.join()
        signal.signal(signal.SIGTERM, old)
    kept = sorted(p.name for p in store.glob(f"{ITEMS}-*.json"))
    assert len(kept) == 2  # the two running, not the third (never submitted)
