"""A buckling scene followed past self-contact (issue 33): :class:`Contact` (the law and
its numbers), :class:`ContactScene` (a :class:`~dyntorsion.buckling.scene.Scene` with a
contact, keyed by the scene's key plus ``"contact"``: scenes without contact keep their
keys and records) and :func:`run_contact_scene`.

**Implicit (default).**  The contact inside the implicit step on the time route of the
centreline (:mod:`.implicit`), marched by :mod:`.marching`; between steps the bookkeeping
below (rebuild, law for the reported overlap, energy, topology) on that route.
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
from ...buckling.simulation import RECORDED
from ...buckling.stops import STRAIGHT
from ...genalpha import ConvergenceError, Grid, Output, Sources, Stops, integrate
from ...genalpha.guard import real
from ...model.cosserat import Cosserat
from .centreline import Reconstruction
from .damped import damped_system
from .law import NO_CONTACT, LawParams, contact_forces, contact_sites, lag_cost
from .marching import march_implicit
from .topology import closed_polygon, link_turns, passage, twist_turns, writhe_turns

__all__ = ["Contact", "ContactScene", "ContactRun", "PassageError", "run_contact_scene"]


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
    implicit : the contact inside the implicit step (:mod:`.implicit`, :mod:`.marching`);
        False: lagged one step (the first cut).
    max_step : implicit: dt_run = scene.dt / m <= max_step [s], > 0 (an accuracy bound:
        the implicit law is stable at any step).
    smooth : implicit: the clip of the law smoothed over a force of ``smooth`` k D
        (:mod:`.implicit`, C3), in (0, 1].
    check : interval of the topology check and of the recorded histories [s], > 0.
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

    def __post_init__(self) -> None:
        for name, lo, strict, hi in (
            ("stiffness", 0.0, True, math.inf), ("damping", 0.0, False, math.inf),
            ("min_arc", 1.0, False, math.inf), ("viscous", 0.0, False, math.inf),
            ("viscous_moment", 0.0, False, math.inf), ("stability", 0.0, True, 2.0),
            ("check", 0.0, True, math.inf), ("max_step", 0.0, True, math.inf),
            ("smooth", 0.0, True, 1.0),
        ):  # fmt: skip
            v = real(name, getattr(self, name))
            if not ((v > lo if strict else v >= lo) and v <= hi):
                low = f"{'>' if strict else '>='} {lo:g}"
                high = "" if hi == math.inf else f" and <= {hi:g}"
                raise ValueError(f"contact {name}={v!r} must be {low}{high}")
            object.__setattr__(self, name, float(v))
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
        if self.scene.ends.name not in ("clamped",):
            raise ValueError(
                f"ends={self.scene.ends.name!r}: past contact needs the ends of eq 30 "
                "('clamped'): both ends on the e3 axis close the writhe"
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
    sites, max overlap / D, energies) and the summary :meth:`result`."""

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

    def check(self) -> ContactRun:
        """Raise :class:`PassageError` if the rod passed through itself."""
        if self.stopped.startswith("passage"):
            raise PassageError(self.stopped)
        return self


