"""Sweeps of the buckling scene over loading rates (section 6, Fig 10), cached in ``data/``.

A :class:`~dyntorsion.buckling.scene.Scene` is everything one buckling run and its onset depend
on; :func:`~dyntorsion.buckling.scene.run_scene` computes it (both re-exported here);
:func:`run_sweep` runs a list of scenes on any
:class:`concurrent.futures.Executor`, writes each finished scene to a
:class:`~dyntorsion.store.results.Store` at once, and skips scenes the store already
holds, so a killed sweep resumes where it stopped.

The presets (:data:`PRESETS`) are the sweeps behind Fig 10 and the direct runs
of Figs 8 and 9 that the fitted law is checked against; ``make data`` computes
them all.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, Unpack

import numpy as np
import pandas as pd

from ..buckling.scene import Scene, run_scene, simulate_scene
from ..store.results import Store, digest, require_result
from ..store.workers import MapOptions, MissingResultError, cached_map

__all__ = [
    "Scene",
    "run_scene",
    "run_sweep",
    "simulate_scene",
    "cached_map",
    "MissingResultError",
    "KIND",
]

KIND = "buckling-onset"
#: what every onset record holds (a record without one is damaged: moved aside, recomputed)
require_result(
    KIND, ("status", "stopped", "steps", "t_c", "kappa3", "uncertainty_t", "uncertainty_kappa3")
)


def _row(scene: Scene, record: dict[str, Any], cached: bool) -> dict[str, Any]:
    res = record["result"]
    family = {k: v for k, v in record["params"].items() if k not in ("t_end", "dt")}
    family["history"] = {k: v for k, v in family["history"].items() if k != "a"}
    return {
        "a": scene.twist.rate,
        "kappa0": scene.twist.kappa0,
        "rho": scene.rod.rho,
        "rod": scene.rod.describe(),
        "tension": float(scene.tension(np.zeros(1))[0]),  # the axial load at t = 0
        "ends": scene.ends.name,
        "seed": scene.seed.magnitude,
        "seed_form": scene.seed.form,
        "n_cells": scene.n_cells,
        "dt": scene.dt,
        "status": res.get("status") or _legacy_status(scene, res),
        "t_c": res["t_c"],
        "kappa3": res["kappa3"],
        "t_ref": res.get("t_ref"),
        "uncertainty_t": res["uncertainty_t"],
        "uncertainty_kappa3": res["uncertainty_kappa3"],
        "t_c_continuous": res.get("t_c_continuous"),
        "kappa3_continuous": res.get("kappa3_continuous"),
        "onset_error": res.get("onset_error"),
        "stopped": res["stopped"],
        "steps": res["steps"],
        "wall_time_s": record["provenance"].get("wall_time_s"),
        "key": record["key"],
        "family": digest(family)[:12],
        "cached": cached,
    }


def _legacy_status(scene: Scene, res: Mapping[str, Any]) -> str:
    """The status of a record written before records carried one (read with
    ``on_stale="accept"``): from its t_c and kappa3 alone."""
    if res["t_c"] is None:
        return "failed" if res["stopped"].startswith("failed") else "no-onset"
    if res["t_c"] < 0:
        return "forced"
    try:
        kc = scene.kappa_cri()
    except ValueError:
        return "unclassified"
    return "buckled" if abs(res["kappa3"]) >= kc else "forced"


def run_sweep(
    scenes: Sequence[Scene],
    store: Store | str | Path | None = None,
    command: str = "dyntorsion sweep",
    **options: Unpack[MapOptions],
) -> pd.DataFrame:
    """Run (or read back) a sweep; one table row per scene, in the given order.

    Scenes that differ only in the loading rate and the time step share a ``family``
    (a hash of their other parameters): one rate sweep, ready for
    :func:`~dyntorsion.buckling.delay_law.fit_power_law`, also when the step follows the rate
    (:mod:`~dyntorsion.studies.pacing`); a family holding one rate at two steps is two sweeps
    (``dyntorsion fit`` splits it by the step).

    Scenes already in ``store`` (default :func:`~dyntorsion.store.location.default_store`) are read, not recomputed;
    the others run on ``executor`` (any :class:`concurrent.futures.Executor`, for
    example ``dask.distributed.Client.get_executor()``), or on ``jobs`` local
    processes (``jobs=1``: in this process).  Each finished scene is written to
    the store the moment it completes, so an interrupted sweep loses at most the
    scenes that were running.  ``on_stale`` is passed to
    :meth:`~dyntorsion.store.results.Store.load`; ``compute=False`` only reads, and
    raises :class:`MissingResultError` for any scene the store lacks, naming ``command``
    as the one that computes them.
    """
    bad = [s for s in scenes if not isinstance(s, Scene)]
    if bad:
        raise TypeError(
            f"scenes must be Scene objects (dyntorsion.buckling.scene.Scene); got "
            f"{type(bad[0]).__name__} {bad[0]!r}: build them with Scene(a=...)"
        )
    records = cached_map(
        scenes,
        run_scene,
        KIND,
        store,
        **options,
        show="kappa3",
        command=command,
    )
    return pd.DataFrame([_row(scenes[i], *records[i]) for i in range(len(scenes))])
