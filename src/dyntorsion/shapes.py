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

import math

import numpy as np

from ._numba import jit

__all__ = [
    "hat",
    "rodrigues",
    "frames_along",
    "centreline",
    "left_end_frame",
    "shape",
    "FrameTracker",
    "self_contact",
    "crossing",
    "shape_kernel",
    "self_contact_kernel",
    "crossing_kernel",
]


def hat(x: np.ndarray) -> np.ndarray:
    """Skew matrices hat(x) y = x cross y, for x of shape (..., 3)."""
    x = np.asarray(x, dtype=float)
    out = np.zeros(x.shape + (3,))
    out[..., 0, 1], out[..., 0, 2] = -x[..., 2], x[..., 1]
    out[..., 1, 0], out[..., 1, 2] = x[..., 2], -x[..., 0]
    out[..., 2, 0], out[..., 2, 1] = -x[..., 1], x[..., 0]
    return out


@jit
def _exp_minus_hat(x0, x1, x2, out):
    """out = exp(-hat(x)) for one x (see :func:`rodrigues`)."""
    th2 = x0 * x0 + x1 * x1 + x2 * x2
    if th2 < 1e-8:  # |x| < 1e-4
        a = 1.0 - th2 / 6.0 + th2 * th2 / 120.0
        b = 0.5 - th2 / 24.0 + th2 * th2 / 720.0
    else:
        th = math.sqrt(th2)
        a = math.sin(th) / th
        b = (1.0 - math.cos(th)) / th2
    # hat(x)^2 = x x^T - |x|^2 E
    out[0, 0] = 1.0 + b * (x0 * x0 - th2)
    out[1, 1] = 1.0 + b * (x1 * x1 - th2)
    out[2, 2] = 1.0 + b * (x2 * x2 - th2)
    out[0, 1] = a * x2 + b * x0 * x1
    out[1, 0] = -a * x2 + b * x1 * x0
    out[0, 2] = -a * x1 + b * x0 * x2
    out[2, 0] = a * x1 + b * x2 * x0
    out[1, 2] = a * x0 + b * x1 * x2
    out[2, 1] = -a * x0 + b * x2 * x1


@jit
def _rodrigues_rows(x, out):
    for m in range(x.shape[0]):
        _exp_minus_hat(x[m, 0], x[m, 1], x[m, 2], out[m])


def rodrigues(x: np.ndarray) -> np.ndarray:
    """``exp(-hat(x)) = E - hat(n) sin|x| + hat(n)^2 (1 - cos|x|)``, ``n = x/|x|`` (eq 20),
    for x of shape (..., 3).

    Written as ``E - a hat(x) + b hat(x)^2`` with ``a = sin|x|/|x|``,
    ``b = (1 - cos|x|)/|x|^2``, whose Taylor series are used for ``|x| < 1e-4`` so
    that ``x -> 0`` is exact.
    """
    x = np.asarray(x, dtype=float)
    flat = np.ascontiguousarray(x.reshape(-1, 3))
    out = np.empty((flat.shape[0], 3, 3))
    _rodrigues_rows(flat, out)
    return out.reshape(x.shape + (3,))


def left_end_frame(theta: float) -> np.ndarray:
    """R at s = 0 after the end has turned by theta about e3 (the only rotation eq 30 allows)."""
    return rodrigues(np.array([0.0, 0.0, theta]))


@jit
def _frames(k, ds, R):
    """R[j] = exp(-hat(ds kbar_j)) R[j-1] from R[0] (see :func:`frames_along`)."""
    step = np.empty((3, 3))
    for j in range(1, k.shape[0]):
        _exp_minus_hat(
            0.5 * ds * (k[j, 0] + k[j - 1, 0]),
            0.5 * ds * (k[j, 1] + k[j - 1, 1]),
            0.5 * ds * (k[j, 2] + k[j - 1, 2]),
            step,
        )
        for a in range(3):
            for c in range(3):
                R[j, a, c] = (
                    step[a, 0] * R[j - 1, 0, c]
                    + step[a, 1] * R[j - 1, 1, c]
                    + step[a, 2] * R[j - 1, 2, c]
                )


