"""The rod: material, cross-section, length, and every property and scale derived from them.

The paper's rod (Table 1) is circular, homogeneous and isotropic; ``Rod()`` is that rod.
Other rods are first-class: a circle of another material (``Rod(E=..., D=...)``), an
elliptic or a rectangular section (:meth:`Rod.elliptic`, :meth:`Rod.rectangular`), or
a rod given directly by what the equations need (:meth:`Rod.from_properties`: bending
stiffnesses B1, B2, torsional stiffness C, mass and rotary inertias per length).

Body frame (section 2): d1 and d2 are the principal axes of the section, d3 the
tangent.  ``I1 = int x2^2 dA`` resists bending about d1 (curvature k1), ``I2 = int x1^2 dA``
about d2; ``J`` is the Saint-Venant torsion constant (C = G J); ``I3 = I1 + I2`` the
polar moment, which carries the rotary inertia rho I3 about d3.  For a circle J = I3.

The scales every module uses are defined here once:

* torsional wave speed ``c = sqrt(C / (rho I3))`` (= sqrt(G / rho) for a circle, eq 22),
* torsional transit time ``transit = L / c`` and first torsional period ``T1 = 4 L / c``,
* bending time ``T0 = L^2 sqrt(rho A / B)`` with ``B = min(B1, B2)``, the weaker axis.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping
from dataclasses import dataclass, field, fields
from types import MappingProxyType
from typing import Any

__all__ = ["TABLE1", "Rod", "Section"]


def _number(name: str, value: Any, allowed: str, ok) -> float:
    """``value`` as a float, or an error that names the parameter and its range."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(
            f"Rod parameter {name}={value!r} must be a real number in {allowed}, "
            f"not {type(value).__name__}"
        )
    x = float(value)
    if not (math.isfinite(x) and ok(x)):
        raise ValueError(f"Rod parameter {name}={value!r} is outside the allowed range {allowed}")
    return x


def _positive(name: str, value: Any, unit: str) -> float:
    return _number(name, value, f"(0, inf) {unit}".strip(), lambda x: x > 0)


def _finite_section(name: str, dims: dict[str, float], make):
    try:
        sec = make()
    except (ZeroDivisionError, OverflowError) as err:
        given = ", ".join(f"{k}={v!r}" for k, v in dims.items())
        raise ValueError(f"{name} section {given} is beyond floating point: {err}") from None
    for k in ("A", "I1", "I2", "J", "I3"):
        v = getattr(sec, k)
        if not (math.isfinite(v) and 1e-300 < v < 1e300):
            given = ", ".join(f"{k}={v!r}" for k, v in dims.items())
            raise ValueError(
                f"{name} section {given}: derived {k} = {v!r} is beyond floating point"
            )
    return sec


def _rectangle_torsion(w: float, h: float, terms: int = 200) -> float:
    """Saint-Venant torsion constant of a w x h rectangle (series, e.g. Timoshenko & Goodier)."""
    long, short = max(w, h), min(w, h)
    tail = sum(math.tanh(n * math.pi * long / (2 * short)) / n**5 for n in range(1, 2 * terms, 2))
    return long * short**3 / 3 * (1 - 192 / math.pi**5 * short / long * tail)


