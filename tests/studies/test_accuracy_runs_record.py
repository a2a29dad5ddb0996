"""The runs of "Accuracy and cost" are a record per fidelity level
(dyntorsion.studies.accuracy_runs), read by the page: committed, current, and saying
what the page says of them."""

from __future__ import annotations

import pytest

from dyntorsion.studies import accuracy_runs as AR
from dyntorsion.studies import fidelity

LEVELS = ("quick", "standard")


@pytest.fixture(scope="module", params=LEVELS)
def runs(request):
    """The committed record at a level; a missing or stale one fails here."""
    return AR.load(request.param)


def test_the_record_is_keyed_by_level_and_refused_when_missing(tmp_path):
    quick, standard = AR.params("quick"), AR.params("standard")
    assert quick["long_steps"]["grid"] != standard["long_steps"]["grid"]
    assert {k: v for k, v in quick.items() if k not in ("level", "long_steps")} == {
        k: v for k, v in standard.items() if k not in ("level", "long_steps")
    }
    with pytest.raises(LookupError, match="make data-studies"):
        AR.load("quick", tmp_path)
    with pytest.raises(ValueError, match="fidelity"):
        AR.load("coarse", tmp_path)


def test_the_record_holds_every_table_of_its_params(runs):
    assert [r["setting (N = 50)"] for r in runs["settings"]] == list(AR.SETTINGS)
    assert [r["route"] for r in runs["routes"]] == list(AR.ROUTES)
    assert [r["a [rad/(m s)]"] for r in runs["long_steps"]] == list(AR.LONG_RATES)
    assert len(runs["paced"]["t_c [s]"]) == 16
    assert {r["sweep"] for r in runs["estimates"]} == set(AR.ESTIMATED)


def test_the_long_steps_move_the_onset_by_less_than_its_uncertainty(runs):
    for r in runs["long_steps"]:
        assert abs(r["t_c long [s]"] - r["t_c at dt [s]"]) < r["uncertainty_t at dt [s]"]
        assert r["long steps until [s]"] < r["t_c at dt [s]"]


def test_the_timed_settings_are_positive_and_the_fast_route_is_cheaper(runs):
    settings = runs["settings"]
    assert all(r["wall, median [s]"] > 0 for r in settings)
    to_end, first_peak, fast = settings
    assert first_peak["steps"] < to_end["steps"]
    assert fast["wall, median [s]"] < to_end["wall, median [s]"]
    # ending at the first peak does not move the onset
    assert first_peak["t_c [s]"] == to_end["t_c [s]"]


def test_the_wave_errors_fall_with_the_level(runs):
    for scene in AR.WAVES:
        rows = {r["level"]: r for r in runs["waves"] if r["scene"] == scene}
        errors = [rows[lvl]["error [1/m]"] for lvl in fidelity.LEVELS]
        assert errors == sorted(errors, reverse=True) and errors[-1] < errors[0] / 5
        assert [rows[lvl]["N"] for lvl in fidelity.LEVELS] == [
            fidelity.get(scene, lvl).n_cells for lvl in fidelity.LEVELS
        ]


def test_the_rtol_run_meets_its_tolerance(runs):
    res = runs["rtol_run"]
    assert res["t_c error [s]"] <= AR.RTOL_RUN["rtol"] * res["t_c [s]"]
    assert res["n_cells"] == res["grids"][-1]["n_cells"]
