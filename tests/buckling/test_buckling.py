"""Section 6: static critical twist, the buckling scene and the onset of buckling."""

import mpmath
import numpy as np
import pytest

from dyntorsion import Rod
from dyntorsion import buckling as b
from dyntorsion.buckling.loading import Ramp
from dyntorsion.buckling.scene import Scene
from dyntorsion.genalpha import ConvergenceError


def test_m_cri_is_the_root_of_tan_pi_m_equals_pi_m():
    with mpmath.workdps(40):
        m = b.M_CRI_MP
        assert abs(mpmath.tan(mpmath.pi * m) - mpmath.pi * m) < mpmath.mpf(10) ** -30
        assert 1 < m < 1.5  # the smallest nonzero root (tan(pi m) - pi m has none in (0, 1))
    assert b.m_cri == pytest.approx(1.4303, abs=5e-5)


def test_critical_twist_table1():
    assert b.critical_twist(Rod.paper()) == pytest.approx(11.2335, abs=5e-5)


@pytest.mark.parametrize(
    "rod", [Rod.paper(), Rod(E=2e11, nu=0.3, D=0.01, L=3.0, rho=7800), Rod(nu=0.45, L=0.4)]
)
def test_eq32_against_linear_stability(rod):
    """Smallest twist with a nontrivial static linearised solution = eq (32), to 1e-6."""
    numeric = b.critical_twist_numerical(rod)
    assert numeric == pytest.approx(b.critical_twist(rod), rel=1e-6)


def test_critical_twist_scales_like_the_formula():
    rod = Rod.paper()
    assert b.critical_twist(rod.with_(L=2.0)) == pytest.approx(b.critical_twist(rod) / 2)
    assert b.critical_twist(rod.with_(rho=5000.0)) == b.critical_twist(rod)


# ------------------------------------------------------------------ the scene
@pytest.fixture(scope="module")
def coarse_run():
    """A short, coarse case: kappa0 = 10, a = 10 rad/s, N = 40, dt = 0.01 s."""
    return b.simulate(
        Scene(a=10.0, kappa0=10.0, n_cells=40, dt=0.01, t_end=6.0),
        on_failure="return",
        snapshots=[0.0, 1.0],
    )


def test_coarse_onset_pin_of_our_output(coarse_run, num_regression):
    """A pin of our own output on a coarse grid (any change of the engine moves it); the onset's accuracy is tested against converged grids on the accuracy ladder (tests/studies/test_fidelity.py)."""
    onset = b.detect_onset(coarse_run)
    assert onset.kappa3 > b.critical_twist(Rod.paper())  # delayed, as in the paper
    num_regression.check(
        {"t_c": [onset.t_c], "kappa3": [onset.kappa3], "uncertainty_t": [onset.uncertainty_t]},
        default_tolerance={"rtol": 1e-6, "atol": 1e-9},
    )


def test_scene_records_what_the_issue_asks(coarse_run):
    run = coarse_run
    assert run.t.shape == run.u3_end.shape == run.kappa3_left.shape == run.omega3_right.shape
    np.testing.assert_allclose(run.kappa3_left, 10.0 + 10.0 * run.t, rtol=1e-12)
    np.testing.assert_array_equal(run.omega3_right, 0.0)
    assert np.all(np.diff(run.t) > 0)
    assert run.run.snapshots.shape[0] == 2


def test_straight_before_onset(coarse_run):
    """Up to well before the onset the rod is straight to the seed's order."""
    early = coarse_run.t < 0.5
    assert np.max(np.abs(coarse_run.u3_end[early])) < 1e-6


def test_no_seed_stays_exactly_straight():
    run = b.simulate(
        Scene(a=10.0, kappa0=10.0, n_cells=20, dt=0.02, t_end=3.0, seed=0.0), snapshots=[3.0]
    )
    y = run.run.snapshots[-1]
    bent = np.delete(y, [5, 8], axis=1)  # all but w3, k3
    assert np.max(np.abs(bent)) == 0.0
    assert np.max(np.abs(run.u3_end)) == 0.0
    with pytest.raises(ValueError, match="straight"):
        b.detect_onset(run)


