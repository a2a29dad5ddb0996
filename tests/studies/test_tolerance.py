"""Accuracy on demand (dyntorsion.studies.tolerance, issue 34 item 1): the onset to a
relative tolerance, with an a-posteriori error estimate that covers a converged reference."""

import json
import math
from dataclasses import replace

import pandas as pd
import pytest
from hypothesis import given
from hypothesis import strategies as st

import dyntorsion
from dyntorsion.app.cli import main
from dyntorsion.buckling.loading import AxialLoad, RampHold
from dyntorsion.buckling.scene import Scene
from dyntorsion.genalpha import Newton
from dyntorsion.studies import fidelity
from dyntorsion.studies import presets as P
from dyntorsion.studies import tolerance as T

BAD = [0.0, -0.1, math.nan, math.inf, 1.0001, 2.0, True, "0.01", None]


@pytest.mark.parametrize("rtol", BAD)
def test_bad_rtol_is_refused_naming_the_parameter_and_its_range(rtol):
    with pytest.raises(ValueError, match=r"rtol=.*\(0, 1\]"):
        T.check_rtol(rtol)
    with pytest.raises(ValueError, match=r"rtol=.*\(0, 1\]"):
        T.onset_within(Scene(a=1.6), rtol)
    if rtol is not None:  # run_scene(scene, rtol=None) is the scene on its own grid
        with pytest.raises(ValueError, match=r"rtol=.*\(0, 1\]"):
            dyntorsion.run_scene(Scene(a=1.6), rtol=rtol)


@pytest.mark.parametrize("text", ["0", "-1", "nan", "1.5", "inf"])
def test_bad_rtol_on_the_command_line_is_refused(text, capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["buckle", "--a", "1.6", "--rtol", text])
    assert exit_.value.code == 2
    assert "--rtol" in capsys.readouterr().err


def test_good_rtol_and_max_cells():
    assert T.check_rtol(1) == 1.0 and T.check_rtol(0.005) == 0.005
    with pytest.raises(ValueError, match=r"max_cells=100; allowed: 200, 400"):
        T.onset_within(Scene(a=1.6), 0.01, max_cells=100)
    with pytest.raises(TypeError, match="need rtol"):
        dyntorsion.run_scene(Scene(a=1.6), max_cells=200)


def test_the_estimate_is_the_larger_of_the_last_two_differences():
    # an exact second-order sequence: covered, and overstated 12 times (|d_{K-1}| = 12 e_K)
    v = [1.0 + 0.3 * 4.0**-k for k in range(5)]
    for k in range(2, 5):
        e = T.error_estimate(v[: k + 1])
        assert e >= abs(v[k] - 1.0)
        assert e == pytest.approx(12 * abs(v[k] - 1.0))
    # first order: covered exactly
    w = [1.0 + 0.3 * 2.0**-k for k in range(4)]
    assert T.error_estimate(w) == pytest.approx(2 * abs(w[-1] - 1.0))
    # two rungs that agree by coincidence do not make a small estimate
    assert T.error_estimate([2.0, 1.0, 1.0 + 1e-9]) == pytest.approx(1.0)
    with pytest.raises(ValueError, match="three"):
        T.error_estimate([1.0, 2.0])
    with pytest.raises(ValueError, match="finite"):
        T.error_estimate([1.0, math.nan, 2.0])


@pytest.mark.parametrize("solver", [-1e-9, math.nan, math.inf, True, "0.1", None])
def test_the_solver_share_is_added_and_bad_values_are_refused(solver):
    v = [1.0 + 0.3 * 4.0**-k for k in range(4)]
    for reading in T.READINGS:
        assert T.error_estimate(v, reading, 0.25) == T.error_estimate(v, reading) + 0.25
        with pytest.raises(ValueError, match=r"solver=.* must be a finite number >= 0"):
            T.error_estimate(v, reading, solver)


@given(solver=st.one_of(st.floats(max_value=-1e-300), st.sampled_from([math.nan, math.inf])))
def test_any_negative_or_non_finite_solver_share_is_refused(solver):
    with pytest.raises(ValueError, match=r"solver=.* must be a finite number >= 0"):
        T.error_estimate([1.0, 1.5, 1.25], "continuous", solver)