@jit
def _centreline(R, ds, r):
    """r[j] = r[j-1] + ds (d3_j + d3_{j-1}) / 2 from r[0] (d3 = R[:, 2, :])."""
    for j in range(1, R.shape[0]):
        for c in range(3):
            r[j, c] = r[j - 1, c] + 0.5 * ds * (R[j, 2, c] + R[j - 1, 2, c])


@jit
def shape_kernel(k, ds, R0, R, r):
    """Frames R and centreline r (r[0] = 0) of the curvatures k, from the frame R0."""
    R[0] = R0
    _frames(k, ds, R)
    r[0] = 0.0
    _centreline(R, ds, r)


def frames_along(k: np.ndarray, ds: float, R0: np.ndarray | None = None) -> np.ndarray:
    """R at every node from the curvatures k (N+1, 3): R_j = exp(-hat(ds kbar_j)) R_{j-1}."""
    k = np.ascontiguousarray(k, dtype=float)
    R = np.empty((k.shape[0], 3, 3))
    R[0] = np.eye(3) if R0 is None else R0
    _frames(k, float(ds), R)
    return R


def centreline(R: np.ndarray, ds: float, r0: np.ndarray | None = None) -> np.ndarray:
    """r from r_s = d3 (trapezoidal), d3 in inertial components = R[:, 2, :]."""
    R = np.ascontiguousarray(R, dtype=float)
    r = np.zeros((R.shape[0], 3))
    _centreline(R, float(ds), r)
    return r if r0 is None else r + r0


def shape(y: np.ndarray, ds: float, theta0: float = 0.0, k_index: int = 6) -> np.ndarray:
    """Centreline (N+1, 3) of a 12-field state y by the spatial route, the left end at the
    origin with its frame turned by theta0 about e3."""
    k = np.ascontiguousarray(np.asarray(y, dtype=float)[:, k_index : k_index + 3])
    R, r = np.empty((k.shape[0], 3, 3)), np.empty((k.shape[0], 3))
    shape_kernel(k, float(ds), left_end_frame(theta0), R, r)
    return r


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


@jit
def _dots(px, py, pz, qx, qy, qz, wx, wy, wz):
    """p.p, p.q, q.q, p.w, q.w of two segment vectors p, q and the vector w."""
    return (
        px * px + py * py + pz * pz,
        px * qx + py * qy + pz * qz,
        qx * qx + qy * qy + qz * qz,
        px * wx + py * wy + pz * wz,
        qx * wx + qy * wy + qz * wz,
    )


@jit
def _segment_distance(r, i, q, j):
    """Smallest distance between segment i of the centreline r and segment j of q."""
    d1x, d1y, d1z = r[i + 1, 0] - r[i, 0], r[i + 1, 1] - r[i, 1], r[i + 1, 2] - r[i, 2]
    d2x, d2y, d2z = q[j + 1, 0] - q[j, 0], q[j + 1, 1] - q[j, 1], q[j + 1, 2] - q[j, 2]
    wx, wy, wz = r[i, 0] - q[j, 0], r[i, 1] - q[j, 1], r[i, 2] - q[j, 2]
    a, b, e, c, f = _dots(d1x, d1y, d1z, d2x, d2y, d2z, wx, wy, wz)
    denom = a * e - b * b
    s = min(max((b * f - c * e) / denom, 0.0), 1.0) if denom > 1e-14 * a * e else 0.0
    t = (b * s + f) / e
    tc = min(max(t, 0.0), 1.0)
    if t != tc:
        s = min(max((b * tc - c) / a, 0.0), 1.0)
    dx = wx + d1x * s - d2x * tc
    dy = wy + d1y * s - d2y * tc
    dz = wz + d1z * s - d2z * tc
    return math.sqrt(dx * dx + dy * dy + dz * dz)


@jit
def _segments(r):
    """Segment lengths and the arc length at the nodes of a centreline."""
    n = r.shape[0] - 1
    seg, arc = np.empty(n), np.zeros(n + 1)
    for i in range(n):
        dx, dy, dz = r[i + 1, 0] - r[i, 0], r[i + 1, 1] - r[i, 1], r[i + 1, 2] - r[i, 2]
        seg[i] = math.sqrt(dx * dx + dy * dy + dz * dz)
        arc[i + 1] = arc[i] + seg[i]
    return seg, arc


