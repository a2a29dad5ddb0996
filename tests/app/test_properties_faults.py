"""Property-based tests of the fault classes of issue 37: each class of bad or extreme
input, drawn by hypothesis rather than picked by hand, gets its answer (a signal stops
a run cleanly, a lease is judged, a run that cannot see its growth says so, a dropped
argument is refused, a run past the budget is refused before it starts, a damaged record
is moved aside, a bad history is named before the run).  The hand-picked cases that first
showed each fault are in tests/app/test_faults.py, test_faults_store.py and test_interrupt.py."""

from __future__ import annotations

import importlib
import json
import math
import os
import signal
import threading
import time
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, event, example, given, settings
from hypothesis import strategies as st

import dyntorsion.studies  # noqa: F401  (registers the record kinds)
from dyntorsion import Rod
from dyntorsion.app.cli import main
from dyntorsion.buckling import simulate
from dyntorsion.buckling.loading import Custom
from dyntorsion.buckling.resolution import judge
from dyntorsion.buckling.scene import Scene
from dyntorsion.buckling.statics import critical_twist
from dyntorsion.genalpha import guard
from dyntorsion.genalpha.guard import BudgetError
from dyntorsion.genalpha.stopping import deferred_signals
from dyntorsion.store import leases as L
from dyntorsion.store.leases import acquire_lease
from dyntorsion.store.results import CorruptResultError, Store
from dyntorsion.studies.sweep import KIND

I = importlib.import_module("dyntorsion.genalpha.integrate")  # the module, not the function

