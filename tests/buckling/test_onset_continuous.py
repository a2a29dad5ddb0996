"""The window rule read in continuous time (dyntorsion.buckling.onset.continuous_window_fit):
exact on a known rise, fourth order in the sampling where the sample rule is first
order, continuous in the sample grid's phase, and second order in dt on the Fig 8 scene
where the sample rule's t_c jumps."""

from __future__ import annotations

import math
from types import SimpleNamespace

import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dyntorsion import Rod
from dyntorsion import buckling as b
from dyntorsion.buckling.loading import Ramp
from dyntorsion.buckling.onset import continuous_window_fit, detect_onset
from dyntorsion.buckling.scene import Scene, run_scene

T0 = 5.0


def _run(t, u, a=2.0, kappa0=1.0):
    return b.BucklingRun(
        t=t, u3_end=u, kappa3_left=kappa0 + a * t, kappa3_right=kappa0 + a * t,
        omega3_left=0 * t, omega3_right=0 * t, theta_left=0 * t,
        run=SimpleNamespace(stopped="t_end"), rod=Rod.paper(), history=Ramp(a=a, kappa0=kappa0),
    )  # fmt: skip


def _sine(dt: float, phase: float):
    """u3(L, t) = -sin(t - T0) from T0 (its first peak at T0 + pi/2), a tiny rise before."""
    t = np.arange(0.0, T0 + 3.6, dt) + phase * dt
    return t, np.where(t > T0, -np.sin(np.clip(t - T0, 0.0, None)), -1e-9 * np.exp(t - T0))


def _exact(lo: float = 0.1, hi: float = 0.5) -> float:
    """t_c of the least-squares line to sin(t - T0) over the window [lo, hi] of its peak,
    as integrals in 30 digits."""
    with mp.workdps(30):
        t0, t1 = T0 + mp.asin(lo), T0 + mp.asin(hi)
        tm = (t0 + t1) / 2
        ym = mp.quad(lambda x: mp.sin(x - T0), [t0, t1]) / (t1 - t0)
        num = mp.quad(lambda x: (x - tm) * (mp.sin(x - T0) - ym), [t0, t1])
        slope = num / ((t1 - t0) ** 3 / 12)
        return float(tm - ym / slope)


def test_on_a_known_rise_the_continuous_reading_converges_at_fourth_order():
    """Over ten phases of the sample grid: the continuous reading's largest error falls
    from 1.4e-9 (dt = 0.04) at an observed order of 3.5 or more a halving (4 for cubic
    pieces; measured 3.6, 5.0, 3.2), while the sample rule's stays first order
    (2.9e-3 at dt = 0.04) and is 1e5 times larger at dt = 0.01."""
    exact = _exact()
    errs_c, errs_s = [], []
    for dt in (0.04, 0.02, 0.01, 0.005):
        ec, es = [], []
        for phase in np.linspace(0.123, 1.023, 10):
            onset = detect_onset(_run(*_sine(dt, phase)), u_ref=0.01)
            ec.append(abs(onset.t_c_continuous - exact))
            es.append(abs(onset.t_c - exact))
        errs_c.append(max(ec))
        errs_s.append(max(es))
    assert errs_c[0] < 1e-8
    orders = [math.log2(a / b) for a, b in zip(errs_c[:-1], errs_c[1:], strict=True)]
    assert min(orders) >= 3.0 and float(np.mean(orders)) >= 3.5, orders
    sample_orders = [math.log2(a / b) for a, b in zip(errs_s[:-1], errs_s[1:], strict=True)]
    assert all(0.5 < p < 1.6 for p in sample_orders), sample_orders
    assert errs_s[2] > 1e5 * errs_c[2]


@settings(max_examples=25, deadline=None)
@given(phase=st.floats(0.0, 1.0), dt=st.floats(0.01, 0.04))
def test_the_continuous_reading_does_not_jump_with_the_sample_grid(phase, dt):
    """Any phase and step: within 5e-9 s of the exact value (the sample rule moves by up
    to a tenth of a step as samples enter and leave its window)."""
    onset = detect_onset(_run(*_sine(dt, phase)), u_ref=0.01)
    assert onset.t_c_continuous == pytest.approx(_exact(), abs=5e-9)
    assert onset.kappa3_continuous == pytest.approx(1.0 + 2.0 * onset.t_c_continuous, rel=1e-15)


