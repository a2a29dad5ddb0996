"""Static stability of the straight twisted rod (section 6, eqs 31-32, and beyond).

The critical twist kappa_cri is the smallest twist kappa3 at which the straight rod,
twisted uniformly with twisting moment M = C kappa3 and loaded by an axial force T
(positive = tension), has an adjacent equilibrium.  Three routes, each a check of the
others:

* closed forms (mpmath, 40 digits) for isotropic sections (B1 = B2 = B): the paper's
  eq (31) (clamped ends, T = 0: tan(pi m) = pi m, M = 2 pi B m / L); Greenhill's
  clamped determinant with tension (w = c1 + c2 s + c3 e^{l+ s} + c4 e^{l- s},
  B l^2 - i M l - T = 0); the pinned formula M^2/(4 B^2) - T/B = (pi/L)^2 (axial torque);
* the body-frame transfer matrix, for any B1, B2: the linearised Kirchhoff equations
  (eq 6 in statics) about the twisted straight state have constant coefficients in the
  body frame::

      B1 k1' + (M - kappa B2) k2 - n2 = 0,   B2 k2' - (M - kappa B1) k1 + n1 = 0,
      n1' = kappa n2 - T k2,                 n2' = -kappa n1 + T k1,

  with k1 = phi1' - kappa phi2, k2 = phi2' + kappa phi1 (phi the small rotation of the
  section) and the lateral position in body components q' = (phi2 + kappa q2,
  -phi1 - kappa q1); the end conditions make an 8 x 8 matrix that is singular at the
  critical twist;
* Chebyshev collocation of the isotropic equation B w'''' - i M w''' - T w'' = 0
  (:func:`~dyntorsion.buckling.chebyshev.critical_twist_numerical`), an eigenproblem for M.

End conditions (:data:`STATIC_ENDS`): ``"clamped"`` (eq 30 in statics: position and
tangent held at both ends, the far end free to slide axially) and ``"pinned"`` (position
held, free to tilt, the end moment axial: Greenhill's classical case, a static theory
only; the dynamic scenes' pinned set applies a follower torque, which this theory does
not cover).  A dynamic end set names its static ends in ``Ends.static``; a user's set
whose critical twist is known only numerically adds a :class:`StaticEnds` with its own
``solver`` to :data:`STATIC_ENDS`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache

import mpmath
import numpy as np
import scipy.linalg
import scipy.optimize

from ..model.rod import Rod

__all__ = [
    "M_CRI_MP",
    "m_cri",
    "STATIC_ENDS",
    "StaticEnds",
    "critical_moment",
    "critical_twist",
    "critical_twist_transfer",
    "checked_tension",
    "greenhill_clamped",
    "greenhill_pinned",
    "euler_load",
]


def _m_cri(digits: int = 40) -> mpmath.mpf:
    """Smallest nonzero root of tan(pi m) = pi m (between 1 and 3/2)."""
    with mpmath.workdps(digits):
        return mpmath.findroot(
            lambda m: mpmath.sin(mpmath.pi * m) - mpmath.pi * m * mpmath.cos(mpmath.pi * m),
            mpmath.mpf("1.43"),
        )


#: the nondimensional critical moment of eq (31), to 40 digits (mpmath)
M_CRI_MP = _m_cri()
#: the nondimensional critical moment of eq (31), m_cri = 1.4303 (the smallest nonzero
#: root of tan(pi m) = pi m), as a float: :data:`M_CRI_MP` rounded
m_cri = float(M_CRI_MP)


def checked_tension(rod: Rod, tension: float, ends: str) -> float:
    """The axial load ``tension`` [N] as a float, after the checks every route shares:
    ``rod`` a :class:`~dyntorsion.model.rod.Rod`, ``ends`` a name of :data:`STATIC_ENDS`,
    ``tension`` finite and no compression at or beyond the Euler load of these ends
    (TypeError or ValueError naming the parameter)."""
    if not isinstance(rod, Rod):
        raise TypeError(f"rod={rod!r} must be a Rod")
    _check_name(ends)
    if isinstance(tension, bool) or not isinstance(tension, int | float | np.floating | np.integer):
        raise TypeError(f"tension={tension!r} must be a real number [N]")
    T = float(tension)
    if not math.isfinite(T):
        raise ValueError(f"tension={tension!r} must be finite")
    if -T >= euler_load(rod, ends):
        raise ValueError(
            f"tension={T!r} N is a compression at or beyond the Euler load "
            f"{euler_load(rod, ends):.6g} N ({ends} ends): the straight rod buckles without twist"
        )
    return T


def euler_load(rod: Rod, ends: str = "clamped") -> float:
    """The compressive load [N] at which the untwisted rod buckles: 4 pi^2 B/L^2 (clamped),
    pi^2 B/L^2 (pinned), B = min(B1, B2)."""
    _check_name(ends)
    return STATIC_ENDS[ends].euler_factor * math.pi**2 * rod.B / rod.L**2


def greenhill_pinned(B: float, L: float, tension: float = 0.0) -> float:
    """Critical twisting moment of the isotropic pinned rod under an axial torque:
    M^2/(4 B^2) - T/B = (pi/L)^2 (T > 0 tension), i.e. M = 2 B sqrt((pi/L)^2 + T/B)."""
    with mpmath.workdps(40):
        B_, L_, T_ = mpmath.mpf(B), mpmath.mpf(L), mpmath.mpf(tension)
        return float(2 * B_ * mpmath.sqrt((mpmath.pi / L_) ** 2 + T_ / B_))


#: the longest rod, in tension lengths L sqrt(T / B), whose critical moment is scanned for
TENSION_LENGTHS = 1e4


def greenhill_clamped(B: float, L: float, tension: float = 0.0, digits: int = 40) -> float:
    """Critical twisting moment of the isotropic clamped rod (Greenhill's determinant).

    T = 0: eq (31), M = 2 pi B m_cri / L.  Otherwise the smallest M > 0 at which
    det[w(0), w'(0), w(L), w'(L)] of w = c1 + c2 s + c3 e^{l+ s} + c4 e^{l- s},
    l+- = (i M +- d)/(2B), d = sqrt(4 B T - M^2), vanishes.  The determinant times
    e^{-i M L/(2B)}/d is real, so its first sign change brackets the root (mpmath).

    The scan runs over 0.05 B/L <= M <= max(40, 2.5 lam + 10) B/L, lam = L sqrt(T/B) the
    rod's length in tension lengths (M L / B tends to 2 lam from above), in steps of
    0.05 B/L."""
    if tension == 0.0:
        return 2 * math.pi * B * m_cri / L
    if not L * math.sqrt(max(tension, 0.0) / B) <= TENSION_LENGTHS:
        raise ValueError(
            f"tension={tension:g} N makes the rod {L * math.sqrt(max(tension, 0.0) / B):.3g} "
            f"tension lengths sqrt(B/T) long; allowed range: at most {TENSION_LENGTHS:g} "
            f"(tension <= {TENSION_LENGTHS**2 * B / L**2:.3g} N), the reach of the scan of "
            "Greenhill's determinant"
        )
    with mpmath.workdps(digits):
        B_, L_, T_ = mpmath.mpf(B), mpmath.mpf(L), mpmath.mpf(tension)

        def g(M):
            d = mpmath.sqrt(4 * B_ * T_ - M**2 + 0j)
            lp, lm = (1j * M + d) / (2 * B_), (1j * M - d) / (2 * B_)
            ep, em = mpmath.exp(lp * L_), mpmath.exp(lm * L_)
            A = mpmath.matrix(
                [[1, 0, 1, 1], [0, 1, lp, lm], [1, L_, ep, em], [0, 1, lp * ep, lm * em]]
            )
            v = mpmath.det(A) * mpmath.exp(-1j * M * L_ / (2 * B_)) / d
            return v.real + v.imag  # one of the two is zero to working precision

        scale = B_ / L_
        # M L / B of a clamped rod L sqrt(T/B) = lam tension lengths long tends to 2 lam from
        # above: beyond 40 the scan goes on in the same steps up to 2.5 lam + 10
        top = max(40.0, 2.5 * L * math.sqrt(max(tension, 0.0) / B) + 10.0)
        xs = np.linspace(0.05, 40.0, 800)
        step = xs[1] - xs[0]
        xs = np.concatenate(
            [xs, 40.0 + step * np.arange(1, int(math.ceil((top - 40.0) / step)) + 1)]
        )
        grid = [scale * mpmath.mpf(x) for x in xs]
        prev = g(grid[0])
        for lo, hi in zip(grid[:-1], grid[1:], strict=True):
            cur = g(hi)
            if mpmath.sign(cur) != mpmath.sign(prev):
                root = mpmath.findroot(g, (lo, hi), solver="anderson")
                return float(root)
            prev = cur
    raise ValueError(f"no critical moment found below {top:.4g} B/L (tension={tension})")


# ---------------------------------------------------------------- transfer matrix
def _system_matrix(b1: float, b2: float, m: float, kappa: float, t: float) -> np.ndarray:
    """z' = A z for z = (phi1, phi2, phi1', phi2', n1, n2, q1, q2), nondimensional
    (length L, stiffness B): b1, b2 = B1/B, B2/B; m = M L/B; kappa L; t = T L^2/B."""
    A = np.zeros((8, 8))
    A[0, 2] = A[1, 3] = 1.0
    # k1 = phi1' - kappa phi2, k2 = phi2' + kappa phi1; phi1'' = k1' + kappa phi2'
    # B1 k1' = n2 - (m - kappa b2) k2 ;  B2 k2' = (m - kappa b1) k1 - n1 ;  phi2'' = k2' - kappa phi1'
    k1 = np.array([0.0, -kappa, 1.0, 0.0, 0, 0, 0, 0])
    k2 = np.array([kappa, 0.0, 0.0, 1.0, 0, 0, 0, 0])
    n1, n2 = np.eye(8)[4], np.eye(8)[5]
    k1p = (n2 - (m - kappa * b2) * k2) / b1
    k2p = ((m - kappa * b1) * k1 - n1) / b2
    A[2] = k1p + kappa * np.eye(8)[3]
    A[3] = k2p - kappa * np.eye(8)[2]
    A[4] = kappa * n2 - t * k2
    A[5] = -kappa * n1 + t * k1
    A[6] = np.eye(8)[1] + kappa * np.eye(8)[7]
    A[7] = -np.eye(8)[0] - kappa * np.eye(8)[6]
    return A


@dataclass(frozen=True)
class StaticEnds:
    """End conditions of the static theory: ``tangent_held`` (clamped) or the end moment
    axial (pinned), the Euler load's factor (4 clamped, 1 pinned: P = factor pi^2 B/L^2),
    the isotropic closed form of the critical moment (``greenhill``, (B, L, T) -> M) and,
    for a set known only numerically, ``solver`` ((rod, T) -> kappa_cri [1/m]), which
    :func:`critical_twist` then calls instead."""

    tangent_held: bool
    euler_factor: float
    greenhill: Callable[[float, float, float], float] | None
    solver: Callable[[Rod, float], float] | None = None
    description: str = ""

    @property
    def route(self) -> str:
        """How its critical twist is found: ``"closed form"`` or ``"numerical"``."""
        return "numerical" if self.solver is not None else "closed form"


#: the end conditions the static theory covers, by the name an ``Ends.static`` gives
STATIC_ENDS: dict[str, StaticEnds] = {
    "clamped": StaticEnds(True, 4.0, greenhill_clamped, description="eq (30): clamped"),
    "pinned": StaticEnds(False, 1.0, greenhill_pinned, description="pinned, axial torque"),
}


def _check_name(ends: str) -> None:
    if ends not in STATIC_ENDS:
        raise ValueError(
            f"ends={ends!r}: the static theory covers {', '.join(map(repr, STATIC_ENDS))} "
            "only (a dynamic end set without a static critical twist needs an explicit t_end)"
        )


def _end_rows(ends: str, b1: float, b2: float, m: float, kappa: float) -> np.ndarray:
    rows = np.zeros((4, 8))
    rows[0, 6] = rows[1, 7] = 1.0  # q = 0: position held
    if STATIC_ENDS[ends].tangent_held:
        rows[2, 0] = rows[3, 1] = 1.0  # phi1 = phi2 = 0: tangent held
    else:  # pinned, axial torque: B1 k1 + M phi2 = 0, B2 k2 - M phi1 = 0
        rows[2] = b1 * np.array([0, -kappa, 1, 0, 0, 0, 0, 0]) + m * np.eye(8)[1]
        rows[3] = b2 * np.array([kappa, 0, 0, 1, 0, 0, 0, 0]) - m * np.eye(8)[0]
    return rows


def _end_matrix(rod: Rod, tension: float, ends: str, kappa_L: float, d=None) -> np.ndarray:
    """The 8 x 8 matrix of the end conditions at s = 0 and s = L (z(L) = expm(A L) z(0)),
    in balanced variables z = D x: A's entries reach (B2/B1) (kappa L)^2 for a flat
    section, so expm(A) is formed as D expm(D^-1 A D) D^-1 with the diagonal D of
    :func:`scipy.linalg.matrix_balance` (powers of 2; computed at this twist unless ``d``
    is given) and the columns are taken times D: det = det(unbalanced) * prod(d), the same
    sign, and a smooth function of the twist for a fixed ``d``."""
    B = rod.B
    b1, b2 = rod.B1 / B, rod.B2 / B
    m = rod.C * kappa_L / B
    t = tension * rod.L**2 / B
    rows = _end_rows(ends, b1, b2, m, kappa_L)
    A = _system_matrix(b1, b2, m, kappa_L, t)
    if d is None:
        d = _balance(A)
    P = scipy.linalg.expm(A * d[None, :] / d[:, None])
    rows = rows * d[None, :]
    return np.vstack([rows, rows @ P])


def _balance(A: np.ndarray) -> np.ndarray:
    return scipy.linalg.matrix_balance(A, permute=False, separate=True)[1][0]


def _balance_at(rod: Rod, tension: float, ends: str, kappa_L: float) -> np.ndarray:
    B = rod.B
    m, t = rod.C * kappa_L / B, tension * rod.L**2 / B
    return _balance(_system_matrix(rod.B1 / B, rod.B2 / B, m, kappa_L, t))


def _smallness(M: np.ndarray) -> float:
    """sigma_min / sigma_max of M with unit rows (0 at a root; scale-free)."""
    s = np.linalg.svd(M / np.linalg.norm(M, axis=1, keepdims=True), compute_uv=False)
    return float(s[-1] / s[0])


#: ratio of successive twists of the scan: the first root is separated from the next by
#: far more (the modes of a rod), a close pair near the isotropic rod is found inside one
SCAN_RATIO = 1.01


def critical_twist_transfer(rod: Rod, tension: float = 0.0, ends: str = "clamped") -> float:
    """kappa_cri [1/m] of any section (B1, B2) by the body-frame transfer matrix (module
    docstring): the first twist at which the end-condition matrix is singular.  A scan in
    twists of ratio :data:`SCAN_RATIO` watches the sign of the determinant (balanced, see
    :func:`_end_matrix`) and the local minima of sigma_min/sigma_max; a sign change is a
    simple root, a minimum without one may hold a close pair (a nearly isotropic section
    splits the isotropic double root), found as the dip of the determinant below zero
    between its neighbours; the lowest root is refined by Brent's method to 1e-15."""
    T = checked_tension(rod, tension, ends)
    iso = STATIC_ENDS[ends].greenhill
    guess = iso(rod.B, rod.L, T) * rod.L / rod.C  # isotropic twist with the weaker B, times L
    top = guess * 3.0 * max(rod.B1, rod.B2) / rod.B
    ks, signs, small = [], [], []
    k = guess * 0.05
    while k < top:
        M = _end_matrix(rod, T, ends, k)
        ks.append(k)
        signs.append(np.linalg.slogdet(M)[0])
        small.append(_smallness(M))
        i = len(ks) - 1
        if i >= 1 and signs[i] != signs[i - 1] and signs[i] != 0:
            return _refine(rod, T, ends, ks[i - 1], ks[i]) / rod.L
        if i >= 2 and small[i - 1] <= min(small[i - 2], small[i]):
            root = _close_pair(rod, T, ends, ks[i - 2], ks[i - 1], ks[i])
            if root is not None:
                return root / rod.L
        k *= SCAN_RATIO
    raise ValueError(f"no critical twist found below {top / rod.L:.4g} 1/m")


def _signed(rod: Rod, T: float, ends: str, mid: float):
    d = _balance_at(rod, T, ends, mid)
    return lambda x: float(np.linalg.det(_end_matrix(rod, T, ends, x, d)))


def _refine(rod: Rod, T: float, ends: str, lo: float, hi: float) -> float:
    """The root of the determinant in [lo, hi] (a sign change), by Brent's method."""
    f = _signed(rod, T, ends, 0.5 * (lo + hi))
    return float(scipy.optimize.brentq(f, lo, hi, xtol=1e-15 * hi, rtol=1e-15))


def _close_pair(rod: Rod, T: float, ends: str, lo: float, mid: float, hi: float):
    """The lower root of a pair inside [lo, hi] (no sign change at the ends), or None:
    the determinant's extremum between them, if it crosses zero, separates the pair; if it
    touches zero (sigma_min / sigma_max below :data:`DOUBLE_ROOT`) it is a double root,
    the isotropic rod's."""
    f = _signed(rod, T, ends, mid)
    sign = np.sign(f(lo))
    k, v = _golden(lambda x: sign * f(x), lo, hi)
    if v >= 0.0:
        return k if _smallness(_end_matrix(rod, T, ends, k)) < DOUBLE_ROOT else None
    return float(scipy.optimize.brentq(f, lo, k, xtol=1e-15 * k, rtol=1e-15))


#: sigma_min / sigma_max at an extremum of the determinant that counts as a double root
DOUBLE_ROOT = 1e-9


def _golden(f, lo: float, hi: float, rtol: float = 1e-14) -> tuple[float, float]:
    """Minimum of a unimodal f on [lo, hi] by golden-section search."""
    g = (math.sqrt(5.0) - 1.0) / 2.0
    a, b = lo, hi
    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = f(c), f(d)
    while b - a > rtol * abs(b):
        if fc < fd:
            b, d, fd = d, c, fc
            c = b - g * (b - a)
            fc = f(c)
        else:
            a, c, fc = c, d, fd
            d = a + g * (b - a)
            fd = f(d)
    return (c, fc) if fc < fd else (d, fd)


# ---------------------------------------------------------------- the public answer
@lru_cache(maxsize=256)
def critical_twist(rod: Rod, tension: float = 0.0, ends: str = "clamped") -> float:
    """kappa_cri = M_cri / C [1/m]: 11.2335 for Table 1 (eq 32).

    Isotropic sections use the closed forms (eq 31 with T = 0; Greenhill's clamped
    determinant or the pinned formula otherwise); B1 != B2 uses the body-frame transfer
    matrix.  ``tension`` [N] is the axial load (positive = tension); ``ends`` is
    ``"clamped"`` (eq 30) or ``"pinned"`` (axial torque).  Other end sets, and
    compressions at or beyond the Euler load, raise :class:`ValueError`."""
    T = checked_tension(rod, tension, ends)
    if STATIC_ENDS[ends].solver is not None:
        return float(STATIC_ENDS[ends].solver(rod, T))
    if not rod.isotropic:
        return critical_twist_transfer(rod, T, ends)
    return critical_moment(rod, T, ends) / rod.C


def critical_moment(rod: Rod, tension: float = 0.0, ends: str = "clamped") -> float:
    """M_cri [N m] of an isotropic rod: 2 pi E I1 m_cri / L (eq 31) for clamped ends without
    load, Greenhill's closed forms otherwise (see :func:`critical_twist`)."""
    T = checked_tension(rod, tension, ends)
    if not rod.isotropic:
        return critical_twist(rod, T, ends) * rod.C
    if not STATIC_ENDS[ends].tangent_held:
        return STATIC_ENDS[ends].greenhill(rod.B1, rod.L, T)
    if T == 0.0 and rod.E is not None:
        return 2 * math.pi * rod.E * rod.I1 * m_cri / rod.L  # eq (31) as written
    return greenhill_clamped(rod.B1, rod.L, T)
