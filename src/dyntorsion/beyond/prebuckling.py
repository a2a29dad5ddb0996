"""The base state of the linear theory: the straight rod's twist, spin and twist angle while
it is twisted at one end (section 5, eq 23-25), about which :mod:`.linear_stability`
linearises the lateral motion."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..model.rod import Rod

__all__ = ["Prebuckling"]


@dataclass(frozen=True)
class Prebuckling:
    """The straight rod's twist, spin and twist angle in the buckling scene (section 5).

    kappa3(0, t) = kappa0 + a t, omega3(L, t) = 0, at rest with kappa3 = kappa0 at
    t = 0 (eq 23).  The solution is the quasi-static ramp kappa0 + a t,
    omega3 = -a (L - s) plus (``waves=True``) the free oscillation left by the
    mismatch of the initial and boundary rates: with k_n = (2n - 1) pi / (2L) and
    b_n = -2 a / (L c k_n^2)::

        kappa3 += sum b_n sin(k_n s) sin(k_n c t),
        omega3 += -c sum b_n cos(k_n s) cos(k_n c t),

    the first ``terms`` terms (the series of eq 25).  ``spin=False`` drops omega3
    (and its rate) altogether: the twist imposed through the whole rod without
    the rotation that carries it, a contrast, not a motion of a real rod.
    """

    rod: Rod
    a: float
    kappa0: float = 10.0
    waves: bool = True
    spin: bool = True
    terms: int = 400

    def __post_init__(self) -> None:
        if not (math.isfinite(self.a) and self.a > 0):
            raise ValueError(f"a={self.a!r} must be finite and > 0 (the loading rate, rad/(m s))")
        if not math.isfinite(self.kappa0):
            raise ValueError(f"kappa0={self.kappa0!r} must be finite")
        if not (isinstance(self.terms, int) and self.terms >= 1):
            raise ValueError(f"terms={self.terms!r} must be an integer >= 1")

    @property
    def wave_numbers(self) -> np.ndarray:
        """k_n = (2n - 1) pi / (2 L), n = 1..terms: the torsional modes kept [1/m]."""
        return (2 * np.arange(1, self.terms + 1) - 1) * np.pi / (2 * self.rod.L)

    def __call__(self, s: np.ndarray, t: float) -> tuple[np.ndarray, ...]:
        """(kappa3, omega3, omega3_t, theta) at the points s and the time t."""
        return self.at(s)(t)

    def at(self, s: np.ndarray):
        """A function t -> (kappa3, omega3, omega3_t, theta) at the fixed points s (the
        spatial factors of the series are computed once)."""
        L, a, c, kappa0 = self.rod.L, self.a, self.rod.c, self.kappa0
        s = np.asarray(s, dtype=float)
        zero = np.zeros_like(s)
        k = self.wave_numbers
        b = -2 * a / (L * c * k**2)
        if self.waves:
            sin_s, cos_s = np.sin(np.outer(s, k)), np.cos(np.outer(s, k))

        def state(t: float) -> tuple[np.ndarray, ...]:
            kappa = np.full_like(s, kappa0 + a * t)
            omega = -a * (L - s)
            omega_t = zero
            theta = -(kappa0 + a * t) * (L - s)
            if self.waves:
                sin_t, cos_t = np.sin(k * c * t), np.cos(k * c * t)
                kappa = kappa + sin_s @ (b * sin_t)
                omega = omega - c * cos_s @ (b * cos_t)
                omega_t = c**2 * cos_s @ (b * k * sin_t)
                theta = theta - cos_s @ (b / k * sin_t)
            if not self.spin:
                omega, omega_t = zero, zero
            return kappa, omega, omega_t, theta

        return state
