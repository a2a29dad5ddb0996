"""The slenderness bound of the thin-rod model (section 2): a buckling run of a rod thicker
than a tenth of its length is outside the theory the equations (6) come from."""

from __future__ import annotations

from ..model.rod import Rod

__all__ = ["SLENDERNESS", "check_slender"]

#: the thin-rod theory of section 2 (inextensible, unshearable: "slender structures") is a
#: model of a rod at least this many thicknesses long; a buckling run of a thicker one is refused
SLENDERNESS = 10.0


def check_slender(rod: Rod) -> None:
    """Refuse a rod too thick for the thin-rod model: thickness / L above 1 / :data:`SLENDERNESS`
    (the thickness is the diameter D of a circle, the contact thickness of other sections).

    Raises
    ------
    ValueError
        Naming the thickness [m], L [m], their ratio, the allowed range (0, 0.1] and the
        theory's limit.
    """
    if not rod.L >= SLENDERNESS * rod.thickness:
        raise ValueError(
            f"the rod's thickness {rod.thickness:g} m (D of a circle) over its length "
            f"L={rod.L:g} m is {rod.thickness / rod.L:.3g}; allowed range (0, {1 / SLENDERNESS:g}]: "
            f"the thin-rod theory (section 2) models rods at least {SLENDERNESS:g} thicknesses long"
        )
