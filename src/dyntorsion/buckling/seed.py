"""The seed of buckling (section 6): "a small perturbative force, of magnitude 1e-8 N, is
added in the d1 direction".  Where it acts the paper does not say: :class:`Perturbation`
makes that a parameter."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..genalpha.guard import real

__all__ = ["STATED", "Perturbation"]

#: the seed's magnitude as section 6 states it: 1e-8 (N; read as N/m along the rod by
#: default, as N at a point with ``form="point"``)
STATED = 1e-8


@dataclass(frozen=True)
class Perturbation:
    """The small force that seeds buckling (section 6: "1e-8 N in the d1 direction").

    The paper does not say where it acts.  ``form="uniform"`` (default) applies
    ``magnitude`` N/m along the whole rod; ``form="point"`` applies ``magnitude`` N at
    the node nearest to ``location`` (as magnitude/ds N/m on that node's row).
    ``direction`` is a body-frame unit vector (default d1).  The force acts for all t.
    """

    magnitude: float = STATED
    form: str = "uniform"
    location: float = 0.5
    direction: tuple[float, float, float] = (1.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        if not (real("perturbation magnitude", self.magnitude) >= 0):
            raise ValueError(f"perturbation magnitude={self.magnitude!r} must be finite and >= 0")
        if self.form not in ("uniform", "point"):
            raise ValueError(f"perturbation form={self.form!r}; allowed: 'uniform', 'point'")
        d = np.asarray(self.direction, dtype=float)
        if d.shape != (3,) or not np.isclose(np.linalg.norm(d), 1.0):
            raise ValueError(f"perturbation direction={self.direction!r} must be a unit 3-vector")

    def force(self, s: np.ndarray, length: float) -> np.ndarray:
        """Body force per length (N+1, 3) at the nodes s."""
        f = np.zeros((s.size, 3))
        if self.form == "uniform":
            f[:] = self.magnitude * np.asarray(self.direction)
        else:
            if not 0 <= self.location <= length:
                raise ValueError(
                    f"perturbation location={self.location!r} must lie in [0, L] = [0, {length}]"
                )
            j = int(np.argmin(np.abs(s - self.location)))
            ds = s[1] - s[0]
            weight = ds if 0 < j < s.size - 1 else 0.5 * ds
            f[j] = self.magnitude / weight * np.asarray(self.direction)
        return f
