"""Tables a page derives from many records are kept as records of their own
(dyntorsion.studies.page_records): the frames come back as they were made, the three
committed records are current, and each equals what its functions compute."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest
from hypothesis import given
from hypothesis import strategies as st

from dyntorsion.studies import (
    claims,
    consistency,
    consistency_tables,
    preset_endings,
    tolerance_tables,
)
from dyntorsion.studies import presets as P
from dyntorsion.studies import tolerance_study as TS
from dyntorsion.studies.page_records import frame_from_json, frame_to_json

floats = st.floats(allow_nan=True, allow_infinity=True)


@st.composite
def frames(draw):
    n = draw(st.integers(0, 6))
    columns = {
        "x": draw(st.lists(floats, min_size=n, max_size=n)),
        "i": draw(st.lists(st.integers(-(2**40), 2**40), min_size=n, max_size=n)),
        "ok": draw(st.lists(st.booleans(), min_size=n, max_size=n)),
        "name": draw(
            st.lists(st.sampled_from(["a", "inf", "nan", "b c", ""]), min_size=n, max_size=n)
        ),
    }
    frame = pd.DataFrame(columns)
    if draw(st.booleans()):
        frame = frame.set_index(["name", "i"]) if draw(st.booleans()) else frame.set_index("i")
    if draw(st.booleans()) and len(frame.columns) >= 2:
        frame.columns = pd.MultiIndex.from_tuples(
            [("v", str(c)) for c in frame.columns], names=["what", "column"]
        )
    return frame


def _round_trip(frame: pd.DataFrame) -> pd.DataFrame:
    return frame_from_json(json.loads(json.dumps(frame_to_json(frame), allow_nan=False)))


@given(frames())
def test_a_frame_comes_back_as_it_was_written(frame):
    pd.testing.assert_frame_equal(_round_trip(frame), frame)


def test_infinities_stay_apart_from_nan():
    frame = pd.DataFrame({"overstatement": [np.inf, np.nan, -np.inf, 2.0]})
    back = _round_trip(frame)["overstatement"].to_numpy()
    assert np.isposinf(back[0]) and np.isnan(back[1]) and np.isneginf(back[2]) and back[3] == 2.0


def test_a_column_that_cannot_come_back_is_refused():
    with pytest.raises(TypeError, match="column 'when' has dtype"):
        frame_to_json(pd.DataFrame({"when": pd.to_datetime(["2026-01-01"])}))


@pytest.mark.parametrize("module", [tolerance_tables, consistency_tables, preset_endings])
def test_a_missing_record_is_refused_naming_the_command(module, tmp_path):
    with pytest.raises(LookupError, match="make data-studies"):
        module.load(tmp_path)


def test_the_tolerance_tables_are_the_study_s_own():
    tables = tolerance_tables.load()  # a missing or stale record fails here
    name = TS.SETS[0]
    pd.testing.assert_frame_equal(tables.pairs(name), TS.pairs(name))
    assert 0 < tables.solver_check_cost() < 1
    assert set(tables.solver_share().set) == {*TS.SETS, "all"}


def test_the_consistency_tables_are_the_study_s_own():
    tables = consistency_tables.load()
    fits = claims.fits(consistency.table("map"))
    pd.testing.assert_frame_equal(tables.fits(), fits[tables.fits().columns])
    at8 = tables.at_claim1_seed()
    assert at8.claim1_seed.all() and set(at8.form) == {"uniform", "point"}
    counts = tables.counts()
    assert 0 <= counts["3 and 4"] <= counts["3"] <= counts["triples"]
    best = tables.closest()
    assert best.form in {"uniform", "point"} and np.isfinite(best.b)


def test_the_endings_list_every_run_of_every_preset():
    endings = preset_endings.load()
    assert list(dict.fromkeys(endings.preset)) == list(P.PRESETS)
    fig10 = endings[endings.preset == "fig10"].reset_index(drop=True)
    cached = P.cached("fig10")
    assert list(fig10.key) == list(cached.key)
    assert list(fig10.end) == [preset_endings.ending(s) for s in cached.stopped]
    assert set(endings.end) <= set(preset_endings.ENDINGS)


@pytest.mark.parametrize(
    ("stopped", "end"),
    [
        ("self-contact at t = 61.945 s (segments 12 and 50)", "self-contact"),
        ("first peak of |u3(L)| passed at t = 20.1 s", "first peak"),
        ("failed: Newton failed at t=3.8", "Newton failure at Δt_min"),
        ("t_end", "t_end"),
    ],
)
def test_each_way_a_run_ends_is_named(stopped, end):
    assert preset_endings.ending(stopped) == end


def test_a_table_record_of_another_layout_is_missing_not_misread(tmp_path, monkeypatch):
    from dyntorsion.studies import page_records

    frame = pd.DataFrame({"x": [1.0, np.inf]})
    made = page_records.read_or_compute_frames(
        "onset-trace", {"demo": 1}, lambda: {"t": frame, "n": 2}, tmp_path, compute=True
    )
    pd.testing.assert_frame_equal(made["t"], frame)
    assert made["n"] == 2
    again = page_records.read_or_compute_frames("onset-trace", {"demo": 1}, dict, tmp_path)
    pd.testing.assert_frame_equal(again["t"], frame)
    monkeypatch.setattr(page_records, "FRAME_FORMAT", page_records.FRAME_FORMAT + 1)
    with pytest.raises(LookupError, match="make data-studies"):
        page_records.read_or_compute_frames("onset-trace", {"demo": 1}, dict, tmp_path)
