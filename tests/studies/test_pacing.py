"""Paced steps (dyntorsion.studies.pacing): the time step from the fast onset estimate."""

import math
from dataclasses import replace

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dyntorsion import Rod
from dyntorsion.beyond.predictions import estimate
from dyntorsion.buckling.loading import AxialLoad, Ramp
from dyntorsion.buckling.scene import Scene, run_scene
from dyntorsion.studies import presets as P
from dyntorsion.studies.pacing import STEPS, TOL, paced, paced_dt


@settings(max_examples=40, deadline=None)
@given(
    steps=st.one_of(
        st.integers(max_value=15), st.integers(min_value=10**6 + 1), st.floats(), st.booleans()
    ),
    tol=st.one_of(
        st.floats(max_value=0.0), st.floats(min_value=1.0), st.just(math.nan), st.booleans()
    ),  # fmt: skip
)
def test_bad_steps_and_tol_name_the_parameter_and_its_range(steps, tol):
    scene = Scene(a=1.6)
    with pytest.raises(ValueError, match=r"steps=.*\[16, 1000000\]"):
        paced(scene, steps=steps)
    with pytest.raises(ValueError, match=r"tol=.*\(0, 1\)"):
        paced(scene, tol=tol)


def test_scenes_the_estimate_does_not_cover_are_refused_with_the_reason():
    with pytest.raises(TypeError, match="Scene"):
        paced_dt("fig10")
    for scene in (
        Scene(history=Ramp(a=1.6, kappa0=10.0), t_end=5.0),
        Scene(a=1.6, tension=AxialLoad(0.01), t_end=5.0),
        Scene(a=1.6, ends="pinned-follower", t_end=5.0),
    ):
        with pytest.raises(ValueError, match="paced steps need the fast onset estimate.*dt"):
            paced(scene)


@pytest.mark.parametrize("a", [P.FIG10_RATES[0], 1.6, P.FIG10_RATES[-1]])
def test_the_step_reaches_the_estimated_onset_in_the_asked_steps(a):
    scene = Scene(a=a, kappa0=10.0, n_cells=60, until="first-peak")
    t_ref = estimate(scene).t_ref
    for steps in (64, STEPS, 5000):
        out = paced(scene, steps=steps)
        assert out.dt == pytest.approx(t_ref / steps, rel=5e-3)  # three significant digits
        assert float(f"{out.dt:.3g}") == out.dt
        assert out.newton.tol == TOL
        # the rest of the scene as it was
        assert replace(out, dt=scene.dt, newton=scene.newton) == scene
    assert paced_dt(scene) == pytest.approx(t_ref / STEPS, rel=5e-3)


def test_the_step_scales_with_the_rod_s_own_time():
    """A rod twice as dense buckles later (the estimate says how much) and is paced so."""
    light, heavy = Scene(a=1.6), Scene(a=1.6, rod=Rod(rho=2 * Rod().rho))
    ratio = estimate(heavy).t_ref / estimate(light).t_ref
    assert ratio > 1.05
    assert paced_dt(heavy) / paced_dt(light) == pytest.approx(ratio, rel=1e-2)


@pytest.mark.parametrize("i", [0, 9, 15])
def test_a_paced_scene_finds_the_standard_grid_s_onset(i):
    """The cached Fig 10 sweep at the standard grid (N = 100, dt = 0.005 s) against the
    same scene paced (about 500 steps instead of 600 to 12,000): within 0.25 % (the
    standard grid's own error against the converged onset is 0.3-0.5 % at these rates;
    measured changes at the 16 rates: at most 0.11 %)."""
    standard = P.cached("fig10").iloc[i]
    scene = P.preset("fig10")[i]
    out = run_scene(paced(replace(scene, until="first-peak")))
    assert out["t_c"] == pytest.approx(standard.t_c, rel=2.5e-3)
    assert out["steps"] < min(800, standard.steps)


def test_the_paced_preset_is_the_fig10_sweep_paced():
    scenes, plain = P.preset("fig10-paced"), P.preset("fig10")
    assert [sc.a for sc in scenes] == [sc.a for sc in plain]
    assert all(sc.until == "first-peak" and sc.newton.tol == TOL for sc in scenes)
    dts = [sc.dt for sc in scenes]
    assert dts == sorted(dts, reverse=True)  # slower ramps, longer steps
    assert dts[0] > 10 * dts[-1]
