"""A run that could not see its instability says so (issue 37, item 3): ``unresolved``,
with the grid that would resolve the growth, never ``no-onset``."""

from __future__ import annotations

import numpy as np
import pytest

from dyntorsion.buckling import resolution as R
from dyntorsion.buckling.loading import Tabulated
from dyntorsion.buckling.scene import Scene, run_scene
from dyntorsion.buckling.seed import Perturbation
from dyntorsion.buckling.statics import critical_twist
from dyntorsion.model.rod import Rod

ROD = Rod()
KC = critical_twist(ROD)


def test_growth_vanishes_at_the_critical_twist_and_grows_as_its_square():
    """lambda = 0 at kappa_cri (the clamped rod's threshold), lambda ~ kappa^2 far above
    (the fastest wave k* = 3 M / 4 B: lambda^2 = 27 M^4 / (256 B^3 rho A))."""
    k_min = ROD.C * KC / ROD.B1
    lam, _ = R.growth(ROD, np.array([KC, 1e3, 2e3]), 0.0, k_min)
    assert lam[0] == 0.0
    assert lam[2] / lam[1] == pytest.approx(4.0, rel=1e-12)
    M = ROD.C * 1e3
    exact = np.sqrt(27 * M**4 / (256 * ROD.B1**3 * ROD.mass_per_length))
    assert lam[1] == pytest.approx(exact, rel=1e-12)


def test_tension_slows_the_growth():
    k_min = ROD.C * KC / ROD.B1
    free, _ = R.growth(ROD, np.array([30.0]), 0.0, k_min)
    pulled, _ = R.growth(ROD, np.array([30.0]), 1e-5, k_min)
    assert 0 < pulled[0] < free[0]


@pytest.mark.parametrize(
    "scene",
    [
        pytest.param(Scene(a=1e6, kappa0=10.0, n_cells=50, dt=0.01), id="a=1e6"),
        pytest.param(
            Scene(a=16.0, kappa0=1000.0, n_cells=50, dt=0.01, t_end=0.6), id="kappa0=1000"
        ),
        pytest.param(
            Scene(
                history=Tabulated((0.0, 1e-3, 0.5), (10.0, 1e6, 1e6)),
                n_cells=50,
                dt=0.01,
                t_end=0.5,
            ),
            id="jump",
        ),
    ],
)
def test_the_issues_three_runs_are_unresolved_with_the_grid_they_need(scene):
    row = run_scene(scene)
    assert row["status"] == "unresolved"
    assert row["needed"]["n_cells"] > scene.n_cells and row["needed"]["dt"] < scene.dt
    assert "needs n_cells >=" in row["onset_error"]


def test_the_grid_it_names_sees_the_onset():
    """kappa0 = 1000 on 50 cells and dt = 0.01 s is unresolved; on the grid the message
    names (764 cells, dt about 1e-4 s) the same rod buckles within milliseconds."""
    coarse = run_scene(Scene(a=16.0, kappa0=1000.0, n_cells=50, dt=0.01, t_end=0.6))
    need = coarse["needed"]
    dt = float(f"{need['dt']:.1g}")
    fine = run_scene(Scene(a=16.0, kappa0=1000.0, n_cells=need["n_cells"], dt=dt, t_end=0.02))
    assert fine["status"] == "buckled" and fine["t_c"] < 0.01


def test_an_unseeded_or_short_run_stays_no_onset():
    """Without a seed the rod never leaves the straight state (an answer); a run ended
    before the seed could grow is too short, not unresolved."""
    plain = Scene(a=1.6, n_cells=20, dt=0.05, t_end=2.0, seed=Perturbation(magnitude=0.0))
    assert run_scene(plain)["status"] == "no-onset"
    short = Scene(a=1.6, n_cells=20, dt=0.05, t_end=0.5)
    row = run_scene(short)
    assert row["status"] == "no-onset" and "needed" not in row
