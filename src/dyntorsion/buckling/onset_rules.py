"""Onset rules: the ways to read a critical time off the rise of ``|u3(L, t)|`` (section 6).

The paper finds t_c by "linearly fitting the initial dramatic variation and
extrapolating back to u3 = 0" and does not say which part of the rise it fits.  The
consistency map (:mod:`dyntorsion.studies.consistency`) therefore reads every run with each of
:data:`RULES`:

* ``"window 10-50 %"``: the straight line through the samples between 10 % and 50 % of
  the first peak, extrapolated to u3 = 0 (this package's default,
  :func:`~dyntorsion.buckling.onset.detect_onset`);
* ``"window 20-80 %"``: the same between 20 % and 80 % of the peak;
* ``"steepest tangent"``: the tangent at the steepest point of the rise (largest
  dU/dt before the peak), extrapolated to u3 = 0;
* ``"threshold"``: the first time U reaches u_ref = L / T0 (no extrapolation: the level a
  linear theory predicts, :mod:`dyntorsion.beyond.linear_stability`).

:func:`run_rules` simulates one :class:`~dyntorsion.buckling.scene.Scene` and returns the onset
under every rule; its records are of kind :data:`KIND`.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .onset import WINDOW, classify_onset, detect_onset, first_peak
from .run import BucklingRun
from .scene import Scene, simulated

__all__ = ["KIND", "RULES", "WINDOWS", "steepest_tangent", "onsets_by_rule", "run_rules"]

KIND = "onset-rules"

#: the window rules: name -> (low, high) fraction of the first peak of ``|u3(L, t)|``
WINDOWS: dict[str, tuple[float, float]] = {
    "window 10-50 %": WINDOW,
    "window 20-80 %": (0.2, 0.8),
}
#: every rule, in the order of the tables
RULES: tuple[str, ...] = (*WINDOWS, "steepest tangent", "threshold")


def steepest_tangent(t: np.ndarray, U: np.ndarray, i_start: int) -> float:
    """t_c of the tangent at the steepest point of the rise of ``U = |u3(L, t)|``: the
    largest centred difference dU/dt between sample ``i_start`` (U reaches u_ref) and
    the first peak (:func:`~dyntorsion.buckling.onset.first_peak`, as
    :func:`~dyntorsion.buckling.onset.detect_onset`), extrapolated to U = 0."""
    i_peak = first_peak(U, i_start)
    lo, hi = max(i_start, 1), min(i_peak, U.size - 2)
    if hi < lo:
        raise ValueError("the rise holds fewer than 3 samples: refine dt")
    idx = np.arange(lo, hi + 1)
    slope = (U[idx + 1] - U[idx - 1]) / (t[idx + 1] - t[idx - 1])
    j = idx[int(np.argmax(slope))]
    s = float(slope[j - lo])
    if not s > 0:
        raise ValueError("|u3(L, t)| does not rise before its first peak")
    return float(t[j] - U[j] / s)


def onsets_by_rule(run: BucklingRun, u_ref: float | None = None) -> dict[str, float]:
    """t_c of ``run`` under every rule of :data:`RULES` (raises ``ValueError`` where
    ``|u3(L, t)|`` never reaches ``u_ref``, default L / T0)."""
    out = {}
    for name, window in WINDOWS.items():
        onset = detect_onset(run, window=window, variations=(), u_ref=u_ref)
        out[name] = onset.t_c
    t, U = np.asarray(run.t), np.abs(np.asarray(run.u3_end))
    i_start = int(np.nonzero(U >= onset.u_ref)[0][0])
    out["steepest tangent"] = steepest_tangent(t, U, i_start)
    out["threshold"] = onset.t_ref
    return out


def run_rules(scene: Scene) -> dict[str, Any]:
    """Simulate ``scene`` and read its onset under every rule: a JSON-ready dict with
    ``t_c`` and ``kappa3`` (the end twist at t_c) per rule and the ``status`` of the
    default rule (:func:`~dyntorsion.buckling.onset.classify_onset`)."""
    run, kc, out = simulated(scene)
    try:
        t_c = onsets_by_rule(run)
    except ValueError as err:
        out.update(status=classify_onset(run, None, kc), onset_error=str(err), rules=None)
        return out
    default = detect_onset(run, window=scene.window, variations=())
    out.update(
        status=classify_onset(run, default, kc),
        onset_error=None,
        rules={
            name: {"t_c": float(tc), "kappa3": float(run.end_twist(tc))} for name, tc in t_c.items()
        },
    )
    return out
