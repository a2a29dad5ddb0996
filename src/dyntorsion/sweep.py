"""Sweeps of the buckling scene over loading rates (section 6, Fig 10), cached in ``data/``.

A :class:`Scene` is everything one buckling run and its onset depend on;
:func:`run_scene` computes it (a plain function, so any process or cluster
worker can run it); :func:`run_sweep` runs a list of scenes on any
:class:`concurrent.futures.Executor`, writes each finished scene to a
:class:`~dyntorsion.results.Store` at once, and skips scenes the store already
holds, so a killed sweep resumes where it stopped.

The presets (:data:`PRESETS`) are the sweeps behind Fig 10 and the direct runs
of Figs 8 and 9 that the fitted law is checked against; ``make data`` computes
them all.
"""

from __future__ import annotations

import concurrent.futures as cf
import math
import os
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from .buckling import (
    BucklingRun,
    Perturbation,
    _load,
    check_window,
    classify_onset,
    detect_onset,
    simulate,
)
from .genalpha import Newton, Scheme, StepControl
from .genalpha.guard import check_time_grid, real
from .loading import ENDS, AxialLoad, Ends, History, Ramp, ends_from_params, history_from_params
from .loading import ends as _ends
from .model import Cosserat
from .results import Store, digest
from .rod import Rod
from .statics import critical_twist, euler_load
from .workers import MissingResultError, cached_map

__all__ = [
    "Scene",
    "run_scene",
    "run_sweep",
    "simulate_scene",
    "cached_map",
    "MissingResultError",
    "KIND",
    "DATA",
    "default_store",
    "FIG10_RATES",
    "SEEDS",
    "PRESETS",
    "preset",
    "cached",
    "paper_law",
]

KIND = "buckling-onset"

#: the source tree's data folder (``data/scenes``)
DATA = Path(__file__).resolve().parents[2] / "data" / "scenes"


def default_store() -> Path:
    """The store used when none is given: ``$DYNTORSION_DATA`` if set, else :data:`DATA`."""
    env = os.environ.get("DYNTORSION_DATA")
    return Path(env) if env else DATA


#: the paper's fit, eq (34); used only to choose how long a run may last
PAPER_B, PAPER_SIGMA = 160.60, 0.5680


def paper_law(a: float | np.ndarray, rod: Rod, kappa_cri: float | None = None):
    """kappa3 of eq (33) with the paper's b = 160.60 and sigma = 0.5680 (eq 34)."""
    kc = critical_twist(rod) if kappa_cri is None else kappa_cri
    return kc + PAPER_B / rod.L * (np.asarray(a) * rod.L / rod.c) ** PAPER_SIGMA


