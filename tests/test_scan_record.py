"""The consistency scan is a record keyed by its settings and its inputs
(dyntorsion.studies.scan_record): read back exactly, refused when its inputs changed."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from dyntorsion.studies import readings
from dyntorsion.studies import scan_record as SR

MAP = pd.DataFrame({"a": [0.2, 1.6], "seed": [1e-8, 1e-6], "t_c": [30.5, 20.8]})
DIRECT = pd.DataFrame({"a": [1.6], "rho": [1500.0], "t_c": [20.86]})


def _scan(map_table, direct, grid_error, step, band):
    """A stand-in for the scan with every kind of column the real one has."""
    return pd.DataFrame({
        "form": ["uniform", "point"], "rule": ["window", "u_ref"],
        "seed": [1e-8, 2.5e-7], "c1": [0.1 * grid_error, np.nan],
        "c4_z": [np.inf, -np.inf], "c3_runs": [3, 4], "claim1_seed": [True, False],
    })  # fmt: skip


def test_the_scan_is_read_back_exactly_and_not_recomputed(tmp_path, monkeypatch):
    monkeypatch.setattr(readings, "scan", _scan)
    with pytest.raises(LookupError, match="make data"):
        SR.load(MAP, DIRECT, 0.01, store=tmp_path)
    made = SR.load(MAP, DIRECT, 0.01, store=tmp_path, compute=True)
    pd.testing.assert_frame_equal(made, _scan(MAP, DIRECT, 0.01, SR.STEP, SR.BAND))
    monkeypatch.setattr(readings, "scan", None)  # a read must not compute
    pd.testing.assert_frame_equal(SR.load(MAP, DIRECT, 0.01, store=tmp_path), made)


def test_other_inputs_or_settings_have_no_record(tmp_path, monkeypatch):
    monkeypatch.setattr(readings, "scan", _scan)
    SR.load(MAP, DIRECT, 0.01, store=tmp_path, compute=True)
    moved = MAP.assign(t_c=MAP.t_c + [0.0, 1e-12])
    assert SR.inputs_digest(moved, DIRECT, 0.01) != SR.inputs_digest(MAP, DIRECT, 0.01)
    for args, kw in (((moved, DIRECT, 0.01), {}), ((MAP, DIRECT, 0.02), {}),
                     ((MAP, DIRECT, 0.01), {"step": 0.5})):  # fmt: skip
        with pytest.raises(LookupError):
            SR.load(*args, store=tmp_path, **kw)
