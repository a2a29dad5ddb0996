"""Property-based tests of the input classes of the fault probe: every end history at
numeric extremes agrees with a direct evaluation of its formula (mpmath, 50 digits) to a
relative 1e-12; an empty or blank string for any command-line option is refused in one
line; ``None`` for any :class:`~dyntorsion.buckling.scene.Scene` field is a TypeError or
ValueError naming the field.  The hand-picked probes are in tests/test_faults_inputs.py."""

from __future__ import annotations

import dataclasses
import math

import mpmath as mp
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from dyntorsion.buckling.loading import Polynomial, Ramp, RampHold, SmoothStart, Tabulated
from dyntorsion.buckling.scene import Scene, run_scene
from dyntorsion.buckling.turning import TurnHold

mp.mp.dps = 50
REL = 1e-12


def _close(got: float, exact: mp.mpf, scale: mp.mpf | None = None) -> bool:
    """``got`` within REL of ``exact`` relative to ``scale`` (default |exact|: the size of
    the terms where the function crosses zero), or both below float's normal range."""
    size = abs(exact) if scale is None else max(abs(exact), abs(scale))
    if size < 1e-290:
        return abs(got) < 1e-290
    return abs(mp.mpf(got) - exact) <= REL * size


def _times(hi: float):
    return st.lists(st.floats(0.0, hi), min_size=1, max_size=8)


BIG = st.floats(1e-150, 1e150)


def _f4(z: mp.mpf) -> mp.mpf:
    """1 - exp(-z^4), section 5's transition complement."""
    return -mp.expm1(-(z**4))


@given(a=BIG, kappa0=st.floats(0.0, 1e150), ts=_times(1e150))
def test_a_ramp_is_its_formula_at_any_scale(a, kappa0, ts):
    h = Ramp(a, kappa0)
    for t, got in zip(ts, h(np.array(ts))):
        assert _close(got, mp.mpf(kappa0) + mp.mpf(a) * mp.mpf(t))


@given(a=BIG, kappa0=st.floats(0.0, 1e150), tau=BIG, ts=_times(1e150))
def test_a_smooth_start_is_its_formula_at_any_scale(a, kappa0, tau, ts):
    h = SmoothStart(a, kappa0, tau)
    for t, got in zip(ts, h(np.array(ts))):
        exact = mp.mpf(kappa0) * _f4(mp.mpf(t) / mp.mpf(tau)) + mp.mpf(a) * mp.mpf(t)
        assert _close(got, exact)


@given(c=st.lists(st.floats(0.0, 1e100), min_size=1, max_size=5), ts=_times(1e50))
def test_a_polynomial_is_its_formula_at_any_scale(c, ts):
    h = Polynomial(tuple(c))
    for t, got in zip(ts, h(np.array(ts))):
        exact = mp.fsum(mp.mpf(ck) * mp.mpf(t) ** k for k, ck in enumerate(c))
        assert _close(got, exact)


@given(
    a=st.floats(1e-6, 1e6),
    kappa0=st.floats(0.0, 1e3),
    rise=st.one_of(st.floats(1e-3, 1e3), st.floats(1e3, 1e300)),
    tau=st.floats(1e-6, 1e6),
    fractions=st.lists(st.floats(0.0, 3.0), min_size=1, max_size=8),
)
def test_a_ramp_hold_is_its_formula_for_any_hold(a, kappa0, rise, tau, fractions):
    """The probe's RampHold(16, 1e17, 10) gave 16, 16, 16, 16, 32 where 10, 14, 18, 22, 26
    are due; at any hold the values are the formula's, h = r - a tau log(1 + e^x),
    r = kappa0 + a t, x = (r - hold) / (a tau), to 1e-12 of the twist's size r."""
    h = RampHold(a, kappa0 + rise, kappa0, tau)
    ts = [f * rise / a for f in fractions] + [0.0, 1.0, 2.0, 3.0]
    for t, got in zip(ts, h(np.array(ts))):
        r = mp.mpf(kappa0) + mp.mpf(a) * mp.mpf(t)
        s = mp.mpf(a) * mp.mpf(tau)
        exact = r - s * mp.log1p(mp.exp((r - mp.mpf(h.hold)) / s))
        assert _close(got, exact, scale=r)


