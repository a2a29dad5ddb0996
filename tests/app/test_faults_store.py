"""Faults of the store and of the command line (issue 37, items 4, 6, 7)."""

from __future__ import annotations

import json
import os

import numpy as np
import pytest

import dyntorsion.studies  # noqa: F401  (registers the record kinds)
from dyntorsion.app.cli import main, parser
from dyntorsion.buckling.scene import Scene
from dyntorsion.store.results import CorruptResultError, Store
from dyntorsion.studies.sweep import KIND, run_sweep

QUICK = ["--kappa0", "10", "--n-cells", "20", "--dt", "0.02"]


@pytest.fixture
def one(tmp_path):
    store = tmp_path / "store"
    assert main(["sweep", "--rates", "16", *QUICK, "--store", str(store), "--quiet"]) == 0
    (path,) = store.glob(f"{KIND}-*.json")
    return store, path


@pytest.mark.parametrize("damage", ["{ not json", "[1, 2, 3]", '{"kind": "x"}'])
def test_a_damaged_record_is_moved_aside_and_recomputed(one, damage, capsys):
    store, path = one
    good = json.loads(path.read_text())
    path.write_text(damage)
    assert main(["sweep", "--rates", "16", *QUICK, "--store", str(store), "--quiet"]) == 0
    assert "moved aside" in capsys.readouterr().err
    assert (path.parent / (path.name + ".corrupt")).read_text() == damage
    assert json.loads(path.read_text())["result"] == good["result"]


def test_on_corrupt_error_keeps_the_old_behaviour(one, capsys):
    store, path = one
    path.write_text("[]")
    code = main(["sweep", "--rates", "16", *QUICK, "--store", str(store), "--on-corrupt", "error"])
    assert code == 1 and "not a record" in capsys.readouterr().err
    with pytest.raises(CorruptResultError, match="not a record"):
        Store(store).read(path)


def test_fit_skips_what_it_cannot_use_and_says_how_many(tmp_path, capsys):
    store = tmp_path / "store"
    rates = "4,8,12,16"
    assert main(["sweep", "--rates", rates, *QUICK, "--store", str(store), "--quiet"]) == 0
    (store / f"{KIND}-0000000000000000dead.json").write_text("[]")
    capsys.readouterr()
    assert main(["fit", "--store", str(store)]) == 0
    out = capsys.readouterr()
    assert "1 record(s)" in out.err and "b = " in out.out


def test_run_sweep_of_numbers_names_the_parameter():
    with pytest.raises(TypeError, match="scenes must be Scene objects"):
        run_sweep([1.6, 3.2])
    with pytest.raises(TypeError, match="got float"):
        run_sweep([Scene(a=1.6), 3.2])


@pytest.mark.parametrize(
    "argv",
    [
        ["sweep", "--kappa0", "10"],
        ["sweep", "--rates", "1,2", "--preset", "fig10"],
        ["sweep", "--rates", "1,2", "--history", "poly:10,16"],
        ["buckle", "--a", "1000", "--history", "poly:10,16"],
        ["buckle", "--a", "1", "--history", "ramp-hold:abc"],
    ],
)
def test_usage_errors_exit_2_with_one_line(argv, capsys, tmp_path):
    assert main([*argv, "--store", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("dyntorsion: error: --")


def test_the_help_and_the_parser_agree_on_ramp_hold():
    buckle_help = parser()._subparsers._group_actions[0].choices["buckle"].format_help()
    assert "ramp-hold:HOLD[:TAU]" in " ".join(buckle_help.split())
    args = parser().parse_args(["buckle", "--a", "1.6", "--history", "ramp-hold:20:0.5"])
    from dyntorsion.app.cli_options import history_from

    hist = history_from(args, 1.6)["history"]
    assert (hist.hold, hist.tau) == (20.0, 0.5)
    assert (
        history_from(parser().parse_args(["buckle", "--history", "ramp-hold:20,0.5"]), 1.6)[
            "history"
        ]
        == hist
    )


def test_negative_numbers_in_exponent_form_are_values():
    args = parser().parse_args(["buckle", "--a", "1.6", "--tension", "-1e9"])
    assert args.tension == -1e9


def test_a_history_below_kappa_cri_is_an_answer_not_a_failure(capsys):
    argv = ["buckle", "--a", "1.6", "--history", "ramp-hold:10:0.5", "--t-end", "12"]
    assert main([*argv, "--n-cells", "20", "--dt", "0.02"]) == 0
    out = capsys.readouterr().out
    assert "no onset: the end twist stays below kappa_cri" in out and "increase t_end" not in out


def test_buckle_says_when_it_served_a_cached_record(tmp_path, capsys):
    argv = ["buckle", "--a", "16", *QUICK, "--store", str(tmp_path)]
    assert main(argv) == 0
    assert "cached" not in capsys.readouterr().out
    assert main(argv) == 0
    assert "read from" in capsys.readouterr().out


def test_a_run_past_the_time_budget_is_refused_before_it_starts(capsys, monkeypatch):
    import warnings

    monkeypatch.delenv("DYNTORSION_MAX_TIME", raising=False)  # --max-time sets it
    argv = ["--max-time", "60", "buckle", "--a", "1.6", "--n-cells", "100000", "--dt", "0.005"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the GridWarning of a grid this fine
        assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "over the budget of 60 s" in err[0] and "raise dt" in err[0]
    assert "DYNTORSION_MAX_TIME" not in os.environ  # the option does not outlive the call


def test_a_long_run_is_announced_with_its_estimate(monkeypatch):
    from dyntorsion.genalpha import guard

    monkeypatch.delenv("DYNTORSION_MAX_TIME", raising=False)
    said = []
    assert guard.check_time(10, 101, 12, say=said.append) < guard.ANNOUNCE_AFTER_S and not said
    guard.check_time(10**6, 1001, 12, say=said.append)
    assert len(said) == 1 and "may take up to" in said[0]
    monkeypatch.setenv("DYNTORSION_MAX_TIME", "-3")
    with pytest.raises(ValueError, match="DYNTORSION_MAX_TIME"):
        guard.max_time()


@pytest.mark.parametrize(
    "func, words",
    [
        (lambda t: np.array([1.0, 2.0]), "a number per time"),
        (lambda t: "x", "a number per time"),
        (lambda t: np.nan * t, "must be finite"),
    ],
)
def test_a_custom_history_is_checked_once_before_the_run(func, words):
    from dyntorsion.buckling import simulate
    from dyntorsion.buckling.loading import Custom

    with pytest.raises(ValueError, match=rf"history=custom 'h': .*{words}"):
        simulate(Scene(history=Custom("h", func), n_cells=10, dt=0.01, t_end=0.05), progress=False)
