"""The seed of buckling (section 6): "a small perturbative force, of magnitude 1e-8 N, is
added in the d1 direction".  Where it acts the paper does not say: :class:`Perturbation`
makes that a parameter.  Its ``form`` names a :class:`SeedForm`: ``"uniform"`` and ``"point"``
are built in, and a subclass with a class attribute ``kind`` registers itself in
:data:`SEED_FORMS` when defined."""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any, ClassVar

import numpy as np

from ..genalpha.guard import real

__all__ = ["STATED", "FRAMES", "Perturbation", "SeedForm", "SEED_FORMS", "Uniform", "Point"]

#: the seed's magnitude as section 6 states it: 1e-8 (N; read as N/m along the rod by
#: default, as N at a point with ``form="point"``)
STATED = 1e-8
#: the frames a seed's direction can be fixed in (:class:`Perturbation` ``frame``)
FRAMES = ("body", "lab")
#: the seed forms by kind (every :class:`SeedForm` subclass with a ``kind``)
SEED_FORMS: dict[str, type[SeedForm]] = {}


class SeedForm:
    """Where along the rod a seed acts: :meth:`force` gives the body force per length
    (N+1, 3) [N/m] of a :class:`Perturbation` at the nodes.  A subclass with a class
    attribute ``kind`` registers itself in :data:`SEED_FORMS` when defined (then
    ``Perturbation(form=kind)`` takes it); the seed's ``location`` [m] is its position,
    which a form may ignore."""

    kind: ClassVar[str] = ""

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if cls.__dict__.get("kind"):
            SEED_FORMS[cls.kind] = cls

    def force(self, seed: Perturbation, s: np.ndarray, length: float) -> np.ndarray:
        raise NotImplementedError


class Uniform(SeedForm):
    """``magnitude`` N/m along the whole rod."""

    kind = "uniform"

    def force(self, seed, s, length):
        f = np.zeros((s.size, 3))
        f[:] = seed.magnitude * np.asarray(seed.direction)
        return f


class Point(SeedForm):
    """``magnitude`` N at the node nearest to ``location``, as magnitude / ds N/m on that
    node's row (half a cell at an end)."""

    kind = "point"

    def force(self, seed, s, length):
        if not 0 <= seed.location <= length:
            raise ValueError(
                f"perturbation location={seed.location!r} must lie in [0, L] = [0, {length}]"
            )
        f = np.zeros((s.size, 3))
        j = int(np.argmin(np.abs(s - seed.location)))
        ds = s[1] - s[0]
        weight = ds if 0 < j < s.size - 1 else 0.5 * ds
        f[j] = seed.magnitude / weight * np.asarray(seed.direction)
        return f


@dataclass(frozen=True)
class Perturbation:
    """The small force that seeds buckling (section 6: "1e-8 N in the d1 direction").

    The paper does not say where it acts, in which frame, or for how long: each is a
    parameter here.  ``form="uniform"`` (default) applies ``magnitude`` N/m along the
    whole rod; ``form="point"`` applies ``magnitude`` N at the node nearest to
    ``location`` (as magnitude/ds N/m on that node's row).  ``direction`` is a unit vector:
    in the body frame (``frame="body"``, default: "in the d1 direction", turning with the
    section) or fixed in space (``frame="lab"``: e1 where ``direction`` is d1 at the
    far end s = L, which does not turn while the rod is straight; its body components
    follow the quasi-static twist of the straight rod, the section at s turned by
    phi(s, t) = -kappa3(0, t) (L - s) against the far end -- the torsional waves about
    that twist are left out of the force's direction).  ``duration=None`` (default)
    lets the force act for all t; a number [s] makes it an impulse that acts on
    0 <= t <= duration only.
    """

    magnitude: float = STATED
    form: str = "uniform"
    location: float = 0.5
    direction: tuple[float, float, float] = (1.0, 0.0, 0.0)
    frame: str = "body"
    duration: float | None = None

    def __post_init__(self) -> None:
        if not (real("perturbation magnitude", self.magnitude) >= 0):
            raise ValueError(f"perturbation magnitude={self.magnitude!r} must be finite and >= 0")
        if self.form not in SEED_FORMS:
            raise ValueError(
                f"perturbation form={self.form!r}; registered: {', '.join(sorted(SEED_FORMS))}"
            )
        d = np.asarray(self.direction, dtype=float)
        if d.shape != (3,) or not np.isclose(np.linalg.norm(d), 1.0):
            raise ValueError(f"perturbation direction={self.direction!r} must be a unit 3-vector")
        if self.frame not in FRAMES:
            raise ValueError(f"perturbation frame={self.frame!r}; allowed: 'body', 'lab'")
        if self.duration is not None:
            if not (real("perturbation duration", self.duration, " [s]") > 0):
                raise ValueError(
                    f"perturbation duration={self.duration!r} must be > 0 s (None: for all t)"
                )
            object.__setattr__(self, "duration", float(self.duration))

    @property
    def constant(self) -> bool:
        """Whether the force per length is the same at every t (body frame, no end)."""
        return self.frame == "body" and self.duration is None

    def params(self) -> dict:
        """The seed's part of a cache key: the frame and the duration only where they
        differ from the defaults (so the keys of every earlier scene stay as they were)."""
        out = asdict(self)
        for name, default in (("frame", "body"), ("duration", None)):
            if out[name] == default:
                del out[name]
        return out

    def time_factor(self, t: np.ndarray) -> np.ndarray:
        """1 while the force acts, else 0 (an impulse ends at ``duration``)."""
        t = np.asarray(t, dtype=float)
        if self.duration is None:
            return np.ones_like(t)
        return (t <= self.duration).astype(float)

    def turned(self, f: np.ndarray, s: np.ndarray, length: float, twist: float) -> np.ndarray:
        """The body components of the lab-fixed force ``f`` (N+1, 3) when the end twist is
        ``twist`` [1/m]: rotated by -phi(s) = twist (L - s) about d3 (see the class)."""
        phi = -twist * (length - s)
        c, sn = np.cos(phi), np.sin(phi)
        out = np.empty_like(f)
        out[:, 0] = c * f[:, 0] + sn * f[:, 1]
        out[:, 1] = -sn * f[:, 0] + c * f[:, 1]
        out[:, 2] = f[:, 2]
        return out

    def force(self, s: np.ndarray, length: float) -> np.ndarray:
        """Body force per length (N+1, 3) at the nodes s."""
        return SEED_FORMS[self.form]().force(self, s, length)
