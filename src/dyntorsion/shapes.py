"""Rod shapes from the body-frame solution (section 4).

R is the matrix whose columns are the inertial basis vectors e1, e2, e3 in body
components (eq 14), so a body-frame vector v has inertial components R^T v and
the director d3 has inertial components R[2, :].  Two routes give R:

* in time (eqs 17-19): R(s, t + dt) = exp(-hat(dtheta)) R(s, t),
  dtheta = dt (w(s, t + dt) + w(s, t)) / 2, and the centreline from the
  velocity, r_t = R^T u (eq 21);
* in space (eq 17, first form): R(s + ds) = exp(-hat(ds kbar)) R(s), starting
  from the frame of the left end, and r_s = d3.

Both use Rodrigues' formula (eq 20) for the exponential.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

__all__ = [
    "hat",
    "rodrigues",
    "frames_along",
    "centreline",
    "left_end_frame",
    "shape",
    "FrameTracker",
    "self_contact",
]


def hat(x: np.ndarray) -> np.ndarray:
    """Skew matrices hat(x) y = x cross y, for x of shape (..., 3)."""
    x = np.asarray(x, dtype=float)
    out = np.zeros(x.shape + (3,))
    out[..., 0, 1], out[..., 0, 2] = -x[..., 2], x[..., 1]
    out[..., 1, 0], out[..., 1, 2] = x[..., 2], -x[..., 0]
    out[..., 2, 0], out[..., 2, 1] = -x[..., 1], x[..., 0]
    return out


def rodrigues(x: np.ndarray) -> np.ndarray:
    """``exp(-hat(x)) = E - hat(n) sin|x| + hat(n)^2 (1 - cos|x|)``, ``n = x/|x|`` (eq 20).

    Written as ``E - a hat(x) + b hat(x)^2`` with ``a = sin|x|/|x|``,
    ``b = (1 - cos|x|)/|x|^2``, whose Taylor series are used for ``|x| < 1e-4`` so
    that ``x -> 0`` is exact.
    """
    x = np.asarray(x, dtype=float)
    th2 = np.sum(x * x, axis=-1)
    th = np.sqrt(th2)
    small = th < 1e-4
    safe = np.where(small, 1.0, th)
    a = np.where(small, 1.0 - th2 / 6.0 + th2**2 / 120.0, np.sin(safe) / safe)
    b = np.where(small, 0.5 - th2 / 24.0 + th2**2 / 720.0, (1.0 - np.cos(safe)) / safe**2)
    X = hat(x)
    return np.eye(3) - a[..., None, None] * X + b[..., None, None] * (X @ X)


def left_end_frame(theta: float) -> np.ndarray:
    """R at s = 0 after the end has turned by theta about e3 (the only rotation eq 30 allows)."""
    return rodrigues(np.array([0.0, 0.0, theta]))


def frames_along(k: np.ndarray, ds: float, R0: np.ndarray | None = None) -> np.ndarray:
    """R at every node from the curvatures k (N+1, 3): R_j = exp(-hat(ds kbar_j)) R_{j-1}."""
    k = np.asarray(k, dtype=float)
    steps = rodrigues(0.5 * ds * (k[1:] + k[:-1]))
    R = np.empty((k.shape[0], 3, 3))
    R[0] = np.eye(3) if R0 is None else R0
    for j in range(1, k.shape[0]):
        R[j] = steps[j - 1] @ R[j - 1]
    return R


def centreline(R: np.ndarray, ds: float, r0: np.ndarray | None = None) -> np.ndarray:
    """r from r_s = d3 (trapezoidal), d3 in inertial components = R[:, 2, :]."""
    d3 = R[:, 2, :]
    r = np.zeros((R.shape[0], 3))
    r[1:] = np.cumsum(0.5 * ds * (d3[1:] + d3[:-1]), axis=0)
    return r if r0 is None else r + r0


def shape(y: np.ndarray, ds: float, theta0: float = 0.0, k_index: int = 6) -> np.ndarray:
    """Centreline (N+1, 3) of a 12-field state y by the spatial route, the left end at the
    origin with its frame turned by theta0 about e3."""
    R = frames_along(y[:, k_index : k_index + 3], ds, left_end_frame(theta0))
    return centreline(R, ds)


class FrameTracker:
    """The time route: frames and centreline of every node, advanced step by step.

    Start from frames ``R`` (N+1, 3, 3) and positions ``r`` (N+1, 3) at t0; call
    :meth:`step` with the spins and velocities (body components) of the old and
    new level.
    """

    def __init__(self, R: np.ndarray, r: np.ndarray):
        self.R = np.array(R, dtype=float)
        self.r = np.array(r, dtype=float)

    def step(self, w_old, w_new, u_old, u_new, dt: float) -> None:
        v_old = np.einsum("nji,nj->ni", self.R, u_old)  # R^T u
        self.R = rodrigues(0.5 * dt * (np.asarray(w_new) + np.asarray(w_old))) @ self.R
        v_new = np.einsum("nji,nj->ni", self.R, u_new)
        self.r = self.r + 0.5 * dt * (v_old + v_new)


def _segment_distances(p0, p1, q0, q1):
    """Smallest distances between segments p0-p1 and q0-q1 (arrays (m, 3))."""
    d1, d2, r = p1 - p0, q1 - q0, p0 - q0
    a = np.einsum("ij,ij->i", d1, d1)
    e = np.einsum("ij,ij->i", d2, d2)
    f = np.einsum("ij,ij->i", d2, r)
    c = np.einsum("ij,ij->i", d1, r)
    b = np.einsum("ij,ij->i", d1, d2)
    denom = a * e - b * b
    s = np.where(
        denom > 1e-14 * a * e, np.clip((b * f - c * e) / np.where(denom > 0, denom, 1), 0, 1), 0.0
    )
    t = (b * s + f) / e
    t_c = np.clip(t, 0, 1)
    s = np.where(t != t_c, np.clip((b * t_c - c) / a, 0, 1), s)
    diff = p0 + d1 * s[:, None] - q0 - d2 * t_c[:, None]
    return np.sqrt(np.einsum("ij,ij->i", diff, diff))


@lru_cache(maxsize=16)
def _all_pairs(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Index pairs i < j - 1 of n segments (never adjacent), computed once per n."""
    i, j = np.triu_indices(n, k=2)
    i.setflags(write=False)
    j.setflags(write=False)
    return i, j


