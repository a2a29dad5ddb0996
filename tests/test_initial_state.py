"""The starts of the rod (dyntorsion.studies.initial_state): the histories say what the
paper's sections say."""

from __future__ import annotations

import numpy as np
import pytest

from dyntorsion.buckling.loading import Ramp
from dyntorsion.studies import initial_state as I


def test_the_step_start_is_unstressed_then_the_papers_ramp():
    h = I.history("step", 1.6, 10.0)
    t = np.array([0.0, 1e-9, 0.5, 2.0])
    assert np.allclose(h(t), [0.0, 10.0 + 1.6e-9, 10.8, 13.2])
    assert h.kappa0 == 0.0


def test_the_smooth_start_is_c2_at_zero_and_joins_the_ramp_after_tau():
    """S(x) = x^3 (10 - 15 x + 6 x^2): the end twist and its first two time derivatives
    start at the unstressed rod's (0 plus the ramp's a t), and after tau it is the ramp."""
    h = I.history("smooth ramp", 2.0, 10.0)
    dt = 1e-6
    t = np.array([0.0, dt, 2 * dt])
    k = h(t)
    assert k[0] == 0.0
    assert (k[1] - k[0]) / dt == pytest.approx(2.0, rel=1e-6)  # only the ramp's rate
    # h'' = 60 kappa0 t / tau^3 near 0: 0.44 1/(m s^2) at t = dt, against kappa0 / tau^2 = 510
    assert abs(k[2] - 2 * k[1] + k[0]) / dt**2 < 1.0
    late = np.array([I.TAU, 2 * I.TAU, 10.0])
    assert np.allclose(h(late), 10.0 + 2.0 * late)


def test_the_pretwisted_start_is_the_papers_ramp_and_others_are_refused():
    assert I.history("pretwisted", 0.5, 10.0) == Ramp(a=0.5, kappa0=10.0)
    with pytest.raises(ValueError, match=r"start='jump'; allowed: pretwisted, step, smooth ramp"):
        I.history("jump", 0.5, 10.0)


def test_two_starts_have_two_keys():
    """The cache key of a custom start holds its parameters (a, kappa0) and its code."""
    a = I.history("step", 0.5, 10.0).params()
    b = I.history("step", 1.0, 10.0).params()
    c = I.history("smooth ramp", 0.5, 10.0).params()
    assert a != b and a["source"] != c["source"]
