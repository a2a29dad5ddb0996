"""The centreline r(s, t) and the frame of a contact scene, reconstructed at every step
from the 12 fields.

Route: the spatial one of section 4 (eq 17, first form, and r_s = d3): from the frame
of the left end, R(0, t) = exp(-hat(theta_L e3)) with theta_L = int_0^t w3(0, t') dt'
(the only rotation eq 30 allows), R(s + ds) = exp(-hat(ds kbar)) R(s) (Rodrigues, eq 20)
and r(s) = r(0) + int_0^s d3 (trapezoidal), :func:`dyntorsion.shapes.shape`.  So r' = d3
holds by construction at every step; what can drift is the consistency of that shape with
the rest of the 12 fields, measured two ways (:class:`Drift`):

* the far end: eq 30 holds s = L on the axis (u1 = u2 = 0) with its frame fixed
  (w = 0), so the reconstructed r(L) must stay on the e3 axis and R(L) equal its
  initial value; ``end_offset`` = |r_perp(L)| / L, ``end_angle`` = the angle of
  R(L) R(L, 0)^T [rad];
* the time route (eqs 17-19, 21), :class:`dyntorsion.shapes.FrameTracker`, advanced from
  the same initial shape with the spins and velocities of every step: ``time_route`` =
  max_j |r_space - r_time| / L, and ``tangent`` = max_j |(r_{j+1} - r_j) / ds - d3_{j+1/2}|
  on the time route (r' = d3 there, d3 the mean of its nodes' frames).

The implicit contact (:mod:`.implicit`) acts on the time route: its positions are those
the velocities move, so the contact holds there (:meth:`Reconstruction.frames`).
**Anchored** (``anchor=True``): after every step the time route is set back onto the
spatial one, so the time route only carries a step, from the rebuilt shape of the old
level to the new one; the drifts ``time_route`` and ``tangent`` are then those of one
step (measured before the reset) and cannot accumulate.  Unanchored, the time route runs
free from t = 0 and its drift grows: at a = 16, N = 400, its tangent stood 1.24 rad off
its chords 0.26 s past the first contact (data/contact/first_contact.json, the record
before anchoring).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ... import shapes

__all__ = ["Drift", "Reconstruction"]


@dataclass
class Drift:
    """The largest drift of the reconstructed shape over a run (module docstring)."""

    end_offset: float = 0.0
    end_angle: float = 0.0
    time_route: float = 0.0
    tangent: float = 0.0
    #: whether the time route is set back onto the spatial one after every step (the
    #: drifts are then those of one step)
    anchored: bool = False

    def as_dict(self) -> dict[str, float]:
        return {
            "end_offset_over_L": self.end_offset,
            "end_angle": self.end_angle,
            "time_route_over_L": self.time_route,
            "time_route_tangent": self.tangent,
            "anchored": self.anchored,
        }


class Reconstruction:
    """Frames R (N+1, 3, 3) and centreline r (N+1, 3) of the current level, rebuilt at
    every step by :meth:`update` from the 12-field state y and the left end's rotation,
    and the drift (:class:`Drift`) of that rebuild against the far end and the time route.
    ``R`` maps inertial to body components (section 4: d3 = R[:, 2, :])."""

    def __init__(self, y0: np.ndarray, ds: float, length: float, k_index: int = 6,
                 u_index: int = 0, w_index: int = 3, time_route: bool = True,
                 anchor: bool = False):  # fmt: skip
        self.ds, self.length = float(ds), float(length)
        self.k, self.u, self.w = k_index, u_index, w_index
        n1 = y0.shape[0]
        self.R, self.r = np.empty((n1, 3, 3)), np.empty((n1, 3))
        self.theta_left = 0.0
        self.drift = Drift(anchored=bool(anchor))
        self._rebuild(y0)
        self.R_far0 = self.R[-1].copy()
        self._y_old = np.array(y0, dtype=float)
        self.tracker = shapes.FrameTracker(self.R, self.r) if time_route else None
        self.anchor = bool(anchor)

    def _rebuild(self, y: np.ndarray) -> None:
        k = np.ascontiguousarray(y[:, self.k : self.k + 3])
        shapes.shape_kernel(k, self.ds, shapes.left_end_frame(self.theta_left), self.R, self.r)

    def update(self, y: np.ndarray, dt: float) -> None:
        """Advance to the level y, a step dt after the previous one."""
        y = np.asarray(y, dtype=float)
        w3 = self.w + 2
        self.theta_left += 0.5 * dt * (y[0, w3] + self._y_old[0, w3])
        self._rebuild(y)
        d = self.drift
        d.end_offset = max(d.end_offset, float(np.hypot(*self.r[-1, :2])) / self.length)
        rel = self.R[-1] @ self.R_far0.T
        cos = np.clip(0.5 * (np.trace(rel) - 1.0), -1.0, 1.0)
        d.end_angle = max(d.end_angle, float(np.arccos(cos)))
        if self.tracker is not None:
            u, w = slice(self.u, self.u + 3), slice(self.w, self.w + 3)
            self.tracker.step(self._y_old[:, w], y[:, w], self._y_old[:, u], y[:, u], dt)
            gap = np.max(np.linalg.norm(self.tracker.r - self.r, axis=1)) / self.length
            d.time_route = max(d.time_route, float(gap))
            # r' = d3 on the time route: each chord against the mean d3 of its two nodes
            chord = np.diff(self.tracker.r, axis=0) / self.ds
            d3 = 0.5 * (self.tracker.R[1:, 2, :] + self.tracker.R[:-1, 2, :])
            d.tangent = max(d.tangent, float(np.max(np.linalg.norm(chord - d3, axis=1))))
            if self.anchor:
                self.tracker.R[:] = self.R
                self.tracker.r[:] = self.r
        self._y_old = y.copy()

    def frames(self, time: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """(R, r) of the spatial route, or with ``time`` of the time route."""
        return (self.tracker.R, self.tracker.r) if time else (self.R, self.r)

    def velocities(self, y: np.ndarray, time: bool = False) -> np.ndarray:
        """Inertial velocities of the nodes, R^T u (N+1, 3) (``time``: the time route's R)."""
        R = self.frames(time)[0]
        return np.einsum("nji,nj->ni", R, np.asarray(y)[:, self.u : self.u + 3])

    def to_body(self, v: np.ndarray, time: bool = False) -> np.ndarray:
        """Body components R v of inertial vectors v (N+1, 3)."""
        return np.einsum("nij,nj->ni", self.frames(time)[0], v)