@given(solver=st.floats(min_value=0.0, max_value=1e6))
def test_any_finite_solver_share_is_added_to_either_estimate(solver):
    v = [3.0, 2.0, 2.5]
    assert T.error_estimate(v, "continuous", solver) == 2 / 3 * max(0.5, 1 / 4) + solver
    assert T.error_estimate(v, "samples", solver) == 1.0 + solver


def test_the_solver_checks_change_needs_two_buckled_runs_with_an_onset():
    assert T.onset_change(("buckled", "buckled"), (2.5, 2.25)) == 0.25
    for status, values in ((("buckled", "no-onset"), (2.5, 2.25)),
                           (("failed", "buckled"), (2.5, 2.25)),
                           (("buckled", "buckled"), (None, 2.25)),
                           (("buckled", "buckled"), (2.5, math.nan))):  # fmt: skip
        assert T.onset_change(status, values) is None


def test_the_solver_check_is_the_standard_rung_at_a_hundredth_of_the_tolerance():
    sc = Scene(a=1.6, kappa0=10.0)
    check, standard = T.solver_check(sc), T.rungs(sc, 3)[-1]
    assert check.n_cells == standard.n_cells == 100 and check.dt == standard.dt
    assert check.newton.tol == sc.newton.tol * T.SOLVER_FACTOR == pytest.approx(1e-12)
    assert check.until == "first-peak" and check.seed == sc.seed
    # never below the tightest tolerance the solve reaches, nor looser than the scene's own
    for tol, checked in ((1e-6, 1e-8), (1e-12, 1e-13), (1e-13, 1e-13), (1e-14, 1e-14)):
        assert T.solver_check(replace(sc, newton=Newton(tol=tol))).newton.tol == checked
    tight = P.preset("tolerance-reference-tight")
    assert {s.newton.tol for s in tight} == {T.REFERENCE_TOL}
    assert [s.n_cells for s in tight] == [s.n_cells for s in P.preset("tolerance-reference")]


def test_the_rungs_halve_ds_and_dt_and_are_paced():
    sc = Scene(a=1.6, kappa0=10.0)
    rungs = T.rungs(sc)
    assert [r.n_cells for r in rungs] == [25, 50, 100, 200, 400]
    assert all(r.until == "first-peak" for r in rungs)
    assert all(b.dt == a.dt / 2 for a, b in zip(rungs, rungs[1:], strict=False))
    t_pace, by = T.pacing_time(sc)
    assert by == "linear estimate"
    assert rungs[2].dt == pytest.approx(t_pace / 384, rel=5e-3)  # the pacing's steps at N = 100
    # an axial load: the delay law paces; a history the static theory does not reach: the ladder
    loaded = Scene(a=1.6, kappa0=10.0, tension=AxialLoad(1e-5))
    assert T.pacing_time(loaded)[1] == "delay law"
    assert T.rungs(loaded, 3)[-1].dt == pytest.approx(T.pacing_time(loaded)[0] / 384, rel=5e-3)
    held = Scene(history=RampHold(1.6, 20.0, 10.0), t_end=20.0)
    assert T.pacing_time(held) == (None, "ladder")
    assert T.rungs(held, 2)[1].dt == fidelity.get("buckling", "quick").dt


def _converged(preset: str, field: str = "t_c_continuous") -> float:
    """The onset on the finest grid of an accuracy ladder in data/ (N = 400, dt = 0.00125 s),
    read as ``--rtol`` reads it by default (in continuous time) unless ``field`` says."""
    t = P.cached(preset)
    return float(t[(t.n_cells == 400) & (t.dt == 0.00125)][field].iloc[0])


