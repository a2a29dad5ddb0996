"""The static critical twist of sections of any aspect ratio (issue 35, item 9), checked
against an independent formulation: the 12-field linearised Kirchhoff rod (small rotation
phi, lateral position q, moment m, force n, all in the body frame) written here with cross
products, shot from s = 0 to s = L in 60-digit arithmetic, unbalanced.  The package's
route is the 8-field transfer matrix in double precision, balanced, with a scan that
separates close pairs (:func:`dyntorsion.buckling.statics.critical_twist_transfer`)."""

from __future__ import annotations

from types import SimpleNamespace

import mpmath as mp
import numpy as np
import pytest

from dyntorsion.buckling import statics as S
from dyntorsion.buckling.onset import classify_onset
from dyntorsion.model.rod import Rod

H = 0.5e-3  # the thinner side [m]


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def det_12_fields(rod: Rod, kappa, tension=0.0):
    """Clamped ends (position and tangent held; at s = L free to slide axially, n3 = 0):
    the determinant of the 6 x 6 map from the free initial (m, n) to the end conditions at
    s = L, for the equations linearised about k0 = kappa e3, m0 = C kappa e3, n0 = T e3:

        phi' = K^-1 m - k0 x phi,          q' = phi x e3 - k0 x q,
        n'   = -(K^-1 m x n0 + k0 x n),    m' = -(K^-1 m x m0 + k0 x m) - e3 x n.
    """
    B1, B2, C, L = (mp.mpf(v) for v in (rod.B1, rod.B2, rod.C, rod.L))
    k0, m0, n0, e3 = [0, 0, kappa], [0, 0, C * kappa], [0, 0, mp.mpf(tension)], [0, 0, 1]
    A = mp.zeros(12, 12)
    for j in range(12):
        x = [0] * 12
        x[j] = 1
        phi, q, m, n = x[0:3], x[3:6], x[6:9], x[9:12]
        dk = [m[0] / B1, m[1] / B2, m[2] / C]
        column = (
            [dk[i] - _cross(k0, phi)[i] for i in range(3)]
            + [_cross(phi, e3)[i] - _cross(k0, q)[i] for i in range(3)]
            + [-(_cross(dk, m0)[i] + _cross(k0, m)[i]) - _cross(e3, n)[i] for i in range(3)]
            + [-(_cross(dk, n0)[i] + _cross(k0, n)[i]) for i in range(3)]
        )
        for i in range(12):
            A[i, j] = column[i]
    P = mp.expm(A * L)
    rows = [0, 1, 2, 3, 4, 11]  # phi(L) = 0, q1(L) = q2(L) = 0, n3(L) = 0
    return mp.det(mp.matrix([[P[r, c] for c in range(6, 12)] for r in rows]))


def _independent_root(rod: Rod, near: float, tension: float = 0.0) -> float:
    with mp.workdps(60):
        f = lambda k: det_12_fields(rod, k, tension)  # noqa: E731
        return float(mp.findroot(f, (mp.mpf(near) * (1 - 1e-7), mp.mpf(near) * (1 + 1e-7))))


SECTIONS = [
    pytest.param(Rod.rectangular(w=1.007 * H, h=H), 1e-9, id="rect-1.007"),
    pytest.param(Rod.rectangular(w=1.01 * H, h=H), 1e-9, id="rect-1.01"),
    pytest.param(Rod.rectangular(w=8 * H, h=H), 1e-9, id="rect-8"),
    pytest.param(Rod.rectangular(w=20 * H, h=H), 1e-9, id="rect-20"),
    pytest.param(Rod.rectangular(w=50 * H, h=H), 1e-6, id="rect-50"),
    pytest.param(Rod.rectangular(w=100 * H, h=H), 1e-6, id="rect-100"),
    pytest.param(Rod.elliptic(a=1.0045 * H, b=H), 1e-9, id="ellipse-1.0045"),
    pytest.param(Rod.elliptic(a=H, b=20 * H), 1e-9, id="ellipse-1:20"),
]


@pytest.mark.parametrize("rod,rtol", SECTIONS)
def test_critical_twist_agrees_with_the_12_field_formulation(rod, rtol):
    kc = S.critical_twist(rod)
    assert kc == pytest.approx(_independent_root(rod, kc), rel=rtol)


@pytest.mark.parametrize("ratio", [1.007, 1.01])
def test_a_close_pair_gives_its_lower_root(ratio):
    """Near the isotropic rod the double root splits; the answer is the lower one: the
    independent determinant keeps its sign from 0.3 kc to just below kc, changes it at kc,
    and again at the upper root of the pair within 1 % above."""
    rod = Rod.rectangular(w=ratio * H, h=H)
    kc = S.critical_twist(rod)
    with mp.workdps(60):
        below = [mp.sign(det_12_fields(rod, k)) for k in np.linspace(0.3 * kc, kc * (1 - 1e-6), 40)]
        above = [
            mp.sign(det_12_fields(rod, k)) for k in np.linspace(kc * (1 + 1e-6), 1.01 * kc, 80)
        ]
    assert len(set(below)) == 1
    assert above[0] == -below[0] and above[-1] == below[0]  # the pair's upper root


def test_the_isotropic_limit_is_continuous():
    """Aspect ratios 1 + 1e-4 and 1 + 1e-3 approach the isotropic square section's closed
    form from below (the weaker bending stiffness is that of the square)."""
    square = S.critical_twist(Rod.rectangular(w=H, h=H))
    near = [S.critical_twist(Rod.rectangular(w=(1 + e) * H, h=H)) for e in (1e-4, 1e-3)]
    assert near[1] < near[0] < square
    assert abs(near[0] / square - 1) < 1e-4


def test_under_tension_too():
    rod = Rod.rectangular(w=8 * H, h=H)
    T = 0.5 * S.euler_load(rod)
    kc = S.critical_twist(rod, tension=T)
    assert kc > S.critical_twist(rod)
    assert kc == pytest.approx(_independent_root(rod, kc, T), rel=1e-9)


def test_an_onset_without_a_static_critical_twist_is_unclassified():
    """A run whose kappa_cri is unknown never says buckled (issue 35, item 9)."""
    run = SimpleNamespace(t=np.array([0.0, 1.0]), stopped="contact")
    onset = SimpleNamespace(t_c=0.5)
    assert classify_onset(run, onset, None) == "unclassified"
