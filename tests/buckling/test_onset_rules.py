"""The onset rules of the consistency map (dyntorsion.buckling.onset_rules) on traces whose
answer is known exactly."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from dyntorsion import Rod
from dyntorsion import buckling as b
from dyntorsion.buckling.loading import Ramp
from dyntorsion.buckling.onset_rules import RULES, onsets_by_rule, steepest_tangent


def _run(t, u, a=2.0, kappa0=1.0):
    return b.BucklingRun(
        t=t,
        u3_end=u,
        kappa3_left=kappa0 + a * t,
        kappa3_right=kappa0 + a * t,
        omega3_left=0 * t,
        omega3_right=0 * t,
        theta_left=0 * t,
        run=SimpleNamespace(stopped="t_end"),
        rod=Rod.paper(),
        history=Ramp(a=a, kappa0=kappa0),
    )


def _ramp(t0: float, slope: float, t_peak: float):
    """A quiet phase, a straight rise from t0 to the peak at t_peak, then a fall."""
    t = np.linspace(0, t_peak + 2, 4001)
    rise = np.where(t > t0, slope * (t - t0), 0.0)
    peak = slope * (t_peak - t0)
    u = np.where(t > t_peak, peak - 0.9 * slope * (t - t_peak), rise)
    return t, -np.abs(u) - 1e-12


def test_every_rule_on_a_straight_rise():
    """A straight rise from t0: the window rules and the steepest tangent all give t0;
    the threshold gives the time the line reaches u_ref."""
    t, u = _ramp(t0=6.0, slope=0.5, t_peak=8.0)
    run = _run(t, u)
    out = onsets_by_rule(run, u_ref=0.05)
    assert tuple(out) == RULES
    for rule in ("window 10-50 %", "window 20-80 %", "steepest tangent"):
        assert out[rule] == pytest.approx(6.0, abs=2e-3), rule
    assert out["threshold"] == pytest.approx(6.0 + 0.05 / 0.5, abs=1e-3)


def test_steepest_tangent_of_a_parabola():
    """U = (t - 1)^2 on [1, 3], then a fall: the steepest point is the end of the rise
    (t = 3, slope 4, U = 4), whose tangent meets U = 0 at t = 2."""
    t = np.linspace(0, 4, 40001)
    U = np.where(t < 1, 0.0, (t - 1) ** 2)
    U = np.where(t > 3, 4 - 3 * (t - 3), U)
    i_start = int(np.nonzero(U >= 1e-3)[0][0])
    assert steepest_tangent(t, U, i_start) == pytest.approx(2.0, abs=1e-3)


@given(
    t0=st.floats(2.0, 20.0),
    length=st.floats(0.5, 5.0),
    shift=st.floats(-1.5, 5.0),
    scale=st.floats(1e-3, 1e3),
)
def test_rules_move_with_the_trace(t0, length, shift, scale):
    """Every rule is a property of the trace's shape: delaying the trace by ``shift``
    delays every onset by ``shift``, and scaling |u3| (with u_ref) changes none."""
    t = np.linspace(0, 60, 24001)

    top = 1e-6 * np.exp(12)

    def U(tt):
        rise = np.where(
            tt < t0 + length,
            1e-6 * np.exp(np.clip(12 * (tt - t0) / length, -50, 12)),
            top * (1 + (tt - t0 - length)),
        )
        fall = np.maximum(top * (1 + length) - 0.5 * (tt - t0 - 2 * length), 0.0)
        return np.where(tt > t0 + 2 * length, fall, rise)

    base = onsets_by_rule(_run(t, -U(t)), u_ref=1e-4)
    moved = onsets_by_rule(_run(t, -scale * U(t - shift)), u_ref=scale * 1e-4)
    for rule in RULES:
        assert moved[rule] == pytest.approx(base[rule] + shift, abs=5 * (t[1] - t[0])), rule


def test_a_trace_that_never_rises_names_u_ref():
    t = np.linspace(0, 5, 501)
    with pytest.raises(ValueError, match="u_ref"):
        onsets_by_rule(_run(t, 1e-9 * np.ones_like(t)), u_ref=1e-3)


@pytest.mark.parametrize("control", [False, True])
def test_a_run_to_the_first_peak_gives_the_onsets_of_the_run_to_contact(control):
    """``Scene(until="first-peak")`` stops after the fall that follows the first peak of
    ``|u3(L)|``, earlier than the run to self-contact, with the same onset under every
    rule; the default keeps its cache key, the other enters it."""
    from dataclasses import replace

    from dyntorsion.buckling.onset import detect_onset
    from dyntorsion.buckling.scene import Scene, simulate_scene
    from dyntorsion.studies.presets import PRESET_CONTROL

    full = Scene(a=8.0, n_cells=30, dt=0.01)
    if control:
        full = replace(full, scheme=replace(full.scheme, control=PRESET_CONTROL))
    short = replace(full, until="first-peak")
    assert "until" not in full.params() and short.params()["until"] == "first-peak"
    assert Scene.from_params(short.params()).params() == short.params()
    r_full, r_short = simulate_scene(full), simulate_scene(short)
    assert r_short.stopped.startswith("first peak") and r_short.t[-1] < r_full.t[-1]
    n = r_short.t.size
    np.testing.assert_array_equal(r_short.u3_end, r_full.u3_end[:n])
    assert detect_onset(r_short) == detect_onset(r_full)
    assert onsets_by_rule(r_short) == onsets_by_rule(r_full)


def test_until_names_the_allowed_values():
    from dyntorsion.buckling.scene import Scene

    with pytest.raises(ValueError, match="until='peak'; allowed: 'contact', 'first-peak'"):
        Scene(a=1.0, until="peak")
