"""Property-based tests of the input classes of the fault probe: every end history at
numeric extremes agrees with a direct evaluation of its formula (mpmath, 50 digits) to a
relative 1e-12; an empty or blank string for any command-line option is refused in one
line; a negative number in any notation is a value; ``None`` for any
:class:`~dyntorsion.buckling.spec.Scene` field is a TypeError or ValueError naming the
field; an interrupt (SIGINT or SIGTERM) keeps the items an executor runs.  The hand-picked
probes are in tests/app/test_faults_inputs.py."""

from __future__ import annotations

import concurrent.futures as cf
import dataclasses
import math
import signal
import threading
import time

import mpmath as mp
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from dyntorsion.buckling.loading import Polynomial, Ramp, RampHold, SmoothStart, Tabulated
from dyntorsion.buckling.scene import Scene, run_scene
from dyntorsion.buckling.turning import TurnHold
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


def _f4(z: mp.mpf) -> mp.mpf:
    """1 - exp(-z^4), section 5's transition complement."""
    return -mp.expm1(-(z**4))


@given(a=BIG, kappa0=st.floats(0.0, 1e150), ts=_times(1e150))
def test_a_ramp_is_its_formula_at_any_scale(a, kappa0, ts):
    h = Ramp(a, kappa0)
    for t, got in zip(ts, h(np.array(ts)), strict=True):
        assert _close(got, mp.mpf(kappa0) + mp.mpf(a) * mp.mpf(t))


@given(a=BIG, kappa0=st.floats(0.0, 1e150), tau=BIG, ts=_times(1e150))
def test_a_smooth_start_is_its_formula_at_any_scale(a, kappa0, tau, ts):
    h = SmoothStart(a, kappa0, tau)
    for t, got in zip(ts, h(np.array(ts)), strict=True):
        exact = mp.mpf(kappa0) * _f4(mp.mpf(t) / mp.mpf(tau)) + mp.mpf(a) * mp.mpf(t)
        assert _close(got, exact)


@given(c=st.lists(st.floats(0.0, 1e100), min_size=1, max_size=5), ts=_times(1e50))
def test_a_polynomial_is_its_formula_at_any_scale(c, ts):
    h = Polynomial(tuple(c))
    for t, got in zip(ts, h(np.array(ts)), strict=True):
        exact = mp.fsum(mp.mpf(ck) * mp.mpf(t) ** k for k, ck in enumerate(c))
        assert _close(got, exact)


@given(
    a=st.floats(1e-6, 1e6),
    kappa0=st.floats(0.0, 1e3),
    rise=st.one_of(st.floats(1e-3, 1e3), st.floats(1e3, 1e300)),
    tau=st.floats(1e-6, 1e6),
    fractions=st.lists(st.floats(0.0, 3.0), min_size=1, max_size=8),
)
def test_a_ramp_hold_is_its_formula_for_any_hold(a, kappa0, rise, tau, fractions):
    """The probe's RampHold(16, 1e17, 10) gave 16, 16, 16, 16, 32 where 10, 14, 18, 22, 26
    are due; at any hold the values are the formula's, h = r - a tau log(1 + e^x),
    r = kappa0 + a t, x = (r - hold) / (a tau), to 1e-12 of the twist's size r."""
    h = RampHold(a, kappa0 + rise, kappa0, tau)
    ts = [f * rise / a for f in fractions] + [0.0, 1.0, 2.0, 3.0]
    for t, got in zip(ts, h(np.array(ts)), strict=True):
        r = mp.mpf(kappa0) + mp.mpf(a) * mp.mpf(t)
        s = mp.mpf(a) * mp.mpf(tau)
        exact = r - s * mp.log1p(mp.exp((r - mp.mpf(h.hold)) / s))
        assert _close(got, exact, scale=r)


