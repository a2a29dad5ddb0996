"""The committed records of the plectoneme scenes (issue 33, items 3 and 5):
data/bench/plectoneme_tension.json (``dyntorsion.studies.contact.plectoneme_tension``) and
data/bench/dyntorsion_plectoneme.json (``dyntorsion.studies.contact.plectoneme_dyntorsion``): current, and
saying what the "Past contact" page says of them."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[3]


@pytest.fixture(scope="module")
def tension(current_record):
    return current_record(
        "bench/plectoneme_tension.json", "dyntorsion.studies.contact.plectoneme_tension"
    )


def test_the_static_critical_torque_is_bracketed_by_the_dynamic_rod(tension):
    """Turned to F x Theta_c and held: straight for 270 s below (bending curvature under
    2 % of 1/L: the seed's static response, measured 0.0021 and 0.0055 1/m at F = 0.98 and
    0.99), buckled within 10 s of the end of the turn above."""
    L = tension["params"]["length"]
    below = [r for r in tension["bracket"] if r["F"] < 1]
    above = [r for r in tension["bracket"] if r["F"] > 1]
    assert {r["F"] for r in below} >= {0.99} and {r["F"] for r in above} >= {1.01}
    for r in below:
        assert r["stopped"] == "t_end" and r["t_last"] == tension["params"]["bracket"]["t_hold"]
        assert r["max_bending_curvature_at_t_hold"] < 0.02 / L
    for r in above:
        assert r["stopped"] != "t_end" and r["max_u3"] > 0.1
        assert r["t_last"] < tension["params"]["bracket"]["t_turn"] + 10.0


def test_the_theory_numbers_are_the_package_s(tension):
    from dyntorsion.beyond.ply import ply

    th = tension["theory"]
    p = tension["params"]
    assert th["ply"]["torque"] == ply(p["tension"], th["B"], p["radius"]).torque
    assert 0.09 < th["eps"] < 0.11 and 9 < th["lam"] < 11
    assert 1.0 < th["critical_torque"] / th["greenhill_infinite"] < 1.05


@pytest.fixture(scope="module")
def side(current_record):
    return current_record(
        "bench/dyntorsion_plectoneme.json", "dyntorsion.studies.contact.plectoneme_dyntorsion"
    )


def test_the_side_by_side_runs_follow_pyelastica_until_its_passage(side):
    """Every run of PyElastica's scene in dyntorsion (min_arc = the arc RodSelfContact skips,
    1.47 D): from 12 s to PyElastica's passage (its link drops by 2 at 46.4 s) the writhe and
    the sliding end follow PyElastica's within 0.15 turns and 1 cm in the median (measured
    0.086-0.124 turns, 5-7 mm), 0.45 turns and 5 cm at worst (0.36, 3.5 cm, where a loop
    forms a few tenths of a second apart in the two codes); the writhe passes 0.1 turns
    within 0.3 s of PyElastica's (8.5 s against 8.4 s)."""
    pe = json.loads((ROOT / "data" / "bench" / "pyelastica_plectoneme.json").read_text())["result"]
    t_pe = np.asarray(pe["t"])
    passage = t_pe[np.argmax(np.diff(pe["link_turns"]) < -1.0) + 1]
    assert 46.0 < passage < 47.0
    assert len(side["runs"]) >= 3
    for run in side["runs"]:
        h = run["history"]
        t = np.asarray(h["t"])
        wr, z = np.asarray(h["writhe_turns"]), np.asarray(h["end_axial_position"])
        buckle = t[np.argmax(wr > 0.1)] - t_pe[np.argmax(np.asarray(pe["writhe_turns"]) > 0.1)]
        assert abs(buckle) < 0.3
        both = (t > 12.0) & (t < passage - 0.5)
        dwr = np.abs(wr[both] - np.interp(t[both], t_pe, pe["writhe_turns"]))
        dz = np.abs(z[both] - np.interp(t[both], t_pe, pe["end_axial_position"]))
        assert np.median(dwr) < 0.15 and dwr.max() < 0.45
        assert np.median(dz) < 0.01 and dz.max() < 0.05