def test_the_probed_ramp_hold_climbs_at_its_rate():
    for hold in (1e17, 1e20, 1e300):
        got = RampHold(16.0, hold, 10.0)(np.array([0.0, 0.25, 0.5, 0.75, 1.0]))
        assert got.tolist() == [10.0, 14.0, 18.0, 22.0, 26.0]


@given(
    turns=st.floats(1e-6, 1e6) | st.floats(-1e6, -1e-6),
    t_turn=st.floats(1e-3, 1e6),
    tau_share=st.floats(1e-6, 0.25),
    fractions=st.lists(st.floats(0.0, 1e6), min_size=1, max_size=8),
)
def test_a_turn_hold_is_its_formula_at_any_scale(turns, t_turn, tau_share, fractions):
    h = TurnHold(turns, t_turn, tau_share * t_turn)
    ts = [f * t_turn for f in fractions]
    omega = 2 * mp.pi * mp.mpf(turns) / mp.mpf(t_turn)
    tau = mp.mpf(h.tau)
    for t, got in zip(ts, h(np.array(ts))):
        t = mp.mpf(t)
        shape = _f4(t / tau) if t < h.t_turn else mp.exp(-(((t - h.t_turn) / tau) ** 4))
        assert _close(got, -omega * shape)


def test_a_turn_hold_whose_spin_overflows_is_refused():
    with pytest.raises(ValueError, match="turns=1e\\+300 in t_turn=1e-10 s.*overflows"):
        TurnHold(1e300, 1e-10, 1e-11)


@given(
    steps=st.lists(st.floats(1e-6, 1e6), min_size=1, max_size=6),
    kappa=st.lists(st.floats(-1e150, 1e150), min_size=7, max_size=7),
)
def test_a_table_passes_through_its_points_and_holds_after_the_last(steps, kappa):
    t = np.concatenate([[0.0], np.cumsum(steps)])
    if np.any(np.diff(t) <= 0):
        return  # a step lost to round-off: not a strictly increasing table
    k = kappa[: len(t)]
    h = Tabulated(tuple(t), tuple(k))
    got = h(np.concatenate([t, [t[-1] * 2 + 1]]))
    scale = max(map(abs, k))
    for g, want in zip(got, [*k, k[-1]]):
        assert _close(g, mp.mpf(want), scale=mp.mpf(scale) * 1e-3 if scale else None)
    assert math.isfinite(float(np.max(np.abs(got))))


# ------------------------------------------------------------ None for a Scene field
SCENE_FIELDS = [f.name for f in dataclasses.fields(Scene)]
#: the fields whose None is documented: the paper's kappa0 = 10, the horizon rule's
#: t_end, the ramp (no other history)
NONE_MEANS = {"kappa0": 10.0, "t_end": None, "history": None}


@given(st.sets(st.sampled_from(SCENE_FIELDS), min_size=1, max_size=3))
def test_none_for_any_scene_field_is_its_default_or_refused_naming_it(names):
    """Scene(seed=None), Scene(scheme=None), ... raised AttributeError on NoneType deep in
    the run; now a TypeError or ValueError names a field set to None, or None is the
    field's documented default."""
    kwargs = {"a": 16.0, "t_end": 1.0, **dict.fromkeys(names)}
    refused = names - set(NONE_MEANS)
    if not refused:
        scene = Scene(**kwargs)
        assert all(getattr(scene, n) == NONE_MEANS[n] for n in names if n != "t_end")
        return
    with pytest.raises((TypeError, ValueError)) as err:
        Scene(**kwargs)
    assert any(f"{n}=None" in str(err.value) or f"{n} " in str(err.value) for n in refused)


@given(
    st.one_of(
        st.none(), st.integers(), st.text(max_size=5), st.dictionaries(st.just("a"), st.floats())
    )
)
def test_run_scene_of_anything_but_a_scene_is_a_typeerror_naming_it(thing):
    with pytest.raises(TypeError, match=r"^scene=.* must be a dyntorsion\.buckling\.scene\.Scene"):
        run_scene(thing)


def test_a_scene_without_variations_is_refused():
    """variations=() gave t_c with both uncertainties 0.0."""
    with pytest.raises(ValueError, match=r"variations=\(\) must hold at least one window"):
        Scene(a=16.0, variations=())
