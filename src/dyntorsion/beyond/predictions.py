"""Linear predictions of one buckling scene's onset (beyond the paper): a
:class:`Prediction` is a :class:`~dyntorsion.buckling.scene.Scene` run through the slow
passage of :meth:`~dyntorsion.beyond.linear_stability.LateralModel.passage` (eq L2), and
:func:`estimate` the cheapest such passage that the pacing of a sweep needs."""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

from ..buckling.scene import Scene
from .linear_stability import LateralModel

__all__ = ["Prediction", "run_prediction", "Estimate", "estimate"]


@dataclass(frozen=True)
class Prediction:
    """The linear prediction of one buckling scene's onset.

    ``scene`` (a :class:`~dyntorsion.buckling.scene.Scene`) gives the rod, the rate, the
    pretwist and the seed; its grid, scheme and Newton options play no part.  The
    other fields are the options of :class:`LateralModel` and
    :meth:`LateralModel.passage`.
    """

    scene: Scene
    waves: bool = True
    spin: bool = True
    rotary_inertia: bool = True
    modes: int = 16
    terms: int = 8

    def model(self) -> LateralModel:
        return LateralModel(
            self.scene.rod,
            modes=self.modes,
            quadrature=max(128, 4 * self.modes + 16),
            rotary_inertia=self.rotary_inertia,
        )

    def __post_init__(self) -> None:
        sc = self.scene
        sc.ends.require("linear", "the linear prediction covers the paper's scene")
        if (
            sc.history is not None
            or not sc.tension.is_zero
            or sc.loads
            or sc.start != "pretwisted"
            or not sc.seed.constant
        ):
            raise ValueError(
                "the linear prediction covers the paper's scene (a ramp from the pretwisted "
                "rod, clamped ends of eq 30, no axial load, a constant seed in the body frame); "
                f"got {sc.label()}"
            )

    def params(self) -> dict[str, Any]:
        p = self.scene.params()
        return {
            "rod": p["rod"],
            "a": self.scene.a,
            "kappa0": self.scene.kappa0,
            "perturbation": p["perturbation"],
            "linear": {
                "waves": self.waves,
                "spin": self.spin,
                "rotary_inertia": self.rotary_inertia,
                "modes": self.modes,
                "quadrature": self.model().quadrature,
                "terms": self.terms if self.waves else None,
            },
        }

    def label(self) -> str:
        opts = [k for k in ("waves", "spin", "rotary_inertia") if not getattr(self, k)]
        return (
            f"linear a={self.scene.a:.4g} kappa0={self.scene.kappa0:g} "
            f"seed={self.scene.seed.magnitude:g} modes={self.modes}"
            + "".join(f" no-{k}" for k in opts)
        )


def run_prediction(pred: Prediction) -> dict[str, Any]:
    """Integrate one :class:`Prediction`: a JSON-ready dict (t_ref None if not reached)."""
    sc = pred.scene
    p = pred.model().passage(
        sc.a, sc.kappa0, sc.seed, waves=pred.waves, spin=pred.spin, terms=pred.terms
    )
    reached = math.isfinite(p.t_ref)
    return {
        "t_ref": p.t_ref if reached else None,
        "kappa3_ref": p.kappa3_ref if reached else None,
        "u_ref": p.u_ref,
        "t_last": float(p.t[-1]),
        "dt": p.params["dt"],
    }


@dataclass(frozen=True)
class Estimate:
    """A fast onset estimate (:func:`estimate`): the threshold time and twist of the
    uniform-ramp linear passage with the number of modes it chose."""

    t_ref: float
    kappa3_ref: float
    modes: int


@lru_cache(maxsize=32)
def _ramp_model(rod: Any, modes: int) -> LateralModel:
    return LateralModel(rod, modes=modes, quadrature=4 * modes + 16)


def estimate(scene: Scene, *, min_modes: int = 6, max_modes: int = 24) -> Estimate:
    """The onset of ``scene`` from the linear theory at the least cost: the passage of
    (L2) on the uniform ramp (no torsional waves), first with ``min_modes`` modes, then
    with enough modes for the helix the rod buckles into.

    At the twist kappa3 the critical helix of the clamped rod has the wave number
    M / (2 B) = C kappa3 / (2 B), about C kappa3 L / (2 pi B) half-waves along the rod;
    the second pass keeps twice that many beam modes plus two (within ``[min_modes,
    max_modes]``).  The rule is empirical: its error against the simulated onsets is
    measured on the "Accuracy and cost" page.  It covers the scenes
    :class:`Prediction` covers, and like the linear theory it fails for seeds that bend
    the rod appreciably before the instability (seeds of 1e-7 N/m and more here).
    """
    Prediction(scene)  # the scenes the linear theory covers, or a ValueError
    sc, rod = scene, scene.rod
    first = _ramp_model(rod, min_modes).passage(sc.a, sc.kappa0, sc.seed, waves=False)
    if not first.reached:
        return Estimate(math.nan, math.nan, min_modes)
    half_waves = rod.C * first.kappa3_ref * rod.L / (2 * math.pi * rod.B1)
    modes = int(min(max_modes, max(min_modes, math.ceil(2 * half_waves) + 2)))
    p = _ramp_model(rod, modes).passage(sc.a, sc.kappa0, sc.seed, waves=False)
    return Estimate(p.t_ref, p.kappa3_ref, modes)