@jit
def _candidate(arc, r, seg, i, j, diameter, min_arc, reach):
    """Whether segments i < j - 1 are more than ``min_arc`` of arc length apart (``arc``
    measured along the rod) and their midpoints in ``r`` lie within
    ``reach`` x (seg_i + seg_j) + ``diameter``: the only pairs that can touch or cross."""
    if not arc[j] - arc[i + 1] > min_arc:
        return False
    acc = 0.0
    for c in range(3):
        m = 0.5 * (r[i + 1, c] + r[i, c]) - 0.5 * (r[j + 1, c] + r[j, c])
        acc += m * m
    return math.sqrt(acc) < reach * (seg[i] + seg[j]) + diameter


@jit
def self_contact_kernel(r, diameter, min_arc):
    """(distance, i, j) of the closest candidate pair, i = -1 when there is none."""
    seg, arc = _segments(r)
    n = seg.size
    best, bi, bj = np.inf, -1, -1
    for i in range(n):
        for j in range(i + 2, n):
            if _candidate(arc, r, seg, i, j, diameter, min_arc, 0.5):
                d = _segment_distance(r, i, r, j)
                if d < best:
                    best, bi, bj = d, i, j
    return best, bi, bj


@jit
def _crossed(r, i, j, seg):
    """(sign of the distance of the lines of segments i, j along d_i x d_j, whether the
    pair is a crossing candidate in this state: at more than 30 degrees, the closest
    points of the lines on both segments, the lines closer than a segment length)."""
    px, py, pz = r[i + 1, 0] - r[i, 0], r[i + 1, 1] - r[i, 1], r[i + 1, 2] - r[i, 2]
    qx, qy, qz = r[j + 1, 0] - r[j, 0], r[j + 1, 1] - r[j, 1], r[j + 1, 2] - r[j, 2]
    cx, cy, cz = py * qz - pz * qy, pz * qx - px * qz, px * qy - py * qx
    norm = math.sqrt(cx * cx + cy * cy + cz * cz)
    if not norm > 0.5 * seg[i] * seg[j]:
        return 0.0, False
    wx, wy, wz = r[j, 0] - r[i, 0], r[j, 1] - r[i, 1], r[j, 2] - r[i, 2]
    dist = wx * (cx / norm) + wy * (cy / norm) + wz * (cz / norm)
    # closest points of the two lines: r_i + s p = r_j + t q (+ dist n)
    a, b, e, c, f = _dots(px, py, pz, qx, qy, qz, wx, wy, wz)
    den = a * e - b * b
    s = (c * e - b * f) / den
    t = (b * c - a * f) / den
    inside = 0.0 <= s <= 1.0 and 0.0 <= t <= 1.0 and abs(dist) < min(seg[i], seg[j])
    return np.sign(dist), inside


@jit
def crossing_kernel(r0, r1, diameter, min_arc):
    """(i, j) of the first pair that passed through each other, (-1, -1) for none."""
    seg0, arc0 = _segments(r0)
    seg1, _ = _segments(r1)
    n = seg1.size
    for i in range(n):
        for j in range(i + 2, n):
            if _candidate(arc0, r1, seg1, i, j, diameter, min_arc, 2.0):
                s0, in0 = _crossed(r0, i, j, seg0)
                s1, in1 = _crossed(r1, i, j, seg1)
                if in0 and in1 and s0 * s1 < 0.0:
                    return i, j
    return -1, -1


def _min_arc(diameter: float, min_arc: float | None) -> float:
    return 2.0 * float(diameter) if min_arc is None else float(min_arc)


def _points(r) -> np.ndarray:
    return np.ascontiguousarray(r, dtype=float)


def self_contact(r: np.ndarray, diameter: float, min_arc: float | None = None):
    """(distance, i, j) of the closest pair of segments i, j of the centreline r whose
    arc-length separation exceeds ``min_arc`` (default 2 diameters, and never
    adjacent segments), or None when no pair comes within ``diameter``."""
    d, i, j = self_contact_kernel(_points(r), float(diameter), _min_arc(diameter, min_arc))
    return (float(d), int(i), int(j)) if i >= 0 and d < diameter else None


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
    i, j = crossing_kernel(
        _points(r_old), _points(r_new), float(diameter), _min_arc(diameter, min_arc)
    )
    return None if i < 0 else (int(i), int(j))
