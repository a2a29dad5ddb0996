"""The end conditions (section 6, eq 30, and the sets a researcher extends it with):
which six fields each end of the rod prescribes.

:class:`Ends` holds the prescribed fields of each end; :data:`ENDS` names the sets
(``"clamped"`` is the paper's eq 30, :data:`EQ30`).  A set the rod equations cannot
satisfy is refused on construction (:class:`IllPosedEndsError`), before any step.

An end set declares what it supports: ``static`` names the end conditions of the
static theory that give its critical twist (None: no static critical twist), ``linear``
whether the linear predictions apply, ``contact`` whether runs past self-contact do,
and its ``relations`` turn prescribed fields into linear relations between fields (a
:class:`Relation`, e.g. a torsional dashpot at s = L).  Code elsewhere asks these
(:meth:`Ends.require`), never the set's name; :func:`register` adds a set to
:data:`ENDS` so the command line and the store find it by name.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from .cosserat import FIELDS
from .system import Boundary

__all__ = [
    "Ends",
    "ENDS",
    "EQ30",
    "ends",
    "IllPosedEndsError",
    "UnsupportedEndsError",
    "ends_from_params",
    "Relation",
    "register",
    "CAPABILITIES",
]


class IllPosedEndsError(ValueError):
    """A set of end conditions the rod equations cannot satisfy (refused before a run)."""


class UnsupportedEndsError(ValueError):
    """An end set asked for something it does not declare (:meth:`Ends.require`)."""


#: what an end set can declare, by attribute, with its name in messages
CAPABILITIES = {
    "static": "a static critical twist",
    "linear": "the linear predictions",
    "contact": "runs past self-contact",
}


@dataclass(frozen=True)
class Relation:
    """A linear relation at one end (``side`` "left" or "right") that replaces the
    prescription of ``field`` (one of the end's six): field + sum_j c_j y_j = ``value``
    with ``terms`` = ((name_j, c_j), ...) in the fields' units (body frame).  A torsional
    dashpot of constant c [N m s] at s = L, m3 = C k3 = -c w3, is
    ``Relation("right", "k3", (("w3", c / C),))``.  (A spring acts on the end's angle,
    which is not a field of the rod's first-order system: it is no such relation.)"""

    side: str
    field: str
    terms: tuple[tuple[str, float], ...]
    value: float = 0.0

    def __post_init__(self) -> None:
        if self.side not in ("left", "right"):
            raise IllPosedEndsError(f"relation side={self.side!r}; allowed: 'left', 'right'")
        names = [self.field, *(str(k) for k, _ in self.terms)]
        unknown = sorted(set(names) - set(FIELDS))
        if unknown:
            raise IllPosedEndsError(f"relation: unknown field(s) {unknown}; fields: {FIELDS}")
        terms = tuple((str(k), float(c)) for k, c in self.terms)
        if not terms or not all(np.isfinite(c) for _, c in terms):
            raise IllPosedEndsError(f"relation on {self.field}: terms={self.terms!r} must be "
                                    "finite coefficients of other fields")  # fmt: skip
        object.__setattr__(self, "terms", terms)
        object.__setattr__(self, "value", float(self.value))

    def params(self) -> dict[str, Any]:
        return {"side": self.side, "field": self.field, "terms": [list(t) for t in self.terms],
                "value": self.value}  # fmt: skip


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
    static: str | None = None
    linear: bool = False
    contact: bool = False
    relations: tuple[Relation, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "relations", tuple(self.relations))
        for r in self.relations:
            if not isinstance(r, Relation):
                raise TypeError(f"relations: {r!r} must be a dyntorsion.model.ends.Relation")
            if r.field not in getattr(self, r.side):
                raise IllPosedEndsError(
                    f"relation on {r.field} at the {r.side} end: the end does not prescribe "
                    f"{r.field} (it prescribes {getattr(self, r.side)})"
                )
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

    def require(self, capability: str, why: str = "") -> None:
        """Refuse (:class:`UnsupportedEndsError`, naming the capability and the set) what
        this set does not declare; ``capability`` is a key of :data:`CAPABILITIES`."""
        if capability not in CAPABILITIES:
            raise ValueError(f"capability={capability!r}; allowed: {', '.join(CAPABILITIES)}")
        if not getattr(self, capability):
            raise UnsupportedEndsError(
                f"ends {self.name!r} do not support {CAPABILITIES[capability]} "
                f"(capability {capability!r} not declared by the set)" + (f": {why}" if why else "")
            )

    def rows(self, system, history: Callable[[Any], Any], load: Callable[[Any], Any]):
        """The engine's boundary rows: (left, right) :class:`~dyntorsion.genalpha.Boundary`,
        each :class:`Relation` written into the row of its field."""
        left, right = self._field_rows(system, history, load)
        return self._related(system, "left", left), self._related(system, "right", right)

    def _related(self, system, side: str, rows):
        mine = [r for r in self.relations if r.side == side]
        if not mine:
            return rows
        a = rows.rows.copy()
        shift = np.zeros(a.shape[0])
        for r in mine:
            i = getattr(self, side).index(r.field)
            for name, c in r.terms:
                a[i, system.index(name)] += c
            shift[i] = r.value
        values = rows.values
        if callable(values):
            return Boundary(a, lambda t: np.asarray(values(t), dtype=float) + shift)
        return Boundary(a, np.asarray(values, dtype=float) + shift)

    def _field_rows(self, system, history, load):
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
        """The set's key: its name and rows (and relations, when it has any); what it
        declares it supports is not keyed (it changes no number)."""
        out = {"name": self.name, "left": list(self.left), "right": list(self.right)}
        if self.relations:
            out["relations"] = [r.params() for r in self.relations]
        return out


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
            static="clamped",
            linear=True,
            contact=True,
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
            contact=True,
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


def register(end_set: Ends) -> Ends:
    """Add ``end_set`` to :data:`ENDS` under its name (a set of the same name is
    replaced) and return it: the command line (``--ends NAME``) and the store find it."""
    if not isinstance(end_set, Ends):
        raise TypeError(f"end_set={end_set!r} must be a dyntorsion.model.ends.Ends")
    ENDS[end_set.name] = end_set
    return end_set


def ends(value: str | Ends) -> Ends:
    """An :class:`Ends` by name (see :data:`ENDS`), or the object itself."""
    if isinstance(value, Ends):
        return value
    if value not in ENDS:
        raise ValueError(f"ends={value!r}; allowed: {', '.join(ENDS)} or an Ends")
    return ENDS[value]


def ends_from_params(p: Mapping[str, Any]) -> Ends:
    """The end set of a cache key: the registered set of that name when its key matches
    (it carries what the set supports), else a set of these rows supporting nothing."""
    relations = tuple(
        Relation(r["side"], r["field"], tuple(map(tuple, r["terms"])), r["value"])
        for r in p.get("relations", ())
    )
    e = Ends(p["name"], tuple(p["left"]), tuple(p["right"]), relations=relations)
    named = ENDS.get(e.name)
    return named if named is not None and named.params() == e.params() else e
