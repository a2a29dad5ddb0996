"""The committed record of benchmarks/contact_convergence.py (data/contact/first_contact.json,
issue 33 item 3): current, and saying what the "Past contact" page says of it."""

from __future__ import annotations

import hashlib
import json
import math
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
RECORD = ROOT / "data" / "contact" / "first_contact.json"
SCRIPT = ROOT / "benchmarks" / "contact_convergence.py"


@pytest.fixture(scope="module")
def record():
    return json.loads(RECORD.read_text())


def test_the_record_is_current_and_complete(record):
    from dyntorsion.store.fingerprint import code_fingerprint

    assert record["code"]["script_sha256"] == hashlib.sha256(SCRIPT.read_bytes()).hexdigest()
    roots = ("dyntorsion.beyond.contact.run:run_contact_scene",)  # the script's ROOTS
    assert record["code"]["code_fingerprint"] == code_fingerprint(roots), (
        "the contact code changed since the record: rerun benchmarks/contact_convergence.py"
    )
    grids = {(r["n_cells"], r["max_step"]) for r in record["runs"]}
    assert grids == {tuple(g) for g in record["params"]["grids"]}
    assert {(p["n_cells"], p["lam_t"]) for p in record["past"]} == {
        (p[0], p[1]) for p in record["params"]["past"]
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
