"""The committed record of ``dyntorsion.studies.contact.contact_convergence`` (data/contact/first_contact.json,
issue 33 item 3): current, and saying what the "Past contact" page says of it."""

from __future__ import annotations

import math

import pytest

from dyntorsion.beyond.contact.budget import share


@pytest.fixture(scope="module")
def record(current_record):
    return current_record(
        "contact/first_contact.json", "dyntorsion.studies.contact.contact_convergence"
    )


def test_the_record_is_complete(record):
    grids = {(r["n_cells"], r["max_step"]) for r in record["runs"]}
    assert grids == {tuple(g) for g in record["params"]["grids"]}
    assert {(p["n_cells"], p["lam_t"], p["t_end"], p["route"]) for p in record["past"]} == {
        tuple(p) for p in record["params"]["past"]
    }


def test_the_link_check_converges_at_second_order_and_is_met_on_the_finest_grid(record):
    step = max(r["max_step"] for r in record["runs"])
    gap = {r["n_cells"]: r["max_link_gap_turns"] for r in record["runs"] if r["max_step"] == step}
    orders = [math.log2(gap[n] / gap[2 * n]) for n in (200, 400)]
    assert min(orders) > 1.7, orders  # measured 1.87, 1.94
    assert gap[800] < 0.01 < gap[400]
    t1 = {r["n_cells"]: r["first_contact_t"] for r in record["runs"] if r["max_step"] == step}
    assert abs(t1[800] - t1[400]) < abs(t1[400] - t1[200]) < abs(t1[200] - t1[100])


def test_the_quick_grid_stops_as_under_resolved_before_any_contact(record):
    quick = next(r for r in record["runs"] if r["n_cells"] == 50)
    assert quick["stopped"].startswith("under-resolved") and quick["first_contact_t"] is None


def _past(record, n, lam_t, t_end, route):
    return next(
        p["result"]
        for p in record["past"]
        if (p["n_cells"], p["lam_t"], p["t_end"], p["route"]) == (n, lam_t, t_end, route)
    )


def test_the_free_time_route_holds_overlap_and_link_just_past_contact_on_800_cells(record):
    """a = 16, lambda_inf = -0.8, to 3.3 s (0.11 s past the first contact): on N = 800 the
    contact on the free time route keeps the overlap below 1 % D and Lk - Tw - Wr below
    0.01 turns (measured 0.54 % and 0.0094); on N = 400 the link misses (0.033)."""
    r800, r400 = _past(record, 800, -0.8, 3.3, "time"), _past(record, 400, -0.8, 3.3, "time")
    assert r800["stopped"] == "t_end" and r800["max_contact_sites"] >= 2
    assert r800["max_penetration_over_D"] < 0.01 and r800["max_link_gap_turns"] < 0.01
    assert r400["max_penetration_over_D"] < 0.01 < r400["max_link_gap_turns"]


def test_anchoring_the_time_route_trades_the_overlap_for_the_link(record):
    """The time route set back onto the rebuilt shape after every step keeps the link
    closer (0.014 and 0.0020 turns on N = 400 and 800) but each reset moves the contact
    points by the step's gap between the two shapes: overlaps of 8 % and 5.3 % D."""
    for n in (400, 800):
        free, anchored = (_past(record, n, -0.8, 3.3, r) for r in ("time", "anchored"))
        assert anchored["drift"]["anchored"] and not free["drift"]["anchored"]
        assert anchored["max_link_gap_turns"] < free["max_link_gap_turns"]
        assert anchored["max_penetration_over_D"] > 0.01 > free["max_penetration_over_D"]


def test_at_the_papers_lambda_the_run_on_800_cells_meets_every_check_past_contact(record):
    """The free time route on N = 800 to 3.3 s: the nodal energy residual falls with
    lambda_inf (2.13, 1.48, 0.10 % at -0.8, -0.9, -1), and at the paper's
    lambda_inf = -1 the run meets issue 33's three bounds 0.11 s past the first contact
    (overlap 0.46 % D, Lk - Tw - Wr 0.0089 turns, energy 0.10 %)."""
    res = [_past(record, 800, lam, 3.3, "time")["energy_residual"] for lam in (-0.8, -0.9, -1.0)]
    assert res[0] > res[1] > res[2] > 0
    r = _past(record, 800, -1.0, 3.3, "time")
    assert r["stopped"] == "t_end" and r["first_contact_t"] < 3.2 and r["max_contact_sites"] >= 2
    assert r["max_penetration_over_D"] < 0.01
    assert r["max_link_gap_turns"] < 0.01
    assert abs(r["energy_residual"]) < 0.01


def test_the_first_contact_is_the_loop_on_an_end_fixture(record):
    """On every grid the first contact is the loop touching the axis continued beyond a
    clamp (the closure of the writhe made solid); the rod touches itself later."""
    touched = [r for r in record["runs"] if r["first_contact_t"] is not None]
    assert len(touched) >= 5
    for r in touched:
        assert r["first_fixture_contact_t"] == r["first_contact_t"]
    r = _past(record, 800, -1.0, 3.3, "time")
    assert r["first_fixture_contact_t"] < r["first_self_contact_t"] < r["t_last"]


def _share(r: dict, key: str) -> float:
    return share(r["energy_scheme"], key)


def test_the_scheme_s_own_budget_splits_the_nodal_residual(record):
    """The lines as the scheme keeps them (dyntorsion.beyond.contact.budget) on N = 800 to
    3.3 s: the scheme's numerical dissipation is zero at the paper's lambda_inf = -1 and
    grows as lambda_inf leaves it, but stays a fraction of the nodal residual (measured
    at -0.8: D 0.40 % against 2.13 %); what the lines leave (the trapezoidal rule's
    residue) is within 1 % of the work on every run that reached 3.3 s (measured 0.08,
    -0.05, -0.17 % on N = 800; the N = 200 run ends under-resolved before it)."""
    runs = {lam: _past(record, 800, lam, 3.3, "time") for lam in (-0.8, -0.9, -1.0)}
    d = [_share(runs[lam], "dissipation") for lam in (-1.0, -0.9, -0.8)]
    assert d[0] == 0.0 < d[1] < d[2]
    assert runs[-0.8]["energy_residual"] > 2.0 * d[2]
    for p in record["past"]:
        r = p["result"]
        if p["t_end"] == 3.3 and r["stopped"] == "t_end":
            assert abs(r["energy_residual_scheme"]) < 0.01, (p["n_cells"], p["lam_t"], p["t_end"])


def test_where_the_contact_is_violent_it_does_work_on_the_rod(record):
    """N = 400, lambda_inf = -0.8, to 3.45 s: as the scheme applies it, the contact does
    positive work on the rod (measured +10.6 % of the work at the ends, against a spring and
    dashpot law), and the nodes hold more energy than the cell averages (8.8 %): the finding
    that an energy-consistent contact is to mend (the Past contact page)."""
    r = _past(record, 400, -0.8, 3.45, "time")
    assert _share(r, "contact") > 0.05
    e = r["energy"]
    assert (e["kinetic_plus_elastic_change"] - r["energy_scheme"]["energy_mid"]) > 0.05 * (
        e["work_ends"] + e["work_seed"]
    )
