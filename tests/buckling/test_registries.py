"""Histories, axial and distributed loads and seed forms defined outside the package
register themselves by ``kind`` and come back from a scene's cache key."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest

from dyntorsion.buckling.history import HISTORIES, History, history_from_params
from dyntorsion.buckling.loads import (
    AXIAL_LOADS,
    DistributedLoad,
    EndLoad,
    load_from_params,
)
from dyntorsion.buckling.scene import Scene
from dyntorsion.buckling.seed import SEED_FORMS, Perturbation, SeedForm
from dyntorsion.store.results import RESULT_KEYS, Store
from dyntorsion.studies import kinds  # noqa: F401  (registers the record kinds)


@dataclass(frozen=True)
class QuadRamp(History):
    a: float
    b: float = 0.0
    kind = "test-quad-ramp"

    def __call__(self, t):
        t = np.asarray(t, dtype=float)
        return 10.0 + self.a * t + self.b * t**2


@dataclass(frozen=True)
class Pulled(EndLoad):
    T: float
    kind = "test-pulled"

    def __call__(self, t):
        return self.T * np.tanh(np.asarray(t, dtype=float))


@dataclass(frozen=True)
class Gravity(DistributedLoad):
    g: float
    kind = "test-gravity"

    def force(self, s, t, length):
        f = np.zeros((s.size, 3))
        f[:, 0] = self.g
        return f


class Ends2(SeedForm):
    kind = "test-ends"

    def force(self, seed, s, length):
        f = np.zeros((s.size, 3))
        f[[1, -2]] = seed.magnitude * np.asarray(seed.direction)
        return f


def test_subclasses_register_by_kind():
    assert HISTORIES["test-quad-ramp"] is QuadRamp
    assert AXIAL_LOADS["test-pulled"] is Pulled
    assert SEED_FORMS["test-ends"] is Ends2
    assert history_from_params(QuadRamp(2.0, 0.5).params()) == QuadRamp(2.0, 0.5)
    assert load_from_params(Pulled(3.0).params()) == Pulled(3.0)


def test_unknown_kind_names_the_registered_ones():
    with pytest.raises(ValueError, match=r"history kind='nope'; registered: .*ramp"):
        history_from_params({"kind": "nope"})


def test_user_parts_round_trip_through_the_store(tmp_path):
    sc = Scene(
        history=QuadRamp(2.0, 0.5), tension=Pulled(1e-4), loads=(Gravity(1e-9),),
        seed=Perturbation(form="test-ends"), t_end=1.0, n_cells=10, dt=0.01,
    )  # fmt: skip
    store = Store(tmp_path)
    result = {"status": "test", **dict.fromkeys(RESULT_KEYS["buckling-onset"])}
    path = store.save("buckling-onset", sc.params(), result)
    back = Scene.from_params(store.read(path)["params"])
    assert back == sc
    assert back.params() == sc.params()
    assert "test-gravity(g=1e-09)" in sc.label()
    with pytest.raises(ValueError, match="static theory covers end loads"):
        Scene(a=1.0, t_end=1.0, loads=(Gravity(1.0),)).kappa_cri()
    with pytest.raises(ValueError, match="changes in time"):
        sc.kappa_cri()


def test_a_user_seed_form_acts_where_it_says():
    s = np.linspace(0.0, 1.0, 11)
    f = Perturbation(magnitude=2.0, form="test-ends").force(s, 1.0)
    assert np.flatnonzero(f[:, 0]).tolist() == [1, 9] and f[1, 0] == 2.0
    with pytest.raises(ValueError, match="registered: .*point.*uniform"):
        Perturbation(form="nope")


def test_end_sets_declare_what_they_support():
    from dyntorsion.beyond.predictions import Prediction
    from dyntorsion.model.ends import ENDS, UnsupportedEndsError

    free = Scene(a=1.0, t_end=1.0, ends="clamped-free")
    with pytest.raises(UnsupportedEndsError, match="'clamped-free' do not support a static"):
        free.kappa_cri()
    with pytest.raises(UnsupportedEndsError, match="'clamped-free' do not support the linear"):
        Prediction(free)
    assert ENDS["clamped"].static == "clamped" and ENDS["clamped-turned"].contact
    with pytest.raises(ValueError, match="t_end=None.*do not support a static critical twist"):
        Scene(a=1.0, ends="pinned-follower")


def test_a_relation_is_written_into_its_row_and_keyed():
    from dyntorsion.buckling.loading import AxialLoad, Ramp
    from dyntorsion.model.cosserat import Cosserat
    from dyntorsion.model.ends import IllPosedEndsError, Relation, ends_from_params, register
    from dyntorsion.model.rod import Rod

    right = ("w1", "w2", "k3", "u1", "u2", "n3")
    e = register(
        __import__("dyntorsion.model.ends", fromlist=["Ends"]).Ends(
            "test-dashpot", ("u1", "u2", "u3", "w1", "w2", "k3"), right,
            relations=(Relation("right", "k3", (("w3", 0.25),), value=1.5),),
        )
    )  # fmt: skip
    system = Cosserat(Rod()).system()
    left, rows = e.rows(system, Ramp(1.0), AxialLoad(1e-3))
    i = right.index("k3")
    assert rows.rows[i, system.index("k3")] == 1.0 and rows.rows[i, system.index("w3")] == 0.25
    assert rows.at(np.array([0.0, 2.0]))[:, i].tolist() == [1.5, 1.5]
    assert rows.at(np.array([2.0]))[0, right.index("n3")] == 1e-3
    assert ends_from_params(e.params()) is e
    assert e.params()["relations"][0]["terms"] == [["w3", 0.25]]
    with pytest.raises(IllPosedEndsError, match="does not prescribe w3"):
        type(e)("bad", e.left, right, relations=(Relation("right", "w3", (("k3", 1.0),)),))


def test_a_numerical_static_twist_reaches_the_scene():
    from dyntorsion.buckling import statics
    from dyntorsion.model.ends import ENDS, Ends, register

    statics.STATIC_ENDS["test-half"] = statics.StaticEnds(
        True, 4.0, None, solver=lambda rod, T: 0.5 * statics.critical_twist(rod, T)
    )
    e = register(Ends("test-half", ENDS["clamped"].left, ENDS["clamped"].right,
                      static="test-half"))  # fmt: skip
    sc = Scene(a=1.0, ends=e)
    assert sc.kappa_cri() == 0.5 * statics.critical_twist(sc.rod)
    assert statics.STATIC_ENDS["test-half"].route == "numerical"
