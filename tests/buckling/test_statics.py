"""Static critical twist for any section and axial load (dyntorsion.buckling.statics).

Three routes are checked against each other: the closed forms (mpmath), the body-frame
transfer matrix (any B1, B2) and Chebyshev collocation (isotropic)."""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest

from dyntorsion import Rod
from dyntorsion.beyond.linear_stability import LateralModel
from dyntorsion.buckling import statics as S
from dyntorsion.buckling.chebyshev import critical_twist_numerical

ROD = Rod()
B, L = ROD.B1, ROD.L
EULER = 4 * math.pi**2 * B / L**2  # clamped Euler load
LOADS = (0.0, 0.6 * EULER, -0.6 * EULER, 3.0 * EULER, 1e-3 * EULER)


def test_table1_value_is_eq_32():
    assert S.critical_twist(ROD) == pytest.approx(11.2335, abs=5e-5)
    assert S.critical_twist(ROD) == 2 * math.pi * ROD.E * ROD.I1 * S.m_cri / ROD.L / ROD.C


@pytest.mark.parametrize("T", LOADS)
def test_greenhill_clamped_root_solves_its_determinant(T):
    """The mpmath root makes Greenhill's clamped determinant vanish to 30 digits."""
    M = S.greenhill_clamped(B, L, T)
    if T == 0.0:
        assert M == pytest.approx(2 * math.pi * B * S.m_cri / L, rel=1e-15)
        return
    with mpmath.workdps(50):
        Mm = mpmath.mpf(M)
        d = mpmath.sqrt(4 * B * T - Mm**2 + 0j)
        lp, lm = (1j * Mm + d) / (2 * B), (1j * Mm - d) / (2 * B)
        A = mpmath.matrix(
            [[1, 0, 1, 1], [0, 1, lp, lm], [1, L, mpmath.exp(lp * L), mpmath.exp(lm * L)],
             [0, 1, lp * mpmath.exp(lp * L), lm * mpmath.exp(lm * L)]]
        )  # fmt: skip
        scale = mpmath.norm(A) ** 4
        # M is a float: the determinant is as small as one rounding of M allows
        assert abs(mpmath.det(A)) / scale < 1e-12


@pytest.mark.parametrize("lam", [20.0, 40.0])
def test_greenhill_clamped_under_a_tension_of_more_than_19_tension_lengths(lam):
    """A clamped rod L sqrt(T/B) = lam long (M L/B near 2 lam > 40, beyond the scan of
    40 B/L it once stopped at; found by ``dyntorsion.studies.contact.plectoneme_plateau``, a 5 m rod of
    PyElastica's section under 5 N) has its critical moment just above Greenhill's
    infinite-rod 2 sqrt(B T)."""
    T = (lam / L) ** 2 * B
    M = S.greenhill_clamped(B, L, T)
    assert 1.0 < M / (2 * math.sqrt(B * T)) < 1.2


@pytest.mark.parametrize("T", [t for t in LOADS if t > -0.25 * EULER] + [-0.2 * EULER])
def test_pinned_formula(T):
    """M^2/(4B^2) - T/B = (pi/L)^2 (T > 0 tension), the classical pinned result."""
    M = S.greenhill_pinned(B, L, T)
    assert M**2 / (4 * B**2) - T / B == pytest.approx((math.pi / L) ** 2, rel=1e-14)


@pytest.mark.parametrize("ends", S.STATIC_ENDS)
@pytest.mark.parametrize("T", LOADS)
def test_three_routes_agree_for_isotropic_rods(ends, T):
    if -T >= S.euler_load(ROD, ends):
        pytest.skip("beyond the Euler load of these ends")
    closed = S.critical_moment(ROD, T, ends) / ROD.C
    transfer = S.critical_twist_transfer(ROD, T, ends)
    cheb = critical_twist_numerical(ROD, 28, T, ends)
    assert transfer == pytest.approx(closed, rel=1e-8)
    assert cheb == pytest.approx(closed, rel=1e-8)


def test_tension_stiffens_and_compression_softens():
    k = [S.critical_twist(ROD, T) for T in (-0.6 * EULER, 0.0, 0.6 * EULER)]
    assert k[0] < k[1] < k[2]
    # towards the Euler load the critical twist falls to zero
    assert S.critical_twist(ROD, -0.999 * EULER) < 0.1 * k[1]


def test_compression_at_or_beyond_euler_is_refused():
    with pytest.raises(ValueError, match="Euler load"):
        S.critical_twist(ROD, -EULER)
    with pytest.raises(ValueError, match="Euler load"):
        S.critical_twist(ROD, -1.01 * math.pi**2 * B / L**2, ends="pinned")


def test_other_ends_are_refused_not_answered_for_another_rod():
    with pytest.raises(ValueError, match="static theory covers"):
        S.critical_twist(ROD, ends="clamped-free-lateral")
    with pytest.raises(TypeError, match="tension"):
        S.critical_twist(ROD, tension="1")


# ------------------------------------------------------------------ anisotropic sections
ELLIPSE = Rod.elliptic(a=0.55e-3, b=0.5e-3)


def test_an_elliptic_rod_uses_both_stiffnesses():
    """The critical twist lies strictly between the isotropic values of the weak and the
    strong axis, and turning the section by 90 degrees does not change it."""
    k = S.critical_twist(ELLIPSE)
    weak = S.greenhill_clamped(ELLIPSE.B1, L) / ELLIPSE.C
    strong = S.greenhill_clamped(ELLIPSE.B2, L) / ELLIPSE.C
    assert weak < k < strong
    turned = Rod.elliptic(a=0.5e-3, b=0.55e-3)
    assert S.critical_twist(turned) == pytest.approx(k, rel=1e-12)
    # the answer the old code gave used E I1 for both axes
    assert abs(k - weak) / k > 1e-3


@pytest.mark.parametrize("ends", S.STATIC_ENDS)
def test_anisotropic_limit_is_continuous(ends):
    """As B2 -> B1 the transfer matrix tends to the isotropic closed form (order 1 in
    the stiffness split, no jump)."""
    errs = []
    for eps in (1e-2, 1e-3, 1e-4):
        rod = Rod.from_properties(
            L=L, B1=B, B2=B * (1 + eps), C=ROD.C, mass_per_length=ROD.mass_per_length,
            rotary_inertia=ROD.rotary_inertia, thickness=ROD.D,
        )  # fmt: skip
        errs.append(abs(S.critical_twist(rod, 0.0, ends) - S.critical_twist(ROD, 0.0, ends)))
    orders = np.log10(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(orders > 0.9) and errs[-1] < 1e-3


def test_the_linear_model_refuses_anisotropic_rods():
    with pytest.raises(ValueError, match="isotropic"):
        LateralModel(ELLIPSE)
    with pytest.raises(ValueError, match="isotropic"):
        critical_twist_numerical(ELLIPSE)
