"""Stability at the extremes: lambda_inf, Courant numbers, loading rates, densities, grids.

Every run returns finite numbers that honour the boundary data (a failed Newton solve,
which says when, after how many iterations and with what residual, is tested on its own in
tests/buckling/test_buckling.py);
the linear wave conserves energy at lambda_inf = -1 and loses it otherwise.
"""

import itertools
import warnings

import numpy as np
import pytest

from dyntorsion import Rod
from dyntorsion import waves as w
from dyntorsion.buckling.scene import Scene
from dyntorsion.buckling.simulation import (
    TESTED_COURANT,
    TESTED_DT_OVER_T0,
    GridWarning,
    simulate,
)
from dyntorsion.genalpha import Scheme, SchemeWarning

ROD = Rod()


def wave_energy(sol, rod=ROD):
    """Discrete energy of eq (22), 1/2 int (C kappa^2 + rho J omega^2) ds, cell means."""
    k = 0.5 * (sol.kappa[:, 1:] + sol.kappa[:, :-1])
    o = 0.5 * (sol.omega[:, 1:] + sol.omega[:, :-1])
    ds = rod.L / (sol.s.size - 1)
    return 0.5 * ds * np.sum(rod.C * k**2 + rod.rho * rod.J * o**2, axis=1)


E0 = 0.5 * ROD.C * 10.0**2 * ROD.L  # energy of the pretwisted rod


def release_run(lam_t, n_cells, courant, steps, rod=ROD):
    """Smooth release of kappa0 = 10 (over at most a quarter of the run and at least five
    steps), then free end (no moment) and clamped end (no spin): no work is done on
    the rod after the release.  Returns the solution and the energy after the release."""
    dt = courant * (rod.L / n_cells) / rod.c
    rate = min(max(50.0, 12.0 / (steps * dt)), 0.2 / dt)
    times = np.arange(1, 21) * (steps // 20) * dt
    problem = w.SmoothRelease(kappa0=10.0, rate=rate)
    sol = w.solve(problem, rod=rod, n_cells=n_cells, dt=dt, times=times, lam_t=lam_t)
    after = sol.t > 3.0 / rate
    assert after.sum() >= 10
    return sol, wave_energy(sol)[after]


def test_energy_is_conserved_at_lambda_minus_one_over_1e5_steps():
    sol, E = release_run(-1.0, 50, 0.577, 100_000)
    assert np.all(np.isfinite(E)) and E[0] > 0.1 * E0
    assert np.ptp(E) < 1e-9 * E0


@pytest.mark.parametrize(
    "lam_t, courant", list(itertools.product((-0.9, -0.5, 0.0), (0.01, 1.0, 1000.0)))
)
def test_energy_never_grows_with_damping(lam_t, courant):
    sol, E = release_run(lam_t, 50, courant, 20_000)
    assert np.all(np.isfinite(sol.kappa)) and np.all(np.isfinite(sol.omega))
    assert np.all(np.diff(E) <= 1e-12 * E0)


@pytest.mark.slow
@pytest.mark.parametrize("lam_t", [-1.0, -0.9, -0.5, 0.0])
@pytest.mark.parametrize("n_cells, courant", [(2, 1.0), (2000, 1.0), (50, 1000.0)])
def test_long_wave_runs_at_grid_extremes(lam_t, n_cells, courant):
    _, E = release_run(lam_t, n_cells, courant, 100_000 if n_cells < 100 else 20_000)
    assert np.all(np.isfinite(E))
    if lam_t == -1.0:
        assert np.ptp(E) <= 1e-9 * E0
    else:
        assert np.all(np.diff(E) <= 1e-12 * E0)


@pytest.mark.parametrize("lam_s", [-0.9, -0.5, 0.0])
def test_lambda_in_space_other_than_minus_one_warns(lam_s):
    with pytest.warns(SchemeWarning, match="lam_s"):
        Scheme(lam_s=lam_s)


# ------------------------------------------------------------------ the nonlinear rod
EXTREMES = list(itertools.product((1e-3, 1e3), (10.0, 1e5), (2, 20), (0.01, 1000.0), (-1.0, 0.0)))


@pytest.mark.parametrize("a, rho, n_cells, courant, lam_t", EXTREMES)
def test_buckling_scene_is_sound_or_says_why(a, rho, n_cells, courant, lam_t):
    rod = ROD.with_(rho=rho)
    dt = courant * (rod.L / n_cells) / rod.c
    t_end = min(200 * dt, 60.0 / a)
    far = dt / rod.T0 > 10 * TESTED_DT_OVER_T0[1] or courant > 10 * TESTED_COURANT[1]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", GridWarning)
        return _sound_or_says_why(rod, a, n_cells, dt, t_end, lam_t, far, caught)


def _sound_or_says_why(rod, a, n_cells, dt, t_end, lam_t, far, caught):
    def warned():
        assert any(issubclass(w.category, GridWarning) for w in caught) == far

    if dt > t_end:  # one step would overshoot t_end: refused before the run (issue 17)
        with pytest.raises(ValueError, match=r"dt=.*exceeds.*t_end"):
            simulate(Scene(rod=rod, a=a, kappa0=10.0, n_cells=n_cells, dt=dt, t_end=t_end))
        return
    run = simulate(
        Scene(
            rod=rod,
            a=a,
            kappa0=10.0,
            n_cells=n_cells,
            dt=dt,
            t_end=t_end,
            scheme=Scheme(lam_t=lam_t),
        ),
        stop_at_contact=False,
        progress=False,
    )
    warned()
    for trace in (run.u3_end, run.kappa3_left, run.kappa3_right, run.omega3_left):
        assert np.all(np.isfinite(trace))
    np.testing.assert_allclose(run.kappa3_left, 10.0 + a * run.t, rtol=1e-9, atol=1e-9)
    assert run.t[-1] == pytest.approx(t_end, abs=dt)


@pytest.mark.slow
def test_1e5_steps_of_the_prebuckling_rod():
    """100 s of slow twisting below the critical twist at dt = 1e-3: straight, finite."""
    run = simulate(
        Scene(a=0.01, kappa0=10.0, n_cells=20, dt=1e-3, t_end=100.0),
        stop_at_contact=False,
        progress=False,
    )
    assert run.t.size == 100_001
    assert np.all(np.isfinite(run.u3_end)) and np.max(np.abs(run.u3_end)) < 1e-6
    np.testing.assert_allclose(run.kappa3_left, 10.0 + 0.01 * run.t, rtol=1e-12)
