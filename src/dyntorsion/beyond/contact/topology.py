"""Link, twist and writhe of the rod: Calugareanu-White-Fuller,
Lk = Tw + Wr, in turns.

* **Twist** from the frame: Tw = (1/2 pi) int_0^L d1' . d2 ds = (1/2 pi) int_0^L kappa3 ds
  (d1' = k x d1, so d1' . d2 = k . d3), trapezoidal on the nodes.
* **Writhe** from the Gauss double integral Wr = (1/4 pi) oint oint
  (r(s) - r(s')) . (r'(s) x r'(s')) / |r(s) - r(s')|^3 ds ds' of a closed curve, evaluated
  exactly for the polygon of the nodes (Klenin and Langowski, Biopolymers 54, 307 (2000):
  each pair of segments contributes the solid angle Omega / 4 pi of the quadrilateral they
  span).  **Closure**: the rod's ends lie on the e3 axis with tangent e3 (eq 30), so the
  curve is closed by the axis itself beyond the ends -- a tail from r(0) down to
  r(0) - Lambda e3 and one from r(L) up to r(L) + Lambda e3 -- and a rectangle in the plane
  (e1, e3) at distance Lambda (``Lambda = CLOSURE`` x L).  The closure is straight and
  planar, so it adds no twist, and its writhe with the rod falls off as L / Lambda
  (1e-4 turns at the default 1e4).
* **Link** from the integrated end rotations: Lk(t) = Tw(0) + Wr(0) + (theta_R - theta_L)/2 pi,
  theta = int w3 dt at each end (d/dt int kappa3 ds = w3(L) - w3(0) for the straight rod;
  the link of the closed ribbon changes only with the end rotations).

A passage of the rod through itself (or round the axis tails beyond its ends) changes
Wr by 2 while Lk and Tw stay continuous: :func:`passage` watches Lk - Tw - Wr.
"""

from __future__ import annotations

import math

import numpy as np

from ..._numba import jit

__all__ = ["CLOSURE", "twist_turns", "closed_polygon", "writhe_turns", "linking_turns",
           "link_turns", "passage"]  # fmt: skip

#: the closure's distance from the rod, in rod lengths
CLOSURE = 1.0e4


def twist_turns(kappa3: np.ndarray, ds: float) -> float:
    """Tw = (1/2 pi) int kappa3 ds (trapezoidal on the nodes) [turns]."""
    k = np.asarray(kappa3, dtype=float)
    return float(ds * (k.sum() - 0.5 * (k[0] + k[-1])) / (2.0 * math.pi))


def closed_polygon(r: np.ndarray, closure: float = CLOSURE) -> np.ndarray:
    """The nodes r (N+1, 3) closed by the axis tails and a far rectangle (module docstring);
    the last vertex joins the first."""
    r = np.asarray(r, dtype=float)
    span = closure * max(
        float(np.linalg.norm(r[-1] - r[0])), float(np.ptp(r, axis=0).max()), 1e-300
    )
    bottom = np.array([0.0, 0.0, r[0, 2] - span])
    top = np.array([0.0, 0.0, r[-1, 2] + span])
    side = np.array([span, 0.0, 0.0])
    return np.vstack([r, top, top + side, bottom + side, bottom])


@jit
def _unit_cross(a0, a1, a2, b0, b1, b2):
    c0, c1, c2 = a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0
    n = math.sqrt(c0 * c0 + c1 * c1 + c2 * c2)
    if n == 0.0:
        return 0.0, 0.0, 0.0, False
    return c0 / n, c1 / n, c2 / n, True


@jit
def _asin(x):
    return math.asin(min(1.0, max(-1.0, x)))


