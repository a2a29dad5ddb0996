"""dyntorsion.verification.richardson: the limit and observed order of a ladder."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from dyntorsion.verification import richardson


@given(
    v0=st.floats(-5, 5),
    c=st.floats(1, 50) | st.floats(-50, -1),
    p=st.floats(0.5, 3.0),
    n0=st.floats(5, 40),
    ratios=st.lists(st.floats(1.3, 2.0), min_size=2, max_size=4),
)
def test_a_power_law_ladder_gives_its_limit_and_order(v0, c, p, n0, ratios):
    """Refinements of 1.3-2 per level (any mix), orders 0.5-3: the order to 1e-5 and
    the limit to 1e-6 of the constant."""
    n = n0 * np.cumprod([1.0, *ratios])
    h = 1.0 / n
    limit, order = richardson(h[::-1], (v0 + c * h**p)[::-1])  # any order of the levels
    assert order == pytest.approx(p, rel=1e-5)
    assert limit == pytest.approx(v0, abs=1e-6 * (1 + abs(c)))


def test_no_order_is_observed_where_the_differences_change_sign():
    assert richardson([0.1, 0.05, 0.025], [1.0, 1.1, 1.05]) is None
    assert richardson([0.1, 0.05, 0.025], [1.0, 1.0, 1.0]) is None


def test_bad_ladders_are_refused_with_the_reason():
    with pytest.raises(ValueError, match="three levels"):
        richardson([0.1, 0.05], [1.0, 2.0])
    with pytest.raises(ValueError, match="distinct positive"):
        richardson([0.1, 0.1, 0.05], [1.0, 2.0, 3.0])
