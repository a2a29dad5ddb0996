"""Long steps while the solution is quiet (genalpha.LongSteps, genalpha.long)."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dyntorsion import buckling as buckling
from dyntorsion import genalpha as ga
from dyntorsion.buckling.scene import Scene, run_scene
from dyntorsion.genalpha.march import closes, make_gate
from dyntorsion.store.results import digest

DT = 2.0**-6  # so that factor * dt is exact
SCENE = dict(a=1.6, kappa0=10.0, n_cells=10, t_end=3.0)


def long(**kw) -> ga.Scheme:
    return ga.Scheme(long_steps=ga.LongSteps(**kw))


# ------------------------------------------------------------------ the option
@settings(max_examples=40, deadline=None)
@given(
    factor=st.one_of(st.integers(max_value=1), st.integers(min_value=4097), st.floats()),
    limit=st.one_of(st.floats(max_value=0.0), st.just(math.inf), st.just(math.nan)),
    tol=st.one_of(st.floats(max_value=0.0), st.floats(min_value=1.0), st.just(math.nan)),
)
def test_bad_long_steps_name_the_parameter_and_its_range(factor, limit, tol):
    with pytest.raises(ValueError, match=r"factor=.*\[2, 4096\]"):
        ga.LongSteps(factor=factor)
    with pytest.raises(ValueError, match=r"limit=.*> 0"):
        ga.LongSteps(limit=limit)
    with pytest.raises(ValueError, match=r"tol=.*\(0, 1\)"):
        ga.LongSteps(tol=tol)


def test_long_steps_name_fields_and_enter_the_cache_key_only_when_set():
    with pytest.raises(ValueError, match="fields"):
        ga.LongSteps(fields=())
    with pytest.raises(TypeError, match="long_steps"):
        ga.Scheme(long_steps=8)
    assert "long_steps" not in Scene(a=1.6).params()["scheme"]
    scene = Scene(a=1.6, scheme=long(factor=4, limit=0.2))
    p = scene.params()["scheme"]["long_steps"]
    assert p == {"factor": 4, "limit": 0.2, "tol": 1e-3, "fields": ["k1", "k2"]}
    back = Scene.from_params(scene.params())
    assert back.scheme == scene.scheme and back.params() == scene.params()
    assert digest(scene.params()) != digest(Scene(a=1.6).params())
    assert scene.label().endswith(" long=4")


# ------------------------------------------------------------------ the error estimate
def _levels(closes_at, values):
    """Feed gauge values (one node, one field) to a fresh gate; the index at which it
    closes, or None."""
    gate = make_gate([0], 1.0, math.inf, closes_at)
    for i, v in enumerate(values):
        if closes(np.array([[v]]), gate):
            return i, gate.state[2]
    return None, gate.state[2]


@pytest.mark.parametrize("sh", [0.05, 0.2, 0.5])
def test_error_estimate_is_the_trapezoidal_error_of_a_growth(sh):
    """For G = e^{s t} the estimate is (s h)^3 / 12 to leading order: a gate with tol just
    above it stays open, one just below closes at the fourth level."""
    values = np.exp(sh * np.arange(20))
    estimate = (1 - np.exp(-sh)) ** 3 / 12  # the third backward difference, exactly
    assert estimate == pytest.approx(sh**3 / 12, rel=2 * sh)
    assert _levels(estimate * 1.01, values) == (None, 0.0)
    assert _levels(estimate * 0.99, values) == (3, 2.0)


def test_error_estimate_vanishes_on_a_quadratic_response_and_the_limit_closes_first():
    t = np.arange(40) * 0.1
    assert _levels(1e-12, 3.0 + 2.0 * t + 5.0 * t**2)[0] is None
    gate = make_gate([0], 2.0, 1.0, 1e-3)
    assert not closes(np.array([[0.4]]), gate)
    assert closes(np.array([[0.5]]), gate) and gate.state[2] == 1.0  # 2 * 0.5 >= 1


# ------------------------------------------------------------------ the run
def test_a_long_phase_to_the_end_is_the_run_with_the_long_step():
    """With a gate that never closes, the run takes the levels of a run at factor * dt,
    bit for bit (the same steps of eq 10-12 with the coefficients of the long step)."""
    runs = buckling.simulate(
        Scene(dt=DT, scheme=long(factor=4, limit=1e9, tol=0.99), **SCENE), stop_at_contact=False
    )
    fixed = buckling.simulate(Scene(dt=4 * DT, **SCENE), stop_at_contact=False)
    meta = runs.run.meta["long_steps"]
    assert meta == {"factor": 4, "steps": 48, "until": 3.0, "ended": "t_end"}
    np.testing.assert_array_equal(runs.t, fixed.t)
    np.testing.assert_array_equal(runs.u3_end, fixed.u3_end)
    np.testing.assert_array_equal(runs.run.y, fixed.run.y)
    assert runs.run.substeps.sum() == 48 and runs.run.steps == fixed.run.steps * 4


def test_the_phase_ends_where_the_gauge_reaches_the_limit_and_goes_on_at_dt():
    run = buckling.simulate(
        Scene(dt=DT, scheme=long(factor=4, limit=5e-4, tol=0.99), **SCENE), stop_at_contact=False
    ).run
    meta = run.meta["long_steps"]
    assert meta["ended"] == "limit" and 0 < meta["steps"] < 48
    until = meta["until"]
    k1, k2 = run.names.index("k1"), run.names.index("k2")
    turn = run.s[1] * np.sum(np.hypot(run.y[:, k1], run.y[:, k2]))
    assert turn > 5e-4  # the run went on past the limit ...
    steps = np.diff(run.t)
    np.testing.assert_allclose(steps[run.t[1:] <= until], 4 * DT, rtol=1e-12)
    np.testing.assert_allclose(steps[run.t[1:] > until], DT, rtol=1e-12)  # ... at dt
    assert run.substeps.sum() == meta["steps"] + round((run.t_final - until) / DT)
    inner = run.iterations[: round(until / DT)].reshape(-1, 4)
    assert np.all(inner[:, :3] == 0) and np.all(inner[:, 3] > 0)  # counted at each end


def test_a_snapshot_off_the_long_levels_ends_the_phase_and_is_landed_on():
    run = buckling.simulate(
        Scene(dt=DT, scheme=long(factor=4, limit=1e9, tol=0.99), **SCENE),
        stop_at_contact=False,
        snapshots=[0.5, 1.0 + DT],
    ).run
    assert run.meta["long_steps"]["ended"] == "landing"
    assert run.meta["long_steps"]["until"] == 1.0
    np.testing.assert_array_equal(run.snapshot_times, [0.5, 1.0 + DT])


def test_onset_with_long_steps_matches_the_fixed_grid_and_refuses_a_coarse_rise():
    """The Fig 10 scene a = 1.6 on a coarse grid: the same onset to a small fraction of its
    uncertainty; a phase that lasts into the rise is refused, not read."""
    base = dict(a=1.6, kappa0=10.0, n_cells=20, dt=0.01, until="first-peak")
    fixed = run_scene(Scene(**base))
    fast = run_scene(Scene(**base, scheme=long()))
    assert fast["long_steps"]["steps"] > 0 and fast["steps"] < fixed["steps"]
    assert abs(fast["t_c"] - fixed["t_c"]) < 0.01 * fixed["uncertainty_t"]
    coarse = Scene(**base, scheme=long(limit=1e9, tol=0.99))
    with pytest.raises(ValueError, match="LongSteps.limit"):
        buckling.detect_onset(buckling.simulate(Scene(a=1.6, kappa0=10.0, n_cells=20, dt=0.01, t_end=coarse.duration(), scheme=coarse.scheme, until="first-peak")))  # fmt: skip