@dataclass(frozen=True)
class Section:
    """Geometric properties of a cross-section [SI].

    ``shape`` and ``dims`` say what it is ("circle" with D; "ellipse" with semi-axes a
    along d1 and b along d2; "rectangle" with width w along d1 and height h along d2;
    "given" for properties set directly); ``thickness`` is the distance two centrelines
    may approach before self-contact is declared (the smallest width of the section).
    """

    shape: str
    dims: tuple[tuple[str, float], ...]
    A: float
    I1: float
    I2: float
    J: float
    I3: float
    thickness: float

    @classmethod
    def circle(cls, D: float) -> Section:
        """A circle of diameter D: A = pi D^2/4, I1 = I2 = A D^2/16, J = I3 = A D^2/8."""
        D = _positive("D", D, "m")

        def make():
            A = math.pi * D**2 / 4.0
            I1 = A * D**2 / 16.0
            J = A * D**2 / 8.0
            return cls("circle", (("D", D),), A, I1, I1, J, J, D)

        return _finite_section("circle", {"D": D}, make)

    @classmethod
    def ellipse(cls, a: float, b: float) -> Section:
        """Semi-axes a (along d1) and b (along d2): A = pi a b, I1 = pi a b^3/4,
        I2 = pi a^3 b/4, J = pi a^3 b^3/(a^2 + b^2)."""
        a, b = _positive("a", a, "m"), _positive("b", b, "m")

        def make():
            I1, I2 = math.pi * a * b**3 / 4.0, math.pi * a**3 * b / 4.0
            J = math.pi * a**3 * b**3 / (a**2 + b**2)
            dims = (("a", a), ("b", b))
            return cls("ellipse", dims, math.pi * a * b, I1, I2, J, I1 + I2, 2 * min(a, b))

        return _finite_section("ellipse", {"a": a, "b": b}, make)

    @classmethod
    def rectangle(cls, w: float, h: float) -> Section:
        """Width w (along d1), height h (along d2): I1 = w h^3/12, I2 = w^3 h/12, J from
        the Saint-Venant series."""
        w, h = _positive("w", w, "m"), _positive("h", h, "m")

        def make():
            I1, I2 = w * h**3 / 12.0, w**3 * h / 12.0
            J = _rectangle_torsion(w, h)
            return cls("rectangle", (("w", w), ("h", h)), w * h, I1, I2, J, I1 + I2, min(w, h))

        return _finite_section("rectangle", {"w": w, "h": h}, make)


#: Table 1 of the paper, the one place its values are written: Young's modulus [Pa],
#: Poisson's ratio, diameter [m], length [m] and density [kg/m^3]
TABLE1: Mapping[str, float] = MappingProxyType(
    {"E": 1.25e7, "nu": 0.25, "D": 1e-3, "L": 1.0, "rho": 1500.0}
)