@dataclass(frozen=True)
class Scene:
    """One buckling run and its onset: everything the result depends on, as data.

    The paper's scene is a ramp kappa3(0, t) = kappa0 + a t (``a``; ``kappa0`` default
    10); any other end twist is a ``history`` (:mod:`dyntorsion.loading`; then ``a`` and
    ``kappa0`` stay None).  ``tension`` is the axial end load [N] (a number or an
    :class:`~dyntorsion.loading.AxialLoad`), ``ends`` a named end-condition set or an
    :class:`~dyntorsion.loading.Ends`; ``terms`` and ``rotary_inertia_scale`` are the
    model switches of :class:`~dyntorsion.model.Cosserat`.

    ``t_end=None`` lets the run last until the twist reaches
    kappa_cri + ``horizon`` x (the paper's delay at this rate, eq 33-34), with kappa_cri
    the static critical twist of this rod, load and ends; scenes the static theory or
    the rule does not cover (a non-ramp history, a ramped load, other ends) need an
    explicit ``t_end``.  The run stops earlier at self-contact or at a Newton failure
    after the onset.  A run that ends before the onset is reported as such, not hidden.
    """

    a: float | None = None
    kappa0: float | None = None
    rod: Rod = field(default_factory=Rod)
    seed: Perturbation = field(default_factory=Perturbation)
    n_cells: int = 100
    dt: float = 0.005
    t_end: float | None = None
    horizon: float = 3.0
    scheme: Scheme = field(default_factory=Scheme)
    newton: Newton = field(default_factory=Newton)
    window: tuple[float, float] = (0.1, 0.5)
    variations: tuple[tuple[float, float], ...] = ((0.05, 0.3), (0.2, 0.7))
    terms: tuple[tuple[str, float], ...] = ()
    rotary_inertia_scale: float = 1.0
    history: History | None = None
    tension: AxialLoad | float = 0.0
    ends: Ends | str = "clamped"

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        if not isinstance(self.rod, Rod):
            raise TypeError(f"rod={self.rod!r} must be a dyntorsion.Rod")
        if self.history is None:
            if self.a is None:
                raise ValueError("a=None: give the loading rate a (the paper's ramp) or a history")
            if not real("a", self.a, " [rad/(m s)]") > 0:
                raise ValueError(f"a={self.a!r} must be a finite loading rate > 0 rad/(m s)")
            kappa0 = 10.0 if self.kappa0 is None else real("kappa0", self.kappa0, " [1/m]")
            set_(self, "a", float(self.a))
            set_(self, "kappa0", float(kappa0))
        else:
            if not isinstance(self.history, History):
                raise TypeError(f"history={self.history!r} must be a dyntorsion.loading.History")
            if self.a is not None or self.kappa0 is not None:
                raise ValueError("give either a (and kappa0) or a history, not both")
        if not isinstance(self.n_cells, int | np.integer) or self.n_cells < 2:
            raise ValueError(f"n_cells={self.n_cells!r} must be an integer >= 2")
        if not real("dt", self.dt, " [s]") > 0:
            raise ValueError(f"dt={self.dt!r} must be > 0")
        if not real("horizon", self.horizon) > 0:
            raise ValueError(f"horizon={self.horizon!r} must be > 0")
        check_window(self.window, self.variations)
        set_(self, "window", tuple(float(v) for v in self.window))
        set_(self, "variations", tuple(tuple(float(v) for v in w) for w in self.variations))
        set_(self, "n_cells", int(self.n_cells))
        set_(self, "dt", float(self.dt))
        set_(self, "terms", _canonical_terms(self.terms))
        set_(self, "rotary_inertia_scale", real("rotary_inertia_scale", self.rotary_inertia_scale))
        set_(self, "tension", _load(self.tension))
        set_(self, "ends", _ends(self.ends))
        Cosserat(self.rod, terms=dict(self.terms), rotary_inertia_scale=self.rotary_inertia_scale)
        if self.t_end is not None and not real("t_end", self.t_end, " [s]") > 0:
            raise ValueError(f"t_end={self.t_end!r} must be > 0 (or None for the horizon rule)")
        if self.duration() <= 0:
            raise ValueError(
                f"kappa0={self.kappa0} lies beyond the horizon twist "
                f"{self.kappa0 + self.a * self.duration():.4g}; give t_end"
            )
        check_time_grid(self.dt, self.duration())

    @classmethod
    def from_params(cls, p: Mapping[str, Any]) -> Scene:
        """The scene of a cache key (:meth:`params`): ``Scene.from_params(s.params())``
        has the key of ``s``."""
        hist = history_from_params(p["history"])
        twist = (
            {"a": hist.a, "kappa0": hist.kappa0} if isinstance(hist, Ramp) else {"history": hist}
        )
        seed = dict(p["perturbation"])
        seed["direction"] = tuple(seed["direction"])
        model = p["model"]
        return cls(
            **twist,
            rod=Rod.from_params(p["rod"]),
            seed=Perturbation(**seed),
            n_cells=p["n_cells"],
            dt=p["dt"],
            t_end=p["t_end"],
            scheme=Scheme(**p["scheme"]),
            newton=Newton(**p["newton"]),
            window=tuple(p["onset"]["window"]),
            variations=tuple(tuple(v) for v in p["onset"]["variations"]),
            terms=tuple(model["terms"].items()),
            rotary_inertia_scale=model["rotary_inertia_scale"],
            tension=AxialLoad(**p["load"]),
            ends=ends_from_params(p["ends"]),
        )

    @property
    def twist(self) -> History:
        """The end-twist history kappa3(0, t) (the ramp kappa0 + a t unless ``history``)."""
        return self.history if self.history is not None else Ramp(a=self.a, kappa0=self.kappa0)

    def kappa_cri(self) -> float:
        """The static critical twist of this rod, axial load and ends
        (:func:`~dyntorsion.statics.critical_twist`); raises where the theory does not
        reach (ends other than eq 30, a ramped load)."""
        if (self.ends.left, self.ends.right) != (ENDS["clamped"].left, ENDS["clamped"].right):
            raise ValueError(
                f"ends={self.ends.name!r}: no static critical twist (the static theory covers "
                "the clamped ends of eq 30)"
            )
        if self.tension.T_rate != 0.0:
            raise ValueError("a ramped axial load has no single static critical twist")
        return critical_twist(self.rod, self.tension.T)

    def duration(self) -> float:
        """The run's t_end (explicit, or from the horizon rule)."""
        if self.t_end is not None:
            return float(self.t_end)
        if self.history is not None:
            raise ValueError(
                f"history={self.history.label()}: the horizon rule (t_end=None) needs the "
                "paper's ramp; give t_end"
            )
        try:
            kc = self.kappa_cri()
        except ValueError as err:
            raise ValueError(f"t_end=None (the horizon rule): {err}; give t_end") from None
        kappa_end = kc + self.horizon * (float(paper_law(self.a, self.rod, kc)) - kc)
        return (kappa_end - self.kappa0) / self.a

    def params(self) -> dict[str, Any]:
        """Everything the result depends on (the cache key), canonical: the rod with its
        derived section properties, the end twist, the axial load, the end conditions,
        the model switches, seed, grid, scheme, Newton options and onset rule."""
        return {
            "rod": self.rod.params(),
            "history": self.twist.params(),
            "load": self.tension.params(),
            "ends": self.ends.params(),
            "model": {
                "terms": dict(self.terms),
                "rotary_inertia_scale": self.rotary_inertia_scale,
            },
            "perturbation": asdict(self.seed),
            "n_cells": self.n_cells,
            "dt": self.dt,
            "t_end": self.duration(),
            "scheme": self.scheme.params(),
            "newton": asdict(self.newton),
            "onset": {
                "window": list(self.window),
                "variations": [list(v) for v in self.variations],
            },
        }

    def label(self) -> str:
        twist = (
            f"a={self.a:.4g} kappa0={self.kappa0:g}"
            if self.history is None
            else self.history.label()
        )
        plain = self.rod.rho is not None and self.rod == Rod(rho=self.rod.rho)
        rod = "" if plain else f" rod=[{self.rod.describe()}]"
        return (
            f"{twist} rho={self.rod.rho if self.rod.rho is not None else '-'}{rod} "
            f"seed={self.seed.magnitude:g} N={self.n_cells} dt={self.dt:g}"
            + (f" T={self.tension.T:g}" if self.tension.T else "")
            + (f" T_rate={self.tension.T_rate:g}" if self.tension.T_rate else "")
            + (f" ends={self.ends.name}" if self.ends.name != "clamped" else "")
            + "".join(f" {k}={v:g}" for k, v in self.terms)
            + (f" rotary={self.rotary_inertia_scale:g}" if self.rotary_inertia_scale != 1 else "")
        )


