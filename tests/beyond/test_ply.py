"""The two-ply theory of the plectoneme plateau (dyntorsion.beyond.ply): eqs 9a and 9c of
Clauvelin, Audoly and Neukirch (2009) are the coexistence of the ply with the tails, and
the thin-rod limit is approached with the stated finite-radius correction."""

from __future__ import annotations

import math

import mpmath
import pytest
from hypothesis import given
from hypothesis import strategies as st

from dyntorsion.beyond.ply import ply, ply_torque_leading

B, A = 6.136e-7, 5e-4  # the paper's rod: bending stiffness, radius


@given(st.floats(1e-6, 1e2))
def test_the_ply_coexists_with_the_tails(T):
    """g(alpha) = B sin^4 / (2 a^2) - M sin(2 alpha) / (2 a) + T is 0 and stationary at the
    ply: eqs 9a and 9c are the energy balance of the module docstring."""
    p = ply(T, B, A)
    s, c = math.sin(p.alpha), math.cos(p.alpha)
    g = B * s**4 / (2 * A * A) - p.torque * 2 * s * c / (2 * A) + T
    dg = 2 * B * s**3 * c / (A * A) - p.torque * math.cos(2 * p.alpha) / A
    assert abs(g) <= 1e-9 * T and abs(dg) <= 1e-9 * p.torque / A
    assert 0 < p.alpha < math.pi / 4


@pytest.mark.parametrize("T", [1e-6, 1e-5, 1e-4])
def test_the_thin_rod_limit_and_its_correction(T):
    """M / leading - 1 = eps / sqrt(6) + O(eps^2), eps = a sqrt(T / B): the remainder
    falls as eps^2."""
    eps = A * math.sqrt(T / B)
    rest = ply(T, B, A).torque / ply_torque_leading(T, B, A) - 1 - eps / math.sqrt(6)
    assert abs(rest) < 2 * eps**2
    assert ply(T, B, A).alpha == pytest.approx((2 / 3) ** 0.25 * math.sqrt(eps), rel=2 * eps)


def test_numbers_for_the_paper_rod():
    """At T = 1e-3 N: alpha 7.335 deg (eq 9a solved again in mpmath), 5.24e-6 N m (0.106 of
    2 sqrt(B T)), 40.3 turns of writhe per metre of rod in the ply."""
    p = ply(1e-3, B, A)
    with mpmath.workdps(40):
        s = mpmath.sin
        eq9a = lambda x: s(x) ** 3 * (mpmath.cos(x) * mpmath.tan(2 * x) - s(x) / 2)  # noqa: E731
        alpha = mpmath.findroot(lambda x: eq9a(x) - mpmath.mpf(1e-3) * A * A / B, 0.128)
    assert p.alpha == pytest.approx(float(alpha), rel=1e-13)
    assert math.degrees(p.alpha) == pytest.approx(7.335, abs=0.001)
    assert p.torque == pytest.approx(5.24e-6, rel=1e-3)
    assert p.torque / (2 * math.sqrt(B * 1e-3)) == pytest.approx(0.106, abs=5e-4)
    assert p.writhe_per_length == pytest.approx(40.3, abs=0.05)


@pytest.mark.parametrize("bad", [0.0, -1.0, math.nan, math.inf])
def test_bad_input_names_the_parameter(bad):
    for name, args in (("tension", (bad, B, A)), ("bending", (1e-3, bad, A)),
                       ("radius", (1e-3, B, bad))):  # fmt: skip
        with pytest.raises(ValueError, match=name):
            ply(*args)
