"""Replication at a glance: the paper's stated values beside ours."""

import json

import pandas as pd
import pytest

from dyntorsion.app import glance
from dyntorsion.store.location import checkout


@pytest.fixture(scope="module")
def table():
    return glance.table()


def test_published_values_have_sources():
    pub = glance.published()
    assert {
        "m_cri",
        "kappa_cri",
        "c",
        "T1",
        "fig8_tc",
        "fig8_kappa3",
        "b",
        "sigma",
        "law_fig8",
        "law_fig9",
    } <= set(pub)
    for entry in pub.values():
        assert entry["where"] and entry["unit"] and entry["digits"] >= 1


def test_every_published_number_has_ours(table):
    assert set(table["id"]) == set(glance.published())
    assert table["ours"].notna().all()


@pytest.mark.parametrize("pid", ["c", "m_cri", "kappa_cri", "T1"])
def test_static_numbers_agree_to_the_digits_stated(table, pid):
    rows = table[table["id"] == pid]
    assert (rows["verdict"] == "agrees to the digits stated").all()


def test_verdict_scale():
    assert glance._verdict(0.0, 4, 20.86) == "agrees to the digits stated"
    assert glance._verdict(0.004, 4, 20.86) == "agrees within 1 %"
    assert glance._verdict(0.03, 4, 20.86) == "close (within 5 %)"
    assert glance._verdict(-0.3, 4, 20.86) == "differs by more than 5 %"


def test_numbers_json_roundtrip(tmp_path, table):
    path = glance.write_numbers(tmp_path / "numbers.json")
    data = json.loads(path.read_text())
    assert len(data["rows"]) == len(table)
    assert not list(tmp_path.glob("*.tmp"))


@pytest.mark.parametrize(
    ("x", "digits", "text"),
    [
        (20.7921, 4, "20.79"),
        (160.6, 5, "160.60"),
        (0.0692816, 4, "0.06928"),
        (-1e-9, 2, "-0.0000000010"),
        (-0.00004, 1, "-0.00004"),
        (14.7008, 4, "14.70"),
    ],
)
def test_sig_keeps_the_significant_figures(x, digits, text):
    assert glance.sig(x, digits) == text


@pytest.mark.parametrize(
    ("x", "digits", "text"),
    [
        (1.25e7, 6, "1.25 × 10⁷"),
        (1e-8, 6, "10⁻⁸"),
        (-1e-17, 3, "-10⁻¹⁷"),
        (4.908738521234051e-14, 6, "4.90874 × 10⁻¹⁴"),
        (57.735026918962575, 5, "57.735"),
        (0.0, 3, "0"),
        (-0.0, 3, "0"),
        (2.5e-7, 2, "2.5 × 10⁻⁷"),
    ],
)
def test_sci_writes_powers_of_ten_for_a_reader(x, digits, text):
    assert glance.sci(x, digits) == text


def test_md_table_has_no_index_and_escapes_pipes():
    t = pd.DataFrame({"$|u_3|$": [1.5, 2.0]}, index=[7, 8])
    lines = glance.md_table(t).splitlines()
    assert lines == ["| $\\|u_3\\|$ |", "|---|", "| 1.5 |", "| 2.0 |"]


def test_sig_never_writes_minus_zero():
    assert glance.sig(-0.0, 3) == "0"
    assert glance.sig(-1e-12, 2) != "-0"


def test_compact_table_for_the_site(table):
    t = glance.compact(prefix="../")
    assert len(t) == len(table)
    assert list(t.columns) == [
        "quantity",
        "unit",
        "seed [N/m]",
        "paper",
        "ours",
        "difference",
        "verdict",
        "evidence",
    ]
    # every quantity typeset, every row linked to an existing page of the site
    assert t["quantity"].str.contains(r"\$").all()
    docs = checkout() / "docs"
    for link in t["evidence"]:
        target = link[link.index("](") + 2 : -1].removeprefix("../")
        assert (docs / target).is_file(), link
    # the paper's value as stated (its digits), ours to the same significant figures
    row = t[(t["quantity"] == "Fig 8: $t_c$") & (t["seed [N/m]"] == "10⁻⁸ (stated)")].iloc[0]
    assert row["paper"] == "20.86" and len(row["ours"].replace(".", "")) == 4
    assert row["difference"].endswith(" %") and row["verdict"] == "differs by more than 5 %"
    assert not t["ours"].str.contains("nan|e[+-]", regex=True).any()
    assert glance.markdown().count("\n") == len(t) + 1


def test_verdict_by_id():
    paper = glance.published()["fig8_tc"]["value"]
    assert glance.verdict("fig8_tc", paper) == "agrees to the digits stated"
    assert glance.verdict("fig8_tc", 0.7 * paper) == "differs by more than 5 %"


def test_the_closest_consistency_cell_is_a_variant(table):
    """The consistency map's cell is a row for each dynamic number it
    gives; its Fig 8 onset is calibrated (the seed is interpolated to it)."""
    rows = table[table["variant"].str.startswith(glance.CLOSEST)].set_index("id")
    assert set(rows.index) == {
        "fig8_tc",
        "fig8_kappa3",
        "b",
        "sigma",
        "law_fig8",
        "law_fig9",
        "kappa_cri_extrapolated",
    }
    assert rows.loc["fig8_tc", "verdict"] == glance.CALIBRATED_VERDICT
    assert rows.loc["fig8_tc", "relative difference"] == pytest.approx(0, abs=5e-5)
    assert rows.loc["sigma", "verdict"] != "agrees to the digits stated"
    compact = glance.compact()
    closest = compact[compact["evidence"].str.contains(glance.CLOSEST_PAGE, regex=False)]
    assert len(closest) == len(rows)
    form = rows["variant"].iloc[0].split(": ", 1)[1].split(" ")[1].rstrip(",")
    assert form in ("uniform", "point")
    said = "N at mid-span" if form == "point" else "uniform"
    assert closest["seed [N/m]"].str.contains(said, regex=False).all()


def test_calibrated_rows_are_not_agreements(table):
    """A number the seed was tuned to (Fig 8's onset, and kappa3 = a t_c with it) says
    "calibrated", however close; every other row keeps its judged verdict."""
    cal = table[table["calibrated"]]
    assert set(cal["id"]) == {"fig8_tc", "fig8_kappa3"}
    assert set(cal["variant"].str.split(":").str[0]) == {glance.TUNED, glance.CLOSEST}
    assert (cal["verdict"] == glance.CALIBRATED_VERDICT).all()
    assert (cal["relative difference"].abs() < 0.01).all()  # they would pass as agreements
    rest = table[~table["calibrated"]]
    assert not rest["verdict"].str.startswith("calibrated").any()
    stated = table[(table["id"] == "fig8_tc") & (table["variant"].str.startswith("stated"))]
    assert not stated["calibrated"].iloc[0]
    assert glance.is_calibrated("fig8_tc", glance.TUNED)
    assert not glance.is_calibrated("b", glance.TUNED)
