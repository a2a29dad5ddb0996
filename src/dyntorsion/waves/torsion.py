"""The reduced model of section 5 (eq 22): kappa3 and omega3 of the straight rod."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .._numba import jacobian_kernel, load_kernel
from ..genalpha import System
from ..model.rod import Rod
from .checks import FIELDS


@load_kernel
def _no_load(y, p, out):
    out[0] = 0.0
    out[1] = 0.0


@jacobian_kernel
def _no_load_jacobian(y, p, out):
    out[:, :] = 0.0


@dataclass(frozen=True)
class Torsion:
    """The reduced torsion model of eq (22) for a rod: y = (kappa, omega).

    Rows:  rho J omega_t - C kappa_s = 0   and   kappa_t - omega_s = 0.
    """

    rod: Rod = field(default_factory=Rod)

    @property
    def mass_matrix(self) -> np.ndarray:
        return np.array([[0.0, self.rod.rotary_inertia[2]], [1.0, 0.0]])

    @property
    def stiffness_matrix(self) -> np.ndarray:
        return np.array([[-self.rod.C, 0.0], [0.0, -1.0]])

    def scales(self) -> tuple[np.ndarray, np.ndarray]:
        r = self.rod
        ys = np.array([1.0 / r.L, r.c / r.L])
        rs = np.array([r.C / r.L**2, r.c / r.L**2])
        return ys, rs

    def system(self) -> System:
        return System.from_model(
            self, names=FIELDS, F=_no_load, dF=_no_load_jacobian, params=np.zeros(1)
        )

    def energy(self, y: np.ndarray, ds: float) -> float:
        """Discrete energy of the box scheme: sum over cells of ds (rhoJ wbar^2 + C kbar^2)/2.

        Bars are cell averages of the two nodes; for lam_s = lam_t = -1 this is
        exactly conserved when no work crosses the ends.
        """
        ybar = 0.5 * (y[1:] + y[:-1])
        r = self.rod
        return float(
            0.5 * ds * np.sum(r.rotary_inertia[2] * ybar[:, 1] ** 2 + r.C * ybar[:, 0] ** 2)
        )
