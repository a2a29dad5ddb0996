"""The wave convergence study is a record: computed once by `make data`, read by the
Accuracy page (dyntorsion.studies.wave_convergence)."""

from __future__ import annotations

import numpy as np
import pytest

from dyntorsion import Rod
from dyntorsion import waves as w
from dyntorsion.studies import wave_convergence as WC

SMALL = {**WC.PARAMS, "lam_t": [-1.0], "m0": [1], "levels": 3}


def test_the_study_is_the_grids_solved_one_by_one():
    cols = WC.convergence(SMALL)
    assert cols["n_cells"] == [25, 50, 100]
    rod, problem, t = Rod.paper(), w.SmoothRelease(10.0, 50.0), SMALL["t"]
    for n, dt, l2 in zip(cols["n_cells"], cols["dt"], cols["l2_error"], strict=True):
        sol = w.solve(problem, rod=rod, times=[t], n_cells=n, dt=dt, lam_t=-1.0)
        ref = problem.dalembert(sol.s, t, c=rod.c, L=rod.L)
        assert sol.errors(ref[None, :])["L2"][0] == l2  # the same number, bit for bit
    assert all(c == pytest.approx(rod.c * t * SMALL["n0"] / rod.L) for c in cols["courant"])
    assert np.all(np.diff(cols["l2_error"]) < 0)
    assert all(s > 0 for s in cols["wall_s"])


def test_load_refuses_a_missing_record_then_computes_and_reads_it(tmp_path):
    with pytest.raises(LookupError, match="make data"):
        WC.load(tmp_path, params=SMALL)
    made = WC.load(tmp_path, compute=True, params=SMALL)
    assert len(list(tmp_path.glob(f"{WC.KIND}-*.json"))) == 1
    assert WC.load(tmp_path, params=SMALL) == made  # read, not recomputed
