"""A buckling scene followed past self-contact: :class:`Contact` (the law and
its numbers), :class:`ContactScene` (a :class:`~dyntorsion.buckling.scene.Scene` with a
contact, keyed by the scene's key plus ``"contact"``: scenes without contact keep their
keys and records) and :func:`run_contact_scene`.

**Implicit (default).**  The contact inside the implicit step on the time route of the
centreline (:mod:`.implicit`), stepped by the engine as a state-dependent source (:mod:`.source`); between steps the bookkeeping
in :mod:`.between` (rebuild, law for the reported overlap, energy, topology) on that route.
**Lagged (``implicit=False``, the first cut).**  The scene's run through the engine,
:func:`dyntorsion.genalpha.integrate`, with two additions made between steps:

* the shape is rebuilt from the 12 fields (:mod:`.centreline`) and the contact law
  (:mod:`.law`) evaluated on it; its nodal forces, in body components per unit length
  (weights ds inside, ds/2 at the ends, those of the box scheme), are the source
  q = (-f, 0, 0, 0) of eq (7) at the next level: the contact is **lagged one step**.
  Lagged, the penalty is explicit, so the step is cut to omega_c dt <= ``stability``
  (omega_c = sqrt(k / rho A)): ``dt_run`` = scene.dt / m, m the smallest integer that
  does it -- the cost of the lag, stated in every result;
* optional linear viscous damping per length, f = -``viscous`` u, m = -``viscous_moment`` w
  (body frame), implicit, in the model (:mod:`.damped`).

Every ``check`` seconds it takes the topology (:mod:`.topology`): link from the end
rotations, twist from kappa3, writhe of the closed centreline; a passage of the rod
through itself (Lk - Tw - Wr jumps by ~2 between two checks; measured: 1.95 to 2.0) ends
the run with ``stopped = "passage: ..."``; the largest |Lk - Tw - Wr| before is the drift of
the reconstruction in turns (``max_link_gap_turns``).
Energy: the work done at the ends and by the seed and contact forces against the change
of kinetic + elastic energy; the rest is the scheme's numerical dissipation (lambda_inf =
-1 damps the highest modes) plus the error of the lag, reported as its own line.
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from ...buckling.scene import Scene
from ...genalpha import ConvergenceError, Grid, Output, Problem, Sources, integrate
from ...genalpha.guard import real
from ...genalpha.state import Substeps
from ...model.cosserat import Cosserat
from .between import Between, run_lagged
from .budget import share
from .damped import damped_system
from .law import LawParams, lag_cost
from .plectoneme import plectoneme_turns
from .source import ContactSource

__all__ = ["Contact", "ContactScene", "ContactRun", "PassageError", "run_contact_scene"]


#: the centrelines the implicit contact can act on (:class:`Contact`, ``route``)
ROUTES: tuple[str, ...] = ("anchored", "time")


class PassageError(RuntimeError):
    """The rod passed through itself (or round an end fixture): Lk - Tw - Wr jumped."""


@dataclass(frozen=True)
class Contact:
    """The contact law of :mod:`.law` and how the run applies it.

    stiffness : k [N/m^2], per unit length of rod, > 0; 5e7 holds the a = 16 loop's
        approach (1.05-1.23 m/s) to 1 % D (k >= rho A (v / 0.01 D)^2; 2e7 gave 1.04 %).
    damping : zeta, damping ratio of the contact oscillator, c = 2 zeta sqrt(k rho A), >= 0.
    min_arc : arc-length gap below which parts never touch, in diameters, >= 1.
    fixtures : the axis beyond both ends is an obstacle (see :mod:`.law`).
    viscous, viscous_moment : linear damping per length of the velocity [N s/m^2] and of
        the spin [N s], >= 0 (0: none).
    stability : omega_c dt_run <= stability (the lagged penalty's step), in (0, 2].
    implicit : the contact inside the implicit step (:mod:`.implicit`, :mod:`.source`);
        False: lagged one step (the first cut).
    max_step : implicit: dt_run = scene.dt / m <= max_step [s], > 0, the longest substep
        near contact (an accuracy bound: the implicit law is stable at any step).
    min_step : implicit: the shortest substep [s], > 0 and <= max_step; fast motion and
        failed Newton solves halve the substep down to it (:mod:`dyntorsion.genalpha.state_steps`).
    max_cell_bend : the run stops ("under-resolved: ...") once the bending within one
        cell, ds |kappa_b|, passes it [rad], > 0.  Measured, a = 16: the loop after the
        first contact tightens to a radius of a few D (3.5 D at N = 400 within 0.26 s);
        N = 200 failed in Newton once a cell held 1.5-2.1 rad; N = 400 with lambda_inf =
        -0.8 in time (0.83 rad) ran on to 3.45 s (data/contact/first_contact.json).
    smooth : implicit: the clip of the law smoothed over a force of ``smooth`` k D
        (:mod:`.implicit`, C3), in (0, 1].
    check : interval of the topology check and of the recorded histories [s], > 0.
    route : implicit: the centreline the contact acts on (:mod:`.centreline`),
        ``"anchored"`` (the time route set back onto the shape rebuilt from the 12 fields
        after every step) or ``"time"`` (the time route left to run from t = 0).
        Measured, a = 16, lambda_inf = -0.8, to 3.3 s (data/contact/first_contact.json):
        anchored keeps Lk - Tw - Wr closer (0.0020 against 0.0094 turns on N = 800) but
        each reset moves the contact points by the step's gap between the two shapes
        (0.15 D), so the overlap reaches 5.3 % D against 0.54 %.
    """

    stiffness: float = 5e7
    damping: float = 0.5
    min_arc: float = 3.0
    fixtures: bool = True
    viscous: float = 0.0
    viscous_moment: float = 0.0
    stability: float = 0.5
    check: float = 0.01
    implicit: bool = True
    max_step: float = 2.5e-4
    smooth: float = 1e-3
    min_step: float = 1e-7
    max_cell_bend: float = 1.0
    route: str = "time"

    def __post_init__(self) -> None:
        for name, lo, strict, hi in (
            ("stiffness", 0.0, True, math.inf), ("damping", 0.0, False, math.inf),
            ("min_arc", 1.0, False, math.inf), ("viscous", 0.0, False, math.inf),
            ("viscous_moment", 0.0, False, math.inf), ("stability", 0.0, True, 2.0),
            ("check", 0.0, True, math.inf), ("max_step", 0.0, True, math.inf),
            ("smooth", 0.0, True, 1.0), ("min_step", 0.0, True, math.inf),
            ("max_cell_bend", 0.0, True, math.inf),
        ):  # fmt: skip
            v = real(name, getattr(self, name))
            if not ((v > lo if strict else v >= lo) and v <= hi):
                low = f"{'>' if strict else '>='} {lo:g}"
                high = "" if hi == math.inf else f" and <= {hi:g}"
                raise ValueError(f"contact {name}={v!r} must be {low}{high}")
            object.__setattr__(self, name, float(v))
        if self.min_step > self.max_step:
            raise ValueError(
                f"contact min_step={self.min_step!r} must be <= max_step={self.max_step!r}"
            )
        if self.route not in ROUTES:
            raise ValueError(f"contact route={self.route!r}; allowed: {', '.join(ROUTES)}")
        object.__setattr__(self, "fixtures", bool(self.fixtures))
        object.__setattr__(self, "implicit", bool(self.implicit))

    def params(self) -> dict[str, Any]:
        return asdict(self)

    def omega(self, mass_per_length: float) -> float:
        """omega_c = sqrt(k / rho A) [rad/s]."""
        return math.sqrt(self.stiffness / mass_per_length)

    def law(self, rod, ds: float) -> LawParams:
        c = 2.0 * self.damping * math.sqrt(self.stiffness * rod.mass_per_length)
        return LawParams(rod.thickness, self.stiffness, c, ds, self.min_arc * rod.thickness)


@dataclass(frozen=True)
class ContactScene:
    """A buckling :class:`~dyntorsion.buckling.scene.Scene` run past self-contact with
    ``contact``; its key is the scene's plus ``"contact"`` (:meth:`params`)."""

    scene: Scene
    contact: Contact = field(default_factory=Contact)

    def __post_init__(self) -> None:
        if not isinstance(self.scene, Scene):
            raise TypeError(f"scene={self.scene!r} must be a dyntorsion.buckling.Scene")
        if not isinstance(self.contact, Contact):
            raise TypeError(f"contact={self.contact!r} must be a Contact")
        if not self.scene.seed.constant:
            raise ValueError(
                f"seed frame={self.scene.seed.frame!r}, duration={self.scene.seed.duration!r}: a "
                "run past contact applies the seed as a constant force in the body frame; give "
                "frame='body' and duration=None"
            )
        rod = self.scene.rod
        if not self.contact.min_arc * rod.thickness < rod.L:
            raise ValueError(
                f"contact min_arc={self.contact.min_arc!r} diameters: allowed range [1, "
                f"{rod.L / rod.thickness:g}), below the rod's length L / D (no two parts of it "
                "could touch)"
            )
        if self.scene.loads:
            raise ValueError(
                "loads: a run past contact applies the seed only (no distributed loads)"
            )
        self.scene.ends.require(
            "contact", "both ends held on the e3 axis close the writhe (eq 30's ends do)"
        )

    def params(self) -> dict[str, Any]:
        return {**self.scene.params(), "contact": self.contact.params()}

    def substeps(self) -> int:
        """m: dt_run = scene.dt / m, the smallest with omega_c dt_run <= stability (lagged)
        or dt_run <= max_step (implicit)."""
        if self.contact.implicit:
            return max(1, math.ceil(self.scene.dt / self.contact.max_step - 1e-12))
        w = self.contact.omega(self.scene.rod.mass_per_length)
        return max(1, math.ceil(w * self.scene.dt / self.contact.stability - 1e-12))

    @property
    def dt_run(self) -> float:
        return self.scene.dt / self.substeps()

    def label(self) -> str:
        c = self.contact
        return f"{self.scene.label()} contact[k={c.stiffness:g} zeta={c.damping:g} dt_run={self.dt_run:.3g}]"


@dataclass
class ContactRun:
    """The outcome: the engine's run, the histories at the checks (t, Lk, Tw, Wr, contact
    sites, max overlap / D, energies, the twisting moment C kappa3 at s = 0) and the summary :meth:`result`."""

    scene: ContactScene
    run: Any
    history: dict[str, np.ndarray]
    summary: dict[str, Any]

    @property
    def stopped(self) -> str:
        return self.summary["stopped"]

    def result(self) -> dict[str, Any]:
        """One JSON-ready dict (what ``dyntorsion buckle --contact --json`` prints)."""
        return dict(self.summary)

    def histories(self, *, plectoneme: bool = False) -> dict[str, list]:
        """The histories at the checks as JSON-ready lists, named as the records in
        ``data/bench`` and ``data/contact`` name them: ``t`` [s]; ``link_turns``,
        ``twist_turns``, ``writhe_turns``; contact ``sites``; the deepest overlap
        ``overlap_over_D``; the twisting moment at s = 0 ``end_moment`` [N m]; the far
        end's axial position ``end_axial_position`` [m].  ``plectoneme`` adds the
        plectoneme turns and touching pairs of each recorded centreline
        (:func:`~.plectoneme.plectoneme_turns` with its default reach)."""
        h = self.history
        out = {
            "t": h["t"].tolist(), "link_turns": h["link"].tolist(),
            "twist_turns": h["twist"].tolist(), "writhe_turns": h["writhe"].tolist(),
            "sites": h["sites"].tolist(), "overlap_over_D": h["overlap_over_D"].tolist(),
            "end_moment": h["end_moment"].tolist(),
            "end_axial_position": h["r"][:, -1, 2].tolist(),
        }  # fmt: skip
        if plectoneme:
            counts = [plectoneme_turns(r, self.scene.scene.rod.thickness) for r in h["r"]]
            out["plectoneme_turns"] = [p.turns for p in counts]
            out["plectoneme_pairs"] = [p.pairs for p in counts]
        return out

    def check(self) -> ContactRun:
        """Raise :class:`PassageError` if the rod passed through itself."""
        if self.stopped.startswith("passage"):
            raise PassageError(self.stopped)
        return self


def run_contact_scene(
    cs: ContactScene, t_end: float | None = None, *, time_route: bool = False
) -> ContactRun:
    """Run ``cs`` to ``t_end`` (default the scene's duration) past self-contact (module
    docstring); a Newton failure ends the run (``stopped = "failed: ..."``), so does a
    passage (``"passage: ..."``, :meth:`ContactRun.check` raises).  ``time_route`` also
    advances the time route of the shape every step to measure the drift of the
    reconstruction against it (:mod:`.centreline`; it costs about a tenth of the run)."""
    wall = time.perf_counter()
    scene = cs.scene
    rod = scene.rod
    t_end = scene.duration() if t_end is None else real("t_end", t_end, " [s]")
    if not t_end > 0:
        raise ValueError(f"t_end={t_end!r} must be > 0 [s]")
    dt, n = cs.dt_run, scene.n_cells
    model = Cosserat(rod, terms=dict(scene.terms), rotary_inertia_scale=scene.rotary_inertia_scale)
    c = cs.contact
    damped = c.viscous > 0 or c.viscous_moment > 0
    system = damped_system(model, c.viscous, c.viscous_moment) if damped else model.system()
    s = np.linspace(0.0, rod.L, n + 1)
    hist, load = scene.twist, scene.tension
    y0 = np.zeros((n + 1, 12))
    y0[:, system.index("k3")] = hist.initial_twist
    y0[:, system.index("n3")] = load(np.zeros(1))[0]
    left, right = scene.ends.rows(system, hist, load)
    q_seed = model.external_force(scene.seed.force(s, rod.L))
    check_every = max(1, int(round(cs.contact.check / dt)))
    between = Between(cs, model, y0, rod.L / n, dt, q_seed, check_every, time_route)
    if c.implicit:
        source = ContactSource(between, q_seed, y0, Substeps(cs.substeps(), c.min_step))
        problem = Problem(system, y0, left, right, Sources(separable=(q_seed, None), state=source))
        try:
            run = integrate(problem, Grid(n, rod.L, scene.dt, t_end), scheme=scene.scheme,
                            newton=scene.newton, output=Output(progress=False))  # fmt: skip
            stopped = run.stopped
        except ConvergenceError as err:
            if err.run is None:
                raise
            run, stopped = err.run, f"failed: {err}"
    else:
        run, stopped = run_lagged(between, system, scene, Grid(n, rod.L, dt, t_end), y0, left,
                                    right, q_seed)  # fmt: skip
    between.finish(run.y, stopped == "t_end" and not c.implicit)
    h = {k: np.asarray(v) for k, v in between.hist.items()}
    work = between.work
    w_in = work["ends"] + work["seed"]
    h["r"] = np.asarray(between.shapes)
    de = between.de
    numerical = sum(work.values()) - de
    summary = {
        "scene": cs.label(),
        "stopped": stopped,
        "t_last": float(h["t"][-1]),
        "dt_run": dt,
        "substeps": cs.substeps(),
        "steps": int(between.k),
        "first_contact_t": between.first_contact_t,
        "first_self_contact_t": between.first_self_t,
        "first_fixture_contact_t": between.first_fixture_t,
        "max_penetration_over_D": between.max_overlap,
        "contact_sites": between.sites,
        "max_contact_sites": between.max_sites,
        "plectoneme_turns": plectoneme_turns(h["r"][-1], rod.thickness, c.min_arc).turns,
        "link_turns": float(h["link"][-1]),
        "twist_turns": float(h["twist"][-1]),
        "writhe_turns": float(h["writhe"][-1]),
        "max_link_gap_turns": between.worst_gap,
        "max_cell_bend": between.max_cell_bend,
        **lag_cost(cs.scene.rod, cs.contact.stability, between.approach),
        "energy": {
            "work_ends": work["ends"],
            "work_seed": work["seed"],
            "work_contact": work["contact"],
            "work_viscous": work["viscous"],
            "contact_dashpots": between.dashpot,
            "kinetic_plus_elastic_change": float(de),
            "contact_energy": float(h["contact_energy"][-1]),
            "numerical_dissipation": float(numerical),
        },  # fmt: skip
        "energy_residual": float(numerical / w_in) if w_in else 0.0,
        "energy_scheme": between.budget.as_dict() if c.implicit else None,
        "energy_residual_scheme": (
            -share(between.budget.as_dict(), "rest") if c.implicit else None
        ),  # fmt: skip
        "drift": between.recon.drift.as_dict(),
        "wall_time": time.perf_counter() - wall,
    }
    if c.implicit:
        summary["implicit"] = source.cost(run.meta["state"], rod.thickness)
    return ContactRun(cs, run, h, summary)