def test_a_straight_rise_gives_its_start_exactly():
    """A line from t0 = 6 to its peak, then a fall: every window of a line extrapolates to
    t0, whatever the interpolant does at the kinks."""
    t = np.linspace(0, 10, 1001)
    U = np.where(t > 6.0, 0.5 * (t - 6.0), 0.0)
    U = np.where(t > 8.0, 1.0 - 0.9 * (t - 8.0), U)
    onset = detect_onset(_run(t, -U), u_ref=0.05)
    assert onset.t_c_continuous == pytest.approx(6.0, abs=1e-12)


def test_a_record_that_ends_at_its_largest_sample_keeps_it_as_the_peak():
    """A run stopped at self-contact while |u3(L)| still rises: the last sample is the
    peak, as for the sample rule, and a straight rise still gives its start."""
    t = np.linspace(0, 8, 801)
    U = np.where(t > 6.0, 0.5 * (t - 6.0), 0.0)
    for end in (len(t), len(t) - 1):
        onset = detect_onset(_run(t[:end], -U[:end]), u_ref=0.05)
        assert onset.t_c_continuous == pytest.approx(6.0, abs=1e-12)


def test_too_few_samples_leave_the_continuous_reading_out_and_say_why():
    t = np.linspace(0.0, 4.0, 5)
    y = np.array([0.0, 0.2, 1.0, 0.5, 0.1])
    with pytest.raises(ValueError, match="too close"):
        continuous_window_fit(t, y, 2, 0.1, 0.5)
    with pytest.raises(ValueError, match="increase"):
        continuous_window_fit(np.array([0.0, 1.0, 1.0, 2.0, 3.0, 4.0]), np.ones(6), 2, 0.1, 0.5)


def test_the_fig08_onset_read_in_continuous_time_converges_at_second_order_in_dt():
    """The Fig 8 scene at N = 100, dt = 0.04, 0.02, 0.01 s (to the first peak): the
    continuous reading's differences shrink by 4.1 (second order; the scheme's), the last
    one 1.05e-3 s; the sample rule's t_c on the same runs moves away from the limit
    (14.7037, 14.7044, 14.7048 s: its window's samples, not the scheme, set its error)."""
    runs = [run_scene(Scene(a=1.6, kappa0=0.0, n_cells=100, dt=dt, until="first-peak"))
            for dt in (0.04, 0.02, 0.01)]  # fmt: skip
    c = [r["t_c_continuous"] for r in runs]
    d1, d2 = c[1] - c[0], c[2] - c[1]
    order = math.log2(d1 / d2)
    assert 1.7 < order < 2.5, order
    assert abs(d2) < 2e-3
    richardson = c[2] + d2 / 3
    s = [r["t_c"] for r in runs]
    assert min(abs(x - richardson) for x in s) > 3 * abs(c[2] - richardson)
    for r in runs:
        assert r["kappa3_continuous"] == pytest.approx(1.6 * r["t_c_continuous"], rel=1e-14)


def test_on_the_cached_fig08_ladder_the_continuous_reading_converges_at_second_order():
    """The committed records of the Fig 8 ladder (preset accuracy-fig08): over the steps
    0.02, 0.01, 0.005 s the continuous reading's observed order is 1.92, 2.22, 2.20 at
    N = 100, 200, 400 (the scheme's second order), the sample rule's -3.4, 5.4, 5.4 (no
    order); the continuous reading's last step (0.005 s) is within 1.2e-4 s of its value
    at 0.00125 s, the sample rule's 8e-4 to 1.8e-3 s away."""
    from dyntorsion.studies import presets as P

    t = P.cached("accuracy-fig08")
    for n in (100, 200, 400):
        rows = t[t.n_cells == n].sort_values("dt", ascending=False)
        for col, lo, hi in (("t_c_continuous", 1.7, 2.5), ("t_c", None, None)):
            v = rows[col].to_numpy()
            p = math.log2(abs(v[0] - v[1]) / abs(v[1] - v[2]))
            if lo is not None:
                assert lo < p < hi, (n, col, p)
            else:
                assert not 1.0 < p < 3.0, (n, col, p)
        c, s = rows.t_c_continuous.to_numpy(), rows.t_c.to_numpy()
        assert abs(c[2] - c[-1]) < 1.2e-4 and abs(s[2] - s[-1]) > 5 * abs(c[2] - c[-1])


def test_the_gauss_legendre_rule_integrates_degree_seven_exactly():
    """The 4-point rule on [0, 1] from its closed forms: the moments 1/(k+1) for k <= 7."""
    from dyntorsion.buckling import onset as O

    for k in range(8):
        assert math.fsum(w * x**k for x, w in zip(O._GL_X, O._GL_W, strict=True)) == pytest.approx(
            1 / (k + 1), rel=1e-15, abs=0
        )