def _candidate_pairs(arc, r, seg, diameter, min_arc, reach):
    """Segment pairs (i, j) more than ``min_arc`` of arc length apart (``arc`` measured
    along the rod) whose midpoints in ``r`` lie within ``reach`` x (seg_i + seg_j) +
    ``diameter``: the only pairs that can touch or cross."""
    i, j = _all_pairs(seg.size)
    keep = arc[j] - arc[i + 1] > (2 * diameter if min_arc is None else min_arc)
    i, j = i[keep], j[keep]
    mid = 0.5 * (r[1:] + r[:-1])
    near = np.linalg.norm(mid[i] - mid[j], axis=1) < reach * (seg[i] + seg[j]) + diameter
    return i[near], j[near]


def _segments(r):
    """(r, segment vectors, segment lengths, arc length at the nodes) of a centreline."""
    r = np.asarray(r, dtype=float)
    d = np.diff(r, axis=0)
    seg = np.linalg.norm(d, axis=1)
    return r, d, seg, np.concatenate([[0.0], np.cumsum(seg)])


def self_contact(r: np.ndarray, diameter: float, min_arc: float | None = None):
    """(distance, i, j) of the closest pair of segments i, j of the centreline r whose
    arc-length separation exceeds ``min_arc`` (default 2 diameters, and never
    adjacent segments), or None when no pair comes within ``diameter``."""
    r, _, seg, arc = _segments(r)
    i, j = _candidate_pairs(arc, r, seg, diameter, min_arc, reach=0.5)
    if i.size == 0:
        return None
    d = _segment_distances(r[i], r[i + 1], r[j], r[j + 1])
    m = int(np.argmin(d))
    return (float(d[m]), int(i[m]), int(j[m])) if d[m] < diameter else None


def crossing(r_old: np.ndarray, r_new: np.ndarray, diameter: float, min_arc: float | None = None):
    """(i, j) of a pair of segments of the centreline that passed through each other
    between two states r_old, r_new (same nodes), or None.

    Contact checked only at time levels misses segments that cross within one step.
    A pair counts as crossed when, in both states, it is not neighbouring (arc-length
    separation above ``min_arc``, default 2 diameters), the segments make an angle of
    more than 30 degrees, the closest points of their lines lie on both segments, and
    those lines are closer than a segment length -- and the signed distance of the
    lines along d_i x d_j changes sign.  Every quantity is taken within one state, so a
    rigid motion of the whole rod between the states does not matter."""
    r0, d0, seg0, arc0 = _segments(r_old)
    r1, d1, seg1, _ = _segments(r_new)
    i, j = _candidate_pairs(arc0, r1, seg1, diameter, min_arc, reach=2.0)
    if i.size == 0:
        return None
    signs = []
    for r, d, seg in ((r0, d0, seg0), (r1, d1, seg1)):
        p, q = d[i], d[j]
        cr = np.cross(p, q)
        norm = np.linalg.norm(cr, axis=1)
        ok = norm > 0.5 * seg[i] * seg[j]  # angle above 30 degrees
        nrm = cr / np.where(ok, norm, 1.0)[:, None]
        w = r[j] - r[i]
        dist = np.einsum("ij,ij->i", w, nrm)
        # closest points of the two lines: r_i + s p = r_j + t q (+ dist n)
        a, b, e = (np.einsum("ij,ij->i", x, y) for x, y in ((p, p), (p, q), (q, q)))
        c, f = np.einsum("ij,ij->i", p, w), np.einsum("ij,ij->i", q, w)
        den = np.where(ok, a * e - b * b, 1.0)
        s = (c * e - b * f) / den
        t = (b * c - a * f) / den
        inside = ok & (s >= 0) & (s <= 1) & (t >= 0) & (t <= 1)
        signs.append((np.sign(dist), inside & (np.abs(dist) < np.minimum(seg[i], seg[j]))))
    hit = signs[0][1] & signs[1][1] & (signs[0][0] * signs[1][0] < 0)
    if not np.any(hit):
        return None
    k = int(np.argmax(hit))
    return int(i[k]), int(j[k])
