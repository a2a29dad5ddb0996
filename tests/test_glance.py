"""Replication at a glance: the paper's stated values beside ours."""

import json

import pytest

from dyntorsion import glance


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
    assert glance._verdict(-0.3, 4, 20.86) == "differs"


def test_numbers_json_roundtrip(tmp_path, table):
    path = glance.write_numbers(tmp_path / "numbers.json")
    data = json.loads(path.read_text())
    assert len(data["rows"]) == len(table)
    assert not list(tmp_path.glob("*.tmp"))
