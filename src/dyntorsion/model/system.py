"""What the engine needs to know about a model (System) and its ends (Boundary), eq (7)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["System", "Boundary"]


@dataclass(frozen=True)
class System:
    """What the engine needs to know about a model.

    F(y, p, out) and dF(y, p, out) are compiled functions (numba) filling the
    load vector (nf,) and its Jacobian (nf, nf) for one node.  ``yscale`` and
    ``rscale`` are characteristic sizes of the fields and of the equation rows:
    they scale the Newton system and set the absolute floor of its
    convergence test.
    """

    names: tuple[str, ...]
    M: np.ndarray
    K: np.ndarray
    F: Any
    dF: Any
    params: np.ndarray
    yscale: np.ndarray
    rscale: np.ndarray

    @classmethod
    def from_model(cls, model, *, names, F, dF, params) -> System:
        """A system from a model with ``mass_matrix``, ``stiffness_matrix`` and ``scales()``."""
        ys, rs = model.scales()
        return cls(
            names=tuple(names),
            M=model.mass_matrix,
            K=model.stiffness_matrix,
            F=F,
            dF=dF,
            params=params,
            yscale=ys,
            rscale=rs,
        )

    @property
    def nf(self) -> int:
        return len(self.names)

    def index(self, name: str | int) -> int:
        if isinstance(name, int | np.integer):
            if not 0 <= name < self.nf:
                raise ValueError(f"field index {name} outside [0, {self.nf})")
            return int(name)
        try:
            return self.names.index(name)
        except ValueError:
            raise ValueError(f"unknown field {name!r}; fields are {self.names}") from None

    def load(self, y: np.ndarray) -> np.ndarray:
        """F(y) at every node of y (..., nf)."""
        y = np.ascontiguousarray(y, dtype=float)
        flat = y.reshape(-1, self.nf)
        out = np.empty_like(flat)
        for j in range(flat.shape[0]):
            self.F(flat[j], self.params, out[j])
        return out.reshape(y.shape)

    def load_jacobian(self, y: np.ndarray) -> np.ndarray:
        y = np.ascontiguousarray(y, dtype=float)
        out = np.empty((self.nf, self.nf))
        self.dF(y, self.params, out)
        return out


@dataclass(frozen=True)
class Boundary:
    """Boundary rows ``rows @ y(end, t) = values(t)`` at one end.

    ``values`` maps an array of times (n,) to an array (n, nb); a constant
    array-like is accepted for time-independent conditions.
    """

    rows: np.ndarray
    values: Callable[[np.ndarray], np.ndarray] | np.ndarray

    @classmethod
    def fields(cls, system: System, names: Sequence[str | int], values=None) -> Boundary:
        """Prescribe the listed fields (``values`` default 0)."""
        rows = np.zeros((len(names), system.nf))
        for r, name in enumerate(names):
            rows[r, system.index(name)] = 1.0
        if values is None:
            values = np.zeros(len(names))
        return cls(rows, values)

    @property
    def nb(self) -> int:
        return self.rows.shape[0]

    def at(self, t: np.ndarray) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        if callable(self.values):
            g = np.asarray(self.values(t), dtype=float)
        else:
            g = np.broadcast_to(np.asarray(self.values, dtype=float), (t.size, self.nb))
        g = np.array(np.broadcast_to(g.reshape(t.size, -1), (t.size, self.nb)), order="C")
        if not np.all(np.isfinite(g)):
            raise ValueError("boundary values are not finite")
        return g
