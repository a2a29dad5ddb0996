"""Compiled stop tests (:mod:`dyntorsion.genalpha.watch`, :mod:`dyntorsion.buckling.stops`): the
march consults them at exactly the levels at which ``integrate`` calls a Python stop, so
a run stops at the same level with the same message and the same traces."""

import numba
import numpy as np
import pytest

from dyntorsion.buckling import simulation as buckling
from dyntorsion.buckling import stops
from dyntorsion.buckling.onset import PEAK_FALL, reference_level
from dyntorsion.buckling.scene import Scene
from dyntorsion.genalpha import LongSteps, Scheme, StepControl
from dyntorsion.genalpha.watch import STOP_SIGNATURE, CompiledStop

CONTROL = Scheme(control=StepControl())


def as_python(monkeypatch):
    """Make simulate hand integrate the same test as a plain Python callable (consulted
    by integrate between chunks, never by the march); returns the levels it was asked."""
    asked = []
    made = stops.scene_stop

    def python_stop(*args, **kwargs):
        compiled = made(*args, **kwargs)

        def stop(t, y):
            asked.append(t)
            return compiled(t, y)

        return stop

    monkeypatch.setattr(buckling, "scene_stop", python_stop)
    return asked


def same_run(a, b):
    assert a.stopped == b.stopped
    assert np.array_equal(a.t, b.t)
    assert np.array_equal(a.u3_end, b.u3_end)
    assert np.array_equal(a.run.y, b.run.y)
    assert np.array_equal(a.run.snapshot_times, b.run.snapshot_times)


@pytest.mark.parametrize(
    "kwargs",
    [
        # every level checked (step control) to self-contact past the whip
        dict(a=16.0, kappa0=10.0, n_cells=100, dt=0.005, t_end=4.0, scheme=CONTROL),
        # checks every 0.1 s, a snapshot off that grid, until the first peak
        dict(a=16.0, kappa0=10.0, n_cells=100, dt=0.005, t_end=4.0, scheme=CONTROL,
             until="first-peak", snapshots=[2.5025]),
        dict(a=1.6, kappa0=10.0, n_cells=40, dt=0.01, t_end=15.0, until="first-peak",
             snapshots=[8.005, 9.0]),
        # long steps first, then every level
        dict(a=1.6, kappa0=10.0, n_cells=40, dt=0.01, t_end=15.0, until="first-peak",
             scheme=Scheme(control=StepControl(), long_steps=LongSteps())),
    ],
)  # fmt: skip
def test_the_march_stops_where_integrate_would(monkeypatch, kwargs):
    run = {"snapshots": kwargs.pop("snapshots", ()), "on_failure": "return"}
    compiled = buckling.simulate(Scene(**kwargs), **run)
    asked = as_python(monkeypatch)
    python = buckling.simulate(Scene(**kwargs), **run)
    assert asked  # the Python path really consulted the test
    same_run(compiled, python)
    assert not compiled.stopped.startswith(("t_end", "failed"))


def test_the_contact_run_ends_at_self_contact_and_the_peak_run_after_the_peak():
    run = buckling.simulate(
        Scene(a=16.0, kappa0=10.0, n_cells=100, dt=0.005, t_end=4.0, scheme=CONTROL)
    )
    assert run.stopped.startswith("self-contact at t = ")
    peak = buckling.simulate(Scene(a=16.0, kappa0=10.0, n_cells=100, dt=0.005, t_end=4.0, scheme=CONTROL, until="first-peak"))  # fmt: skip
    assert peak.stopped.startswith("first peak of |u3(L)| passed at t = ")
    u = np.abs(peak.u3_end)
    assert u[-1] < PEAK_FALL * u.max() <= PEAK_FALL * u[:-1].max()  # stopped at the fall
    assert u.max() >= reference_level(peak.rod)
    assert peak.t[-1] < run.t[-1]


@numba.njit(STOP_SIGNATURE)
def counting(y, watch):
    watch.state[1] += 1.0
    return False


@pytest.mark.parametrize("scheme", [Scheme(), CONTROL])
@pytest.mark.parametrize("check_every", [1, 7])
def test_a_compiled_stop_is_consulted_at_the_checks_and_snapshots(monkeypatch, scheme, check_every):
    """Every ``check_every`` levels from t0 and at the snapshots, never at the last level,
    as often as integrate would call a Python stop."""
    made = []

    def counted(*args, **kwargs):
        made.append(CompiledStop(counting, np.zeros(0), np.zeros(2), np.zeros(0), str))
        return made[-1]

    monkeypatch.setattr(buckling, "scene_stop", counted)
    kw = dict(a=1.6, kappa0=10.0, n_cells=10, dt=0.05, t_end=3.0, until="first-peak",
              scheme=scheme)  # fmt: skip
    run = dict(stop_at_contact=False, snapshots=[0.5, 1.025, 3.0], check_every=check_every)
    buckling.simulate(Scene(**kw), **run)
    n_steps = 60
    levels = {i for i in range(1, n_steps) if i % check_every == 0} | {10, 20}
    assert made[0].state[1] == len(levels)
    made.clear()
    asked = []
    monkeypatch.setattr(buckling, "scene_stop", lambda *a, **k: lambda t, y: asked.append(t))
    buckling.simulate(Scene(**kw), **run)
    assert len(asked) == len(levels)