def _canonical_terms(terms: Any) -> tuple[tuple[str, float], ...]:
    """Model switches as a sorted tuple of (name, weight); a name given twice is refused
    (it would be keyed as one weight and simulated with another)."""
    pairs = list(terms.items()) if isinstance(terms, Mapping) else list(terms)
    names = [str(k) for k, _ in pairs]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise ValueError(f"terms: switch(es) {twice} given more than once")
    out = []
    for k, v in pairs:
        try:
            w = float(v)
        except (TypeError, ValueError):
            raise ValueError(f"terms[{k!r}]={v!r} must be a number (a weight, 1 = on)") from None
        if not math.isfinite(w):
            raise ValueError(f"terms[{k!r}]={v!r} must be a finite weight")
        out.append((str(k), w))
    return tuple(sorted(out))


def simulate_scene(scene: Scene, t_end: float | None = None) -> BucklingRun:
    """:func:`~dyntorsion.buckling.simulate` with everything ``scene`` sets, to ``t_end``
    (default: the scene's own duration); a Newton failure ends the run."""
    return simulate(
        scene.rod,
        history=scene.twist,
        tension=scene.tension,
        ends=scene.ends,
        n_cells=scene.n_cells,
        dt=scene.dt,
        t_end=scene.duration() if t_end is None else t_end,
        perturbation=scene.seed,
        scheme=scene.scheme,
        newton=scene.newton,
        progress=False,
        on_failure="return",
        terms=dict(scene.terms),
        rotary_inertia_scale=scene.rotary_inertia_scale,
    )