def test_no_run_passes_through_itself_and_the_finer_grids_run_to_the_end(side):
    """No run passes the rod through itself.  N = 150 and 200 run to 100 s (the tip at a
    curvature radius of 0.37 and 0.40 D at its tightest): their writhes agree within 0.1
    turns over the whole run (measured 0.049) and their plectonemes within 0.05 turns (1.44,
    1.45); the energy budget closes within 0.1 % (measured 6e-5, 8e-7); Lk - Tw - Wr falls
    with N (0.088, 0.042: the issue's 0.01 not met) and the overlap stays under 3 % D
    (1.8 %, 2.2 %: the issue's 1 % not met after ~40 s), pinned as measured.  N = 100 at
    both steps stops as under-resolved within 5 s of the end of the turning, the tip closed
    to one cell; its two steps' writhes agree within 0.1 turns to 50 s (measured 0.068)."""
    runs = {(r["n_cells"], r["dt"]): r for r in side["runs"]}
    t_turn, t_end = side["params"]["t_turn"], side["params"]["t_turn"] + side["params"]["t_hold"]
    for run in runs.values():
        assert not run["result"]["stopped"].startswith("passage")
    fine = [runs[(200, 0.02)], runs[(150, 0.02)]]
    for run in fine:
        res = run["result"]
        assert res["stopped"] == "t_end" and res["t_last"] == t_end
        assert res["max_cell_bend"] < 0.5 and abs(res["energy_residual"]) < 1e-3
        assert res["max_penetration_over_D"] < 0.03 and res["max_link_gap_turns"] < 0.1
        assert 1.3 < abs(run["plectoneme"]["turns"]) < 1.6
    assert fine[0]["result"]["max_link_gap_turns"] < fine[1]["result"]["max_link_gap_turns"]
    whole = np.arange(1.0, t_end + 1e-9, 0.1)
    wa, wb = (np.interp(whole, r["history"]["t"], r["history"]["writhe_turns"]) for r in fine)
    assert np.abs(wa - wb).max() < 0.1
    assert abs(abs(fine[0]["plectoneme"]["turns"]) - abs(fine[1]["plectoneme"]["turns"])) < 0.05
    coarse = [runs[(100, 0.01)], runs[(100, 0.02)]]
    for run in coarse:
        res = run["result"]
        assert res["stopped"].startswith("under-resolved")
        assert t_turn < res["t_last"] < t_turn + 5.0 and 1.0 <= res["max_cell_bend"] < 1.1
    until = np.arange(1.0, t_turn + 1e-9, 0.1)
    wa, wb = (np.interp(until, r["history"]["t"], r["history"]["writhe_turns"]) for r in coarse)
    assert np.abs(wa - wb).max() < 0.1


def test_the_torque_rotation_curve_rises_jumps_and_levels_above_the_ply_theory(tension):
    """Turned at 0.05 turns/s: the torque follows the elastic C Theta / L of the straight rod
    (within 0.03 N m: the light spin damping's viscous torque, ~0.013 N m), peaks 7.6 % above
    C kappa_cri(T) (late, the delayed instability), falls by 74 % within 5 s, and over the
    first turn after the jump has a median 1.22 times the two-ply plateau; the overlap stays
    under 1 % of D, the energy budget as the scheme keeps it within the issue's 1 %
    (measured 0.56 %; counted at the nodes 1.01 %, capped at 2 %), Lk - Tw - Wr within 0.2
    turns (measured 0.11: the coarse grid's drift, not met at the issue's 0.01)."""
    th, p = tension["theory"], tension["params"]
    h, out = tension["curve"]["history"], tension["curve"]["result"]
    t, M = np.asarray(h["t"]), np.asarray(h["end_moment"])
    rot = np.asarray(h["link_turns"]) - h["link_turns"][0]
    straight = (rot > 1.0) & (rot < 0.95 * th["critical_turns"])
    elastic = th["C"] * 2 * np.pi * rot / p["length"]
    assert np.abs(M[straight] - elastic[straight]).max() < 0.03
    k = int(np.argmax(M))
    assert 1.0 < M[k] / th["critical_torque"] < 1.15 and rot[k] > th["critical_turns"]
    after = (t > t[k]) & (t < t[k] + 5.0)
    assert M[after].min() < 0.35 * M[k]
    ply = (rot >= rot[k] + 0.25) & (rot <= rot[k] + 1.0)
    assert 1.0 < np.median(M[ply]) / th["ply"]["torque"] < 1.4
    assert out["stopped"] == "t_end" and out["max_penetration_over_D"] < 0.01
    assert abs(out["energy_residual"]) < 0.02 and out["max_link_gap_turns"] < 0.2
    assert abs(out["energy_residual_scheme"]) < 0.01
    assert 1.0 < abs(out["plectoneme_turns"]) < 2.0


