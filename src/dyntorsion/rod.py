"""The rod of Table 1: material, geometry and the derived stiffnesses and speeds.

A circular, homogeneous, isotropic rod.  Everything the equations need follows
from five numbers: Young's modulus E, Poisson's ratio nu, diameter D, length L
and density rho (SI units).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, replace


def _check(name: str, value: float, ok: bool, allowed: str) -> None:
    if not (isinstance(value, int | float) and math.isfinite(value) and ok):
        raise ValueError(f"Rod parameter {name}={value!r} is outside the allowed range {allowed}")


@dataclass(frozen=True)
class Rod:
    """A circular elastic rod (Table 1 of the paper by default).

    Derived (Table 1 and eqs 6, 22, 31): ``G = E/(2(1+nu))``, ``A = pi D^2/4``,
    ``I1 = I2 = A D^2/16``, ``J = A D^2/8``, ``B1 = E I1``, ``B2 = E I2``, ``C = G J``,
    ``mass_per_length = rho A``, the torsional wave speed ``c = sqrt(G/rho)``
    and the period of the first torsional mode ``T1 = 4 L / c`` (section 7).

    Parameters
    ----------
    E
        Young's modulus [Pa], > 0.
    nu
        Poisson's ratio [-], in (-1, 0.5].
    D
        diameter [m], > 0.
    L
        length [m], > 0.
    rho
        density [kg/m^3], > 0.
    """

    E: float = 1.25e7
    nu: float = 0.25
    D: float = 1e-3
    L: float = 1.0
    rho: float = 1500.0
    G: float = field(init=False)
    A: float = field(init=False)
    I1: float = field(init=False)
    I2: float = field(init=False)
    J: float = field(init=False)
    B1: float = field(init=False)
    B2: float = field(init=False)
    C: float = field(init=False)
    mass_per_length: float = field(init=False)
    c: float = field(init=False)
    T1: float = field(init=False)

    def __post_init__(self) -> None:
        _check("E", self.E, self.E > 0, "(0, inf) Pa")
        _check("nu", self.nu, -1.0 < self.nu <= 0.5, "(-1, 0.5]")
        _check("D", self.D, self.D > 0, "(0, inf) m")
        _check("L", self.L, self.L > 0, "(0, inf) m")
        _check("rho", self.rho, self.rho > 0, "(0, inf) kg/m^3")
        G = self.E / (2.0 * (1.0 + self.nu))
        A = math.pi * self.D**2 / 4.0
        I1 = A * self.D**2 / 16.0
        J = A * self.D**2 / 8.0
        derived = {
            "G": G,
            "A": A,
            "I1": I1,
            "I2": I1,
            "J": J,
            "B1": self.E * I1,
            "B2": self.E * I1,
            "C": G * J,
            "mass_per_length": self.rho * A,
            "c": math.sqrt(G / self.rho),
        }
        derived["T1"] = 4.0 * self.L / derived["c"]
        for name, value in derived.items():
            object.__setattr__(self, name, value)

    @classmethod
    def paper(cls) -> Rod:
        """The rod of Table 1 (rho = 1500 kg/m^3), identical to ``Rod()``."""
        return cls()

    def with_(self, **changes: float) -> Rod:
        """A copy with some of E, nu, D, L, rho changed (derived values follow)."""
        return replace(self, **changes)

    def as_dict(self) -> dict[str, float]:
        """All parameters, given and derived, as a plain dict (for provenance records)."""
        return {f.name: getattr(self, f.name) for f in fields(self)}
