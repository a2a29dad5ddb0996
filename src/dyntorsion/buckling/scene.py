"""The buckling scene as data (section 6): :class:`Scene` holds everything one run and
its onset depend on -- rod, end twist, axial load, ends, model switches, seed, grid,
scheme, Newton options, onset rule -- and is the cache key of its record;
:func:`run_scene` simulates it and detects its onset (a plain function, so any process
or cluster worker can run it).  Sweeps over scenes are in :mod:`dyntorsion.studies.sweep`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from ..genalpha import Newton, Scheme
from ..genalpha.guard import check_time_grid, real
from ..model.cosserat import Cosserat
from ..model.ends import Ends, ends_from_params
from ..model.ends import ends as _ends
from ..model.rod import Rod
from .delay_law import paper_law
from .loading import ENDS, AxialLoad, History, Ramp, SmoothStart, history_from_params
from .onset import WINDOW, check_window, classify_onset, detect_onset
from .resolution import judge
from .run import BucklingRun
from .scene_fields import TYPED as _TYPED
from .scene_fields import canonical_terms as _canonical_terms
from .scene_fields import public as _public
from .seed import Perturbation
from .simulation import _load, simulate
from .statics import critical_twist

__all__ = ["Scene", "UNTIL", "START", "simulate_scene", "simulated", "run_scene"]

#: how far a scene's run goes (:class:`Scene` ``until``)
UNTIL = ("contact", "first-peak")
#: the initial states of a scene (:class:`Scene` ``start``)
START = ("pretwisted", "step", "smooth")


@dataclass(frozen=True)
class Scene:
    """One buckling run and its onset: everything the result depends on, as data.

    The paper's scene is a ramp kappa3(0, t) = kappa0 + a t (``a``; ``kappa0`` default
    10); any other end twist is a ``history`` (:mod:`dyntorsion.buckling.loading`; then ``a`` and
    ``kappa0`` stay None).  ``tension`` is the axial end load [N] (a number or an
    :class:`~dyntorsion.buckling.loading.AxialLoad`), ``ends`` a named end-condition set or an
    :class:`~dyntorsion.model.ends.Ends`; ``terms`` and ``rotary_inertia_scale`` are the
    model switches of :class:`~dyntorsion.model.cosserat.Cosserat`.

    ``t_end=None`` lets the run last until the twist reaches
    kappa_cri + ``horizon`` x (the paper's delay at this rate, eq 33-34), with kappa_cri
    the static critical twist of this rod, load and ends; scenes the static theory or
    the rule does not cover (a non-ramp history, a ramped load, other ends) need an
    explicit ``t_end``.  The run stops earlier at self-contact or at a Newton failure
    after the onset.  A run that ends before the onset is reported as such, not hidden.

    ``start`` is the initial state, which the paper gives twice: ``"pretwisted"``
    (default; section 5: "the rod is pretwisted by a twisting moment C h(0)", uniformly
    to kappa0 without stress in bending), ``"step"`` (section 6: the unstressed rod,
    y(s, 0) = 0, so that the end twist jumps to kappa0 at t = 0) or ``"smooth"`` (the
    unstressed rod with kappa0 brought in by section 5's transition over about
    ``start_tau``, :class:`~dyntorsion.buckling.loading.SmoothStart`).

    ``until="first-peak"`` ends the run, too, once ``|u3(L, t)|`` has passed its first
    peak (``simulate(stop_after_first_peak=True)``): the same onset under every rule of
    :mod:`~dyntorsion.buckling.onset_rules`, without the whip after it (``"contact"``, the
    default, follows the whip to self-contact; it is left out of :meth:`params` so that
    the keys of such scenes do not change).
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
    window: tuple[float, float] = WINDOW
    variations: tuple[tuple[float, float], ...] = ((0.05, 0.3), (0.2, 0.7))
    terms: tuple[tuple[str, float], ...] = ()
    rotary_inertia_scale: float = 1.0
    history: History | None = None
    tension: AxialLoad | float = 0.0
    ends: Ends | str = "clamped"
    until: str = "contact"
    start: str = "pretwisted"
    start_tau: float = 0.02

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        if self.until not in UNTIL:
            raise ValueError(f"until={self.until!r}; allowed: {', '.join(map(repr, UNTIL))}")
        if self.start not in START:
            raise ValueError(f"start={self.start!r}; allowed: {', '.join(map(repr, START))}")
        if not real("start_tau", self.start_tau, " [s]") > 0:
            raise ValueError(f"start_tau={self.start_tau!r} must be > 0 s")
        if self.start == "smooth" and self.history is not None:
            raise ValueError(
                "start='smooth' shapes the paper's ramp; a history brings its own start "
                "(start='step' runs it from the unstressed rod)"
            )
        for name, kind in _TYPED.items():
            if not isinstance(getattr(self, name), kind):
                raise TypeError(f"{name}={getattr(self, name)!r} must be a {_public(kind)}")
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
                raise TypeError(
                    f"history={self.history!r} must be a dyntorsion.buckling.loading.History"
                )
            if self.a is not None or self.kappa0 is not None:
                raise ValueError("give either a (and kappa0) or a history, not both")
        if not isinstance(self.n_cells, int | np.integer) or self.n_cells < 2:
            raise ValueError(f"n_cells={self.n_cells!r} must be an integer >= 2")
        if not real("dt", self.dt, " [s]") > 0:
            raise ValueError(f"dt={self.dt!r} must be > 0")
        if not real("horizon", self.horizon) > 0:
            raise ValueError(f"horizon={self.horizon!r} must be > 0")
        if not isinstance(self.variations, tuple | list) or not self.variations:
            raise ValueError(
                f"variations={self.variations!r} must hold at least one window (lo, hi): "
                "the onset's uncertainty is its spread over them"
            )
        check_window(self.window, self.variations)
        set_(self, "window", tuple(float(v) for v in self.window))
        set_(self, "variations", tuple(tuple(float(v) for v in w) for w in self.variations))
        set_(self, "n_cells", int(self.n_cells))
        set_(self, "dt", float(self.dt))
        set_(self, "terms", _canonical_terms(self.terms))
        set_(self, "rotary_inertia_scale", real("rotary_inertia_scale", self.rotary_inertia_scale))
        set_(self, "tension", _load(self.tension))
        set_(self, "ends", _ends(self.ends))
        self.ends.check_history(self.twist)
        Cosserat(self.rod, terms=dict(self.terms), rotary_inertia_scale=self.rotary_inertia_scale)
        if self.t_end is not None and not real("t_end", self.t_end, " [s]") > 0:
            raise ValueError(f"t_end={self.t_end!r} must be > 0 (or None for the horizon rule)")
        if self.duration() <= 0:
            raise ValueError(
                f"kappa0={self.kappa0} lies beyond the horizon twist (kappa_cri + horizon x "
                "the paper's delay at this rate, eqs 33-34): the run would end before it starts; give t_end"
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
        if isinstance(hist, SmoothStart):
            twist = {"a": hist.a, "kappa0": hist.kappa0, "start_tau": hist.tau}
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
            until=p.get("until", "contact"),
            start=p.get("start", "pretwisted"),
        )

    @property
    def twist(self) -> History:
        """The end-twist history kappa3(0, t) (the ramp kappa0 + a t unless ``history``)."""
        if self.history is not None:
            return self.history
        if self.start == "smooth":
            return SmoothStart(a=self.a, kappa0=self.kappa0, tau=self.start_tau)
        return Ramp(a=self.a, kappa0=self.kappa0)

    def kappa_cri(self) -> float:
        """The static critical twist of this rod, axial load and ends
        (:func:`~dyntorsion.buckling.statics.critical_twist`); raises where the theory does not
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
            "perturbation": self.seed.params(),
            "n_cells": self.n_cells,
            "dt": self.dt,
            "t_end": self.duration(),
            "scheme": self.scheme.params(),
            "newton": asdict(self.newton),
            "onset": {
                "window": list(self.window),
                "variations": [list(v) for v in self.variations],
            },
            **({} if self.until == "contact" else {"until": self.until}),
            **({} if self.start == "pretwisted" else {"start": self.start}),
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
            + (f" until={self.until}" if self.until != "contact" else "")
            + (f" start={self.start}" if self.start != "pretwisted" else "")
            + (f" seed_frame={self.seed.frame}" if self.seed.frame != "body" else "")
            + (f" seed_duration={self.seed.duration:g}" if self.seed.duration else "")
            + (f" long={self.scheme.long_steps.factor}" if self.scheme.long_steps else "")
        )


def simulate_scene(scene: Scene, t_end: float | None = None) -> BucklingRun:
    """:func:`~dyntorsion.buckling.simulation.simulate` with everything ``scene`` sets, to ``t_end``
    (default: the scene's own duration); a Newton failure ends the run."""
    if not isinstance(scene, Scene):
        raise TypeError(f"scene={scene!r} must be a {_public(Scene)}")
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
        stop_after_first_peak=scene.until == "first-peak",
        start="pretwisted" if scene.start == "pretwisted" else "unstressed",
    )


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
    load = _load(scene.tension)
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