@pytest.fixture(scope="module")
def matched(current_record):
    return current_record("bench/plectoneme_matched.json", "plectoneme_matched.py")


def test_the_matched_ladders_are_complete_and_reproduce_the_long_runs(matched, side):
    """Every rung of both ladders ran in one invocation of the script, the finest rungs to
    t*; the finest rungs repeat the long records' runs of the same grids to t* (same scene,
    same code: dyntorsion's N = 200 at dt = 0.02 s and PyElastica's example, to 1e-9 turns)."""
    p = matched["params"]
    assert sorted(r["n"] for r in matched["dyntorsion"]) == sorted(p["dyntorsion_cells"])
    assert sorted(r["n"] for r in matched["pyelastica"]) == sorted(p["pyelastica_elements"])
    rows = matched["dyntorsion"] + matched["pyelastica"]
    assert len({r["invocation"] for r in rows}) == 1
    t_star = p["t_star"]
    for r in rows:
        assert r["stopped"] != "t_end" or abs(r["t_last"] - t_star) < 1e-6
    dyn = max(matched["dyntorsion"], key=lambda r: r["n"])
    pe = max(matched["pyelastica"], key=lambda r: r["n"])
    assert dyn["stopped"] == pe["stopped"] == "t_end"
    long = next(
        r for r in side["runs"] if (r["n_cells"], r["dt"]) == (dyn["n"], p["dyntorsion_dt"])
    )
    t = np.asarray(long["history"]["t"])
    i = int(np.argmin(np.abs(t - t_star)))
    assert abs(t[i] - t_star) < 1e-9
    assert abs(long["history"]["writhe_turns"][i] - dyn["writhe"]) < 1e-9
    pe_ref = json.loads((ROOT / "data" / "bench" / "pyelastica_plectoneme.json").read_text())
    assert pe["n"] == pe_ref["params"]["n_elem"]
    t = np.asarray(pe_ref["result"]["t"])
    i = int(np.argmin(np.abs(t - t_star)))
    assert abs(t[i] - t_star) < 1e-6
    assert abs(pe_ref["result"]["writhe_turns"][i] - pe["writhe"]) < 1e-9


def test_the_matched_analysis_is_the_record_s_runs_extrapolated(matched):
    """The limits in the record's analysis are Richardson's on the three finest rungs that
    reached t*; dyntorsion's writhe converges faster than first order, PyElastica's at about
    first order (as the page says), and every rung's error against the limit falls with n."""
    from dyntorsion.verification import richardson

    a = matched["analysis"]
    orders = {}
    for code in ("dyntorsion", "pyelastica"):
        rows = sorted((r for r in matched[code] if r["stopped"] == "t_end"), key=lambda r: r["n"])
        value, order = richardson([1 / r["n"] for r in rows], [r["writhe"] for r in rows])
        lim = a["codes"][code]["limit"]["writhe"]
        assert lim["value"] == pytest.approx(value, abs=1e-12)
        assert lim["order"] == pytest.approx(order, abs=1e-9)
        orders[code] = order
        err = [r["writhe_error"] for r in a["codes"][code]["rungs"]]
        assert err == sorted(err, reverse=True), (code, err)
    assert 1.2 < orders["dyntorsion"] < 3.0 and 0.7 < orders["pyelastica"] < 1.3, orders
    for pair in a["pairs"]:
        d, p = pair["dyntorsion"], pair["pyelastica"]
        assert d is not None and d["writhe_error"] <= p["writhe_error"]
        assert pair["ratio"] == pytest.approx(p["wall"] / d["wall"])


@pytest.fixture(scope="module")
def plateau(current_record):
    return current_record(
        "bench/plectoneme_plateau.json", "dyntorsion.studies.contact.plectoneme_plateau"
    )