@jit
def _solid_angle(p, i, q, j):
    """Signed solid angle Omega of segments p[i]->p[i+1] and q[j]->q[j+1] (Klenin and
    Langowski 2000, eq 15): the pair's contribution to the Gauss integral is Omega/4 pi.
    (Scalar arithmetic: no array is made per pair.)"""
    x1x, x1y, x1z = p[i, 0], p[i, 1], p[i, 2]
    x2x, x2y, x2z = p[i + 1, 0], p[i + 1, 1], p[i + 1, 2]
    x3x, x3y, x3z = q[j, 0], q[j, 1], q[j, 2]
    x4x, x4y, x4z = q[j + 1, 0], q[j + 1, 1], q[j + 1, 2]
    a13x, a13y, a13z = x3x - x1x, x3y - x1y, x3z - x1z
    a14x, a14y, a14z = x4x - x1x, x4y - x1y, x4z - x1z
    a23x, a23y, a23z = x3x - x2x, x3y - x2y, x3z - x2z
    a24x, a24y, a24z = x4x - x2x, x4y - x2y, x4z - x2z
    n1x, n1y, n1z, ok1 = _unit_cross(a13x, a13y, a13z, a14x, a14y, a14z)
    n2x, n2y, n2z, ok2 = _unit_cross(a14x, a14y, a14z, a24x, a24y, a24z)
    n3x, n3y, n3z, ok3 = _unit_cross(a24x, a24y, a24z, a23x, a23y, a23z)
    n4x, n4y, n4z, ok4 = _unit_cross(a23x, a23y, a23z, a13x, a13y, a13z)
    if not (ok1 and ok2 and ok3 and ok4):
        return 0.0  # the two segments lie on one line or meet: no solid angle
    om = (
        _asin(n1x * n2x + n1y * n2y + n1z * n2z)
        + _asin(n2x * n3x + n2y * n3y + n2z * n3z)
        + _asin(n3x * n4x + n3y * n4y + n3z * n4z)
        + _asin(n4x * n1x + n4y * n1y + n4z * n1z)
    )
    a34x, a34y, a34z = x4x - x3x, x4y - x3y, x4z - x3z
    a12x, a12y, a12z = x2x - x1x, x2y - x1y, x2z - x1z
    c0 = a34y * a12z - a34z * a12y
    c1 = a34z * a12x - a34x * a12z
    c2 = a34x * a12y - a34y * a12x
    s = c0 * a13x + c1 * a13y + c2 * a13z
    return om if s > 0.0 else (-om if s < 0.0 else 0.0)


@jit
def _writhe(p):
    """Sum over the non-adjacent segment pairs of the closed polygon p (last vertex joins the
    first) of Omega / 2 pi (each unordered pair counted once, twice in the Gauss sum)."""
    m = p.shape[0]
    q = np.empty((m + 1, 3))
    q[:m] = p
    q[m] = p[0]
    total = 0.0
    for i in range(m):
        for j in range(i + 2, m):
            if i == 0 and j == m - 1:
                continue  # adjacent through the closing vertex
            total += _solid_angle(q, i, q, j)
    return total / (2.0 * math.pi)


@jit
def _linking(p, q):
    """Gauss linking number of two closed polygons: sum of Omega / 4 pi over all pairs."""
    a = np.empty((p.shape[0] + 1, 3))
    a[:-1], a[-1] = p, p[0]
    b = np.empty((q.shape[0] + 1, 3))
    b[:-1], b[-1] = q, q[0]
    total = 0.0
    for i in range(p.shape[0]):
        for j in range(q.shape[0]):
            total += _solid_angle(a, i, b, j)
    return total / (4.0 * math.pi)


def writhe_turns(closed: np.ndarray) -> float:
    """Wr of a closed polygon (vertices (M, 3), the last joins the first), exact for the
    polygon (module docstring); :func:`closed_polygon` closes the rod."""
    return float(_writhe(np.ascontiguousarray(closed, dtype=float)))


def linking_turns(a: np.ndarray, b: np.ndarray) -> float:
    """Gauss linking number of two closed polygons (an integer up to round-off)."""
    return float(_linking(np.ascontiguousarray(a, float), np.ascontiguousarray(b, float)))


def link_turns(lk0: float, theta_left: float, theta_right: float) -> float:
    """Lk = Lk(0) + (theta_R - theta_L) / 2 pi (module docstring)."""
    return float(lk0 + (theta_right - theta_left) / (2.0 * math.pi))


def passage(gap_before: float, gap_now: float, limit: float = 1.0) -> bool:
    """Whether Lk - Tw - Wr jumped (by ~2 at a passage) by more than ``limit`` turns between
    two checks (a slow drift of the reconstruction is no passage)."""
    return abs(gap_now - gap_before) > limit