class _Between:
    """What the run does between steps (module docstring): the engine's stop test and the
    source q(s, t) of the next level."""

    def __init__(self, cs: ContactScene, model: Cosserat, y0, ds, dt, q_seed, check_every,
                 time_route: bool):  # fmt: skip
        rod, self.c = cs.scene.rod, cs.contact
        self.model, self.ds, self.dt, self.rod = model, ds, dt, rod
        self.law = cs.contact.law(rod, ds)
        self.q_seed, self.f_seed = q_seed, -q_seed[:, 0:3]
        #: the implicit contact acts on the time route (:mod:`.centreline`): the geometry of
        #: the law, the writhe and the shapes; the lagged one on the spatial route
        self.time = cs.contact.implicit
        self.recon = Reconstruction(y0, ds, rod.L, time_route=time_route or self.time)
        n1 = y0.shape[0]
        self.weights = np.full(n1, ds)
        self.weights[[0, -1]] = 0.5 * ds
        self.q = {0: np.zeros((n1, 12))}
        self.pending = np.zeros((n1, 12))
        self.check_every, self.k = check_every, 0
        self.theta = [0.0, 0.0]
        self.y_old = np.array(y0, float)
        self.first_contact_t, self.max_overlap, self.max_sites, self.sites = None, 0.0, 0, 0
        self.approach = 0.0
        self.e0 = self._energy(y0)
        self.work = {"ends": 0.0, "seed": 0.0, "contact": 0.0, "viscous": 0.0}
        self.power_old = self._powers(y0, np.zeros((n1, 12)))
        self.dashpot, self.de = 0.0, 0.0
        self.shapes: list[np.ndarray] = []
        tw0 = twist_turns(y0[:, 8], ds)
        self.lk0 = tw0 + writhe_turns(closed_polygon(self.recon.r))
        self.hist: dict[str, list] = {k: [] for k in (
            "t", "link", "twist", "writhe", "sites", "overlap_over_D", "contact_energy",
            "energy", "work")}  # fmt: skip
        self.worst_gap, self.last_gap, self.passage = 0.0, 0.0, None
        self._topology(0.0, y0, 0, 0.0)

    def _energy(self, y) -> float:
        e = self.model.energy_density(y)
        return float(self.ds * (e.sum() - 0.5 * (e[0] + e[-1])))

    def _powers(self, y, q) -> np.ndarray:
        """Power at the ends, of the seed, of the contact and viscous sources [W]."""
        r = self.rod
        m0 = np.array([r.B1, r.B2, r.C]) * y[0, 6:9]
        mL = np.array([r.B1, r.B2, r.C]) * y[-1, 6:9]
        ends = (
            -(m0 @ y[0, 3:6] + y[0, 9:12] @ y[0, 0:3]) + mL @ y[-1, 3:6] + y[-1, 9:12] @ y[-1, 0:3]
        )
        w = self.weights
        seed = float(np.sum(w * np.einsum("ni,ni->n", self.f_seed, y[:, 0:3])))
        src = -q  # f of the source (the contact), body frame
        lin = float(np.sum(w * np.einsum("ni,ni->n", src[:, 0:3], y[:, 0:3])))
        visc = -float(np.sum(w * (self.c.viscous * np.sum(y[:, 0:3] ** 2, axis=1)
                                  + self.c.viscous_moment * np.sum(y[:, 3:6] ** 2, axis=1))))  # fmt: skip
        return np.array([ends, seed, lin, visc])

    def field(self, s, t: float) -> np.ndarray:
        """The source q(s, t) of the level at t (the contact part; lagged)."""
        key = int(round(t / self.dt))
        if key not in self.q:
            self.q[key] = self.pending
            self.q.pop(key - 3, None)
        return self.q[key]

    def __call__(self, t: float, y: np.ndarray, dt: float | None = None,
                 check: bool | None = None) -> str | None:  # fmt: skip
        """The engine's stop test at the level t, y: rebuild, contact, source, topology.
        ``dt`` the step that reached it (default the run's), ``check`` whether to take the
        topology there (default every ``check_every`` calls)."""
        self.k += 1
        y = np.asarray(y)
        if dt is not None:
            self.dt = dt
        self.recon.update(y, self.dt)
        self.theta[0] += 0.5 * self.dt * (y[0, 5] + self.y_old[0, 5])
        self.theta[1] += 0.5 * self.dt * (y[-1, 5] + self.y_old[-1, 5])
        # energy budget of the step just taken (trapezoidal powers, the source it used)
        p_new = self._powers(y, self.q.get(self.k, self.pending))
        dw = 0.5 * self.dt * (self.power_old + p_new)
        for name, v in zip(("ends", "seed", "contact", "viscous"), dw, strict=True):
            self.work[name] += float(v)
        v = self.recon.velocities(y, self.time)
        r_law = self.recon.frames(self.time)[1]
        if self.ds * np.sum(np.hypot(y[:, 6], y[:, 7])) < STRAIGHT:
            cf = NO_CONTACT._replace(force=np.zeros_like(v))  # no part can reach another
        else:
            cf = contact_forces(self.law, r_law, v, self.c.fixtures)
        f_body = self.recon.to_body(cf.force, self.time) / self.weights[:, None]
        q = np.zeros_like(self.pending)
        q[:, 0:3] = -f_body
        self.pending = q
        self.power_old = p_new
        self.dashpot += self.dt * cf.dissipation
        self.y_old = y.copy()
        overlap = cf.max_overlap / self.rod.thickness
        self.max_overlap = max(self.max_overlap, overlap)
        self.approach = max(self.approach, cf.approach)
        self.sites = contact_sites(cf.touching)
        self.max_sites = max(self.max_sites, self.sites)
        if cf.pairs and self.first_contact_t is None:
            self.first_contact_t = float(t)
        if (self.k % self.check_every == 0) if check is None else check:
            self._topology(t, y, self.sites, overlap, cf.energy)
            if self.passage is not None:
                return self.passage
        return None

    def finish(self, y: np.ndarray, last: bool) -> None:
        """The energy change at the final level y (``last``: the engine did not consult
        the test there, so the budget of the last step is added here)."""
        if last:
            p_new = self._powers(y, self.q.get(self.k + 1, self.pending))
            dw = 0.5 * self.dt * (self.power_old + p_new)
            for name, v in zip(("ends", "seed", "contact", "viscous"), dw, strict=True):
                self.work[name] += float(v)
        self.de = self._energy(y) - self.e0

    def _topology(self, t, y, sites, overlap, e_contact=0.0) -> None:
        tw = twist_turns(y[:, 8], self.ds)
        r = self.recon.frames(self.time)[1]
        wr = writhe_turns(closed_polygon(r))
        lk = link_turns(self.lk0, self.theta[0], self.theta[1])
        h = self.hist
        for name, val in (("t", t), ("link", lk), ("twist", tw), ("writhe", wr), ("sites", sites),
                          ("overlap_over_D", overlap), ("contact_energy", e_contact),
                          ("energy", self._energy(y) - self.e0), ("work", sum(self.work.values()))):  # fmt: skip
            h[name].append(float(val))
        self.shapes.append(r.copy())
        gap, jump = lk - tw - wr, lk - tw - wr - self.last_gap
        self.last_gap = gap
        if passage(gap - jump, gap) and self.passage is None:
            self.passage = (
                f"passage: the rod passed through itself at t <= {t:.6g} s (Lk - Tw - Wr = "
                f"{gap:.3f} turns, a jump of {jump:.3f} since the last check: a passage changes the writhe by 2 while the link and twist "
                "stay continuous); stiffen the contact, shorten the step or refine the grid"
            )
        else:  # the drift of the reconstruction, where no passage intervened
            self.worst_gap = max(self.worst_gap, abs(gap))


