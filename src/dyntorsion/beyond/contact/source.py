"""The contact as a state-dependent source of the engine (:mod:`dyntorsion.genalpha.state`).

Each step, the candidate pairs from the known level (:func:`.implicit.candidates`); none:
the engine's own Newton solve of the step, as a scene without contact.  Some: the contact's
source and Jacobian at every iteration (the frames' blocks of (C5) into the banded
Jacobian, a rank-one term a pressing pair).  A step is split into substeps while the rod
moves fast (:meth:`ContactSource.too_fast`).  After every step the run's
:class:`.between.Between` does its bookkeeping (rebuild, the law on the rebuilt shape for the
reported overlap, the energy budget with the source the step used, topology) and may end
the run.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ...buckling.stops import STRAIGHT
from ...genalpha.state import StateSource, StateTerms, Substeps
from .budget import Level, Loads
from .implicit import Known, Layout, StepParams, candidates, contact_source

__all__ = ["ContactSource"]


class ContactSource(StateSource):
    """The implicit contact of one run: ``between`` its :class:`.between.Between`, ``q_seed``
    (N+1, nf) the seed's source, ``y0`` the initial level, ``substeps`` how a coupled step
    is split."""

    max_iterations = 12
    failure = "Newton did not converge (implicit contact step) at the shortest substep"

    def __init__(self, between, q_seed: np.ndarray, y0: np.ndarray, substeps: Substeps):
        self.between, self.substeps = between, substeps
        self.q_seed = np.ascontiguousarray(q_seed, float)
        self.y_old = y0
        self.largest, self.last, self._motion = 0.0, None, None

    def level(self, h: float, con) -> tuple[StepParams, Layout]:
        co, b = con.co, self.between
        sp = StepParams(b.law, h, 0.5, co.b_t, co.b_s, b.c.smooth)  # C1: the time route's rule
        layout = Layout(self.y_old.shape[1], con.left_rows.shape[0], con.rscale, con.yscale)
        return sp, layout

    def motion(self) -> dict[str, Any]:
        """The nodes' lab velocities at the known level, their largest speed and spin:
        computed once per accepted step (the known level changes only there)."""
        if self._motion is None:
            V = self.between.recon.velocities(self.y_old, True)
            self._motion = {
                "V": V,
                "speed": float(np.max(np.linalg.norm(V, axis=1))),
                "spin": float(np.max(np.linalg.norm(self.y_old[:, 3:6], axis=1))),
            }
        return self._motion

    def moved(self, y: np.ndarray) -> None:
        self.y_old, self._motion = y, None

    def begin(self, level, y_old: np.ndarray):
        sp, layout = level
        b = self.between
        if b.ds * np.sum(np.hypot(y_old[:, 6], y_old[:, 7])) < STRAIGHT:
            return None  # no part can reach another while the rod is nearly straight
        recon = b.recon
        pairs = candidates(sp.law, recon.frames(True)[1], self.motion()["V"], sp.dt, b.c.fixtures)
        if pairs.nodes.shape[0] == 0:
            return None
        R, _ = recon.frames(True)
        known = Known(R, self.motion()["V"], np.ascontiguousarray(y_old[:, 3:6]))
        return sp, layout, pairs, known

    def terms(self, step, y: np.ndarray, jacobian: bool, band: bool) -> StateTerms:
        sp, layout, pairs, known = step
        w = self.between.weights
        if jacobian:
            src = contact_source(sp, pairs, known, y, w, layout, True, band)
        else:
            src = contact_source(sp, pairs, known, y, w, layout, False)
        self.last = src
        return StateTerms(src.q, src.U, src.G, src.nodes, src.turn)

    def converged(self, step) -> None:
        self.largest = max(self.largest, self.last.overlap)

    def too_fast(self, h: float) -> bool:
        """Whether a step h moves a node more than D / 2 or turns a frame by more than
        0.1 rad (the time route's trapezoidal rule, C1, then loses the link: a = 16,
        N = 200 in whole steps of 0.01 s, Lk - Tw - Wr went from 1e-4 to 0.05 turns in the
        whip before the first contact)."""
        m = self.motion()
        return h * m["speed"] > 0.5 * self.between.rod.thickness or h * m["spin"] > 0.1

    def step_taken(self, co, h: float, old, new, q_old, q_new) -> None:
        b = self.between
        b.budget.step(co, h, Level(*old), Level(*new), Loads(self.q_seed, q_old, q_new))
        b.pending = q_new

    def level_reached(self, t: float, y: np.ndarray, h: float, check: bool) -> str | None:
        return self.between(t, y, h, check)

    def check_every(self, dt: float) -> int:
        return max(1, int(round(self.between.c.check / dt)))

    def cost(self, state: dict[str, Any], diameter: float) -> dict[str, float]:
        """What the implicit contact cost (``state``: the run's ``meta["state"]``): steps with
        contact candidates, their Newton iterations, wall time per step with and without,
        the largest predicted overlap."""
        coupled = state["coupled_steps"]
        free = max(state["steps"] - coupled, 1)
        return {
            "contact_steps": coupled,
            "contact_newton_iterations": state["coupled_iterations"],
            "seconds_per_contact_step": state["coupled_seconds"] / max(coupled, 1),
            "seconds_per_free_step": state["free_seconds"] / free,
            "largest_predicted_overlap_over_D": self.largest / diameter,
            "failed_solves_retried_shorter": state["failed_solves"],
            "shortest_step": state["shortest_step"],
        }
