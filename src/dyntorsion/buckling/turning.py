"""Rotation control: the end s = 0 turned by a prescribed angle instead of loaded by a
prescribed twist (the ends ``"clamped-turned"`` of :mod:`dyntorsion.model.ends`, which
prescribe w3(0, t) where eq 30 prescribes kappa3(0, t)).

:class:`TurnHold` turns the end by ``turns`` full turns in ``t_turn`` seconds at a constant
rate Omega = 2 pi turns / t_turn and then holds it, both corners rounded by section 5's
transition f(x) = exp(-x^4) (eq 28) over ``tau``:

    omega(t) = Omega (1 - exp(-(t / tau)^4))       for t <  t_turn,
    omega(t) = Omega exp(-((t - t_turn) / tau)^4)   for t >= t_turn,

so the spin starts from rest with its first three time derivatives 0 (no clash of the
initial and boundary conditions, section 4) and the end's angle reaches exactly
2 pi turns (the lag at the start, Omega tau Gamma(5/4), is made up after t_turn).  The
value prescribed is w3(0, t) = -omega(t): by the compatibility equation (eq 7,
k_t = w_s + k x w) turning s = 0 that way against a far end held in rotation raises the
twist, so positive ``turns`` twist the rod as the paper's positive kappa3 does, and the
link grows by ``turns`` (Lk = Lk0 + (theta_L - theta_R) / 2 pi with theta = -integral w3).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.special import gamma, gammainc

from .history import History, finite_value

__all__ = ["TurnHold"]

_G54 = gamma(1.25)


@dataclass(frozen=True)
class TurnHold(History):
    """Turn s = 0 by ``turns`` in ``t_turn`` [s] and hold (module docstring); ``tau`` [s] the
    rounding of both corners, 0 < tau <= t_turn / 4; ``pretwist`` [1/m] the rod's uniform
    twist at t = 0 (the pretwisted start; 0 = the unstressed rod)."""

    turns: float
    t_turn: float
    tau: float = 0.1
    pretwist: float = 0.0
    kind = "turn-hold"
    quantity = "spin"

    def __post_init__(self) -> None:
        for name in ("turns", "t_turn", "tau", "pretwist"):
            object.__setattr__(self, name, finite_value(name, getattr(self, name)))
        if self.turns == 0.0:
            raise ValueError("turn-hold turns=0: give a non-zero number of turns")
        if not self.t_turn > 0:
            raise ValueError(f"turn-hold t_turn={self.t_turn!r} must be > 0 s")
        if not math.isfinite(self.spin_rate):
            raise ValueError(
                f"turn-hold turns={self.turns!r} in t_turn={self.t_turn!r} s: the spin "
                "2 pi turns / t_turn overflows; give fewer turns or a longer t_turn"
            )
        if not 0 < self.tau <= self.t_turn / 4:
            raise ValueError(
                f"turn-hold tau={self.tau!r} must be > 0 and <= t_turn / 4 = {self.t_turn / 4:g} s"
            )

    @property
    def spin_rate(self) -> float:
        """Omega = 2 pi turns / t_turn [rad/s]."""
        return 2.0 * math.pi * self.turns / self.t_turn

    def __call__(self, t):
        t = np.asarray(t, dtype=float)
        cap = 1e10 * self.tau  # exp(-x^4) is 0 to the last bit past x = 1e10; x**4 stays finite
        x = np.clip(t, 0.0, cap) / self.tau
        y = np.clip(t - self.t_turn, 0.0, cap) / self.tau
        on = t < self.t_turn
        omega = np.where(on, -np.expm1(-(x**4)), np.exp(-(y**4)))
        return -self.spin_rate * omega

    def angle(self, t) -> np.ndarray:
        """The end's angle theta(t) [rad] the spin has turned it by, the integral of omega
        (closed form: int_0^y exp(-x^4) dx = Gamma(5/4) P(1/4, y^4))."""
        t = np.asarray(t, dtype=float)
        lag = lambda z: self.tau * _G54 * gammainc(0.25, np.maximum(z, 0.0) ** 4)  # noqa: E731
        before = t - lag(t / self.tau)
        after = self.t_turn - lag(self.t_turn / self.tau) + lag((t - self.t_turn) / self.tau)
        return self.spin_rate * np.where(t < self.t_turn, np.maximum(before, 0.0), after)

    @property
    def kappa0(self) -> float:
        return self.pretwist

    @property
    def initial_twist(self) -> float:
        return self.pretwist

    def params(self) -> dict[str, Any]:
        return {
            "kind": "turn-hold",
            "turns": self.turns,
            "t_turn": self.t_turn,
            "tau": self.tau,
            "pretwist": self.pretwist,
        }
