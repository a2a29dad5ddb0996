"""Linear stability of the straight, twisted, spinning rod (beyond the paper).

Why does the rod of section 6 buckle late?  Linearise eq (6) about the
prebuckling state of section 5 -- straight, with the twist kappa3(s, t) and the
spin omega3(s, t) -- for the lateral displacement of the centreline,
w = x + i y (lab frame, complex).  The model of :mod:`dyntorsion.model.cosserat` is
inextensible and unshearable, so its linearisation is the Kirchhoff one: with
the bending stiffness B = E I1 (isotropic), the twisting moment M = C kappa3,
the rotary inertias rho I (bending) and rho J (spin), no axial force (n3 = 0 at
s = L) and the seed f (lateral force per length, complex)::

    rho A w_tt - rho I w_tt'' + i rho J (omega3 w_t' + omega3_t w')'
        + B w'''' - i (M w')''  =  f                                   (L1)

(' = d/ds) with w = w' = 0 at s = 0 and s = L (eq 30 in the lateral
directions).  For a uniform, frozen twist and no spin, w = W exp(lambda t) and
lambda^2 changes sign at the static critical twist of eq (32): the static limit
of (L1) is the equation of :func:`~dyntorsion.buckling.chebyshev.critical_twist_numerical`.

Galerkin discretisation: w = sum_j q_j(t) phi_j(s) over the first ``modes``
clamped-clamped beam modes phi_j (real, closed form), and (L1)
multiplied by phi_i and integrated by parts::

    Mr q'' + G(t) q' + (Kb + K_M(t) + K_w(t)) q = F(t)                 (L2)

    Mr_ij  = int rho A phi_i phi_j + rho I phi_i' phi_j'
    Kb_ij  = int B phi_i'' phi_j''
    K_M_ij = -i int M phi_i'' phi_j'
    G_ij   = -i rho J int omega3 phi_i' phi_j'
    K_w_ij = -i rho J int omega3_t phi_i' phi_j'
    F_i    = int phi_i f

The prebuckling state (:class:`Prebuckling`) is that of the buckling scene:
kappa3(0, t) = kappa0 + a t, omega3(L, t) = 0, at rest with kappa3 = kappa0 at
t = 0.  ``waves=True`` takes the exact solution of section 5 (eq 23, a uniform
ramp plus the free torsional oscillation the start of the loading leaves behind);
``waves=False`` the quasi-static twist kappa3 = kappa0 + a t through the whole rod
(with the spin that compatibility requires, omega3 = -a (L - s), unless ``spin``
is off).  The seed of :class:`~dyntorsion.buckling.seed.Perturbation` acts in the body
frame, so in the lab frame it turns with the cross-section:
f = magnitude (e1 + i e2) exp(i theta(s, t)), theta the angle of d1 (d1(L) = e1).

:meth:`LateralModel.passage` integrates (L2) from rest and returns the time at
which the end-shortening speed ``|u3(L, t)| = |d/dt int |w'|^2 / 2 ds|`` first reaches
the onset detector's level u_ref (:func:`~dyntorsion.buckling.onset.detect_onset`): a
prediction of the buckling time with no fitted parameter.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import lru_cache
from typing import NamedTuple

import numpy as np
import scipy.linalg
import scipy.optimize

from ..buckling.onset import reference_level
from ..buckling.seed import SEED_FORMS, STATED, Perturbation, Point, Uniform
from ..buckling.statics import critical_twist
from ..model.rod import Rod
from . import passage as passage_kernel
from .passage import Passage
from .prebuckling import Prebuckling

__all__ = ["Prebuckling", "LateralModel", "PassageSteps", "Passage", "wkb_exponents"]


def _beta(j: int) -> float:
    """The j-th root (j >= 1) of cos(beta) cosh(beta) = 1, written as cos = sech."""
    mid = (j + 0.5) * np.pi
    return float(
        scipy.optimize.brentq(
            lambda b: np.cos(b) - 1.0 / np.cosh(b), mid - 0.5, mid + 0.5, xtol=1e-15, rtol=1e-15
        )
    )


@lru_cache(maxsize=8)
def _beam_modes(modes: int, quadrature: int) -> tuple[np.ndarray, ...]:
    """The first ``modes`` clamped-clamped beam modes on [0, 1] at the ``quadrature``
    Gauss-Legendre points: (x, weights, phi, d phi/dx, d2 phi/dx2, beta) with
    phi'''' = beta^4 phi and int phi^2 = 1.

    phi = cosh bx - cos bx - sigma (sinh bx - sin bx), sigma = (cosh b - cos b) /
    (sinh b - sin b), evaluated as (1 + sigma)/2 e^{-bx} + (1 - sigma)/2 e^{bx}
    - cos bx + sigma sin bx with 1 - sigma in a form that does not cancel.
    """
    g, gw = np.polynomial.legendre.leggauss(quadrature)
    x, w = (g + 1.0) / 2.0, gw / 2.0
    phi, d1, d2 = (np.empty((x.size, modes)) for _ in range(3))
    betas = np.array([_beta(j) for j in range(1, modes + 1)])
    for j, b in enumerate(betas):
        e = math.exp(-b)
        # (1 - sigma) / 2 = e^{-b} r, so (1 - sigma)/2 e^{bx} = r e^{b(x - 1)}
        r = (-e - math.sin(b) + math.cos(b)) / (1.0 - e * e - 2.0 * math.sin(b) * e)
        sigma = 1.0 - 2.0 * e * r
        lo = (1.0 + sigma) / 2.0 * np.exp(-b * x)
        hi = r * np.exp(b * (x - 1.0))
        c, s = np.cos(b * x), np.sin(b * x)
        phi[:, j] = lo + hi - c + sigma * s
        d1[:, j] = b * (-lo + hi + s + sigma * c)
        d2[:, j] = b * b * (lo + hi + c - sigma * s)
    norm = np.sqrt(w @ phi**2)
    return x, w, phi / norm, d1 / norm, d2 / norm, betas


# ======================================================================= the lateral model
class PassageSteps(NamedTuple):
    """How :meth:`LateralModel.passage` integrates: until ``t_end`` [s], or until
    ``|u3(L)|`` reaches ``u_ref`` [m/s], in steps ``dt`` [s], keeping ``samples`` levels;
    None chooses the default (see the method)."""

    t_end: float | None = None
    u_ref: float | None = None
    dt: float | None = None
    samples: int = 2000


@dataclass(frozen=True)
class LateralModel:
    """Eq (L2) of the module docstring: the Galerkin model of (L1).

    ``modes`` clamped-clamped beam modes, integrals by Gauss-Legendre quadrature on
    ``quadrature`` points.  ``rotary_inertia=False`` drops rho I; ``gyro=False``
    drops both spin terms (rho J omega3).
    """

    rod: Rod = field(default_factory=Rod)
    modes: int = 16
    quadrature: int = 128
    rotary_inertia: bool = True
    gyro: bool = True

    def __post_init__(self) -> None:
        if not (isinstance(self.modes, int) and 1 <= self.modes <= 60):
            raise ValueError(f"modes={self.modes!r} must be an integer in [1, 60]")
        if not (isinstance(self.quadrature, int) and self.quadrature >= 4 * self.modes + 16):
            raise ValueError(
                f"quadrature={self.quadrature!r} must be an integer >= 4 modes + 16 = "
                f"{4 * self.modes + 16}"
            )
        if not self.rod.isotropic:
            raise ValueError(
                "LateralModel covers isotropic sections (B1 = B2: one complex lateral "
                f"displacement); this rod has B1={self.rod.B1:.6g}, B2={self.rod.B2:.6g}"
            )
        L = self.rod.L
        x, w, phi, dphi, ddphi, _ = _beam_modes(self.modes, self.quadrature)
        sc = {
            "s": x * L,
            "w": w * L,
            "phi": phi / math.sqrt(L),
            "dphi": dphi / L**1.5,
            "ddphi": ddphi / L**2.5,
        }
        for k, v in sc.items():
            object.__setattr__(self, "_" + k, v)
        r = self.rod
        rhoI = r.rotary_inertia[0] if self.rotary_inertia else 0.0
        object.__setattr__(self, "_rhoJ", r.rotary_inertia[2] if self.gyro else 0.0)
        M = r.mass_per_length * self.integral(self._phi, self._phi)
        M = M + rhoI * self.integral(self._dphi, self._dphi)
        object.__setattr__(self, "_M", M)
        object.__setattr__(self, "_Kb", r.B1 * self.integral(self._ddphi, self._ddphi))
        object.__setattr__(self, "_P", self.integral(self._dphi, self._dphi))

    def integral(self, f, g, weight=None) -> np.ndarray:
        """int f_i g_j (times ``weight``) ds over the rod, as a matrix (m, m): ``f``, ``g``
        (and ``weight``) at the quadrature points :attr:`nodes`, one column per mode."""
        w = self._w if weight is None else self._w * weight
        return f.T @ (w[:, None] * g)

    @property
    def nodes(self) -> np.ndarray:
        """The quadrature points s [m] at which the modes are tabulated."""
        return self._s

    @property
    def slopes(self) -> np.ndarray:
        """phi_i'(s) at :attr:`nodes` (points, m) [1/m^1.5]."""
        return self._dphi

    @property
    def curvatures(self) -> np.ndarray:
        """phi_i''(s) at :attr:`nodes` (points, m) [1/m^2.5]."""
        return self._ddphi

    @property
    def mass_matrix(self) -> np.ndarray:
        """Mr = rho A int phi phi + rho I int phi' phi' (m, m) of (L2)."""
        return self._M

    @property
    def bending_stiffness(self) -> np.ndarray:
        """Kb = B int phi'' phi'' (m, m) of (L2)."""
        return self._Kb

    @property
    def u3_matrix(self) -> np.ndarray:
        """P = int phi' phi' (m, m): u3(L) = -Re(q* P q_t)."""
        return self._P

    @property
    def spin_inertia(self) -> float:
        """rho J of the spin terms (0 with ``gyro=False``) [kg m]."""
        return self._rhoJ

    # -------------------------------------------------------------- frozen coefficients
    def stiffness(self, kappa3, omega3_t=0.0) -> np.ndarray:
        """Kb + K_M + K_w (complex, m x m) for a twist kappa3 (scalar or at the nodes)."""
        M = self.rod.C * np.broadcast_to(np.asarray(kappa3, dtype=float), self._s.shape)
        K = self._Kb - 1j * self.integral(self._ddphi, self._dphi, M)
        if self._rhoJ and np.any(omega3_t):
            K = K - 1j * self._rhoJ * self.integral(
                self._dphi, self._dphi, np.broadcast_to(omega3_t, self._s.shape)
            )
        return K

    def gyroscopic(self, omega3) -> np.ndarray:
        """G (complex, skew-Hermitian) for the spin omega3 (scalar or at the nodes)."""
        if not self._rhoJ:
            return np.zeros_like(self._M, dtype=complex)
        return (
            -1j
            * self._rhoJ
            * self.integral(self._dphi, self._dphi, np.broadcast_to(omega3, self._s.shape))
        )

    def spectrum(self, kappa3: float, spin_rate: float = 0.0) -> np.ndarray:
        """The exponents lambda of w = W exp(lambda t) for the frozen twist kappa3 and the
        quasi-static spin omega3 = -spin_rate (L - s), sorted by real part (largest first)."""
        K = self.stiffness(kappa3)
        if spin_rate == 0.0 or not self._rhoJ:
            nu = scipy.linalg.eigh(K, self._M, eigvals_only=True)
            lam = np.sqrt(-nu.astype(complex))
        else:
            G = self.gyroscopic(-spin_rate * (self.rod.L - self._s))
            m = self.modes
            Minv = np.linalg.inv(self._M)
            A = np.block([[np.zeros((m, m)), np.eye(m)], [-Minv @ K, -Minv @ G]])
            lam = np.linalg.eigvals(A)
        return lam[np.argsort(-lam.real)]

    def growth_rate(self, kappa3, spin_rate: float = 0.0) -> np.ndarray | float:
        """Largest real part of the exponents (1/s): > 0 beyond the critical twist."""
        out = np.array([self.spectrum(k, spin_rate)[0].real for k in np.atleast_1d(kappa3)])
        return out if np.ndim(kappa3) else float(out[0])

    def critical_twist(self) -> float:
        """The twist at which the lowest eigenvalue of (Kb + K_M, Mr) crosses zero."""

        def lowest(k):
            return scipy.linalg.eigh(self.stiffness(k), self._M, eigvals_only=True)[0]

        guess = critical_twist(self.rod)
        return float(
            scipy.optimize.brentq(lowest, 0.8 * guess, 1.2 * guess, xtol=1e-14, rtol=1e-15)
        )

    def efold_table(self, top: float, points: int = 801) -> tuple[np.ndarray, np.ndarray]:
        """(kappa, I): I(kappa) = int_{kappa_cri}^{kappa} lambda dkappa of the frozen growth
        rate (no spin) by the trapezoidal rule, on ``points`` twists from kappa_cri to
        ``top`` spaced geometrically in kappa - kappa_cri (down to 1e-6 of the span), where
        lambda ~ (kappa - kappa_cri)^(1/2) varies fastest."""
        kc = self.critical_twist()
        span = max(float(top) - kc, 0.0)
        if span == 0.0:
            return np.array([kc]), np.zeros(1)
        kappa = kc + np.concatenate([[0.0], np.geomspace(1e-6 * span, span, points - 1)])
        lam = np.maximum(self.growth_rate(kappa), 0.0)
        return kappa, np.concatenate(
            [[0.0], np.cumsum(0.5 * np.diff(kappa) * (lam[1:] + lam[:-1]))]
        )

    def efolds(self, a: float, kappa3: np.ndarray) -> np.ndarray:
        """N = int lambda dt = (1/a) int_{kappa_cri}^{kappa3} lambda(kappa) dkappa: the number of
        e-foldings the frozen growth rate (no spin) accumulates up to kappa3 (WKB;
        :meth:`efold_table`)."""
        kappa3 = np.atleast_1d(np.asarray(kappa3, dtype=float))
        kappa, integral = self.efold_table(float(kappa3.max()))
        return np.interp(kappa3, kappa, integral) / a

    # ------------------------------------------------------------------ the slow passage
    def seed_rows(self, seed: Perturbation) -> tuple[np.ndarray, np.ndarray]:
        """The body-frame seed as modal rows R_p at points s_p: F_i = sum_p R_pi
        exp(i theta(s_p)), theta the angle of d1 (quadrature points for a uniform
        seed, the point itself for a point seed)."""
        if not seed.constant:
            raise ValueError(
                f"seed frame={seed.frame!r}, duration={seed.duration!r}: the linear passage "
                "takes a constant seed in the body frame"
            )
        d = np.asarray(seed.direction, dtype=float)
        lateral = (d[0] + 1j * d[1]) * seed.magnitude
        form = SEED_FORMS[seed.form]
        if issubclass(form, Uniform):
            return (self._w * lateral)[:, None] * self._phi, self._s
        if not issubclass(form, Point):
            raise ValueError(
                f"perturbation form={seed.form!r}: the linear passage takes the forms "
                "'uniform' and 'point' only"
            )
        if not 0 <= seed.location <= self.rod.L:
            raise ValueError(
                f"perturbation location={seed.location!r} must lie in [0, L] = [0, {self.rod.L}]"
            )
        phi0 = np.array(
            [np.interp(seed.location, self._s, self._phi[:, j]) for j in range(self.modes)]
        )
        return (phi0 * lateral)[None, :], np.array([float(seed.location)])

    def seed_load(self, seed: Perturbation) -> Callable[[np.ndarray], np.ndarray]:
        """theta -> F_i = int phi_i f ds: the modal load of the body-frame seed for the
        angle theta of d1 at the seed's points (:meth:`seed_rows`)."""
        rows, _ = self.seed_rows(seed)
        return lambda theta: rows.T @ np.exp(1j * np.asarray(theta))

    def passage(
        self,
        a: float,
        kappa0: float = 10.0,
        seed: Perturbation | float = STATED,
        *,
        waves: bool = True,
        spin: bool = True,
        terms: int = 8,
        steps: PassageSteps | None = None,
    ) -> Passage:
        """Integrate (L2) from rest through the instability until ``|u3(L)| = u_ref``.

        Classical Runge-Kutta (order 4) with the fixed step ``steps.dt``; the default is
        0.5 / omega_max, omega_max the largest frequency of (L2) at the twist reached
        at ``t_end``, and with ``waves`` also 1 / omega_T, omega_T = (2 terms - 1) pi c
        / (2 L) the fastest of the ``terms`` torsional modes kept in the prebuckling
        state (:class:`Prebuckling`).  ``steps.u_ref`` defaults to the onset detector's
        L / T0.  ``steps.t_end`` defaults to the time at which the ramp passes kappa_cri
        plus 4 T0 (T0 = L^2 sqrt(rho A / B1)).  The crossing time ``t_ref`` is
        found on the cubic Hermite interpolant of u3 over the step (order 4, like the
        steps); it is nan if u_ref is not reached.  ``steps``: :class:`PassageSteps`
        (default: every field chosen as above, 2000 samples kept).
        """
        t_end, u_ref, dt, samples = steps or PassageSteps()
        if not isinstance(seed, Perturbation):
            seed = Perturbation(magnitude=float(seed))
        base = Prebuckling(self.rod, a, kappa0, waves=waves, spin=spin, terms=terms)
        r = self.rod
        T0 = r.T0
        if u_ref is None:
            u_ref = reference_level(r)
        if not (math.isfinite(u_ref) and u_ref > 0):
            raise ValueError(f"u_ref={u_ref!r} must be finite and > 0")
        if t_end is None:
            t_end = max(0.0, (critical_twist(r) - kappa0) / a) + 4 * T0
        if not (math.isfinite(t_end) and t_end > 0):
            raise ValueError(f"t_end={t_end!r} must be finite and > 0")
        if dt is None:
            nu = scipy.linalg.eigh(self.stiffness(kappa0 + a * t_end), self._M, eigvals_only=True)
            dt = 0.5 / math.sqrt(np.max(np.abs(nu)))
            if waves:
                dt = min(dt, 2 * r.L / ((2 * terms - 1) * math.pi * r.c))
        if not (math.isfinite(dt) and 0 < dt < t_end):
            raise ValueError(f"dt={dt!r} must be finite and in (0, t_end = {t_end})")
        n_steps = int(math.ceil(t_end / dt))
        return passage_kernel.run(self, base, seed, t_end / n_steps, n_steps, samples, u_ref)


def wkb_exponents(
    a: np.ndarray,
    kappa3: np.ndarray,
    rates: np.ndarray,
    table: tuple[np.ndarray, np.ndarray],
    kappa_cri: float | None = None,
) -> tuple[np.ndarray, np.ndarray, float]:
    """The local exponent d ln(kappa3 - kappa_cri) / d ln a of the WKB delay law at
    ``rates``: the e-foldings N = I(kappa3) / a of the onsets (``a``, ``kappa3``) fitted
    as N = n0 + n1 ln a, and kappa3(a) the twist where I = a N(a) (``table`` from
    :meth:`LateralModel.efold_table`).  Returns (exponent, valid, n1), valid where
    N(a) > 1; as a -> 0 the exponent tends to 2/3 (1 + n1 / N), as lambda ~
    (kappa - kappa_cri)^(1/2) past kappa_cri."""
    kappa, integral = table
    kc = float(kappa[0]) if kappa_cri is None else kappa_cri
    a, rates = np.asarray(a, dtype=float), np.asarray(rates, dtype=float)
    n = np.interp(kappa3, kappa, integral) / a
    n1, n0 = np.polyfit(np.log(a), n, 1)
    n_of_a = n0 + n1 * np.log(rates)
    k3 = np.interp(np.maximum(n_of_a, 0.5) * rates, integral, kappa)
    return np.gradient(np.log(k3 - kc), np.log(rates)), n_of_a > 1.0, float(n1)