def test_the_estimate_covers_the_converged_onset_of_a_cheap_scene():
    """The fast scene (a = 16): four rungs, a few seconds; the converged onset is the
    ladder's finest grid (whose own neighbours agree to 1e-4 s)."""
    ref = _converged("accuracy-fast")
    res = T.onset_within(Scene(a=16.0, kappa0=10.0), 0.005)
    assert res.reading == T.DEFAULT_READING == "continuous"
    assert res.met and res.status == "buckled"
    assert res.rung == "fine" and res.n_cells == 200
    assert abs(res.t_c - ref) <= res.t_c_error <= 0.005 * res.t_c
    assert abs(res.kappa3 - (10.0 + 16.0 * ref)) <= res.kappa3_error
    assert [g["n_cells"] for g in res.grids] == [25, 50, 100, 200]
    # the estimate: the rungs' differences plus the solver check's change
    s = res.solver
    assert s["n_cells"] == 100 and s["newton_tol"] == pytest.approx(1e-12)
    standard = res.grids[2]
    assert s["t_c_change"] == abs(s["t_c"] - standard["t_c"])
    assert res.t_c_error == T.error_estimate([g["t_c"] for g in res.grids], res.reading,
                                             s["t_c_change"])  # fmt: skip
    assert res.kappa3_error == T.error_estimate([g["kappa3"] for g in res.grids], res.reading,
                                                s["kappa3_change"])  # fmt: skip
    # the paper's rule off the samples, asked for by name: the same check, that reading
    ref_s = _converged("accuracy-fast", "t_c")
    res_s = T.onset_within(Scene(a=16.0, kappa0=10.0), 0.005, reading="samples")
    assert res_s.met and abs(res_s.t_c - ref_s) <= res_s.t_c_error <= 0.005 * res_s.t_c
    # the standard rung is never vouched for, however loose the tolerance
    assert T.onset_within(Scene(a=16.0, kappa0=10.0), 1.0).n_cells == 200
    # a tolerance the fine rung cannot meet, and no more cells allowed: said so
    tight = T.onset_within(Scene(a=16.0, kappa0=10.0), 1e-9, max_cells=200)
    assert not tight.met and tight.n_cells == 200 and len(tight.grids) == 4
    assert "rtol=1e-09 not met up to N = 200" in tight.note
    assert tight.t_c == res.t_c and tight.t_c_error == res.t_c_error


def test_the_continuous_readings_estimate_is_twice_richardsons_for_second_order():
    # exactly second order: Richardson's |d_K| / 3 is the error; the estimate twice that
    v = [1.0 + 0.3 * 4.0**-k for k in range(5)]
    for k in range(2, 5):
        assert T.error_estimate(v[: k + 1], "continuous") == pytest.approx(2 * abs(v[k] - 1.0))
    # two rungs that agree by coincidence: the previous difference over 4 keeps it
    assert T.error_estimate([2.0, 1.0, 1.0 + 1e-9], "continuous") == pytest.approx(1 / 6)
    with pytest.raises(ValueError, match="reading="):
        T.error_estimate(v, "spline")


def test_the_continuous_reading_is_asked_for_by_name():
    """``reading="continuous"``: the rungs give the window read in continuous time (the
    records' t_c_continuous), judged the same way; an unknown reading is refused naming
    the allowed ones."""
    with pytest.raises(ValueError, match=r"reading='spline'; allowed: 'samples', 'continuous'"):
        T.onset_within(Scene(a=16.0, kappa0=10.0), 0.005, reading="spline")
    res = T.onset_within(Scene(a=16.0, kappa0=10.0), 0.005, max_cells=200, reading="continuous")
    assert res.reading == "continuous" and res.n_cells == 200
    last = dyntorsion.buckling.scene.run_scene(T.rungs(Scene(a=16.0, kappa0=10.0), 4)[-1])
    assert res.t_c == last["t_c_continuous"] and res.kappa3 == last["kappa3_continuous"]
    assert res.t_c != last["t_c"]


