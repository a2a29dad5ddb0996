"""The end conditions (section 6, eq 30, and the sets a researcher extends it with):
which six fields each end of the rod prescribes.

:class:`Ends` holds the prescribed fields of each end; :data:`ENDS` names the sets
(``"clamped"`` is the paper's eq 30, :data:`EQ30`).  A set the rod equations cannot
satisfy is refused on construction (:class:`IllPosedEndsError`), before any step.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from .cosserat import FIELDS
from .system import Boundary

__all__ = ["Ends", "ENDS", "EQ30", "ends", "IllPosedEndsError", "ends_from_params"]


class IllPosedEndsError(ValueError):
    """A set of end conditions the rod equations cannot satisfy (refused before a run)."""


@dataclass(frozen=True)
class Ends:
    """Six prescribed fields at each end (body frame, section 2).

    The left end must prescribe ``k3`` (the twist history: moment control, the paper's)
    or ``w3`` (the spin history: rotation control); the right end prescribes ``n3`` (the
    axial load) unless it holds ``u3``.  All other prescribed fields are 0.
    """

    name: str
    left: tuple[str, ...]
    right: tuple[str, ...]
    description: str = ""

    def __post_init__(self) -> None:
        for side in ("left", "right"):
            names = tuple(getattr(self, side))
            object.__setattr__(self, side, names)
            unknown = set(names) - set(FIELDS)
            if unknown:
                raise IllPosedEndsError(
                    f"{side} end: unknown field(s) {sorted(unknown)}; fields: {FIELDS}"
                )
            if len(set(names)) != len(names):
                raise IllPosedEndsError(f"{side} end prescribes a field twice: {names}")
            if len(names) != 6:
                raise IllPosedEndsError(
                    f"{side} end prescribes {len(names)} fields; the 12-field rod needs 6 at each end"
                )
        if "k3" not in self.left and "w3" not in self.left:
            raise IllPosedEndsError(
                "the left end must prescribe k3 (the end-twist history, moment control) or w3 "
                "(the end's spin history, rotation control)"
            )
        if "u3" in self.left and "u3" in self.right:
            raise IllPosedEndsError(
                "u3 prescribed at both ends: inextensibility (u3_s = k2 u1 - k1 u2) fixes the "
                "axial velocity along the rod from one end, so a second condition over-determines "
                "it and leaves the axial force n3 undetermined; prescribe n3 at one end instead"
            )
        for pair in (("u1", "n1"), ("u2", "n2"), ("u3", "n3")):
            for side in ("left", "right"):
                if set(pair) <= set(getattr(self, side)):
                    raise IllPosedEndsError(
                        f"{side} end prescribes both {pair[0]} and {pair[1]}: a velocity and the "
                        "force conjugate to it cannot both be given at one end"
                    )
        for pair in (("w1", "k1"), ("w2", "k2"), ("w3", "k3")):
            for side in ("left", "right"):
                if set(pair) <= set(getattr(self, side)):
                    raise IllPosedEndsError(
                        f"{side} end prescribes both {pair[0]} and {pair[1]}: an angular velocity "
                        "and the moment conjugate to it cannot both be given at one end"
                    )

    @property
    def holds_axial_load(self) -> bool:
        return "n3" in self.right

    @property
    def driven(self) -> str:
        """The left end's history field: ``"k3"`` (the twist) or ``"w3"`` (the spin)."""
        return "k3" if "k3" in self.left else "w3"

    def check_history(self, history: Any) -> None:
        """Refuse a history whose ``quantity`` (``"twist"`` [1/m] or ``"spin"`` [rad/s]) is
        not the field the left end prescribes (``k3`` or ``w3``)."""
        quantity = getattr(history, "quantity", "twist")
        wanted = {"k3": "twist", "w3": "spin"}[self.driven]
        if quantity != wanted:
            raise IllPosedEndsError(
                f"ends {self.name!r} prescribe {self.driven} at s = 0, so the history must be "
                f"a {wanted} history; got a {quantity} history"
                + (" (ends='clamped-turned' take a spin history)" if wanted == "twist" else "")
            )

    def rows(self, system, history: Callable[[Any], Any], load: Callable[[Any], Any]):
        """The engine's boundary rows: (left, right) :class:`~dyntorsion.genalpha.Boundary`."""
        self.check_history(history)
        e_h = np.zeros(6)
        e_h[self.left.index(self.driven)] = 1.0
        left = Boundary.fields(system, list(self.left), lambda t: np.outer(history(t), e_h))
        if self.holds_axial_load and not load.is_zero:
            e_n3 = np.zeros(6)
            e_n3[self.right.index("n3")] = 1.0
            right = Boundary.fields(system, list(self.right), lambda t: np.outer(load(t), e_n3))
        else:
            if not load.is_zero:
                raise IllPosedEndsError(
                    f"ends {self.name!r} hold u3 at the far end: no axial load can act"
                )
            right = Boundary.fields(system, list(self.right))
        return left, right

    def params(self) -> dict[str, Any]:
        return {"name": self.name, "left": list(self.left), "right": list(self.right)}


#: the named end-condition sets (body-frame fields prescribed at s = 0 and s = L)
ENDS: dict[str, Ends] = {
    e.name: e
    for e in (
        Ends(
            "clamped",
            ("u1", "u2", "u3", "w1", "w2", "k3"),
            ("w1", "w2", "w3", "u1", "u2", "n3"),
            "eq (30): s = 0 clamped and twisted; s = L held in rotation and laterally, free to "
            "slide axially under n3 = T",
        ),
        Ends(
            "clamped-free-lateral",
            ("u1", "u2", "u3", "w1", "w2", "k3"),
            ("w1", "w2", "w3", "n1", "n2", "n3"),
            "s = L held in rotation, free laterally (no lateral force) and axially",
        ),
        Ends(
            "clamped-free",
            ("u1", "u2", "u3", "w1", "w2", "k3"),
            ("n1", "n2", "n3", "k1", "k2", "k3"),
            "s = L free: no force (but the axial load) and no moment",
        ),
        Ends(
            "clamped-turned",
            ("u1", "u2", "u3", "w1", "w2", "w3"),
            ("w1", "w2", "w3", "u1", "u2", "n3"),
            "rotation control: s = 0 clamped and turned about its axis at the prescribed spin "
            "w3(0, t) (a spin history, e.g. TurnHold); s = L as eq (30), held in rotation and "
            "laterally, free to slide axially under n3 = T",
        ),
        Ends(
            "pinned-follower",
            ("u1", "u2", "u3", "k1", "k2", "k3"),
            ("u1", "u2", "n3", "k1", "k2", "w3"),
            "both ends held in position, free to tilt (no bending moment); the twisting moment "
            "follows the tangent (a follower torque, not Greenhill's axial one)",
        ),
    )
}


#: the paper's end conditions, eq (30): the rows every eq (30) scene uses
EQ30: Ends = ENDS["clamped"]


def ends(value: str | Ends) -> Ends:
    """An :class:`Ends` by name (see :data:`ENDS`), or the object itself."""
    if isinstance(value, Ends):
        return value
    if value not in ENDS:
        raise ValueError(f"ends={value!r}; allowed: {', '.join(ENDS)} or an Ends")
    return ENDS[value]


def ends_from_params(p: Mapping[str, Any]) -> Ends:
    """The end set of a cache key (the named set when its rows match)."""
    e = Ends(p["name"], tuple(p["left"]), tuple(p["right"]))
    named = ENDS.get(e.name)
    return named if named is not None and (named.left, named.right) == (e.left, e.right) else e
