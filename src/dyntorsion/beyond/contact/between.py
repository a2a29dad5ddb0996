"""Work between the steps of a run past contact: shape, overlap, energy and topology.

What a run past contact does between steps (:mod:`.run`): the rebuilt shape, the
contact law on it for the reported overlap, the energy budget and the topology (the
engine's stop test on the lagged route, consulted after every step by the engine (:mod:`.source`) on
the implicit one), and the lagged route through the engine."""

from __future__ import annotations

from typing import Any

import numpy as np

from ...buckling.simulation import RECORDED
from ...buckling.stops import STRAIGHT
from ...genalpha import ConvergenceError, Output, Problem, Sources, Stops, integrate
from ...model.cosserat import Cosserat, Params
from .budget import SchemeBudget
from .centreline import Reconstruction
from .law import NO_CONTACT, contact_forces, contact_sites
from .topology import closed_polygon, link_turns, passage, twist_turns, writhe_turns


class Between:
    """What the run does between steps (module docstring): the engine's stop test and the
    source q(s, t) of the next level."""

    def __init__(self, cs: Any, model: Cosserat, y0, ds, dt, q_seed, check_every,
                 time_route: bool):  # fmt: skip
        rod, self.c = cs.scene.rod, cs.contact
        self.model, self.ds, self.dt, self.rod = model, ds, dt, rod
        self.law = cs.contact.law(rod, ds)
        self.q_seed, self.f_seed = q_seed, -q_seed[:, 0:3]
        #: the implicit contact acts on the time route (:mod:`.centreline`): the geometry of
        #: the law, the writhe and the shapes; the lagged one on the spatial route
        self.time = cs.contact.implicit
        anchor = self.time and cs.contact.route == "anchored"
        self.recon = Reconstruction(
            y0, ds, rod.L, time_route=time_route or self.time, anchor=anchor
        )
        n1 = y0.shape[0]
        self.weights = np.full(n1, ds)
        self.weights[[0, -1]] = 0.5 * ds
        self.q = {0: np.zeros((n1, 12))}
        self.pending = np.zeros((n1, 12))
        self.check_every, self.k = check_every, 0
        self.theta = [0.0, 0.0]
        self.y_old = np.array(y0, float)
        self.max_overlap, self.max_sites, self.sites = 0.0, 0, 0
        #: the first touch of two parts of the rod, and of the rod and an end fixture
        self.first_self_t: float | None = None
        self.first_fixture_t: float | None = None
        self.max_cell_bend = 0.0
        self.approach = 0.0
        self.e0 = self._energy(y0)
        self.work = {"ends": 0.0, "seed": 0.0, "contact": 0.0, "viscous": 0.0}
        self.power_old = self._powers(y0, np.zeros((n1, 12)))
        self.dashpot, self.de = 0.0, 0.0
        #: the budget as the scheme keeps it (:mod:`.budget`; the implicit route fills it)
        self.budget = SchemeBudget(Params(*model.params), ds, self.c.viscous, self.c.viscous_moment)
        self.shapes: list[np.ndarray] = []
        tw0 = twist_turns(y0[:, 8], ds)
        self.lk0 = tw0 + writhe_turns(closed_polygon(self.recon.r))
        self.hist: dict[str, list] = {k: [] for k in (
            "t", "link", "twist", "writhe", "sites", "overlap_over_D", "contact_energy",
            "energy", "work", "end_moment")}  # fmt: skip
        self.worst_gap, self.last_gap, self.passage = 0.0, 0.0, None
        self._topology(0.0, y0, 0, 0.0)

    @property
    def first_contact_t(self) -> float | None:
        """The first touch of any kind: the earlier of the rod on itself and on a fixture."""
        times = [t for t in (self.first_self_t, self.first_fixture_t) if t is not None]
        return min(times) if times else None

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
        fixture = cf.touching[:, 1] < 0  # (segment, -1 - end) for a fixture
        if self.first_self_t is None and (~fixture).any():
            self.first_self_t = float(t)
        if self.first_fixture_t is None and fixture.any():
            self.first_fixture_t = float(t)
        if (self.k % self.check_every == 0) if check is None else check:
            self._topology(t, y, self.sites, overlap, cf.energy)
            if self.passage is not None:
                return self.passage
        return self._resolved(t, y)

    def _resolved(self, t: float, y: np.ndarray) -> str | None:
        """The run's stop where the bending within one cell, ds |kappa_b|, passes the
        contact's ``max_cell_bend``: the grid no longer resolves the loop."""
        bend = self.ds * np.hypot(y[:, 6], y[:, 7])
        j = int(np.argmax(bend))
        self.max_cell_bend = max(self.max_cell_bend, float(bend[j]))
        if bend[j] <= self.c.max_cell_bend:
            return None
        n = y.shape[0] - 1
        need = int(np.ceil(n * bend[j] / self.c.max_cell_bend))
        return (
            f"under-resolved: the bending within a cell reached {bend[j]:.3g} rad at "
            f"t={t:.6g} s (node {j} of {n}: curvature {bend[j] / self.ds:.4g} 1/m, a loop of "
            f"radius {self.ds / bend[j] / self.rod.thickness:.3g} D on cells of "
            f"{self.ds / self.rod.thickness:.3g} D); max_cell_bend is "
            f"{self.c.max_cell_bend:g} rad: refine the grid (n_cells >= {need} holds this "
            "curvature at the limit; loops after contact tighten further) or raise "
            "max_cell_bend"
        )

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
                          ("energy", self._energy(y) - self.e0), ("work", sum(self.work.values())),
                          ("end_moment", self.rod.C * y[0, 8])):  # fmt: skip
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


def run_lagged(between, system, scene, grid, y0, left, right, q_seed):
    """The lagged route through the engine (module docstring), checked every
    ``between.check_every`` steps: the run and how it ended."""
    check_every = between.check_every
    try:
        run = integrate(
            Problem(
                system,
                y0,
                left,
                right,
                sources=Sources(separable=(q_seed, None), field=between.field),
            ),
            grid,
            scheme=scene.scheme,
            newton=scene.newton,
            output=Output(record=RECORDED, every=check_every, progress=False),
            stops=Stops(test=between, check_every=1),
        )
        return run, run.stopped
    except ConvergenceError as err:
        if err.run is None:
            raise
        return err.run, f"failed: {err}"
