"""The thin-rod theory of the plectoneme: the torque plateau of a
twisted rod under tension once a plectoneme grows, for the quasi-static comparison.

The plectoneme is taken as a uniform two-ply: two strands wound round each other, in
contact, so each strand's centreline lies on a helix of radius R = a (the rod's radius)
about the ply axis, at the ply angle alpha between a strand's tangent and that axis.  With
tension T and twisting moment M in the straight tails (Clauvelin, Audoly and Neukirch,
"Elasticity and electrostatics of plectonemic DNA", Biophys. J. 96 (2009) 3716, eqs 9a and
9c without the electrostatic energy, U = 0):

    T R^2 / B = sin^3(alpha) (cos(alpha) tan(2 alpha) - sin(alpha) / 2)      (9a)
    M = (2 / sin(2 alpha)) (B sin^4(alpha) / (2 R) + R T)                   (9c)

(eq 9a fixes alpha in (0, pi/4) at a given T; eq 9c gives the plateau torque).  They are the
coexistence of the ply with the straight tails: the energy per length of rod in the ply at
fixed M and T, g(alpha) = B sin^4(alpha) / (2 R^2) - M sin(2 alpha) / (2 R) + T (bending of
the strand, curvature sin^2(alpha) / R; the torque's work on the ply's writhe, sin(2 alpha)
/ (2 R) radians per length; the tension's work) must vanish and be stationary in alpha:
g = 0 and g' = 0 give 9a and 9c (checked in the tests).

For a thin rod, eps = a sqrt(T / B) -> 0, alpha ~ (2/3)^(1/4) eps^(1/2) and

    M = 2 (2/3)^(3/4) B^(1/4) T^(3/4) a^(1/2) (1 + eps / sqrt(6) + O(eps^2)),

so the plateau vanishes like sqrt(a): the rod's radius sets it at leading order, and
eps / sqrt(6) is the finite-radius correction to that leading term (not a correction to
Greenhill's 2 sqrt(B T), which is the buckling torque of the infinite rod, far above it).
The theory leaves out the end loop and the junctions of the ply with the tails (they
matter for short plies), friction, and the rod's own shear and extension.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from scipy.optimize import brentq

__all__ = ["Ply", "ply", "ply_torque_leading"]


class Ply(NamedTuple):
    """The uniform two-ply at tension T: ply angle ``alpha`` [rad], plateau torque
    ``torque`` [N m], writhe per length of rod in the ply ``writhe_per_length`` [turns/m]
    (sin(2 alpha) / (4 pi a)) and pitch ``pitch`` [m] (2 pi a / tan(alpha))."""

    alpha: float
    torque: float
    writhe_per_length: float
    pitch: float


def _positive(name: str, value: float) -> float:
    v = float(value)
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{name}={value!r} must be finite and > 0")
    return v


def ply(tension: float, bending: float, radius: float) -> Ply:
    """The two-ply of eqs 9a and 9c (module docstring) at tension T [N] > 0 for a rod of
    bending stiffness B [N m^2] and radius a [m] (the strands' helix radius R = a)."""
    T, B, a = (_positive(n, v) for n, v in (("tension", tension), ("bending", bending),
                                            ("radius", radius)))  # fmt: skip

    def eq9a(al: float) -> float:
        s, c = math.sin(al), math.cos(al)
        return s**3 * (c * math.tan(2 * al) - 0.5 * s) - T * a * a / B

    alpha = brentq(eq9a, 1e-12, math.pi / 4 - 1e-12, xtol=1e-300, rtol=8.9e-16)
    torque = 2.0 / math.sin(2 * alpha) * (B * math.sin(alpha) ** 4 / (2 * a) + a * T)
    return Ply(
        alpha, torque, math.sin(2 * alpha) / (4 * math.pi * a), 2 * math.pi * a / math.tan(alpha)
    )


def ply_torque_leading(tension: float, bending: float, radius: float) -> float:
    """The thin-rod limit 2 (2/3)^(3/4) B^(1/4) T^(3/4) a^(1/2) [N m] (module docstring)."""
    T, B, a = (_positive(n, v) for n, v in (("tension", tension), ("bending", bending),
                                            ("radius", radius)))  # fmt: skip
    return 2.0 * (2.0 / 3.0) ** 0.75 * B**0.25 * T**0.75 * math.sqrt(a)