def _lagged(between, system, scene, grid, y0, left, right, q_seed, check_every):
    """The lagged route through the engine (module docstring): the run and how it ended."""
    try:
        run = integrate(
            system, grid, y0=y0, left=left, right=right, scheme=scene.scheme,
            newton=scene.newton, sources=Sources(separable=(q_seed, None), field=between.field),
            output=Output(record=RECORDED, every=check_every, progress=False),
            stops=Stops(test=between, check_every=1),
        )  # fmt: skip
        return run, run.stopped
    except ConvergenceError as err:
        if err.run is None:
            raise
        return err.run, f"failed: {err}"


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
    y0[:, system.index("k3")] = hist(np.zeros(1))[0]
    y0[:, system.index("n3")] = load(np.zeros(1))[0]
    left, right = scene.ends.rows(system, hist, load)
    q_seed = model.external_force(scene.seed.force(s, rod.L))
    check_every = max(1, int(round(cs.contact.check / dt)))
    between = _Between(cs, model, y0, rod.L / n, dt, q_seed, check_every, time_route)
    if c.implicit:
        grid = Grid(n, rod.L, scene.dt, t_end)
        run = march_implicit(between, system, scene.scheme, scene.newton, grid, y0, left, right,
                             q_seed, cs.substeps())  # fmt: skip
        stopped = run.stopped
    else:
        run, stopped = _lagged(between, system, scene, Grid(n, rod.L, dt, t_end), y0, left,
                               right, q_seed, check_every)  # fmt: skip
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
        "max_penetration_over_D": between.max_overlap,
        "contact_sites": between.sites,
        "max_contact_sites": between.max_sites,
        "link_turns": float(h["link"][-1]),
        "twist_turns": float(h["twist"][-1]),
        "writhe_turns": float(h["writhe"][-1]),
        "max_link_gap_turns": between.worst_gap,
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
        "drift": between.recon.drift.as_dict(),
        "wall_time": time.perf_counter() - wall,
    }
    if c.implicit:
        summary["implicit"] = run.cost(rod.thickness)
    return ContactRun(cs, run, h, summary)