def run_scene(scene: Scene) -> dict[str, Any]:
    """Simulate one scene and detect its onset (section 6): a JSON-ready dict whose
    ``status`` says what happened (:func:`~dyntorsion.buckling.classify_onset`: only
    ``"buckled"`` onsets measure the delay law; a ``"forced"`` one keeps its t_c and
    kappa3, with ``onset_error`` saying why it is no critical twist)."""
    run = simulate_scene(scene)
    try:
        kc = scene.kappa_cri()
    except ValueError:
        kc = None
    out: dict[str, Any] = {
        "stopped": run.stopped,
        "steps": int(run.t.size - 1),
        "t_last": float(run.t[-1]),
        "u3_peak": float(np.max(np.abs(run.u3_end))),
        "kappa_cri": kc,
    }
    if scene.scheme.control is not None:
        out["control"] = run.run.meta["control"]
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
        )
        return out
    status = classify_onset(run, onset, kc)
    passes = "t = 0" if kc is None else f"the end twist passes kappa_cri = {kc:.4g} 1/m"
    forced = (
        f"forced: the onset (t_c = {onset.t_c:.4g} s, end twist {onset.kappa3:.4g} 1/m) comes "
        f"before {passes}: the seed bent the rod, no delayed instability"
    )
    out.update(
        status=status,
        onset_error=forced if status == "forced" else None,
        t_c=onset.t_c,
        kappa3=onset.kappa3,
        uncertainty_t=onset.uncertainty_t,
        uncertainty_kappa3=onset.uncertainty_kappa3,
        slope=onset.slope,
        intercept=onset.intercept,
        t_ref=onset.t_ref,
        u_ref=onset.u_ref,
    )
    return out


