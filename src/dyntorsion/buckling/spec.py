"""The buckling scene as data (section 6): :class:`Scene` holds everything one run and
its onset depend on -- rod, end twist, axial and distributed loads, ends, model switches,
seed, grid, scheme, Newton options, onset rule -- and is the cache key of its record.
:mod:`.scene` runs it (:func:`~dyntorsion.buckling.scene.run_scene`)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from ..genalpha import Newton, Scheme
from ..genalpha.guard import check_time_grid, real
from ..model.cosserat import Cosserat
from ..model.ends import EQ30, Ends, ends_from_params
from ..model.ends import ends as _ends
from ..model.rod import Rod
from .delay_law import paper_law
from .loading import History, Ramp, SmoothStart, history_from_params
from .loads import DistributedLoad, EndLoad, as_load, distributed_from_params, load_from_params
from .onset import WINDOW, check_window
from .scene_fields import TYPED, canonical_terms, public
from .seed import Perturbation
from .statics import critical_twist

__all__ = ["Scene", "UNTIL", "START"]

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
    peak: the same onset under every rule of
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
    tension: EndLoad | float = 0.0
    loads: tuple[DistributedLoad, ...] = ()
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
        if not isinstance(self.seed, Perturbation):
            set_(self, "seed", Perturbation(magnitude=real("seed", self.seed, " [N/m]")))
        for name, kind in TYPED.items():
            if not isinstance(getattr(self, name), kind):
                raise TypeError(f"{name}={getattr(self, name)!r} must be a {public(kind)}")
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
        set_(self, "terms", canonical_terms(self.terms))
        set_(self, "rotary_inertia_scale", real("rotary_inertia_scale", self.rotary_inertia_scale))
        set_(self, "tension", as_load(self.tension))
        if not isinstance(self.loads, tuple | list):
            raise TypeError(
                f"loads={self.loads!r} must be a tuple of dyntorsion.buckling.loads.DistributedLoad"
            )
        set_(self, "loads", tuple(self.loads))
        for i, load in enumerate(self.loads):
            if not isinstance(load, DistributedLoad):
                raise TypeError(
                    f"loads[{i}]={load!r} must be a dyntorsion.buckling.loads.DistributedLoad"
                )
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
        twist = cls.twist_keywords(history_from_params(p["history"]))
        seed = dict(p["perturbation"])
        seed["direction"] = tuple(seed["direction"])
        model = p["model"]
        return cls(
            **{"start": p.get("start", "pretwisted"), **twist},
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
            tension=load_from_params(p["load"]),
            loads=tuple(distributed_from_params(q) for q in p.get("loads", ())),
            ends=ends_from_params(p["ends"]),
            until=p.get("until", "contact"),
        )

    @staticmethod
    def twist_keywords(history: History) -> dict[str, Any]:
        """The Scene keywords of an end history: ``a``, ``kappa0`` (and ``start_tau``) for
        the paper's ramp (and its smooth start), ``history`` for any other, so that a
        scene built from a history has the key of the scene it came from."""
        if type(history) is Ramp:
            return {"a": history.a, "kappa0": history.kappa0}
        if type(history) is SmoothStart:
            return {"a": history.a, "kappa0": history.kappa0, "start_tau": history.tau,
                    "start": "smooth"}  # fmt: skip
        return {"history": history}

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
        self.ends.require("static", "give the scene an explicit t_end")
        if self.tension.constant is None:
            raise ValueError(
                f"axial load {self.tension.label()}: a load that changes in time has "
                "no single static critical twist"
            )
        if self.loads:
            raise ValueError("distributed loads: the static theory covers end loads only")
        return critical_twist(self.rod, self.tension.constant, self.ends.static)

    @property
    def pretwisted(self) -> bool:
        """Whether the run starts from the rod pretwisted to the history's initial twist
        (``start="pretwisted"``), not from the unstressed rod (``"step"``, ``"smooth"``)."""
        return self.start == "pretwisted"

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
            **({"loads": [q.params() for q in self.loads]} if self.loads else {}),
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
            + (f" {self.tension.label()}" if self.tension.label() else "")
            + "".join(f" {q.label()}" for q in self.loads)
            + (f" ends={self.ends.name}" if self.ends != EQ30 else "")
            + "".join(f" {k}={v:g}" for k, v in self.terms)
            + (f" rotary={self.rotary_inertia_scale:g}" if self.rotary_inertia_scale != 1 else "")
            + (f" until={self.until}" if self.until != "contact" else "")
            + (f" start={self.start}" if self.start != "pretwisted" else "")
            + (f" seed_frame={self.seed.frame}" if self.seed.frame != "body" else "")
            + (f" seed_duration={self.seed.duration:g}" if self.seed.duration else "")
            + (f" long={self.scheme.long_steps.factor}" if self.scheme.long_steps else "")
        )
