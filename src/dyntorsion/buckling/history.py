"""The base of every end history (:class:`History`): kappa3(0, t) [1/m] on an array of
times (moment control, eq 30), or the end's spin w3(0, t) [rad/s] (``quantity = "spin"``,
rotation control).  The histories themselves are in :mod:`.loading` and :mod:`.turning`.

A subclass with a class attribute ``kind`` registers itself in :data:`HISTORIES` when it
is defined (the registries of py-pde's boundary conditions): the store rebuilds it from
its ``params()`` (:func:`history_from_params`) and the command line reaches it by its
kind, in a user's own file as in the package."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from typing import Any, ClassVar

import numpy as np

__all__ = ["History", "HISTORIES", "history_from_params", "Registered", "finite_value"]


def finite_value(name: str, value: Any) -> float:
    """``value`` as a float if it is a finite real number, else a TypeError or ValueError
    naming the parameter ``name``."""
    if isinstance(value, bool) or not isinstance(value, int | float | np.floating | np.integer):
        raise TypeError(f"{name}={value!r} must be a real number")
    x = float(value)
    if not math.isfinite(x):
        raise ValueError(f"{name}={value!r} must be finite")
    return x


class Registered:
    """A base whose subclasses with a class attribute ``kind`` register themselves in the
    base's ``registry`` when defined (``__init_subclass__``).

    A base declares ``registry: ClassVar[dict[str, type]] = {}`` and ``what`` (its name in
    messages).  A kind defined again (a user's file imported twice) replaces the earlier
    class.  :meth:`from_params` rebuilds an object of a dataclass subclass from its
    ``params()`` (``kind`` and the constructor's keywords; lists become tuples); a
    subclass whose parameters are not its fields overrides it."""

    registry: ClassVar[dict[str, type]] = {}
    what: ClassVar[str] = "object"
    kind: ClassVar[str] = ""

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        kind = cls.__dict__.get("kind")
        if kind:
            if not isinstance(kind, str):
                raise TypeError(f"{cls.__qualname__}.kind={kind!r} must be a string")
            cls.registry[kind] = cls

    @classmethod
    def lookup(cls, kind: Any) -> type:
        """The registered class of ``kind``; ValueError naming the registered kinds."""
        try:
            return cls.registry[kind]
        except (KeyError, TypeError):
            raise ValueError(
                f"{cls.what} kind={kind!r}; registered: {', '.join(sorted(cls.registry))} "
                "(a subclass with a class attribute kind registers itself when defined)"
            ) from None

    @classmethod
    def from_params(cls, params: Mapping[str, Any]) -> Any:
        """The object of ``params`` (its ``params()``, ``kind`` included or not)."""
        q = {k: tuple(v) if isinstance(v, list) else v for k, v in params.items() if k != "kind"}
        return cls(**q)

    def label(self) -> str:
        """``kind(name=value, ...)`` of the parameters."""
        return (
            self.kind
            + "("
            + ", ".join(f"{k}={v}" for k, v in self.params().items() if k != "kind")
            + ")"
        )

    def params(self) -> dict[str, Any]:
        """``kind`` and the dataclass fields (a subclass that is no dataclass overrides)."""
        if not dataclasses.is_dataclass(self):
            raise NotImplementedError(f"{type(self).__qualname__} must define params()")
        fields = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}
        return {"kind": self.kind, **{k: list(v) if isinstance(v, tuple) else v
                                      for k, v in fields.items()}}  # fmt: skip


#: the end histories by kind (every :class:`History` subclass with a ``kind``)
HISTORIES: dict[str, type[History]] = {}


class History(Registered):
    """An end-twist history kappa3(0, t) [1/m]: ``h(t)`` on an array of times.
    (``quantity = "spin"``: the end's spin w3(0, t) [rad/s] instead, for rotation control;
    :class:`~dyntorsion.buckling.turning.TurnHold`.)

    A subclass sets ``kind`` (it then registers in :data:`HISTORIES`), is a frozen
    dataclass of numbers (its key is ``kind`` and its fields, :meth:`params`) and defines
    ``__call__``."""

    registry: ClassVar[dict[str, type]] = HISTORIES
    what: ClassVar[str] = "history"
    quantity: str = "twist"

    def __call__(self, t: np.ndarray) -> np.ndarray:
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


def history_from_params(p: Mapping[str, Any]) -> History:
    """The history of a cache key (its ``params()``), by its registered ``kind``
    (:data:`HISTORIES`); ValueError naming the registered kinds."""
    return History.lookup(p.get("kind")).from_params(p)