def _row(scene: Scene, record: dict[str, Any], cached: bool) -> dict[str, Any]:
    res = record["result"]
    family = {k: v for k, v in record["params"].items() if k != "t_end"}
    family["history"] = {k: v for k, v in family["history"].items() if k != "a"}
    return {
        "a": scene.twist.rate,
        "kappa0": scene.twist.kappa0,
        "rho": scene.rod.rho,
        "rod": scene.rod.describe(),
        "tension": scene.tension.T,
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
    try:
        kc = scene.kappa_cri()
    except ValueError:
        kc = -math.inf
    return "buckled" if res["t_c"] >= 0 and abs(res["kappa3"]) >= kc else "forced"


def run_sweep(
    scenes: Sequence[Scene],
    store: Store | str | Path | None = None,
    *,
    executor: cf.Executor | None = None,
    jobs: int = 1,
    on_stale: str = "recompute",
    compute: bool = True,
    progress: bool | None = None,
    log: Callable[[str], None] | None = None,
) -> pd.DataFrame:
    """Run (or read back) a sweep; one table row per scene, in the given order.

    Scenes that differ only in the loading rate share a ``family`` (a hash of
    their other parameters): one rate sweep, ready for
    :func:`~dyntorsion.buckling.fit_power_law`.

    Scenes already in ``store`` (default :func:`default_store`: ``$DYNTORSION_DATA`` or :data:`DATA`) are read, not recomputed;
    the others run on ``executor`` (any :class:`concurrent.futures.Executor`, for
    example ``dask.distributed.Client.get_executor()``), or on ``jobs`` local
    processes (``jobs=1``: in this process).  Each finished scene is written to
    the store the moment it completes, so an interrupted sweep loses at most the
    scenes that were running.  ``on_stale`` is passed to
    :meth:`~dyntorsion.results.Store.load`; ``compute=False`` only reads, and
    raises :class:`MissingResultError` for any scene the store lacks.
    """
    records = cached_map(
        scenes,
        run_scene,
        KIND,
        store,
        executor=executor,
        jobs=jobs,
        on_stale=on_stale,
        compute=compute,
        progress=progress,
        log=log,
        show="kappa3",
        command="dyntorsion sweep",
    )
    return pd.DataFrame([_row(scenes[i], *records[i]) for i in range(len(scenes))])


# ----------------------------------------------------------------- presets
#: 16 loading rates, 1.6 x 10^(k/6) for k = -9..6: 0.0506 to 16 rad/(m s), 2.5 decades
FIG10_RATES: tuple[float, ...] = tuple(float(1.6 * 10 ** (k / 6)) for k in range(-9, 7))

#: the seed stated in section 6 (1e-8 N, read as N/m along the rod) and the seed
#: that reproduces the onset times of Figs 8 and 9 (see the Fig 8 page)
SEEDS: dict[str, Perturbation] = {"stated": Perturbation(1e-8), "tiny": Perturbation(1e-17)}


def _fig10(seed: str, rates: Iterable[float] = FIG10_RATES, **grid: Any) -> list[Scene]:
    return [Scene(a=a, kappa0=10.0, seed=SEEDS[seed], **grid) for a in rates]


def _fig08_09(seed: str) -> list[Scene]:
    return [
        Scene(a=1.6, kappa0=0.0, rod=Rod(rho=rho), seed=SEEDS[seed]) for rho in (1500.0, 5000.0)
    ]


def _grid(seed: str) -> list[Scene]:
    ends = (FIG10_RATES[0], 1.6, FIG10_RATES[-1])
    return [
        sc for n, dt in ((50, 0.01), (200, 0.0025)) for sc in _fig10(seed, ends, n_cells=n, dt=dt)
    ]


#: the grid ladder of the accuracy-and-cost page: N x dt, Courant number 28.9 on the diagonal
LADDER_N: tuple[int, ...] = (25, 50, 100, 200, 400)
LADDER_DT: tuple[float, ...] = (0.02, 0.01, 0.005, 0.0025, 0.00125)
#: Newton tolerances of the sensitivity study
NEWTON_TOLS: tuple[float, ...] = (1e-3, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12)


def _ladder(a: float, kappa0: float) -> list[Scene]:
    return [Scene(a=a, kappa0=kappa0, n_cells=n, dt=dt) for n in LADDER_N for dt in LADDER_DT]


#: the seeds of the Fig 8 page: uniform magnitudes [N/m], then point forces of 1e-8 N
FIG08_SEEDS: tuple[Perturbation, ...] = (
    *(Perturbation(m) for m in (1e-6, 1e-8, 1e-10, 1e-12, 1e-14, 1e-16, 1e-17)),
    *(Perturbation(1e-8, "point", x) for x in (0.5, 0.1, 0.9)),
)


def _fig08_seeds() -> list[Scene]:
    return [Scene(a=1.6, kappa0=0.0, seed=seed) for seed in FIG08_SEEDS]


#: imperfection sensitivity ("Why is buckling delayed?"): three rates, uniform seeds
#: 1e-12..1e-4 N/m, point seeds of 1e-8 N at three places, and no seed at all
IMPERFECTION_RATES: tuple[float, ...] = (0.2, 1.6, 12.8)
IMPERFECTION_SEEDS: tuple[Perturbation, ...] = (
    *(Perturbation(10.0**k) for k in range(-12, -3)),
    *(Perturbation(1e-8, "point", x) for x in (0.1, 0.5, 0.9)),
    Perturbation(0.0),
)


def _imperfection() -> list[Scene]:
    return [Scene(a=a, kappa0=10.0, seed=p) for a in IMPERFECTION_RATES for p in IMPERFECTION_SEEDS]


#: mechanisms ("Why is buckling delayed?"): the gyroscopic term off, the bending rotary
#: inertia scaled by 0.1 and 10 (torsional wave speed unchanged), and the rotating-frame
#: transport term rho A (w x u) off (not a physical model: a probe of the spin coupling of
#: the lateral motion), at the three rates
MECHANISMS: dict[str, dict[str, Any]] = {
    "gyroscopic term off": {"terms": (("gyro", 0.0),)},
    "rotary inertia x 0.1": {"rotary_inertia_scale": 0.1},
    "rotary inertia x 10": {"rotary_inertia_scale": 10.0},
    "rotating-frame transport off": {"terms": (("wxu", 0.0),)},
}


def _mechanisms() -> list[Scene]:
    return [Scene(a=a, kappa0=10.0, **kw) for a in IMPERFECTION_RATES for kw in MECHANISMS.values()]


#: the delay law under an axial load ("Tension and compression" page): loads as fractions
#: of the clamped Euler load 4 pi^2 B / L^2, every third Fig 10 rate, the stated seed,
#: and the pretwist at the paper's ratio kappa0 / kappa_cri = 10 / 11.2335 of each load
TENSION_FRACTIONS: tuple[float, ...] = (-0.5, -0.25, 0.0, 0.5, 1.0)
TENSION_RATES: tuple[float, ...] = FIG10_RATES[::3]


def tension_scenes(fraction: float, rates: Iterable[float] = TENSION_RATES) -> list[Scene]:
    """The rate sweep at axial load ``fraction`` x the clamped Euler load (Table 1 rod)."""
    rod = Rod()
    T = fraction * euler_load(rod, "clamped")
    kappa0 = 10.0 if T == 0.0 else 10.0 * critical_twist(rod, T) / critical_twist(rod)
    return [Scene(a=a, kappa0=kappa0, tension=T, seed=SEEDS["stated"]) for a in rates]


def _newton(a: float, kappa0: float) -> list[Scene]:
    return [Scene(a=a, kappa0=kappa0, newton=Newton(tol=tol)) for tol in NEWTON_TOLS]


#: name -> function returning the scenes; ``make data`` runs them all
PRESETS: dict[str, Callable[[], list[Scene]]] = {
    "fig10": lambda: _fig10("stated"),
    "fig10-tiny-seed": lambda: _fig10("tiny"),
    "fig08-09": lambda: _fig08_09("stated"),
    "fig08-09-tiny-seed": lambda: _fig08_09("tiny"),
    "fig10-grid": lambda: _grid("stated"),
    "fig10-grid-tiny-seed": lambda: _grid("tiny"),
    "accuracy-fig08": lambda: _ladder(1.6, 0.0),
    "accuracy-fast": lambda: _ladder(16.0, 10.0),
    "newton-fig08": lambda: _newton(1.6, 0.0),
    "newton-fast": lambda: _newton(16.0, 10.0),
    "fig08-seeds": _fig08_seeds,
    "imperfection": _imperfection,
    "mechanisms": _mechanisms,
    "tension": lambda: [sc for f in TENSION_FRACTIONS for sc in tension_scenes(f)],
}


def cached(name: str, store: Store | str | Path | None = None) -> pd.DataFrame:
    """The table of a named preset read from ``store`` (default :func:`default_store`: ``$DYNTORSION_DATA`` or :data:`DATA`), computing
    nothing: a missing scene raises :class:`MissingResultError`, a stale one
    :class:`~dyntorsion.results.StaleResultError`, each asking for ``make data``."""
    return run_sweep(preset(name), store, compute=False, on_stale="error", progress=False)


#: the step-size control every preset runs with (issue 15): identical to fixed steps
#: until the first rejected step, so the onsets do not move, and the runs go on past the
#: post-buckling whip to self-contact or t_end instead of stopping on a Newton failure
PRESET_CONTROL = StepControl()


def preset(name: str) -> list[Scene]:
    """The scenes of a named sweep (see :data:`PRESETS`), each with the step-size
    control :data:`PRESET_CONTROL`."""
    if name not in PRESETS:
        raise ValueError(f"preset={name!r}; allowed: {', '.join(PRESETS)}")
    return [
        replace(sc, scheme=replace(sc.scheme, control=PRESET_CONTROL)) for sc in PRESETS[name]()
    ]