def test_failure_keeps_the_computed_steps():
    """A Newton failure raises with time, iteration and residual and carries the partial run."""
    from dyntorsion.genalpha import Newton

    scene = Scene(a=10.0, kappa0=10.0, n_cells=20, dt=0.05, t_end=2.0,
                  newton=Newton(max_iter=1, tol=1e-14))  # fmt: skip
    with pytest.raises(ConvergenceError) as info:
        b.simulate(scene)
    err = info.value
    assert err.t > 0 and err.residual > 0
    assert err.run is not None and err.run.steps == err.step - 1
    assert err.run.t[-1] == pytest.approx(err.t - 0.05)
    partial = b.simulate(scene, on_failure="return")
    assert partial.stopped.startswith("failed")


def test_perturbation_forms():
    s = np.linspace(0, 1, 11)
    uni = b.Perturbation().force(s, 1.0)
    np.testing.assert_allclose(uni[:, 0], 1e-8)
    pt = b.Perturbation(2e-8, "point", 0.52).force(s, 1.0)
    assert np.count_nonzero(pt) == 1 and pt[5, 0] == pytest.approx(2e-8 / 0.1)
    # the total force of a point seed is its magnitude (trapezoidal integral)
    assert np.trapezoid(pt[:, 0], s) == pytest.approx(2e-8)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"seed": b.Perturbation(form="point", location=2.0)}, "location"),
        ({"n_cells": 1}, "n_cells"),
        ({"a": float("nan")}, "a="),
        ({"on_failure": "ignore"}, "on_failure"),
    ],
)
def test_bad_input(kwargs, match):
    args = {"a": 1.0, "kappa0": 0.0, "n_cells": 10, "dt": 0.01, "t_end": 0.02}
    run = {k: args.pop(k) for k in ("on_failure",) if k in args}
    with pytest.raises(ValueError, match=match):
        args.update(kwargs)
        run |= {k: args.pop(k) for k in ("on_failure",) if k in args}
        b.simulate(Scene(**args), **run)


def test_bad_perturbation_values():
    with pytest.raises(ValueError, match="magnitude"):
        b.Perturbation(-1.0)
    with pytest.raises(ValueError, match="direction"):
        b.Perturbation(direction=(1.0, 1.0, 0.0))
    with pytest.raises(ValueError, match="form"):
        b.Perturbation(form="ring")


def test_onset_of_a_synthetic_trace():
    """detect_onset recovers the zero crossing of a clean ramp after a quiet phase."""
    t = np.linspace(0, 10, 2001)
    u = np.where(t < 6, 1e-9 * np.exp(t), 0.0) + np.where(t > 6, -0.5 * (t - 6), 0.0)
    u = np.where(t > 8, -1.0 + 0.9 * (t - 8), u)  # the peak, then a fall
    run = b.BucklingRun(
        t=t,
        u3_end=u,
        kappa3_left=t,
        kappa3_right=t,
        omega3_left=0 * t,
        omega3_right=0 * t,
        theta_left=0 * t,
        run=None,
        rod=Rod.paper(),
        history=Ramp(a=2.0, kappa0=1.0),
    )
    onset = b.detect_onset(run)
    assert onset.t_c == pytest.approx(6.0, abs=1e-3)
    assert onset.kappa3 == pytest.approx(13.0, abs=2e-3)
    assert onset.uncertainty_t < 1e-3


@pytest.mark.slow
@pytest.mark.parametrize("rho", [1500.0, 5000.0], ids=["fig08", "fig09"])
def test_paper_scene_onset_pin_of_our_output(rho, num_regression):
    """The full Fig 8 / Fig 9 scenes (kappa0 = 0, a = 1.6, default seed, N = 100, dt = 0.005)."""
    run = b.simulate(
        Scene(rod=Rod.paper().with_(rho=rho), a=1.6, n_cells=100, dt=0.005, t_end=45.0, kappa0=0.0),
        on_failure="return",
    )
    onset = b.detect_onset(run)
    assert onset.kappa3 > b.critical_twist(Rod.paper())
    num_regression.check(
        {"t_c": [onset.t_c], "kappa3": [onset.kappa3]},
        default_tolerance={"rtol": 1e-6, "atol": 1e-9},
    )
