"""The loads on the rod other than its end twist: the axial end load n3(L, t)
(:class:`EndLoad`; the built-in :class:`AxialLoad` is T + T_rate t) and distributed
forces per length along it (:class:`DistributedLoad`, a source q(s, t) of eq 7).

Each base keeps a registry (:data:`AXIAL_LOADS`, :data:`DISTRIBUTED_LOADS`): a subclass
with a class attribute ``kind`` registers itself when defined, so the store rebuilds it
from its ``params()`` (:func:`load_from_params`, :func:`distributed_from_params`) and the
command line reaches it by its kind (``--load KIND:name=value,...``).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from .history import Registered, finite_value

__all__ = [
    "EndLoad",
    "AxialLoad",
    "AXIAL_LOADS",
    "load_from_params",
    "as_load",
    "DistributedLoad",
    "DISTRIBUTED_LOADS",
    "distributed_from_params",
]

#: the axial end loads by kind (every :class:`EndLoad` subclass with a ``kind``)
AXIAL_LOADS: dict[str, type] = {}
#: the distributed loads by kind (every :class:`DistributedLoad` subclass with a ``kind``)
DISTRIBUTED_LOADS: dict[str, type] = {}


class EndLoad(Registered):
    """The axial force at the far end, n3(L, t) [N] on an array of times (positive =
    tension).  A subclass sets ``kind``, is a frozen dataclass of numbers and defines
    ``__call__``; the initial state carries n3 = n3(L, 0) along the rod."""

    registry: ClassVar[dict[str, type]] = AXIAL_LOADS
    what: ClassVar[str] = "axial load"

    def __call__(self, t: np.ndarray) -> np.ndarray:
        raise NotImplementedError

    @property
    def is_zero(self) -> bool:
        """Whether the force is 0 at every time (then a set holding u3 at s = L takes it)."""
        return False

    @property
    def constant(self) -> float | None:
        """The force [N] when it does not change in time (the static theory's T), else None."""
        return None


@dataclass(frozen=True)
class AxialLoad(EndLoad):
    """Axial force at the far end, n3(L, t) = T + T_rate t [N]; positive = tension.

    The initial state carries n3 = T along the whole rod (the straight rod under an
    axial force T is in equilibrium), so a constant load starts without a jolt.  Its key
    holds no ``kind`` (the keys of every scene keyed before the registry stay as they were)."""

    T: float = 0.0
    T_rate: float = 0.0
    kind = "linear"

    def __post_init__(self) -> None:
        object.__setattr__(self, "T", finite_value("tension T", self.T))
        object.__setattr__(self, "T_rate", finite_value("tension rate T_rate", self.T_rate))

    def __call__(self, t):
        return self.T + self.T_rate * np.asarray(t, dtype=float)

    @property
    def is_zero(self) -> bool:
        return self.T == 0.0 and self.T_rate == 0.0

    @property
    def constant(self) -> float | None:
        return self.T if self.T_rate == 0.0 else None

    def params(self) -> dict[str, Any]:
        return {"T": self.T, "T_rate": self.T_rate}

    def label(self) -> str:
        """``T=.. T_rate=..`` (the non-zero ones; "" for no load)."""
        return " ".join(f"{k}={v:g}" for k, v in (("T", self.T), ("T_rate", self.T_rate)) if v)


def load_from_params(p: Mapping[str, Any]) -> EndLoad:
    """The axial load of a cache key (no ``kind``: :class:`AxialLoad`)."""
    return EndLoad.lookup(p.get("kind", AxialLoad.kind)).from_params(p)


def as_load(tension: Any) -> EndLoad:
    """An :class:`EndLoad` as it is, a number T [N] as ``AxialLoad(T)``."""
    if isinstance(tension, EndLoad):
        return tension
    return AxialLoad(T=tension)


class DistributedLoad(Registered):
    """A force per length along the rod [N/m] in the body frame, f(s, t) at the nodes s
    (N+1,) at one time t: :meth:`force` returns (N+1, 3).  It enters eq (7) as a source
    beside the seed.  A subclass sets ``kind``, is a frozen dataclass of numbers and
    defines :meth:`force`; a force that depends on the rod's state needs the engine's
    state-dependent sources and is not expressible here."""

    registry: ClassVar[dict[str, type]] = DISTRIBUTED_LOADS
    what: ClassVar[str] = "distributed load"

    def force(self, s: np.ndarray, t: float, length: float) -> np.ndarray:
        raise NotImplementedError


def distributed_from_params(p: Mapping[str, Any]) -> DistributedLoad:
    """The distributed load of a cache key, by its registered ``kind``."""
    return DistributedLoad.lookup(p.get("kind")).from_params(p)