def test_the_longer_rod_shows_no_plateau_and_says_where_it_stops_being_trusted(plateau):
    """The 4 m rod under 5 N turned 11 turns (``dyntorsion.studies.contact.plectoneme_plateau``), pinned as
    measured: the peak 1.00-1.15 times C kappa_cri(T) past the static critical rotation
    (1.067); 5 s after it the far end pulled in by more than 1.5 m (3.96 -> 1.69 m) with
    more than one plectoneme turn (1.19); while |Lk - Tw - Wr| <= 0.05 turns (to 118.5 s)
    the torque stays above the two-ply plateau and rises by more than 0.15 N m (0.73 ->
    0.97 N m) as the ply grows by more than 0.4 turns (1.19 -> 1.79); past it the run fails
    the issue's checks (Lk - Tw - Wr 0.76 turns, energy residual 13 %), as the page says.
    Those last two are of the untrusted part and move with the arithmetic: 0.85 turns and
    41 % with the contact's Jacobian in six columns a node (before 2026-11-27), where every
    reading above was the same."""
    th, p = plateau["theory"], plateau["params"]
    h, out = plateau["curve"]["history"], plateau["curve"]["result"]
    t, M = np.asarray(h["t"]), np.asarray(h["end_moment"])
    rot = np.asarray(h["link_turns"]) - h["link_turns"][0]
    z, plect = np.asarray(h["end_axial_position"]), np.abs(np.asarray(h["plectoneme_turns"]))
    gap = np.abs(np.asarray(h["link_turns"]) - np.asarray(h["twist_turns"])
                 - np.asarray(h["writhe_turns"]))  # fmt: skip
    assert out["stopped"] == "t_end" and out["t_last"] == p["t_end"]
    k = int(np.argmax(M))
    assert 1.0 < M[k] / th["critical_torque"] < 1.15 and rot[k] > th["critical_turns"]
    j = int(np.argmin(np.abs(t - (t[k] + 5.0))))
    assert z[k] - z[j] > 1.5 and plect[j] > 1.0
    lost = k + int(np.argmax(gap[k:] > 0.05))
    held = slice(j, lost + 1)
    assert t[lost] - t[j] > 20.0
    assert M[held].min() > th["ply"]["torque"] and M[held][-1] - M[held][0] > 0.15
    assert plect[held][-1] - plect[held][0] > 0.4
    assert out["max_link_gap_turns"] > 0.5 and out["energy_residual"] > 0.1


@pytest.fixture(scope="module")
def bounds(current_record):
    return current_record(
        "bench/plectoneme_bounds.json", "dyntorsion.studies.contact.plectoneme_bounds"
    )


def test_a_stiffer_contact_on_a_finer_grid_meets_the_issue_s_bounds(bounds, side):
    """PyElastica's scene with the contact 4 times stiffer (``dyntorsion.studies.contact.plectoneme_bounds``):
    both runs go to 100 s without passage, overlap within 1 % of D (0.87 %, 0.84 %), energy
    residual within 0.1 % (1.2e-4, 1.5e-4); Lk - Tw - Wr falls from N = 400 to 500 at an
    observed order above 2 (0.0104 -> 0.0052 turns, order 3.1) and meets the issue's 0.01 on
    500 cells; the two grids' writhes agree within 0.02 turns over the run (0.006) and end
    within 0.1 turns of the side-by-side record's N = 200 run (default stiffness; 0.04)."""
    runs = {r["n_cells"]: r for r in bounds["runs"]}
    assert sorted(runs) == [400, 500]
    for r in runs.values():
        out = r["result"]
        assert out["stopped"] == "t_end" and out["t_last"] == 100.0
        assert out["max_penetration_over_D"] <= 0.01
        assert abs(out["energy_residual"]) < 1e-3
    g4, g5 = (runs[n]["result"]["max_link_gap_turns"] for n in (400, 500))
    assert g5 <= 0.01 < g4
    assert np.log(g4 / g5) / np.log(500 / 400) > 2.0
    whole = np.arange(1.0, 100.0 + 1e-9, 0.1)

    def writhe(run):
        return np.interp(whole, run["history"]["t"], run["history"]["writhe_turns"])

    assert np.abs(writhe(runs[400]) - writhe(runs[500])).max() < 0.02
    ref = next(r for r in side["runs"] if (r["n_cells"], r["dt"]) == (200, 0.02))
    assert np.abs(writhe(runs[500]) - writhe(ref)).max() < 0.1
