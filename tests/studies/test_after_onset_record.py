"""The runs of "After the onset" are a record per fidelity level
(dyntorsion.studies.after_onset), read by the page."""

from __future__ import annotations

import pytest

from dyntorsion.studies import after_onset as AO


def test_the_after_onset_record_is_keyed_by_level_and_refused_when_missing(tmp_path):
    quick, standard = AO.params("quick"), AO.params("standard")
    assert len(quick["contact_grids"]) == 2 and len(standard["contact_grids"]) == 3
    assert quick["grid"] != standard["grid"]
    with pytest.raises(LookupError, match="make data"):
        AO.load("quick", tmp_path)
    with pytest.raises(ValueError, match="fidelity"):
        AO.load("coarse", tmp_path)
