"""Paced steps: a buckling scene whose time step is a fixed fraction of its own onset
time, as the fast onset estimate predicts it.

The standard grid (N = 100, dt = 0.005 s) resolves the torsional transit of the
Table 1 rod at every loading rate, so a slow scene pays for tens of thousands of
steps: at a = 0.05 rad/(m s) the onset comes after 55 s.  What the onset time needs
resolved is the growth of the bending (section 6), and that takes a time of the
order of the onset time itself: a slow ramp buckles slowly.  :func:`paced` sets

    dt = t_ref / steps

with t_ref the threshold time of :func:`~dyntorsion.beyond.predictions.estimate`
(the uniform-ramp passage of the linear theory, a few ms), rounded to three
significant digits, so that every scene reaches its onset in about ``steps`` steps
whatever its rate, and loosens the Newton tolerance to ``tol`` (the onset does not
see the difference: "Accuracy and cost" page).  The estimate only sets the step: an
estimate 30 % off costs 30 % more or fewer steps, never a different onset rule.

The defaults (384 steps, tol 1e-6) were chosen on the 16 rates of Fig 10 by comparing
the paced onsets with the standard grid's and with the converged onset, in a fraction of
the steps and of the time (the "Accuracy and cost" page shows the comparison).  They
are a choice for the Table 1 rod, not a guarantee for another: check a new rod or load
against the standard grid on a few rates first.
"""

from __future__ import annotations

import math
from dataclasses import replace

from ..beyond.predictions import estimate
from ..buckling.scene import Scene

__all__ = ["STEPS", "TOL", "paced", "paced_dt"]

#: steps to the estimated onset
STEPS = 384
#: Newton tolerance of the paced scenes
TOL = 1e-6


def paced_dt(scene: Scene, steps: int = STEPS) -> float:
    """The time step that reaches the estimated onset of ``scene`` in ``steps`` steps,
    to three significant digits."""
    if isinstance(steps, bool) or not isinstance(steps, int) or not 16 <= steps <= 10**6:
        raise ValueError(f"steps={steps!r} must be an integer in [16, 1000000]")
    if not isinstance(scene, Scene):
        raise TypeError(f"scene={scene!r} must be a dyntorsion.buckling.scene.Scene")
    try:
        est = estimate(scene)
    except ValueError as err:
        raise ValueError(
            f"paced steps need the fast onset estimate, which does not cover this scene ({err}); "
            "give the scene's dt yourself"
        ) from None
    if not (math.isfinite(est.t_ref) and est.t_ref > 0):
        raise ValueError(
            f"the fast onset estimate finds no onset for {scene.label()}: no time scale to pace "
            "the steps by; give the scene's dt yourself"
        )
    return float(f"{est.t_ref / steps:.3g}")


def paced(scene: Scene, steps: int = STEPS, tol: float = TOL) -> Scene:
    """``scene`` with the time step :func:`paced_dt` and the Newton tolerance ``tol``;
    everything else (rod, rate, seed, N, scheme, ``until``) as it was."""
    if isinstance(tol, bool) or not isinstance(tol, int | float) or not 0 < tol < 1:
        raise ValueError(f"tol={tol!r} must be a number in (0, 1)")
    return replace(scene, dt=paced_dt(scene, steps), newton=replace(scene.newton, tol=float(tol)))
