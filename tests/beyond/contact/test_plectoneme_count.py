"""The plectoneme turns of a centreline (dyntorsion.beyond.contact.plectoneme), against
two-ply plectonemes built by hand: two helices of radius D / 2 wound n times round each
other about a straight axis, joined at the top by a half circle."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from dyntorsion.beyond.contact.plectoneme import plectoneme_turns

D = 0.05


def two_ply(n: float, hand: int = 1, pitch: float = 0.15, ds: float = 0.004) -> np.ndarray:
    z = np.arange(0.0, n * pitch, ds / 2)
    phase = hand * 2 * np.pi * z / pitch
    up = np.c_[D / 2 * np.cos(phase), D / 2 * np.sin(phase), z]
    down = np.c_[-D / 2 * np.cos(phase), -D / 2 * np.sin(phase), z][::-1]
    centre, v = 0.5 * (up[-1] + down[0]), up[-1] - 0.5 * (up[-1] + down[0])
    th = np.linspace(0.0, np.pi, 40)[1:-1]
    tip = centre + np.outer(np.cos(th), v) + np.outer(np.sin(th), [0, 0, np.linalg.norm(v)])
    p = np.vstack([up, tip, down])
    s = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))]
    sn = np.linspace(0.0, s[-1], int(s[-1] / ds) + 1)
    return np.column_stack([np.interp(sn, s, p[:, k]) for k in range(3)])


@pytest.mark.parametrize("n", [1.0, 2.5, 4.0])
@pytest.mark.parametrize("hand", [1, -1])
def test_the_turns_of_a_two_ply_are_counted(n, hand):
    """Counted where the strands touch farther apart than min_arc: with min_arc = 1 D all
    but the last few nodes before the tip (3 % of a turn)."""
    p = plectoneme_turns(two_ply(n, hand), D, min_arc=1.0)
    assert p.turns == pytest.approx(hand * n, abs=0.04)
    assert hand * p.turns < n  # never more than wound
    # the default min_arc (3 D) leaves out the strands' last 3 D before the tip
    assert abs(plectoneme_turns(two_ply(n, hand), D).turns) == pytest.approx(n - 0.2, abs=0.05)


def test_a_straight_rod_or_a_single_loop_has_no_plectoneme():
    s = np.linspace(0.0, 1.0, 101)
    assert plectoneme_turns(np.c_[0 * s, 0 * s, s], D) == (0.0, 0, (-1, -1, -1, -1))
    ring = np.c_[0.2 * np.cos(2 * np.pi * s), 0.2 * np.sin(2 * np.pi * s), 0 * s]
    assert plectoneme_turns(ring, D).turns == 0.0


@given(
    angles=st.tuples(*[st.floats(-np.pi, np.pi)] * 3),
    shift=st.tuples(*[st.floats(-10.0, 10.0)] * 3),
)
def test_the_count_does_not_depend_on_where_the_rod_is(angles, shift):
    r = two_ply(2.5)
    moved = Rotation.from_euler("xyz", angles).apply(r) + np.array(shift)
    assert plectoneme_turns(moved, D).turns == pytest.approx(plectoneme_turns(r, D).turns, abs=1e-9)


def test_bad_input_is_refused():
    with pytest.raises(ValueError, match="shape"):
        plectoneme_turns(np.zeros((5, 2)), D)
    with pytest.raises(ValueError, match="diameter"):
        plectoneme_turns(two_ply(1.0), 0.0)
