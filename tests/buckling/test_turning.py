"""Rotation control (dyntorsion.buckling.turning, ends "clamped-turned"): the end s = 0
turned by a prescribed angle, the history giving its spin w3(0, t)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.integrate import quad

from dyntorsion import Rod
from dyntorsion.beyond.contact.run import ContactScene
from dyntorsion.buckling import simulate
from dyntorsion.buckling.loading import Ramp, history_from_params
from dyntorsion.buckling.scene import Scene
from dyntorsion.buckling.seed import Perturbation
from dyntorsion.buckling.turning import TurnHold
from dyntorsion.model.ends import ENDS, IllPosedEndsError

TURN = TurnHold(turns=2.0, t_turn=10.0, tau=0.5)


def test_the_end_turns_by_exactly_the_turns_asked_for():
    """theta(t) is the integral of the spin (closed form against quadrature), and the lag
    of the rounded start is made up after t_turn: 2 pi turns once both corners are past."""
    for t in (0.3, 1.0, 5.0, 9.9, 10.0, 10.4, 12.0):
        num, _ = quad(lambda x: -TURN(np.array([x]))[0], 0.0, t, points=[10.0], limit=200)
        assert TURN.angle(t) == pytest.approx(num, rel=1e-10, abs=1e-12)
    assert TURN.angle(20.0) == pytest.approx(2.0 * math.tau, rel=1e-14)
    assert TURN.angle(5.0) == pytest.approx(
        TURN.spin_rate * (5.0 - 0.5 * math.gamma(1.25)), rel=1e-12
    )


def test_the_spin_starts_and_stops_smoothly():
    """w3(0, t) = 0 at t = 0 with three derivatives 0 (eq 28's transition); continuous
    with its first three derivatives at t_turn; sign: -Omega on the ramp (raises kappa3)."""
    h = 1e-3
    t = np.array([0.0, h, 2 * h])
    w = TURN(t)
    assert w[0] == 0.0 and abs(w[1]) < TURN.spin_rate * (h / 0.5) ** 4 * 1.01
    assert TURN(np.array([5.0]))[0] == pytest.approx(-TURN.spin_rate, rel=1e-12)
    below, above = TURN(np.array([10.0 - 1e-9, 10.0 + 1e-9]))
    assert below == pytest.approx(above, rel=1e-12)
    assert TURN(np.array([30.0]))[0] == 0.0
    assert history_from_params(TURN.params()) == TURN


@given(turns=st.one_of(st.just(0.0), st.sampled_from([math.nan, math.inf, -math.inf])))
def test_a_turn_hold_without_a_finite_nonzero_turn_is_refused(turns):
    with pytest.raises(ValueError, match="turns"):
        TurnHold(turns=turns, t_turn=1.0)


@given(t_turn=st.one_of(st.floats(max_value=0.0, allow_nan=False), st.just(math.nan)))
def test_a_turn_hold_without_a_positive_duration_is_refused(t_turn):
    with pytest.raises(ValueError, match="t_turn"):
        TurnHold(turns=1.0, t_turn=t_turn)


@pytest.mark.parametrize("tau", [0.0, -1.0, 2.6])
def test_a_rounding_longer_than_a_quarter_of_the_turn_is_refused(tau):
    with pytest.raises(ValueError, match="tau"):
        TurnHold(turns=1.0, t_turn=10.0, tau=tau)


def test_a_history_must_be_the_quantity_the_ends_prescribe():
    with pytest.raises(IllPosedEndsError, match="spin history"):
        Scene(history=Ramp(a=1.0, kappa0=10.0), ends="clamped-turned", t_end=1.0)
    with pytest.raises(IllPosedEndsError, match="twist history"):
        Scene(history=TURN, t_end=1.0)
    with pytest.raises(ValueError, match="frame='body'"):
        simulate(Scene(history=TURN, ends="clamped-turned", n_cells=10, dt=0.1, t_end=1.0, seed=Perturbation(frame="lab")))  # fmt: skip


def test_a_contact_scene_refuses_a_seed_it_would_not_apply():
    sc = Scene(history=TURN, ends="clamped-turned", t_end=1.0, seed=Perturbation(duration=0.5))
    with pytest.raises(ValueError, match="duration"):
        ContactScene(sc)


def test_turning_slowly_twists_the_straight_rod_uniformly():
    """Below kappa_cri, no seed, turned slowly: the twist along the rod is the end's angle
    over L (quasi-statically), the end's spin is the one prescribed, and the twisting moment
    at s = 0 reads C angle / L: rotation control's torque-rotation curve, its linear part."""
    rod = Rod()
    turns = 0.5 * 11.2335 * rod.L / math.tau  # half of kappa_cri
    hist = TurnHold(turns=turns, t_turn=40.0, tau=2.0)
    run = simulate(Scene(history=hist, ends="clamped-turned", rod=rod, n_cells=20, dt=0.05, t_end=50.0, seed=0.0), on_failure="return", snapshots=[50.0])  # fmt: skip
    assert ENDS["clamped-turned"].driven == "w3"
    np.testing.assert_allclose(run.omega3_left, hist(run.t), rtol=1e-9, atol=1e-12)
    # theta_left is the trapezoid rule on w3(0, t): error <= t dt^2 / 12 max |w3''|
    tt = np.linspace(0.0, 50.0, 20001)
    w2 = np.abs(np.gradient(np.gradient(hist(tt), tt), tt)).max()
    bound = run.t * 0.05**2 / 12 * w2 * 1.05
    assert np.all(np.abs(run.theta_left + hist.angle(run.t)) <= bound + 1e-12)
    k3 = run.run.snapshots[-1, :, 8]
    kappa = hist.angle(50.0) / rod.L
    np.testing.assert_allclose(k3, kappa, rtol=1e-3)
    assert abs(run.u3_end).max() < 1e-12