@dataclass(frozen=True)
class Rod:
    """An elastic rod; ``Rod()`` is the circular rod of Table 1.

    Parameters (circular rod)
    -------------------------
    E : Young's modulus [Pa], > 0.
    nu : Poisson's ratio [-], in (-1, 0.5].
    D : diameter [m], > 0.
    L : length [m], > 0.
    rho : density [kg/m^3], > 0.

    Other sections: :meth:`elliptic`, :meth:`rectangular`; a rod given by its
    stiffnesses and inertias: :meth:`from_properties`.  Derived, for every rod:
    ``G``, ``A``, ``I1``, ``I2``, ``J`` (torsion constant), ``I3`` (polar moment),
    ``B1 = E I1``, ``B2 = E I2``, ``C = G J``, ``mass_per_length = rho A``,
    ``rotary_inertia = (rho I1, rho I2, rho I3)``, ``c``, ``transit``, ``T1``,
    ``T0``, ``B`` and ``thickness`` (see the module docstring).
    """

    E: float | None = TABLE1["E"]
    nu: float | None = TABLE1["nu"]
    D: float | None = TABLE1["D"]
    L: float = TABLE1["L"]
    rho: float | None = TABLE1["rho"]
    section: Section | None = None
    G: float = field(init=False)
    A: float = field(init=False)
    I1: float = field(init=False)
    I2: float = field(init=False)
    J: float = field(init=False)
    I3: float = field(init=False)
    B1: float = field(init=False)
    B2: float = field(init=False)
    C: float = field(init=False)
    mass_per_length: float = field(init=False)
    rotary_inertia: tuple[float, float, float] = field(init=False)
    thickness: float = field(init=False)
    c: float = field(init=False)
    transit: float = field(init=False)
    T1: float = field(init=False)
    B: float = field(init=False)
    T0: float = field(init=False)

    def __post_init__(self) -> None:
        try:
            self._derive()
        except (ZeroDivisionError, OverflowError) as err:
            raise ValueError(
                f"the rod's inputs (E={self.E!r}, nu={self.nu!r}, D={self.D!r}, L={self.L!r}, "
                f"rho={self.rho!r}, section={self.section!r}) are beyond floating point: {err}"
            ) from None

    def _derive(self) -> None:
        set_ = object.__setattr__
        L = _positive("L", self.L, "m")
        set_(self, "L", L)
        if self.section is not None and self.section.shape == "given":
            self._derive_given()
        else:
            E = _positive("E", self.E, "Pa")
            nu = _number("nu", self.nu, "(-1, 0.5]", lambda x: -1.0 < x <= 0.5)
            rho = _positive("rho", self.rho, "kg/m^3")
            if self.section is None:
                sec = Section.circle(self.D)
                set_(self, "D", sec.dims[0][1])
            else:
                if not isinstance(self.section, Section):
                    raise TypeError(f"section={self.section!r} must be a Section")
                if self.D is not None:
                    raise ValueError("D is the diameter of a circle: give D=None with a section")
                sec = self.section
            G = E / (2.0 * (1.0 + nu))
            values = {
                "E": E,
                "nu": nu,
                "rho": rho,
                "G": G,
                "A": sec.A,
                "I1": sec.I1,
                "I2": sec.I2,
                "J": sec.J,
                "I3": sec.I3,
                "B1": E * sec.I1,
                "B2": E * sec.I2,
                "C": G * sec.J,
                "mass_per_length": rho * sec.A,
                "rotary_inertia": (rho * sec.I1, rho * sec.I2, rho * sec.I3),
                "thickness": sec.thickness,
            }
            for k, v in values.items():
                set_(self, k, v)
            # c = sqrt(C / (rho I3)); written so that a circle (J = I3) gives sqrt(G / rho) exactly
            set_(self, "c", math.sqrt(G / rho * (sec.J / sec.I3)))
        self._derive_scales()

    def _derive_given(self) -> None:
        sec = self.section
        set_ = object.__setattr__
        for name in ("E", "nu", "D", "rho"):
            if getattr(self, name) is not None:
                raise ValueError(f"{name} has no meaning for a rod given by its properties")
        props = dict(sec.dims)
        for k in ("B1", "B2", "C", "mass_per_length"):
            set_(self, k, props[k])
        ri = (props["rho_I1"], props["rho_I2"], props["rho_I3"])
        set_(self, "rotary_inertia", ri)
        for k in ("G", "A", "I1", "I2", "J", "I3"):
            set_(self, k, None)
        set_(self, "thickness", sec.thickness)
        set_(self, "c", math.sqrt(self.C / ri[2]))

    def _derive_scales(self) -> None:
        set_ = object.__setattr__
        set_(self, "transit", self.L / self.c)
        set_(self, "T1", 4.0 * self.L / self.c)
        set_(self, "B", min(self.B1, self.B2))
        set_(self, "T0", self.L**2 * math.sqrt(self.mass_per_length / self.B))
        derived = ("B1", "B2", "C", "mass_per_length", "c", "T0", "thickness")
        for name in derived:
            v = getattr(self, name)
            if not (math.isfinite(v) and v > 0 and v >= 1e-300 and v <= 1e300):
                raise ValueError(
                    f"derived {name} = {v!r} is not a usable positive number: "
                    f"the rod's parameters ({self.describe()}) are beyond floating point"
                )

    # ------------------------------------------------------------ constructors
    @classmethod
    def paper(cls) -> Rod:
        """The rod of Table 1 (rho = 1500 kg/m^3), identical to ``Rod()``."""
        return cls()

    @classmethod
    def elliptic(cls, *, a: float, b: float, E: float = TABLE1["E"], nu: float = TABLE1["nu"],
                 L: float = TABLE1["L"], rho: float = TABLE1["rho"]) -> Rod:  # fmt: skip
        """An elliptic section with semi-axes ``a`` (along d1) and ``b`` (along d2)."""
        return cls(E=E, nu=nu, D=None, L=L, rho=rho, section=Section.ellipse(a, b))

    @classmethod
    def rectangular(cls, *, w: float, h: float, E: float = TABLE1["E"], nu: float = TABLE1["nu"],
                    L: float = TABLE1["L"], rho: float = TABLE1["rho"]) -> Rod:  # fmt: skip
        """A rectangular section, width ``w`` along d1 and height ``h`` along d2."""
        return cls(E=E, nu=nu, D=None, L=L, rho=rho, section=Section.rectangle(w, h))

    @classmethod
    def from_properties(
        cls,
        *,
        L: float,
        B1: float,
        B2: float,
        C: float,
        mass_per_length: float,
        rotary_inertia: tuple[float, float, float],
        thickness: float,
    ) -> Rod:
        """A rod given by what eq (6) needs: bending stiffnesses B1, B2 [N m^2], torsional
        stiffness C [N m^2], rho A [kg/m], rotary inertias (rho I1, rho I2, rho I3) [kg m]
        and the contact thickness [m] (e.g. a composite or hollow rod)."""
        if not isinstance(rotary_inertia, tuple | list) or len(rotary_inertia) != 3:
            raise ValueError(f"rotary_inertia={rotary_inertia!r} must be 3 numbers (kg m)")
        dims = (
            ("B1", _positive("B1", B1, "N m^2")),
            ("B2", _positive("B2", B2, "N m^2")),
            ("C", _positive("C", C, "N m^2")),
            ("mass_per_length", _positive("mass_per_length", mass_per_length, "kg/m")),
            *(
                (f"rho_I{i + 1}", _positive(f"rotary_inertia[{i}]", v, "kg m"))
                for i, v in enumerate(rotary_inertia)
            ),
        )
        t = _positive("thickness", thickness, "m")
        section = Section("given", dims, None, None, None, None, None, t)
        return cls(E=None, nu=None, D=None, L=L, rho=None, section=section)

    # ------------------------------------------------------------ views
    @property
    def isotropic(self) -> bool:
        """B1 == B2: every direction of bending alike (the classical Greenhill problem)."""
        return self.B1 == self.B2

    def with_(self, **changes: Any) -> Rod:
        """A copy with some inputs changed (E, nu, D, L, rho; derived values follow).
        Sections: change the section itself (``section=Section.ellipse(...)``)."""
        allowed = {"E", "nu", "D", "L", "rho", "section"}
        unknown = set(changes) - allowed
        if unknown:
            raise ValueError(
                f"with_: unknown input(s) {sorted(unknown)}; allowed: {sorted(allowed)}"
            )
        inputs = {k: getattr(self, k) for k in allowed} | changes
        return Rod(**inputs)

    def params(self) -> dict[str, Any]:
        """The rod as a cache key: its inputs and every derived property the equations use."""
        shape = "circle" if self.section is None else self.section.shape
        inputs = {"E": self.E, "nu": self.nu, "rho": self.rho}
        return {
            "section": {"shape": shape, **dict(self._dims())},
            **{k: v for k, v in inputs.items() if v is not None},
            "L": self.L,
            "B1": self.B1,
            "B2": self.B2,
            "C": self.C,
            "mass_per_length": self.mass_per_length,
            "rotary_inertia": list(self.rotary_inertia),
            "thickness": self.thickness,
        }

    def _dims(self) -> tuple[tuple[str, float], ...]:
        return (("D", self.D),) if self.section is None else self.section.dims

    @classmethod
    def from_params(cls, p: dict[str, Any]) -> Rod:
        """The rod of a cache key (:meth:`params`); the derived properties are checked."""
        sec = dict(p["section"])
        shape = sec.pop("shape")
        if shape == "circle":
            rod = cls(E=p["E"], nu=p["nu"], D=sec["D"], L=p["L"], rho=p["rho"])
        elif shape == "ellipse":
            rod = cls.elliptic(a=sec["a"], b=sec["b"], E=p["E"], nu=p["nu"], L=p["L"], rho=p["rho"])
        elif shape == "rectangle":
            rod = cls.rectangular(
                w=sec["w"], h=sec["h"], E=p["E"], nu=p["nu"], L=p["L"], rho=p["rho"]
            )
        elif shape == "given":
            rod = cls.from_properties(
                L=p["L"],
                B1=sec["B1"],
                B2=sec["B2"],
                C=sec["C"],
                mass_per_length=sec["mass_per_length"],
                rotary_inertia=(sec["rho_I1"], sec["rho_I2"], sec["rho_I3"]),
                thickness=p["thickness"],
            )
        else:
            raise ValueError(f"section shape={shape!r}; allowed: circle, ellipse, rectangle, given")
        if rod.params() != p:
            raise ValueError("rod parameters are inconsistent with their derived properties")
        return rod

    def describe(self) -> str:
        """A short label: the section and the material."""
        dims = " ".join(f"{k}={v:g}" for k, v in self._dims() if isinstance(v, float))
        shape = "circle" if self.section is None else self.section.shape
        mat = "" if self.E is None else f" E={self.E:g} nu={self.nu:g} rho={self.rho:g}"
        return f"{shape} {dims}{mat} L={self.L:g}"

    def as_dict(self) -> dict[str, Any]:
        """All parameters, given and derived, as a plain dict (for provenance records)."""
        out = {f.name: getattr(self, f.name) for f in fields(self) if f.name != "section"}
        out["section"] = {"shape": "circle" if self.section is None else self.section.shape}
        out["section"].update(dict(self._dims()))
        return out
