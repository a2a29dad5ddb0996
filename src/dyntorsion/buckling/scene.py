"""Running a buckling scene (section 6): :func:`run_scene` simulates a
:class:`~dyntorsion.buckling.spec.Scene` (defined in :mod:`.spec`, re-exported here) and
detects its onset (a plain function, so any process or cluster worker can run it).
Sweeps over scenes are in :mod:`dyntorsion.studies.sweep`."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .onset import classify_onset, detect_onset
from .resolution import judge
from .run import BucklingRun
from .simulation import simulate
from .spec import START, UNTIL, Scene

__all__ = ["Scene", "UNTIL", "START", "simulate_scene", "simulated", "run_scene"]


def simulate_scene(scene: Scene) -> BucklingRun:
    """:func:`~dyntorsion.buckling.simulation.simulate` of ``scene`` as a study runs it:
    no progress bar, and a Newton failure ends the run (``on_failure="return"``)."""
    return simulate(scene, progress=False, on_failure="return")


def simulated(scene: Scene) -> tuple[BucklingRun, float | None, dict[str, Any]]:
    """Simulate ``scene``: the run, the static critical twist of its rod, load and ends
    (None where the static theory does not reach, :meth:`Scene.kappa_cri`) and the
    JSON-ready head of every record of a simulated scene (``stopped``, ``steps``,
    ``kappa_cri``)."""
    run = simulate_scene(scene)
    try:
        kc = scene.kappa_cri()
    except ValueError:
        kc = None
    return run, kc, {"stopped": run.stopped, "steps": int(run.t.size - 1), "kappa_cri": kc}


def _unresolved(scene: Scene, run: BucklingRun, kc: float | None) -> dict[str, Any]:
    """``status="unresolved"``, why, and the grid that would resolve the growth, for a run
    without an onset whose grid could not see it (:func:`.resolution.judge`); else {}."""
    if kc is None or scene.seed.magnitude == 0.0 or run.t.size < 2:
        return {}
    t = np.union1d(run.t, np.linspace(run.t[0], run.t[-1], 100_001))
    load = scene.tension
    res = judge(
        scene.rod, t, run.end_twist(t), load(t), kc, scene.n_cells, scene.dt
    )  # fmt: skip
    if res is None or res.resolved:
        return {}
    return {
        "status": "unresolved",
        "onset_error": res.message(scene.n_cells, scene.dt),
        "needed": {"n_cells": res.n_cells, "dt": res.dt},
    }


#: why an onset of a scene without a static critical twist is ``"unclassified"``
UNCLASSIFIED = (
    "unclassified: no static kappa_cri for this scene (its ends or section are outside the "
    "static theory), so nothing tells a delayed instability from a rod bent by its seed"
)


def run_scene(scene: Scene) -> dict[str, Any]:
    """Simulate one scene and detect its onset (section 6): a JSON-ready dict whose
    ``status`` says what happened (:func:`~dyntorsion.buckling.onset.classify_onset`: only
    ``"buckled"`` onsets measure the delay law; a ``"forced"`` one keeps its t_c and
    kappa3, with ``onset_error`` saying why it is no critical twist)."""
    run, kc, out = simulated(scene)
    out.update(t_last=float(run.t[-1]), u3_peak=float(np.max(np.abs(run.u3_end))))
    if scene.scheme.control is not None:
        out["control"] = run.run.meta["control"]
    if scene.scheme.long_steps is not None:
        out["long_steps"] = run.run.meta["long_steps"]
    try:
        onset = detect_onset(run, window=scene.window, variations=scene.variations)
    except ValueError as err:
        out.update(
            status=classify_onset(run, None, kc),
            onset_error=str(err),
            t_c=None,
            kappa3=None,
            uncertainty_t=None,
            uncertainty_kappa3=None,
            t_ref=None,
            t_c_continuous=None,
            kappa3_continuous=None,
        )
        if out["status"] == "no-onset":
            out.update(_unresolved(scene, run, kc))
        return out
    status = classify_onset(run, onset, kc)
    continuous = {
        "t_c_continuous": onset.t_c_continuous,
        "kappa3_continuous": onset.kappa3_continuous,
    }
    passes = "t = 0" if kc is None else f"the end twist passes kappa_cri = {kc:.4g} 1/m"
    forced = (
        f"forced: the onset (t_c = {onset.t_c:.4g} s, end twist {onset.kappa3:.4g} 1/m) comes "
        f"before {passes}: the seed bent the rod, no delayed instability"
    )
    out.update(
        status=status,
        onset_error={"forced": forced, "unclassified": UNCLASSIFIED}.get(status),
        t_c=onset.t_c,
        kappa3=onset.kappa3,
        uncertainty_t=onset.uncertainty_t,
        uncertainty_kappa3=onset.uncertainty_kappa3,
        slope=onset.slope,
        intercept=onset.intercept,
        t_ref=onset.t_ref,
        u_ref=onset.u_ref,
        **{k: v if math.isfinite(v) else None for k, v in continuous.items()},
    )
    return out
