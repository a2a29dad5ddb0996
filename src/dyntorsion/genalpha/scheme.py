"""The parameters of the generalised-alpha scheme (eq 13) and the constants of one step."""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import NamedTuple

__all__ = ["parameters", "QUADRATURES", "SchemeWarning", "Scheme", "Coefficients"]


def parameters(lam: float) -> tuple[float, float, float]:
    """alpha, beta, gamma of eq (13) for a spectral radius at infinity lambda in [-1, 0].

    lambda = -1: alpha = beta = gamma = 1/2 (no numerical damping, the paper's choice);
    lambda = 0: the high-frequency limit is annihilated (alpha = -1/2, beta = 0, gamma = 1).
    """
    lam = float(lam)
    if not (math.isfinite(lam) and -1.0 <= lam <= 0.0):
        raise ValueError(f"lambda_inf={lam!r} is outside the allowed range [-1, 0]")
    alpha = (3.0 * lam + 1.0) / (2.0 * lam - 2.0)
    beta = lam / (lam - 1.0)
    gamma = 1.0 / (1.0 - lam)
    return alpha, beta, gamma


QUADRATURES = ("trapezoidal", "midpoint")


class SchemeWarning(UserWarning):
    """A scheme setting that is allowed but known to be unsound (see the docs)."""


class Coefficients(NamedTuple):
    """The scalars of one step of eq (10)-(12) on a grid (ds, dt), for the kernels.

    abar = c_M (y^i - y^{i-1}) + c_A y_t^{i-1} is the time-averaged rate (eq 11 in eq 10).
    """

    c_M: float  # (1 - a_t) / (g_t dt)
    c_A: float  # a_t - (1 - a_t)(1 - g_t) / g_t
    a_s: float
    b_s: float
    b_t: float
    g_t: float
    inv_ds: float
    dt: float
    trapezoidal: bool


@dataclass(frozen=True)
class Scheme:
    """Generalised-alpha parameters in space and time and the load-vector quadrature.

    lam_s, lam_t : spectral radius at infinity in space and in time, each in [-1, 0]
        (eq 13).  The paper uses -1 for both.
    quadrature : "trapezoidal" (eq 9: average of F at the corners; the paper's)
        or "midpoint" (F at the averaged state).
    """

    lam_s: float = -1.0
    lam_t: float = -1.0
    quadrature: str = "trapezoidal"

    def __post_init__(self) -> None:
        for name in ("lam_s", "lam_t"):
            try:
                parameters(getattr(self, name))
            except ValueError as err:
                raise ValueError(f"{name}: {err}") from None
        if self.quadrature not in QUADRATURES:
            raise ValueError(f"quadrature={self.quadrature!r}; allowed: {QUADRATURES}")
        if self.lam_s != -1.0:
            warnings.warn(
                f"lam_s={self.lam_s}: with eq (13) in space the scheme is a theta-method in s "
                "that is only first order and, for the hyperbolic torsion rows, unstable "
                "(spectral radius > 1) and ill-conditioned at small Courant numbers; "
                "lam_s = -1 (the paper's choice) is the sound one",
                SchemeWarning,
                stacklevel=3,
            )

    @property
    def space(self) -> tuple[float, float, float]:
        return parameters(self.lam_s)

    @property
    def time(self) -> tuple[float, float, float]:
        return parameters(self.lam_t)

    def coefficients(self, ds: float, dt: float) -> Coefficients:
        """The constants of one step on the grid (ds, dt)."""
        a_s, b_s, _ = self.space
        a_t, b_t, g_t = self.time
        return Coefficients(
            c_M=(1.0 - a_t) / (g_t * dt),
            c_A=a_t - (1.0 - a_t) * (1.0 - g_t) / g_t,
            a_s=a_s,
            b_s=b_s,
            b_t=b_t,
            g_t=g_t,
            inv_ds=1.0 / ds,
            dt=float(dt),
            trapezoidal=self.quadrature == "trapezoidal",
        )
