"""Scenes as data: twist histories, axial loads, end sets, and rods of any section run
through the public API (dyntorsion.buckling.loading, buckling.simulation, sweep.Scene)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dyntorsion import Rod
from dyntorsion.buckling import GridWarning, simulate
from dyntorsion.buckling.loading import (
    ENDS,
    AxialLoad,
    Custom,
    Polynomial,
    Ramp,
    RampHold,
    Tabulated,
    history_from_params,
)
from dyntorsion.buckling.onset import detect_onset
from dyntorsion.buckling.scene import Scene
from dyntorsion.buckling.turning import TurnHold
from dyntorsion.model.ends import Ends, IllPosedEndsError
from dyntorsion.studies import fidelity
from dyntorsion.studies import sweep as S

COARSE = {"n_cells": 20, "dt": 0.02}


def test_histories_evaluate_what_they_say():
    t = np.linspace(0.0, 5.0, 11)
    np.testing.assert_array_equal(Ramp(a=1.6, kappa0=10.0)(t), 10.0 + 1.6 * t)
    np.testing.assert_allclose(Polynomial((1.0, 2.0, 3.0))(t), 1 + 2 * t + 3 * t**2, rtol=1e-15)
    hold = RampHold(a=2.0, hold=16.0, kappa0=10.0, tau=0.1)
    h = hold(t)
    assert np.all(np.diff(h) >= 0) and h[-1] == pytest.approx(
        16.0 - 0.2 * np.log1p(np.exp(-20.0)), rel=1e-15
    )
    assert h[2] == pytest.approx(10.0 + 2.0 * t[2], rel=1e-6)  # still on the ramp at t = 1
    tab = Tabulated((0.0, 1.0, 2.0), (10.0, 11.0, 11.5))
    np.testing.assert_allclose(tab(np.array([0.0, 1.0, 2.0, 9.0])), [10.0, 11.0, 11.5, 11.5])
    c = Custom("exp", lambda t, tau: 10.0 + np.expm1(t / tau), {"tau": 2.0})
    np.testing.assert_allclose(c(t), 10.0 + np.expm1(t / 2.0), rtol=1e-15)
    for hist in (Ramp(a=1.6, kappa0=10.0), Polynomial((1.0, 2.0)), hold, tab):
        assert history_from_params(hist.params()) == hist


@pytest.mark.parametrize(
    "left, right, why",
    [
        (
            ("u1", "u2", "u3", "w1", "w2", "k3"),
            ("w1", "w2", "w3", "u1", "u2", "u3"),
            "u3 prescribed at both",
        ),
        (("u1", "u2", "u3", "w1", "w2", "n3"), ENDS["clamped"].right, "must prescribe k3"),
        (("u1", "u2", "u3", "w1", "w2", "k3"), ("w1", "w2", "w3", "u1", "n1", "n3"), "u1 and n1"),
        (("u1", "u2", "u3", "w3", "w2", "k3"), ENDS["clamped"].right, "w3 and k3"),
        (("u1", "u2", "u3", "w1", "k3"), ENDS["clamped"].right, "needs 6"),
        (("u1", "u2", "u3", "w1", "w1", "k3"), ENDS["clamped"].right, "twice"),
    ],
)
def test_ill_posed_end_sets_are_refused_with_the_reason(left, right, why):
    with pytest.raises(IllPosedEndsError, match=why):
        Ends("bad", left, right)


def test_an_ill_posed_set_never_reaches_the_first_step(monkeypatch):
    import dyntorsion.buckling.simulation as B

    monkeypatch.setattr(B, "integrate", lambda *a, **k: pytest.fail("integrate was called"))
    with pytest.raises(IllPosedEndsError, match="inextensibility"):
        simulate(Scene(a=1.6, t_end=1.0, **COARSE, ends=Ends("both-u3", ENDS["clamped"].left, ("w1", "w2", "w3", "u1", "u2", "u3"))))  # fmt: skip


def test_the_onset_twist_of_a_nonlinear_history_is_read_from_the_run():
    """kappa3(0, t) = 10 + 0.5 t^2: the reported twist is the history at t_c (the old
    code reported kappa0 + a t_c with a the run's nonexistent rate)."""
    hist = Polynomial((10.0, 0.0, 0.5))
    run = simulate(Scene(history=hist, n_cells=40, dt=0.01, t_end=8.0), on_failure="return")
    onset = detect_onset(run)
    assert onset.kappa3 == pytest.approx(10.0 + 0.5 * onset.t_c**2, rel=1e-14)
    np.testing.assert_allclose(run.kappa3_left, hist(run.t), rtol=1e-9, atol=1e-9)
    i = np.searchsorted(run.t, onset.t_c)
    assert onset.kappa3 == pytest.approx(
        run.kappa3_left[i], abs=abs(run.kappa3_left[i + 1] - run.kappa3_left[i])
    )
    assert onset.kappa3 > 11.2335


def test_axial_load_starts_in_equilibrium_and_is_applied_at_the_far_end():
    T = 2e-6
    run = simulate(Scene(a=1.0, kappa0=5.0, tension=AxialLoad(T, 1e-7), t_end=2.0, **COARSE, seed=0.0), snapshots=[0.0, 2.0])  # fmt: skip
    n3 = run.run.snapshots[:, :, 11]
    np.testing.assert_allclose(n3[0], T, rtol=1e-12)  # n3 = T along the rod at t = 0
    np.testing.assert_allclose(n3[-1, -1], T + 1e-7 * 2.0, rtol=1e-9)
    # no seed, below kappa_cri: straight, so the axial force is uniform
    np.testing.assert_allclose(n3[-1], n3[-1, -1], rtol=1e-9)


@pytest.mark.parametrize("name", sorted(ENDS))
def test_every_named_end_set_runs(name):
    t_end = 1.0
    if ENDS[name].driven == "w3":  # rotation control: the history is the end's spin
        run = simulate(Scene(history=TurnHold(0.1, 0.8, tau=0.1, pretwist=10.0), ends=name, t_end=t_end, **COARSE), on_failure="return")  # fmt: skip
        np.testing.assert_allclose(run.omega3_left, run.history(run.t), rtol=1e-9, atol=1e-9)
    else:
        run = simulate(Scene(a=1.6, kappa0=10.0 if name != "clamped-free" else 0.0, ends=name, t_end=t_end, **COARSE), on_failure="return")  # fmt: skip
        np.testing.assert_allclose(run.kappa3_left, run.history(run.t), rtol=1e-9, atol=1e-9)
    assert run.t[-1] == pytest.approx(t_end) and np.all(np.isfinite(run.u3_end))


def test_scenes_with_another_history_or_ends_need_an_explicit_t_end():
    with pytest.raises(ValueError, match="give t_end"):
        S.Scene(history=Polynomial((10.0, 1.0)))
    with pytest.raises(ValueError, match="give t_end"):
        S.Scene(a=1.6, ends="clamped-free-lateral")
    with pytest.raises(ValueError, match="not both"):
        S.Scene(a=1.6, history=Polynomial((10.0, 1.0)), t_end=1.0)


STEEL = Rod(E=2.0e11, nu=0.3, rho=7850.0)
ELLIPSE = Rod.elliptic(a=0.6e-3, b=0.5e-3)


@pytest.mark.parametrize("rod", [STEEL, ELLIPSE], ids=["steel", "ellipse"])
def test_other_rods_run_at_the_quick_preset_to_their_onset(rod):
    """The presets scale with the rod's own time scales: the steel wire (T0 = 0.79 s)
    failed at the absolute Table 1 step; now it buckles past its own kappa_cri."""
    grid = fidelity.get("buckling", "quick", rod)
    assert grid.n_cells == fidelity.get("buckling", "quick").n_cells
    sc = S.Scene(a=1.6, kappa0=10.0, rod=rod, **grid.simulate_kwargs())
    with warnings.catch_warnings():
        warnings.simplefilter("error", GridWarning)
        out = S.run_scene(sc)
    assert out["onset_error"] is None
    assert out["kappa3"] > sc.kappa_cri()


@pytest.mark.slow
@pytest.mark.parametrize("level", fidelity.LEVELS)
@pytest.mark.parametrize("rod", [STEEL, ELLIPSE], ids=["steel", "ellipse"])
def test_other_rods_run_at_every_preset(rod, level):
    grid = fidelity.get("buckling", level, rod)
    out = S.run_scene(S.Scene(a=1.6, kappa0=10.0, rod=rod, **grid.simulate_kwargs()))
    assert out["onset_error"] is None and out["kappa3"] > 0


def test_table1_presets_are_unchanged_by_the_scaling():
    for level in fidelity.LEVELS:
        assert fidelity.get("buckling", level, Rod()) == fidelity.get("buckling", level)
        assert fidelity.get("waves", level, Rod()) == fidelity.get("waves", level)


def test_a_step_far_beyond_the_tested_range_warns():
    with pytest.warns(GridWarning, match="T0"):
        simulate(Scene(rod=STEEL, a=1.6, kappa0=10.0, n_cells=20, dt=0.02, t_end=0.04))


# ------------------------------------------------------------------ property: any end set
PAIRS = (("u1", "n1"), ("u2", "n2"), ("u3", "n3"), ("w1", "k1"), ("w2", "k2"), ("w3", "k3"))


@settings(max_examples=25, deadline=None, derandomize=True)
@given(
    left=st.lists(st.booleans(), min_size=5, max_size=5),
    right=st.lists(st.booleans(), min_size=6, max_size=6),
)
def test_any_end_set_is_refused_with_a_reason_or_runs(left, right):
    """Each end prescribes one field of every conjugate pair (the structure of eq 30): the
    set is either refused before a run with the reason, or the scene runs and honours
    its twist history at s = 0."""
    lf = tuple(PAIRS[i][b] for i, b in enumerate(left)) + ("k3",)
    rf = tuple(PAIRS[i][b] for i, b in enumerate(right))
    try:
        e = Ends("probe", lf, rf)
    except IllPosedEndsError as err:
        assert "u3 prescribed at both ends" in str(err)
        assert "u3" in lf and "u3" in rf
        return
    assert not ("u3" in lf and "u3" in rf)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", GridWarning)
        run = simulate(
            Scene(a=1.0, kappa0=5.0, n_cells=8, dt=0.01, t_end=0.05, ends=e), stop_at_contact=False
        )
    assert np.all(np.isfinite(run.u3_end))
    np.testing.assert_allclose(run.kappa3_left, 5.0 + run.t, rtol=1e-9, atol=1e-9)
