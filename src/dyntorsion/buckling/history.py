"""The base of every end history (:class:`History`): kappa3(0, t) [1/m] on an array of
times (moment control, eq 30), or the end's spin w3(0, t) [rad/s] (``quantity = "spin"``,
rotation control).  The histories themselves are in :mod:`.loading` and :mod:`.turning`."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["History", "finite_value"]


def finite_value(name: str, value: Any) -> float:
    """``value`` as a float if it is a finite real number, else a TypeError or ValueError
    naming the parameter ``name``."""
    if isinstance(value, bool) or not isinstance(value, int | float | np.floating | np.integer):
        raise TypeError(f"{name}={value!r} must be a real number")
    x = float(value)
    if not math.isfinite(x):
        raise ValueError(f"{name}={value!r} must be finite")
    return x


_finite = finite_value  # the name loading.py imports


class History:
    """An end-twist history kappa3(0, t) [1/m]: ``h(t)`` on an array of times.
    (``quantity = "spin"``: the end's spin w3(0, t) [rad/s] instead, for rotation control;
    :class:`~dyntorsion.buckling.turning.TurnHold`.)"""

    kind: str = ""
    quantity: str = "twist"

    def __call__(self, t: np.ndarray) -> np.ndarray:
        raise NotImplementedError

    def params(self) -> dict[str, Any]:
        raise NotImplementedError

    @property
    def rate(self) -> float | None:
        """The constant loading rate a of a ramp (eq 33's a), None for other histories."""
        return None

    @property
    def kappa0(self) -> float:
        return float(self(np.zeros(1))[0])

    @property
    def initial_twist(self) -> float:
        """kappa3 of the pretwisted rod at t = 0 [1/m] (the history's own value at 0)."""
        return self.kappa0

    def label(self) -> str:
        return (
            self.kind
            + "("
            + ", ".join(f"{k}={v}" for k, v in self.params().items() if k != "kind")
            + ")"
        )
