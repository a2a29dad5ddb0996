"""A new end-twist history in one file: the paper's ramp modulated by a sine,

    kappa3(0, t) = kappa0 + a t + amp sin(2 pi freq t),

registered by its ``kind`` when this file is imported.  :func:`demo` runs it through a
Scene, the store (written and read back), a small sweep and the command line with
``--plugin``; with ``amp = 0`` it is the paper's ramp, and its onset is the ramp's to the
last digit."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dyntorsion.app.cli import main
from dyntorsion.buckling.history import History
from dyntorsion.buckling.scene import Scene, run_scene
from dyntorsion.studies.sweep import run_sweep


@dataclass(frozen=True)
class SineRamp(History):
    """kappa0 + a t + amp sin(2 pi freq t) [1/m]; a [1/(m s)], freq [Hz]."""

    a: float
    amp: float = 0.0
    freq: float = 1.0
    kappa0: float = 10.0
    kind = "sine-ramp"

    @property
    def rate(self) -> float:
        return self.a

    def __call__(self, t):
        t = np.asarray(t, dtype=float)
        return self.kappa0 + self.a * t + self.amp * np.sin(2 * np.pi * self.freq * t)


#: a coarse grid: each run takes a second or two
GRID = {"n_cells": 20, "dt": 0.01, "t_end": 3.0, "until": "first-peak"}


def demo(store: Path) -> dict:
    """Scene, store, sweep and command line for the sine ramp; the numbers to check."""
    plain = run_scene(Scene(a=16.0, kappa0=10.0, **GRID))
    same = run_scene(Scene(history=SineRamp(a=16.0), **GRID))
    wavy = Scene(history=SineRamp(a=16.0, amp=2.0, freq=2.0), **GRID)
    table = run_sweep([wavy, Scene(history=SineRamp(a=8.0, amp=2.0, freq=2.0), **GRID)],
                      store, progress=False)  # fmt: skip
    record = json.loads(next(Path(store).glob(f"*-{table['key'][0]}.json")).read_text())
    back = Scene.from_params(record["params"])
    status = main([
        "buckle", "--plugin", __file__, "--history", "sine-ramp:amp=2,freq=2", "--a", "16",
        "--kappa0", "10", "--n-cells", "20", "--dt", "0.01", "--t-end", "3",
        "--until", "first-peak", "--store", str(store),
    ])  # fmt: skip
    return {"plain": plain, "same": same, "table": table, "back": back, "wavy": wavy,
            "cli": status}  # fmt: skip
