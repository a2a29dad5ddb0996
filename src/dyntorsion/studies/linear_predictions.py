"""Cached linear predictions of the buckling scenes' onsets (beyond the paper).

A :class:`Prediction` is one :class:`~dyntorsion.buckling.scene.Scene` run through the slow
passage of :meth:`~dyntorsion.beyond.linear_stability.LateralModel.passage` (eq L2 of
:mod:`dyntorsion.beyond.linear_stability`); :func:`predict` caches them in ``data/`` like
the simulated scenes, and the presets mirror the sweeps they explain.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, Unpack

import numpy as np
import pandas as pd

from ..beyond.predictions import Prediction, run_prediction
from ..buckling.scene import Scene
from ..store.results import Store
from ..store.workers import MapOptions, cached_map
from .presets import IMPERFECTION_RATES
from .presets import preset as sweep_preset_scenes

__all__ = [
    "KIND",
    "Prediction",
    "run_prediction",
    "predict",
    "VARIANTS",
    "PRESETS",
    "preset",
    "cached",
]

#: record kind of a cached linear prediction (its code fingerprint: fingerprint.KIND_ROOTS)
KIND = "linear-onset"


def predict(
    preds: Sequence[Prediction],
    store: Store | str | Path | None = None,
    **options: Unpack[MapOptions],
) -> pd.DataFrame:
    """Run (or read back) linear predictions; one row per prediction, in order.

    Cached like the buckling scenes (:func:`~dyntorsion.store.workers.cached_map`): read from
    ``store`` (default :func:`~dyntorsion.store.location.default_store`) when present and fresh,
    otherwise computed on ``jobs`` processes and written the moment each finishes;
    ``compute=False`` raises :class:`~dyntorsion.store.workers.MissingResultError` for a
    missing one.
    """
    records = cached_map(
        preds,
        run_prediction,
        KIND,
        store,
        **{"progress": False, **options},
        show="kappa3_ref",
        command="dyntorsion linear",
    )
    rows = []
    for pred, (rec, _) in zip(preds, records, strict=True):
        res, sc = rec["result"], pred.scene
        rows.append(
            {
                "a": sc.a,
                "kappa0": sc.kappa0,
                "seed": sc.seed.magnitude,
                "seed_form": sc.seed.form,
                "location": sc.seed.location,
                "waves": pred.waves,
                "spin": pred.spin,
                "rotary_inertia": pred.rotary_inertia,
                "modes": pred.modes,
                "t_ref": np.nan if res["t_ref"] is None else res["t_ref"],
                "kappa3_ref": np.nan if res["kappa3_ref"] is None else res["kappa3_ref"],
                "wall_time_s": rec["provenance"].get("wall_time_s"),
            }
        )
    return pd.DataFrame(rows)


#: the variants of the linear model compared on the "Why is buckling delayed?" page
VARIANTS: dict[str, dict[str, Any]] = {
    "full: waves and spin": {},
    "no waves (uniform ramp)": {"waves": False},
    "no spin (twist imposed through the rod)": {"waves": False, "spin": False},
    "no rotary inertia": {"waves": False, "rotary_inertia": False},
    "32 modes (no waves)": {"waves": False, "modes": 32},
}


def _from(sweep_preset: str, **options: Any) -> list[Prediction]:
    return [Prediction(sc, **options) for sc in sweep_preset_scenes(sweep_preset)]


def _variants() -> list[Prediction]:
    rates = IMPERFECTION_RATES
    return [Prediction(Scene(a=a), **kw) for a in rates for kw in VARIANTS.values()]


def _imperfection() -> list[Prediction]:
    scenes = sweep_preset_scenes("imperfection")
    return [Prediction(sc, waves=False) for sc in scenes if sc.seed.magnitude > 0]


#: name -> function returning the predictions; ``make data-studies`` runs them all
PRESETS: dict[str, Callable[[], list[Prediction]]] = {
    "linear-fig10": lambda: _from("fig10"),
    "linear-fig10-tiny-seed": lambda: _from("fig10-tiny-seed", waves=False),
    "linear-imperfection": _imperfection,
    "linear-variants": _variants,
}


def preset(name: str) -> list[Prediction]:
    """The predictions of a named preset (see :data:`PRESETS`)."""
    if name not in PRESETS:
        raise ValueError(f"preset={name!r}; allowed: {', '.join(PRESETS)}")
    return PRESETS[name]()


def cached(name: str, store: Store | str | Path | None = None) -> pd.DataFrame:
    """A named preset's table read from ``store``, computing nothing."""
    return predict(preset(name), store, compute=False, on_stale="error")