FEW = max(3, settings.default.max_examples // 4)  # examples that run a scene
TMP_OK = [HealthCheck.function_scoped_fixture]  # tmp_path shared across examples: each
#                                                 example uses a folder of its own in it


def _fresh(tmp_path: Path, tag: str) -> Path:
    folder = tmp_path / f"{tag}-{time.monotonic_ns()}"
    folder.mkdir()
    return folder


# ------------------------------------------------------------- 1. signals in a march
@given(st.lists(st.sampled_from([signal.SIGINT, signal.SIGTERM]), min_size=1, max_size=4))
def test_signals_in_a_compiled_block_are_noted_and_the_first_reraised_once(sigs):
    """Inside the block a signal only notes itself (the chunk runs to its end); on the way
    out the first is raised once under the handler that was in force."""
    seen: list[int] = []
    old = {s: signal.signal(s, lambda n, f: seen.append(n)) for s in set(sigs)}
    try:
        finished = False
        with deferred_signals() as caught:
            for s in sigs:
                signal.raise_signal(s)
            finished = True  # the "chunk" was not cut
            assert caught == sigs and not seen
        assert finished and seen == [sigs[0]]
    finally:
        for s, h in old.items():
            signal.signal(s, h)


def test_a_signal_ignored_on_entry_stays_ignored():
    """A background job's SIGINT is ignored (SIG_IGN): the block leaves it so, notes
    nothing and re-raises nothing (before, it noted the signal and the run's internal stop
    escaped: the re-raise went into SIG_IGN)."""
    old = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        with deferred_signals() as caught:
            assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
            signal.raise_signal(signal.SIGINT)
            assert caught == []
        assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
    finally:
        signal.signal(signal.SIGINT, old)


@settings(max_examples=FEW)
@given(st.floats(0.0, 0.4))
def test_an_interrupted_run_raises_keyboardinterrupt_and_the_next_run_works(delay):
    """SIGINT at any moment of an in-process run: KeyboardInterrupt (never a crash), and the
    interpreter (a notebook's kernel) runs the next scene normally."""
    kw = dict(a=16.0, kappa0=10.0, n_cells=400, dt=0.0005, t_end=1.0)
    timer = threading.Timer(delay, signal.raise_signal, args=(signal.SIGINT,))
    try:
        timer.start()  # inside: at delay 0 the signal may come before start() returns
        simulate(Scene(**kw), progress=False)
        event("finished before the signal")
    except KeyboardInterrupt:
        event("interrupted")
    finally:
        timer.join()
    run = simulate(Scene(**{**kw, "n_cells": 10, "dt": 0.02, "t_end": 0.2}))
    assert run.stopped == "t_end"


# ------------------------------------------------------------------------ 2. leases
LEASE_CONTENT = st.one_of(
    st.binary(max_size=64),
    st.builds(
        lambda owner, start, taken: json.dumps({"owner": owner, "start": start, "taken": taken}),
        st.one_of(st.text(max_size=20), st.integers()),
        st.one_of(st.none(), st.floats(allow_nan=False), st.text(max_size=4)),
        st.one_of(st.floats(0, 2e9), st.text(max_size=4)),
    ),
)


@settings(suppress_health_check=TMP_OK)
@given(content=LEASE_CONTENT, age=st.floats(0.0, 3 * L.STALE_AFTER_S))
def test_any_lease_is_judged_broken_with_one_line_or_held_by_a_named_holder(tmp_path, content, age):
    folder = _fresh(tmp_path, "lease")
    record = folder / "x.json"
    path = Path(f"{record}.lease")
    (path.write_bytes if isinstance(content, bytes) else path.write_text)(content)
    os.utime(path, (time.time() - age,) * 2)
    said: list[str] = []
    lease = acquire_lease(record, say=said.append)
    if lease is None:
        event("held")
        assert not said
        assert age <= L.STALE_AFTER_S  # a stopped heartbeat never holds
        assert isinstance(L.holder_of(path), str)
    else:
        event("broken" if said else "free")
        assert len(said) <= 1 and all(path.name in s for s in said)
        lease.release()
    if age > L.WRITING_S:
        try:
            json.loads(content)["owner"]
        except (ValueError, KeyError, TypeError, UnicodeDecodeError):
            assert lease is not None and "unreadable" in said[0]  # an empty or torn lease


# --------------------------------------------------------------- 3. unresolved runs
ROD = Rod()
KAPPA_CRI = critical_twist(ROD)


@given(
    kappa_end=st.floats(1.01 * KAPPA_CRI, 1e6),
    duration=st.floats(1e-4, 30.0),
    n_cells=st.integers(4, 5000),
    dt=st.floats(1e-7, 0.1),
)
def test_the_grid_a_run_is_told_it_needs_is_judged_resolved(kappa_end, duration, n_cells, dt):
    """Any ramp past kappa_cri: the judge either finds no 5-e-fold growth, or names a grid;
    the run is resolved exactly when it is at least that grid, and that grid is resolved."""
    t = np.linspace(0.0, duration, 4001)
    kappa = 10.0 + (kappa_end - 10.0) * t / duration
    tension = np.zeros_like(t)
    got = judge(ROD, t, kappa, tension, KAPPA_CRI, n_cells, dt)
    if got is None:
        event("never grew 5 e-folds")
        return
    event("resolved" if got.resolved else "unresolved")
    assert got.n_cells >= 1 and got.dt > 0 and got.kappa3 > KAPPA_CRI
    assert got.resolved == (n_cells >= got.n_cells and dt <= got.dt)
    assert judge(ROD, t, kappa, tension, KAPPA_CRI, got.n_cells, got.dt).resolved
    if not got.resolved:
        assert str(got.n_cells) in got.message(n_cells, dt)


# ------------------------------------------------------------ 4. dropped arguments
HISTORIES = st.one_of(
    st.lists(st.floats(-100, 100).map(lambda c: f"{c:g}"), min_size=1, max_size=4).map(
        lambda cs: "poly:" + ",".join(cs)
    ),
    st.just("table:/nonexistent.csv"),
)


@settings(suppress_health_check=TMP_OK)
@given(
    history=HISTORIES,
    rate=st.one_of(
        st.tuples(st.just("--a"), st.floats(1e-3, 1e4).map(lambda a: f"{a:g}")),
        st.tuples(st.just("--rates"), st.just("1,2,4")),
    ),
    command=st.sampled_from(["buckle", "sweep"]),
)
def test_a_rate_with_a_history_that_fixes_its_own_twist_is_refused(
    history, rate, command, tmp_path_factory, capsys
):
    if command == "buckle" and rate[0] == "--rates":
        rate = ("--a", "1.6")
    if command == "sweep" and rate[0] == "--a":  # sweep's rates are --rates
        rate = ("--rates", rate[1])
    capsys.readouterr()
    argv = [command, *rate, "--history", history, "--store", str(tmp_path_factory.mktemp("s"))]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("dyntorsion: error: --")
    assert "--a" in err[0] or "--rates" in err[0]


# ----------------------------------------------------------------- 5. time budget
@settings(suppress_health_check=TMP_OK)
@given(
    n_steps=st.integers(1, 10**9),
    n_nodes=st.integers(2, 10**6),
    nf=st.sampled_from([12, 18]),
    budget=st.floats(1.0, 1e6),
)
def test_a_run_past_the_budget_is_refused_and_one_within_it_is_not(
    n_steps, n_nodes, nf, budget, monkeypatch
):
    monkeypatch.setenv("DYNTORSION_MAX_TIME", repr(budget))
    need = guard.run_seconds(n_steps, n_nodes, nf)
    assert need > 0 and guard.run_seconds(2 * n_steps, n_nodes, nf) > need
    said: list[str] = []
    if need > budget:
        with pytest.raises(BudgetError, match="over the budget") as err:
            guard.check_time(n_steps, n_nodes, nf, say=said.append)
        assert all(w in str(err.value) for w in ("raise dt", "fewer cells", "--max-time"))
    else:
        assert guard.check_time(n_steps, n_nodes, nf, say=said.append) == need
        assert len(said) == (need > guard.ANNOUNCE_AFTER_S)


@settings(max_examples=FEW, suppress_health_check=TMP_OK)
@given(n_cells=st.integers(20_000, 200_000), dt=st.floats(1e-6, 1e-3))
def test_the_command_line_refuses_a_run_past_the_budget_before_it_starts(
    n_cells, dt, capsys, monkeypatch
):
    import warnings

    monkeypatch.delenv("DYNTORSION_MAX_TIME", raising=False)
    monkeypatch.setattr(I, "Stepper", lambda *a, **k: pytest.fail("the run started"))
    argv = ["--max-time", "10", "buckle", "--a", "1.6", "--n-cells", str(n_cells), "--dt", repr(dt)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the GridWarning of a grid this fine
        assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "over the budget of 10 s" in err[0]


# -------------------------------------------------------------- 6. damaged records
DAMAGE = st.one_of(
    st.binary(max_size=200),
    st.text(max_size=200).map(str.encode),
    st.recursive(
        st.none() | st.booleans() | st.floats() | st.text(max_size=5),
        lambda kids: (
            st.lists(kids, max_size=3) | st.dictionaries(st.text(max_size=6), kids, max_size=3)
        ),
        max_leaves=10,
    ).map(lambda v: json.dumps(v).encode()),
    st.builds(
        lambda params, result: json.dumps(
            {"kind": KIND, "params": params, "result": result}
        ).encode(),
        st.dictionaries(st.text(max_size=4), st.integers(), max_size=2),
        st.dictionaries(st.text(max_size=4), st.floats(allow_nan=False), max_size=2),
    ),
)


@settings(suppress_health_check=TMP_OK)
@given(damage=DAMAGE)
@example(damage=b"[" * 100_000)  # nested past the parser's recursion limit
@example(damage=b"1" * 5000)  # an integer past Python's digit limit
def test_any_damaged_record_is_refused_as_corrupt(tmp_path, damage):
    path = _fresh(tmp_path, "rec") / f"{KIND}-0000000000000000dead.json"
    path.write_bytes(damage)
    with pytest.raises(CorruptResultError):
        Store(path.parent).read(path)


QUICK = ["--kappa0", "10", "--n-cells", "20", "--dt", "0.02"]


@pytest.fixture(scope="module")
def one_record(tmp_path_factory):
    store = tmp_path_factory.mktemp("store")
    assert main(["sweep", "--rates", "16", *QUICK, "--store", str(store), "--quiet"]) == 0
    (path,) = store.glob(f"{KIND}-*.json")
    return path.name, path.read_bytes()


@settings(max_examples=FEW, suppress_health_check=TMP_OK)
@given(damage=DAMAGE)
def test_a_sweep_moves_any_damaged_record_aside_and_recomputes_it(
    tmp_path, one_record, damage, capsys
):
    name, good = one_record
    store = _fresh(tmp_path, "store")
    (store / name).write_bytes(damage)
    capsys.readouterr()
    assert main(["sweep", "--rates", "16", *QUICK, "--store", str(store), "--quiet"]) == 0
    assert "moved aside" in capsys.readouterr().err
    assert (store / (name + ".corrupt")).read_bytes() == damage
    assert json.loads((store / name).read_text())["result"] == json.loads(good)["result"]


# --------------------------------------------------------- 7. histories that mislead
BAD_OUTPUT = st.one_of(
    st.sampled_from(["x", None, "1e7", [1.0, 2.0], {"k": 1}, 1j]),
    st.sampled_from([math.nan, math.inf, -math.inf]).map(lambda v: lambda t: v + 0 * t),
    st.integers(2, 5).map(lambda n: lambda t: np.zeros((n, np.size(t)))),
    st.integers(1, 3).map(lambda n: lambda t: np.zeros(np.size(t) + n)),
    st.floats(0.0, 0.1).map(lambda t_bad: lambda t: np.where(t >= t_bad, np.nan, 10.0 + 0 * t)),
)


@given(BAD_OUTPUT)
def test_a_custom_history_with_bad_output_is_named_before_the_run(bad):
    func = bad if callable(bad) else (lambda t: bad)
    with pytest.MonkeyPatch.context() as mp:  # before the run, not deep inside it
        mp.setattr(I, "Stepper", lambda *a, **k: pytest.fail("the run started"))
        with pytest.raises(ValueError, match=r"history=custom 'h': kappa3\(0, t\)"):
            simulate(
                Scene(history=Custom("h", func), n_cells=10, dt=0.01, t_end=0.1), progress=False
            )
