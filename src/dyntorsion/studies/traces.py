"""The end-shortening speed u3(L, t) of a buckling scene, simulated and linear, side by side.

The onset detector (:func:`~dyntorsion.buckling.onset.detect_onset`) and the linear
prediction (:mod:`~dyntorsion.beyond.linear_stability`) meet at one number, the time
``|u3(L, t)|`` reaches u_ref.  A trace comparison shows the whole approach: how long the
simulated rod follows the linear growth, and where it departs.  Records of kind
``onset-trace`` (cached in ``data/``, ``make data-studies``) hold both traces sampled on a
common time grid.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np

from ..beyond.linear_stability import LateralModel, PassageSteps
from ..buckling.onset import reference_level
from ..buckling.scene import Scene, simulate_scene
from ..store.location import default_store
from ..store.results import Store

__all__ = ["KIND", "SCENES", "compare", "load"]

KIND = "onset-trace"

#: the three rates of the imperfection study, stated seed, standard grid
SCENES: tuple[Scene, ...] = tuple(Scene(a=a) for a in (0.2, 1.6, 12.8))


def _params(scene: Scene, modes: int, samples: int) -> dict[str, Any]:
    return scene.params() | {"linear": {"modes": modes, "waves": True}, "samples": samples}


def compare(scene: Scene, modes: int = 16, samples: int = 1200) -> dict[str, Any]:
    """Simulate ``scene`` (stopping shortly after its u_ref crossing) and integrate the
    linear model with the torsional waves up to 30 u_ref; both ``|u3(L, t)|`` on
    ``samples`` common times (JSON-ready)."""
    rod = scene.rod
    u_ref = reference_level(rod)
    lin = LateralModel(rod, modes=modes).passage(
        scene.a, scene.kappa0, scene.seed, steps=PassageSteps(u_ref=30 * u_ref)
    )
    t_stop = 1.1 * lin.t_ref + 1.0
    run = simulate_scene(replace(scene, t_end=t_stop))
    t = np.linspace(0.0, min(run.t[-1], lin.t[-1]), samples)
    return {
        "t": t,
        "u3_simulated": np.interp(t, run.t, np.abs(run.u3_end)),
        "u3_linear": np.interp(t, lin.t, np.abs(lin.u3)),
        "u_ref": u_ref,
    }


def load(
    scenes: tuple[Scene, ...] = SCENES,
    store: Store | str | None = None,
    *,
    compute: bool = False,
    on_stale: str = "recompute",
    modes: int = 16,
    samples: int = 1200,
) -> list[dict[str, Any]]:
    """The trace records of ``scenes`` from ``store`` (default data/scenes); missing or
    stale ones are computed with ``compute=True`` (a stale one refused with
    ``on_stale="error"``) and refused otherwise."""
    store = (
        Store(default_store() if store is None else store)
        if not isinstance(store, Store)
        else store
    )
    out = []
    for sc in scenes:
        params = _params(sc, modes, samples)
        rec = store.load(KIND, params, on_stale=on_stale if compute else "error")
        if rec is None:
            if not compute:
                raise LookupError(
                    f"no {KIND} record for {sc.label()} in {store.root}: run `make data-studies`"
                )
            rec = store.read(store.save(KIND, params, compare(sc, modes, samples)))
        out.append(rec["result"])
    return out


if __name__ == "__main__":  # make data-studies
    import argparse

    from ..store.results import ON_STALE

    parser = argparse.ArgumentParser(description="compute the traces of the three scenes")
    parser.add_argument("--on-stale", choices=ON_STALE, default="recompute")
    args = parser.parse_args()
    for scene, rec in zip(SCENES, load(compute=True, on_stale=args.on_stale), strict=True):
        print(f"{scene.label()}: {len(rec['t'])} samples to t = {rec['t'][-1]:.4f} s")