def test_the_probed_ramp_hold_climbs_at_its_rate():
    for hold in (1e17, 1e20, 1e300):
        got = RampHold(16.0, hold, 10.0)(np.array([0.0, 0.25, 0.5, 0.75, 1.0]))
        assert got.tolist() == [10.0, 14.0, 18.0, 22.0, 26.0]


@given(
    turns=st.floats(1e-6, 1e6) | st.floats(-1e6, -1e-6),
    t_turn=st.floats(1e-3, 1e6),
    tau_share=st.floats(1e-6, 0.25),
    fractions=st.lists(st.floats(0.0, 1e6), min_size=1, max_size=8),
)
def test_a_turn_hold_is_its_formula_at_any_scale(turns, t_turn, tau_share, fractions):
    h = TurnHold(turns, t_turn, tau_share * t_turn)
    ts = [f * t_turn for f in fractions]
    omega = 2 * mp.pi * mp.mpf(turns) / mp.mpf(t_turn)
    tau = mp.mpf(h.tau)
    for t, got in zip(ts, h(np.array(ts)), strict=True):
        t = mp.mpf(t)
        shape = _f4(t / tau) if t < h.t_turn else mp.exp(-(((t - h.t_turn) / tau) ** 4))
        assert _close(got, -omega * shape)


def test_a_turn_hold_whose_spin_overflows_is_refused():
    with pytest.raises(ValueError, match="turns=1e\\+300 in t_turn=1e-10 s.*overflows"):
        TurnHold(1e300, 1e-10, 1e-11)


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


# ------------------------------------------------------------ None for a Scene field
SCENE_FIELDS = [f.name for f in dataclasses.fields(Scene)]
#: the fields whose None is documented: the paper's kappa0 = 10, the horizon rule's
#: t_end, the ramp (no other history)
NONE_MEANS = {"kappa0": 10.0, "t_end": None, "history": None}


@given(st.sets(st.sampled_from(SCENE_FIELDS), min_size=1, max_size=3))
def test_none_for_any_scene_field_is_its_default_or_refused_naming_it(names):
    """Scene(seed=None), Scene(scheme=None), ... raised AttributeError on NoneType deep in
    the run; now a TypeError or ValueError names a field set to None, or None is the
    field's documented default."""
    kwargs = {"a": 16.0, "t_end": 1.0, **dict.fromkeys(names)}
    refused = names - set(NONE_MEANS)
    if not refused:
        scene = Scene(**kwargs)
        assert all(getattr(scene, n) == NONE_MEANS[n] for n in names if n != "t_end")
        return
    with pytest.raises((TypeError, ValueError)) as err:
        Scene(**kwargs)
    assert any(f"{n}=None" in str(err.value) or f"{n} " in str(err.value) for n in refused)


@given(
    st.one_of(
        st.none(), st.integers(), st.text(max_size=5), st.dictionaries(st.just("a"), st.floats())
    )
)
def test_run_scene_of_anything_but_a_scene_is_a_typeerror_naming_it(thing):
    with pytest.raises(TypeError, match=r"^scene=.* must be a dyntorsion\.buckling\.scene\.Scene"):
        run_scene(thing)


def test_a_scene_without_variations_is_refused():
    """variations=() gave t_c with both uncertainties 0.0."""
    with pytest.raises(ValueError, match=r"variations=\(\) must hold at least one window"):
        Scene(a=16.0, variations=())


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
    # Python's own Ctrl-C handler: a test run started as a background job ignores SIGINT
    old_int = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(delay, signal.raise_signal, args=(sig,))
    try:
        timer.start()
        with pytest.raises(KeyboardInterrupt):
            cached_map([_Item(1), _Item(2), _Item(3)], _slow, ITEMS, store,
                       executor=pool, jobs=2, progress=False)  # fmt: skip
    finally:
        timer.join()
        signal.signal(signal.SIGTERM, old)
        signal.signal(signal.SIGINT, old_int)
    kept = sorted(p.name for p in store.glob(f"{ITEMS}-*.json"))
    assert len(kept) == 2  # the two running, not the third (never submitted)
