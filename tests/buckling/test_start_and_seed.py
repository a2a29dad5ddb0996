"""The initial state and the seed's form as parameters (issue 35, item 6): the paper's
section 6 starts from the unstressed rod, y(s, 0) = 0, section 5 pretwists it by C h(0);
the seed's frame and duration are unstated.  Each choice is a parameter with the old
behaviour as its default, so the keys of every earlier scene are unchanged."""

from __future__ import annotations

import math

import numpy as np
import pytest

import dyntorsion.studies  # noqa: F401  (registers the record kinds)
from dyntorsion import Rod
from dyntorsion.beyond.predictions import Prediction
from dyntorsion.buckling import simulate
from dyntorsion.buckling.loading import SmoothStart, history_from_params
from dyntorsion.buckling.scene import Scene, run_scene
from dyntorsion.buckling.seed import Perturbation
from dyntorsion.store.location import default_store
from dyntorsion.store.results import Store
from dyntorsion.studies import presets as P

FAST = dict(a=16.0, kappa0=10.0, n_cells=20, dt=0.01)


def test_the_keys_of_the_default_choices_are_those_of_the_committed_records():
    store = Store(default_store())
    scenes = P.preset("fig10")
    assert all(store.path("buckling-onset", sc.params()).exists() for sc in scenes)
    p = Scene(**FAST).params()
    assert "start" not in p
    assert set(p["perturbation"]) == {"magnitude", "form", "location", "direction"}


def test_the_smooth_start_begins_unstressed_and_joins_the_ramp():
    h = SmoothStart(a=1.6, kappa0=10.0, tau=0.02)
    assert h(np.zeros(1))[0] == 0.0
    t = np.array([1e-3, 2e-3])  # kappa0 (t/tau)^4 to leading order: flat at t = 0
    twist = h(t) - 1.6 * t
    assert twist == pytest.approx(10.0 * (t / 0.02) ** 4, rel=1e-3)
    late = np.linspace(0.04, 5.0, 100)
    assert np.max(np.abs(h(late) - (10.0 + 1.6 * late))) <= 10.0 * math.exp(-16) * 1.0000001
    assert history_from_params(h.params()) == h
    from dyntorsion.waves.transitions import smoothing  # section 5's f, the same function

    tt = np.linspace(0.0, 0.1, 1001)
    assert np.allclose(h(tt), 10.0 * (1 - smoothing(tt / 0.02)) + 1.6 * tt, rtol=1e-14, atol=1e-14)
    with pytest.raises(ValueError, match="tau"):
        SmoothStart(a=1.6, kappa0=10.0, tau=0.0)


def test_a_step_start_sends_the_square_wave_of_section_5_down_the_rod():
    rod = Rod()
    transit = rod.L / rod.c
    run = simulate(Scene(rod=rod, a=1e-6, kappa0=10.0, n_cells=200, dt=transit / 100, t_end=1.9 * transit, start="step", seed=0.0), stop_at_contact=False, progress=False)  # fmt: skip
    before = run.t < 0.8 * transit
    after = run.t > 1.2 * transit
    assert run.kappa3_left[0] == 0.0 and run.kappa3_left[1] == pytest.approx(10.0)  # the jump
    assert np.max(np.abs(run.kappa3_right[before])) < 0.5
    # reflected at the far end (omega3 = 0: d kappa3 / ds = 0), the square wave doubles
    assert np.median(run.kappa3_right[after]) == pytest.approx(20.0, rel=0.05)


def test_without_a_pretwist_both_starts_are_the_same_run():
    kw = dict(a=16.0, kappa0=0.0, n_cells=20, dt=0.01, t_end=0.5)
    pre = simulate(Scene(**kw, start="pretwisted"), progress=False)
    uns = simulate(Scene(**kw, start="step"), progress=False)
    assert np.array_equal(pre.u3_end, uns.u3_end) and np.array_equal(pre.t, uns.t)


def test_an_impulse_that_never_ends_is_the_constant_seed():
    long = Perturbation(duration=1e9)
    assert long.params()["duration"] == 1e9 and not long.constant
    assert run_scene(Scene(**FAST, seed=long))["t_c"] == run_scene(Scene(**FAST))["t_c"]
    short = Perturbation(duration=0.1)
    assert short.time_factor(np.array([0.0, 0.1, 0.1000001])).tolist() == [1.0, 1.0, 0.0]


def test_the_lab_frame_turns_the_force_with_the_straight_rods_twist():
    seed = Perturbation(magnitude=1.0, frame="lab")
    s = np.linspace(0.0, 1.0, 5)
    f = seed.force(s, 1.0)
    turned = seed.turned(f, s, 1.0, twist=math.pi / 2)
    assert np.allclose(turned[-1], f[-1], rtol=0, atol=1e-15)  # the far end does not turn
    assert np.allclose(np.linalg.norm(turned, axis=1), 1.0, rtol=0, atol=1e-15)
    # the section at s = L - 1/2 is turned by phi = -pi/4: e1 has body components
    # (e1.d1, e1.d2) = (cos phi, -sin phi) = (cos pi/4, sin pi/4)
    c = math.cos(math.pi / 4)
    assert np.allclose(turned[2], [c, c, 0.0], rtol=0, atol=1e-15)
    assert np.array_equal(seed.turned(f, s, 1.0, twist=0.0), f)


def test_a_lab_frame_seed_moves_the_onset_and_says_so_in_its_key():
    lab = Scene(**FAST, seed=Perturbation(frame="lab"))
    assert lab.params()["perturbation"]["frame"] == "lab"
    res = run_scene(lab)
    assert res["status"] == "buckled"
    assert res["t_c"] != run_scene(Scene(**FAST))["t_c"]


@pytest.mark.parametrize(
    "kw",
    [
        {"start": "step"},
        {"start": "smooth", "start_tau": 0.05},
        {"seed": Perturbation(frame="lab", duration=0.5)},
    ],
)
def test_scenes_of_each_choice_round_trip_through_their_key(kw):
    sc = Scene(**FAST, **kw)
    assert Scene.from_params(sc.params()).params() == sc.params()
    assert sc.params() != Scene(**FAST).params()


@pytest.mark.parametrize(
    "kw, words",
    [
        ({"start": "relaxed"}, "start='relaxed'; allowed"),
        ({"start": "smooth", "start_tau": -1.0}, "start_tau=-1.0 must be > 0"),
        ({"seed": Perturbation(frame="lab")}, None),
    ],
)
def test_bad_starts_are_named(kw, words):
    if words is None:
        Scene(**FAST, **kw)
        return
    with pytest.raises(ValueError, match=words):
        Scene(**FAST, **kw)


@pytest.mark.parametrize(
    "kw, words",
    [({"frame": "world"}, "frame='world'"), ({"duration": 0.0}, "duration=0.0 must be > 0")],
)
def test_bad_seed_forms_are_named(kw, words):
    with pytest.raises(ValueError, match=words):
        Perturbation(**kw)


def test_the_linear_theory_refuses_what_it_does_not_model():
    for kw in ({"start": "step"}, {"seed": Perturbation(duration=0.1)}):
        with pytest.raises(ValueError, match="pretwisted rod"):
            Prediction(Scene(**FAST, **kw))


def test_scene_is_a_public_name_beside_run_scene():
    import dyntorsion

    assert dyntorsion.Scene is Scene and "Scene" in dyntorsion.__all__
    with pytest.raises(AttributeError, match="no attribute 'Sceen'"):
        dyntorsion.Sceen  # noqa: B018