def test_buckle_rtol_reading_continuous_on_the_command_line(tmp_path, capsys):
    argv = ["buckle", "--a", "16", "--kappa0", "10", "--rtol", "0.01", "--store", str(tmp_path)]
    assert main([*argv, "--reading", "continuous", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["reading"] == "continuous" and out["grid"]["n_cells"] == 200
    assert out["solver"]["n_cells"] == 100 and out["solver"]["t_c_change"] >= 0
    assert main([*argv, "--reading", "continuous"]) == 0
    text = capsys.readouterr().out
    assert "onset read in continuous time" in text
    assert "solver     Newton tol 1e-12 N=100" in text and "changes t_c by" in text
    assert main(argv) == 0  # the default reading
    assert "onset read in continuous time" in capsys.readouterr().out
    assert main([*argv, "--reading", "samples"]) == 0
    assert "onset read off the samples" in capsys.readouterr().out
    with pytest.raises(SystemExit) as exit_:
        main([*argv, "--reading", "spline"])
    assert exit_.value.code == 2 and "--reading" in capsys.readouterr().err


def test_buckle_rtol_json_covers_the_converged_onset(capsys):
    """Issue 34's "done when": ``dyntorsion buckle --a 1.6 --rtol 0.005 --json`` (the
    Fig 8 scene, kappa0 = 0) returns t_c with an error that covers the converged value."""
    code = main(["buckle", "--a", "1.6", "--rtol", "0.005", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0
    for key in ("t_c", "t_c_error", "kappa3", "kappa3_error", "grid"):
        assert key in out
    assert set(out["grid"]) == {"rung", "n_cells", "dt"}
    ref = _converged("accuracy-fig08")
    assert abs(out["t_c"] - ref) <= out["t_c_error"] <= 0.005 * out["t_c"]
    assert abs(out["kappa3"] - 1.6 * ref) <= out["kappa3_error"]


def test_buckle_json_without_rtol_is_one_object(capsys):
    code = main(["buckle", "--a", "16", "--kappa0", "10", "--n-cells", "30", "--dt", "0.01",
                 "--until", "first-peak", "--json"])  # fmt: skip
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and out["status"] == "buckled"
    assert out["t_c"] > 0 and "N=30" in out["scene"]


def test_sweep_rtol_runs_each_rate_and_caches_the_rungs(tmp_path, capsys):
    argv = ["sweep", "--rates", "16", "--kappa0", "10", "--rtol", "0.01", "--store", str(tmp_path)]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert "t_c_error" in out and "fine" in out
    # N = 25, 50, 100, 200 and the solver check (N = 100 at a hundredth of the tolerance)
    assert len(list(tmp_path.glob("buckling-onset-*.json"))) == 5
    # read back, computing nothing
    res = T.onset_within(Scene(a=16.0, kappa0=10.0), 0.01, store=tmp_path, compute=False)
    assert res.met and res.n_cells == 200
    with pytest.raises(ValueError, match="give store"):
        T.onset_within(Scene(a=16.0, kappa0=10.0), 0.01, compute=False)
    assert main([*argv, "--jobs", "2"]) == 2
    assert "drop --jobs" in capsys.readouterr().err


def test_the_hold_out_sets_are_covered():
    """Issue 34's honesty check of the sample rule's estimate on the committed records of
    the three sets judged before the solver check (presets tolerance-holdout to -3): on at
    least 60 scenes of each set, every one buckled on every rung, the fine rung's estimate
    of t_c covers its true error (against N = 800, preset tolerance-reference) in at least
    95 % of the scenes, and the chooser's answers at rtol 0.005 are covered as often.  (On
    the fourth set it covers 90 %: the solver's share test below.)"""
    from dyntorsion.studies import tolerance_study as TS

    for name in TS.SETS[:3]:
        p = TS.pairs(name)
        fine = p[(p.rung == "fine") & (p.quantity == "t_c")]
        assert fine.scene.nunique() >= 60 and fine.buckled.all()
        assert fine.covered.mean() >= 0.95
        c = TS.chooser(0.005, name)
        met = c[c.met]
        assert len(met) > len(c) / 2
        assert (met.t_c_covered & met.kappa3_covered).mean() >= 0.95


def test_the_reference_is_finer_than_what_it_judges():
    """The N = 800 reference: the last step of the ladder (N = 400 to 800; about the N = 400
    rung's error, more than the reference's own) is below half the fine rung's true
    error in the median (measured 0.016 % against 0.051 % and 0.055 % of t_c), and the fine
    rung's true error exceeds it in at least three scenes of four (83 % in both sets)."""
    from dyntorsion.studies import tolerance_study as TS

    ref = TS.reference_error()
    assert (ref["last step, median"] < 0.5 * ref["fine, true error, median"]).all(), ref
    assert (ref["fine errors above the last step"] >= 0.75).all(), ref


def test_no_multiple_of_an_error_indicator_is_both_safe_and_within_3_times():
    """Issue 34 asked for estimates covering 95 % and within 3 times the true error in most:
    read off the samples, for every indicator of
    :data:`~dyntorsion.studies.tolerance_study.INDICATORS`, the 95th percentile of true
    error / indicator exceeds 3 times its median on one of the first two sets at least
    (measured: 3.7 or more), so no multiple of it does both there (the page says so)."""
    from dyntorsion.studies import tolerance_study as TS

    assert (TS.spread()[list(TS.SETS[:2])].max(axis=1) > 3.0).all()


def test_read_in_continuous_time_the_estimate_is_honest_on_the_set_computed_after_it():
    """The continuous reading's estimate (2/3) max(|d_K|, |d_K-1|/4), fixed before the third
    hold-out set was defined: on that set the fine rung's estimates cover at least 95 % of
    the true errors against N = 800 (measured 95.0 %, 57 of 60) and are within 3 times
    in most (67 %); on the first two sets, looked at when the rule was fixed, they cover
    90.9 and 91.7 % (asserted: at least 90 %) at a median overstatement of 2.3.  The
    indicator's spread is at most 3 on every set (2.97, 2.51, 2.42), where the samples'
    reaches 4.8, and the fine rung is closer in continuous time (median true error
    0.016 % of t_c against 0.051 %)."""
    from dyntorsion.studies import tolerance_study as TS

    fine = {}
    for reading in ("samples", "continuous"):
        for name in TS.SETS[:3]:
            p = TS.pairs(name, reading=reading)
            f = p[(p.rung == "fine") & (p.quantity == "t_c")]
            assert f.buckled.all() and f.scene.nunique() >= 60
            fine[reading, name] = f
    third = fine["continuous", TS.SETS[2]]
    assert third.covered.mean() >= 0.95 and (third.overstatement <= 3).mean() > 0.5
    for name in TS.SETS[:3]:
        f = fine["continuous", name]
        assert f.covered.mean() >= 0.90 and f.overstatement.median() < 3
    spread = TS.spread(reading="continuous").loc["max(|d_K|, |d_K-1| / 4)"]
    assert (spread <= 3).all()
    assert TS.spread().loc["max(|d_K|, |d_K-1| / 4)"].max() > 4

    def median_true(reading):
        f = pd.concat([fine[reading, name] for name in TS.SETS[:3]])
        return (f.true / f.reference.abs()).median()

    assert median_true("continuous") < 0.5 * median_true("samples")


def test_the_solver_check_makes_the_continuous_estimate_honest_on_the_set_computed_after_it():
    """The solver check, added after a look at the first three sets against references at
    the scenes' own Newton tolerance: judged against the N = 800 references converged in
    the solver (tol 1e-13), the continuous reading's estimate with the check covers at
    least 95 % of the fine rung's true errors on the fourth set, defined and computed after
    it (measured 96.7 %), and over all four sets (97.2 %), within 3 times in most (60 % and
    61 %); without the check, against the old references, the fourth set is covered in
    under 95 % (86.7 %).  Off the samples the estimate stays several times too large
    (median overstatement above 3 on every set).  The check is what catches the tiny seeds:
    its change exceeds the rungs' estimate in some scenes of every seed of 1e-14 N/m and
    below, and in none of the larger seeds, the other rods or the loads."""
    from dyntorsion.studies import solver_share as SS
    from dyntorsion.studies import tolerance_study as TS

    share = SS.solver_share()
    before, after = (share[share.judged == v].set_index(["reading", "set"]) for v in SS.VARIANTS)
    for name in (TS.SETS[3], "all"):
        row = after.loc["continuous", name]
        assert row["fine: covered"] >= 95 and row["within 3x"] > 50, row
        assert row["kappa3 covered"] >= 95
    assert after.loc["continuous", "all"].scenes == 246
    assert before.loc["continuous", TS.SETS[3]]["fine: covered"] < 95
    assert (after.loc["samples"]["overstatement, median"] > 3).all()
    met, n = map(int, after.loc["continuous", TS.SETS[3]]["rtol 0.005: met"].split("/"))
    assert met == n == 60
    groups = SS.by_group()
    above = groups["change above the estimate [% of scenes]"]
    tiny = [g for g in groups.index if any(f"10⁻¹{d} " in g for d in "⁴⁵⁶⁷")]
    assert len(tiny) == 4 and (above.loc[tiny] > 0).all()
    assert (above.drop(tiny) == 0).all()
    # its price: one more standard run, a small part of the ladder (measured 15 %)
    assert 0.05 < SS.check_cost() < 0.3
