"""Property-based tests over every public entry point (issue 17).

The rule: any input gives a finite result that honours the scene's invariants, or a
ValueError/TypeError that names the offending parameter -- within a time budget (small
grids; runs beyond a step budget are not drawn).  The hypothesis profile comes from
``$DYNTORSION_HYPOTHESIS`` (tests/conftest.py): ``fast`` in `make test`, ``long`` in
`make test-all`.  ``hypothesis.event`` tallies the outcomes
(``pytest --hypothesis-show-statistics``).
"""

from __future__ import annotations

import math
import re
import subprocess
import sys
import tempfile
import warnings

import numpy as np
import pytest
from hypothesis import assume, event, given, settings
from hypothesis import strategies as st

from dyntorsion import Rod
from dyntorsion import waves as W
from dyntorsion.buckling import STATUSES, GridWarning, Perturbation, simulate
from dyntorsion.buckling.delay_law import fit_power_law
from dyntorsion.buckling.loading import Ramp
from dyntorsion.buckling.scene import Scene
from dyntorsion.studies import sweep as S

FEW = max(3, settings.default.max_examples // 4)  # for examples that run a scene or a process

#: inputs a user may pass by mistake: non-finite, negative, zero, huge, tiny, wrong types
JUNK = st.one_of(
    st.sampled_from([math.nan, math.inf, -math.inf, 0.0, -1.0, 1e308, 1e-320, -0.0]),
    st.sampled_from(["1e7", "", None, True, (1.0,), np.float32(1.5), np.int64(3)]),
)


def number(lo: float, hi: float) -> st.SearchStrategy:
    return st.one_of(st.floats(lo, hi), JUNK)


def names_one_of(err: Exception, names) -> None:
    """The message names one of ``names`` as a parameter: the name as a word of its own,
    followed by ``=``, ``must`` or ``and`` (so that "s" is not found in "must")."""
    msg = str(err)
    found = [n for n in names if re.search(rf"(?<![\w.]){re.escape(n)}\s*(=|must\b|and\b)", msg)]
    assert found, f"{type(err).__name__} names none of {names} as a parameter: {msg}"


# ------------------------------------------------------------------------------ Rod
ROD_ARGS = {
    "E": number(1e3, 1e12),
    "nu": number(-0.99, 0.5),
    "D": number(1e-5, 1e-1),
    "L": number(1e-2, 1e2),
    "rho": number(1.0, 1e5),
}


@given(st.fixed_dictionaries({}, optional=ROD_ARGS))
def test_rod_is_usable_or_names_the_parameter(kw):
    try:
        rod = Rod(**kw)
    except (ValueError, TypeError) as err:
        event(f"Rod: {type(err).__name__}")
        names_one_of(err, list(kw))
        return
    event("Rod: result")
    for v in (rod.c, rod.T0, rod.B1, rod.C, rod.mass_per_length):
        assert math.isfinite(v) and v > 0


# ------------------------------------------------------------------------- simulate
SIM_ARGS = {
    "a": number(-50.0, 50.0),
    "kappa0": number(-30.0, 30.0),
    "n_cells": st.one_of(st.integers(-2, 6), JUNK),
    "dt": number(1e-3, 0.5),
    "t_end": number(1e-3, 0.5),
    "perturbation": number(0.0, 1e-3),
    "check_every": st.one_of(st.none(), st.integers(-1, 5), JUNK),
    "snapshots": st.one_of(st.just(()), st.lists(number(0.0, 0.5), max_size=2)),
}
SIM_NAMES = ["a", "kappa0", "n_cells", "dt", "t_end", "seed", "check_every", "snapshots"]
RUN_OPTIONS = ("check_every", "snapshots")


def _simulate(kw):
    """simulate() of a Scene with the ramp kappa0 + a t (any sign of a) and kw's options."""
    run = {k: kw[k] for k in RUN_OPTIONS}
    ramp = Ramp(a=kw["a"], kappa0=kw["kappa0"])
    scene = Scene(history=ramp, n_cells=kw["n_cells"], dt=kw["dt"], t_end=kw["t_end"],
                  seed=kw["perturbation"])  # fmt: skip
    return simulate(scene, progress=False, on_failure="return", **run)


def _steps(kw) -> float:
    dt, t_end = kw.get("dt"), kw.get("t_end")
    if all(isinstance(v, float) and math.isfinite(v) and v > 0 for v in (dt, t_end)):
        return t_end / dt
    return 0.0


@given(st.fixed_dictionaries(SIM_ARGS))
def test_simulate_honours_the_imposed_twist_or_names_the_parameter(kw):
    assume(_steps(kw) <= 200)  # the time budget
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", GridWarning)
            run = _simulate(kw)
    except (ValueError, TypeError) as err:
        event(f"simulate: {type(err).__name__}")
        names_one_of(err, SIM_NAMES)
        return
    event(f"simulate: result ({'failed' if run.stopped.startswith('failed') else 'ran'})")
    for trace in (run.u3_end, run.kappa3_left, run.kappa3_right, run.omega3_left):
        assert np.all(np.isfinite(trace))
    np.testing.assert_allclose(
        run.kappa3_left, kw["kappa0"] + kw["a"] * run.t, rtol=1e-9, atol=1e-9 * (1 + abs(kw["a"]))
    )
    assert run.t[-1] <= kw["t_end"] + kw["dt"] * (1 + 1e-9)
    if run.stopped == "t_end":
        assert run.t[-1] >= kw["t_end"] - 1e-12


@given(
    st.fixed_dictionaries(
        {
            "a": st.floats(-20.0, 20.0),
            "kappa0": st.floats(-20.0, 20.0),
            "n_cells": st.integers(2, 6),
            "dt": st.floats(0.005, 0.05),
            "t_end": st.floats(0.05, 0.5),
            "perturbation": st.floats(0.0, 1e-3),
            "check_every": st.one_of(st.none(), st.integers(1, 5)),
            "snapshots": st.lists(st.floats(0.0, 0.05), max_size=2),
        }
    )
)
def test_simulate_of_plain_inputs_honours_the_imposed_twist(kw):
    test_simulate_honours_the_imposed_twist_or_names_the_parameter.hypothesis.inner_test(kw)


# ----------------------------------------------------------------- exact series
WAVE = {
    "c": st.floats(1.0, 100.0),
    "L": st.floats(0.1, 3.0),
    "s": st.floats(0.0, 1.0),
    "t": st.floats(0.0, 5.0),
    "terms": st.integers(1, 60),
}


@given(st.fixed_dictionaries(WAVE), st.floats(-10.0, 10.0), st.floats(-10.0, 10.0))
def test_linear_loading_series_is_within_its_bound_of_the_closed_form(p, a, kappa0):
    s = p["s"] * p["L"]
    kw = {"a": a, "kappa0": kappa0, "c": p["c"], "L": p["L"]}
    series = W.linear_loading_exact(s, p["t"], series=W.Series(terms=p["terms"]), **kw)
    exact = W.linear_loading_dalembert(s, p["t"], **kw)
    bound = W.linear_loading_bound(p["terms"], s, p["t"], a=a, c=p["c"], L=p["L"])
    scale = 1 + abs(kappa0) + abs(a) * p["t"]
    assert np.isfinite(series) and np.isfinite(exact)
    assert abs(series - exact) <= bound + 1e-9 * scale
    event("linear loading: within the bound")


@given(st.fixed_dictionaries(WAVE), st.floats(-10.0, 10.0))
def test_instant_release_series_is_within_its_bound_of_the_closed_form(p, kappa0):
    s = p["s"] * p["L"]
    kw = {"kappa0": kappa0, "c": p["c"], "L": p["L"]}
    series = W.instant_release_exact(s, p["t"], series=W.Series(terms=p["terms"]), **kw)
    exact = W.instant_release_dalembert(s, p["t"], **kw)
    bound = W.instant_release_bound(p["terms"], s, p["t"], **kw)
    assert np.isfinite(series)
    assert abs(series - exact) <= bound + 1e-9 * (1 + abs(kappa0))
    event("instant release: within the bound")


@given(st.floats(0.0, 1.0), st.floats(0.0, 0.2), st.integers(1, 12), st.floats(-10.0, 10.0))
def test_smooth_release_series_is_within_its_bound_of_the_closed_form(s, t, terms, kappa0):
    kw = {"kappa0": kappa0, "c": 57.7, "L": 1.0}
    series = W.smooth_release_exact(s, t, series=W.Series(terms=terms), **kw)
    exact = W.smooth_release_dalembert(s, t, **kw)
    bound = W.smooth_release_bound(terms, t, **kw)
    assert abs(float(series[()]) - float(exact)) <= float(bound[0]) + 1e-8 * (1 + abs(kappa0))
    event("smooth release: within the bound")


@given(
    st.sampled_from(["linear", "instant", "smooth"]),
    st.fixed_dictionaries({"c": number(1.0, 100.0), "L": number(0.1, 3.0)}),
    st.one_of(st.floats(0.0, 1.0), JUNK),
    st.one_of(st.floats(0.0, 1e12), JUNK),
    st.one_of(st.none(), st.integers(-2, 50), JUNK),
)
def test_series_and_closed_forms_answer_or_name_the_parameter(problem, kw, s, t, terms):
    args = {"linear": {"a": 1.0}, "instant": {"kappa0": 1.0}, "smooth": {"kappa0": 1.0}}[problem]
    fns = {
        "linear": (W.linear_loading_exact, W.linear_loading_dalembert),
        "instant": (W.instant_release_exact, W.instant_release_dalembert),
        "smooth": (W.smooth_release_exact, W.smooth_release_dalembert),
    }[problem]
    for fn, extra in ((fns[0], lambda: {"series": W.Series(terms=terms)}), (fns[1], dict)):
        try:
            out = fn(s, t, **kw, **args, **extra())
        except (ValueError, TypeError) as err:
            event(f"{problem} {fn.__name__.split('_')[-1]}: {type(err).__name__}")
            names_one_of(err, ["c", "L", "s", "t", "series.terms", "series.tol", "images", "t up"])
            continue
        event(f"{problem} {fn.__name__.split('_')[-1]}: result")
        assert np.all(np.isfinite(np.asarray(out, dtype=float)))


# ---------------------------------------------------------------- fit_power_law
@given(
    st.lists(st.tuples(number(1e-3, 50.0), number(5.0, 80.0)), min_size=0, max_size=8),
    st.one_of(st.just("static"), st.none(), number(0.0, 15.0), st.just("dynamic")),
    st.integers(0, 10),
)
def test_fit_is_finite_or_says_why(points, kappa_cri, n_boot):
    a = [p[0] for p in points]
    k = [p[1] for p in points]
    try:
        f = fit_power_law(a, k, kappa_cri=kappa_cri, n_boot=n_boot)
    except (ValueError, TypeError) as err:
        event(f"fit: {type(err).__name__}")
        names_one_of(err, ["a", "kappa3", "kappa_cri", "rate", "points"])
        return
    event("fit: result")
    for v in (f.b, f.sigma, f.kappa_cri, f.b_err, f.sigma_err, f.residual_rms):
        assert math.isfinite(v)


@given(
    st.lists(st.tuples(st.floats(1e-3, 50.0), st.floats(5.0, 80.0)), min_size=3, max_size=10),
    st.one_of(st.just("static"), st.none(), st.floats(0.0, 15.0)),
)
def test_fit_of_plain_numbers_is_finite_or_says_why(points, kappa_cri):
    test_fit_is_finite_or_says_why.hypothesis.inner_test(points, kappa_cri, 0)


# ----------------------------------------------------------------- Scene, run_sweep
SCENE_ARGS = {
    "a": number(1.0, 40.0),
    "kappa0": number(0.0, 14.0),
    "n_cells": st.one_of(st.integers(1, 6), JUNK),
    "dt": number(0.01, 0.05),
    "t_end": st.one_of(st.none(), number(0.05, 1.5)),
    "window": st.one_of(st.just((0.1, 0.5)), st.tuples(number(0.0, 1.0), number(0.0, 1.0))),
    "tension": number(-1e-3, 1e-3),
}
SCENE_NAMES = ["a", "kappa0", "n_cells", "dt", "t_end", "window", "tension", "T", "horizon"]


@given(st.fixed_dictionaries(SCENE_ARGS))
def test_scene_is_made_or_names_the_parameter(kw):
    try:
        S.Scene(**kw)
    except (ValueError, TypeError) as err:
        event(f"Scene: {type(err).__name__}")
        names_one_of(err, SCENE_NAMES)
        return
    event("Scene: made")


@settings(max_examples=FEW)
@given(
    st.fixed_dictionaries(
        {
            "a": st.floats(4.0, 40.0),
            "kappa0": st.floats(0.0, 14.0),
            "n_cells": st.integers(2, 6),
            "dt": st.floats(0.01, 0.05),
            "t_end": st.floats(0.05, 1.5),
            "seed": st.builds(Perturbation, st.floats(0.0, 1e-3)),
        }
    )
)
def test_run_sweep_gives_a_status_and_serves_it_again(kw):
    scene = S.Scene(**kw)
    assume(scene.duration() / scene.dt <= 150)  # the time budget
    with tempfile.TemporaryDirectory() as store, warnings.catch_warnings():
        warnings.simplefilter("ignore", GridWarning)
        row = S.run_sweep([scene], store, progress=False).iloc[0]
        again = S.run_sweep([scene], store, progress=False).iloc[0]
    event(f"run_sweep: {row['status']}")
    assert row["status"] in STATUSES and again["cached"] and again["status"] == row["status"]
    if row["status"] == "buckled":
        assert row["t_c"] >= 0 and row["kappa3"] >= scene.kappa_cri()
    if row["status"] in ("no-onset", "failed"):
        assert row["t_c"] is None or math.isnan(row["t_c"])


# ------------------------------------------------------------ the command line
OPTIONS = {
    "--a": st.sampled_from(["1.6", "16", "0", "-1", "nan", "x"]),
    "--dt": st.sampled_from(["0.02", "0.05", "0", "-1", "nan", "abc", "inf"]),
    "--t-end": st.sampled_from(["0.1", "0.5", "1e12", "inf", "-2", "0.01"]),
    "--n-cells": st.sampled_from(["4", "8", "1", "-3", "2.5"]),
    "--seed": st.sampled_from(["1e-8", "0", "-1", "nan"]),
    "--rho": st.sampled_from(["1500", "0", "1e-320", "inf"]),
}


@settings(max_examples=FEW)
@given(st.fixed_dictionaries({}, optional=OPTIONS), st.sampled_from(["buckle", "sweep"]))
def test_cli_answers_or_prints_one_line(opts, command):
    args = [command, "--kappa0", "10"]
    for k, v in opts.items():
        args += [k, v] if command == "buckle" or k != "--a" else ["--rates", v]
    if command == "sweep" and "--a" not in opts:
        args += ["--rates", "16"]
    if command == "sweep":
        args.append("--quiet")
    with tempfile.TemporaryDirectory() as store:
        proc = subprocess.run(
            [sys.executable, "-m", "dyntorsion", *args, "--store", store],
            capture_output=True,
            text=True,
            timeout=300,
        )
    assert "Traceback" not in proc.stderr, proc.stderr
    if proc.returncode == 2 and "usage:" in proc.stderr:
        event("cli: argparse refusal")
        return
    event(f"cli: exit {proc.returncode}")
    if proc.returncode in (0, 1) and "dyntorsion: error" not in proc.stderr:
        assert "status" in proc.stdout or "kappa3" in proc.stdout, proc.stdout
        return
    lines = [ln for ln in proc.stderr.splitlines() if ln.startswith("dyntorsion: error:")]
    assert proc.returncode in (1, 2) and len(lines) == 1, proc.stderr


@pytest.mark.parametrize("magnitude", [-1.0, math.nan])
def test_bad_seed_is_named(magnitude):
    with pytest.raises(ValueError, match="magnitude"):
        Perturbation(magnitude)
