"""The contact law of the rod with itself and with its end fixtures.

**Law.**  A penalty spring-dashpot between segments of the centreline polygon whose arc
length gap exceeds ``min_arc`` (a few diameters: closer parts touch only by bending
through a loop of radius below the rod's): at the closest points of two segments, a
distance d < D (D the rod's thickness) gives the overlap delta = D - d and, along the
unit normal n joining the closest points, the force on each segment

    F = ds * max(0, k delta - c v_n) n,        v_n = (v_i - v_j) . n  (approach: v_n < 0),

shared between the segment's end nodes by the linear weights of the closest point, equal
and opposite on the other (halved for each closest point at a segment's end node, which
the neighbour segment finds too: a contact at a node counts once).  ``k`` [N/m^2] is the stiffness per unit length, ``c``
[N s/m^2] = 2 zeta sqrt(k rho A) the damping per unit length (zeta the damping ratio of the
contact oscillator, ``damping``).  The contact is frictionless and its force passes
through both centrelines, so it exerts no moment about them: it enters the linear
momentum balance only (the angular balance through the moment arm of the nodal sharing,
O(ds)).  The stored energy is sum ds k delta^2 / 2 (same halving).

**Why this law.**  It is PyElastica's ``RodSelfContact`` (elastica/_contact_functions.py,
``_calculate_contact_forces_self_rod``: a linear spring k gamma plus a dashpot nu v.n on
the overlap gamma of the closest points of two elements, split between their nodes,
neighbours within 1 + 0.8 pi r / l elements skipped), with three changes: the force is
per unit length (k and c scale with the segment, so the law does not change with N), the
total is clipped at 0 (a dashpot pulling separating parts together is adhesion), and
PyElastica's O(N^2) double loop is replaced by a broad phase in O(N log N): a k-d tree
(scipy ``cKDTree.query_pairs``) of the segment midpoints within ds + D.  A smooth barrier
(IPC) or an implicit contact Jacobian would allow larger steps; the penalty is lagged one
step in the implicit scheme (:mod:`.run`), which bounds the step by the contact
oscillator: omega_c dt <= ``stability`` with omega_c = sqrt(k / rho A).

**End fixtures.**  The clamps at s = 0 and s = L are continued by the e3 axis beyond the
ends (the closure of the writhe, :mod:`.topology`): a loop that slid round that axis would
change the link without a self-crossing.  With ``fixtures`` the two axis pieces of length
L beyond the ends are rigid obstacles of the rod's thickness under the same law.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from scipy.spatial import cKDTree

from ..._numba import jit

__all__ = [
    "LawParams",
    "ContactForces",
    "NO_CONTACT",
    "contact_forces",
    "contact_sites",
    "lag_cost",
    "closest_points",
    "node_share",
]


class LawParams(NamedTuple):
    """The law's numbers as the compiled kernel reads them."""

    diameter: float
    stiffness: float  # k [N/m^2]
    damping: float  # c [N s/m^2]
    ds: float
    min_arc: float


class ContactForces(NamedTuple):
    """Nodal forces (N+1, 3) in inertial components [N], and per level: the largest overlap
    [m], the number of touching segment pairs, the stored energy [J], the power of the
    dashpots [W] (<= 0), the touching pairs and the fastest approach among them [m/s]."""

    force: np.ndarray
    max_overlap: float
    pairs: int
    energy: float
    dissipation: float
    touching: np.ndarray  # (pairs, 2) segment indices (obstacle segments: -1, -2)
    approach: float = 0.0  # the fastest approach of touching parts, -v_n [m/s]


@jit
def closest_points(a0, a1, b0, b1):
    """Closest points of segments a0-a1 and b0-b1: (s, t, distance vector a(s) - b(t))."""
    d1, d2, w = a1 - a0, b1 - b0, a0 - b0
    a = d1 @ d1
    e = d2 @ d2
    b = d1 @ d2
    c = d1 @ w
    f = d2 @ w
    den = a * e - b * b
    s = min(max((b * f - c * e) / den, 0.0), 1.0) if den > 1e-14 * a * e else 0.0
    t = (b * s + f) / e
    if t < 0.0:
        t, s = 0.0, min(max(-c / a, 0.0), 1.0)
    elif t > 1.0:
        t, s = 1.0, min(max((b - c) / a, 0.0), 1.0)
    return s, t, w + s * d1 - t * d2


@jit
def node_share(s):
    """1/2 when the closest point is a segment's end node (the neighbour segment sharing it
    finds the same contact: a contact at a node counts once), else 1."""
    return 0.5 if s <= 0.0 or s >= 1.0 else 1.0


@jit
def _pair(p: LawParams, a0, a1, va, b0, b1, vb, obstacle):
    """(overlap, s, t, force on segment a, dashpot power, energy, approach speed) of one
    pair; overlap <= 0: no contact.  ``obstacle``: b is a fixed piece (no neighbour shares its ends)."""
    s, t, dv = closest_points(a0, a1, b0, b1)
    d = math.sqrt(dv @ dv)
    delta = p.diameter - d
    if delta <= 0.0 or d == 0.0:
        return delta, s, t, np.zeros(3), 0.0, 0.0, 0.0
    n = dv / d
    vrel = (1.0 - s) * va[0] + s * va[1] - (1.0 - t) * vb[0] - t * vb[1]
    vn = vrel @ n
    w = p.ds * node_share(s) * (1.0 if obstacle else node_share(t))
    mag = max(0.0, p.stiffness * delta - p.damping * vn)
    dash = -p.damping * vn if mag > 0.0 else 0.0
    return delta, s, t, w * mag * n, w * dash * vn, 0.5 * w * p.stiffness * delta * delta, -vn


@jit
def ordered_apart(p: LawParams, i, j):
    """The segment pair (i, j) ordered i <= j, and whether the two lie farther apart along
    the rod than ``min_arc`` (nearer pairs are neighbours, never in contact): the pair
    filter of the law here and of the implicit step's candidates (:mod:`.implicit`)."""
    if i > j:
        i, j = j, i
    return i, j, (j - i - 1) * p.ds > p.min_arc


@jit
def fixture_apart(p: LawParams, n_seg, i, side):
    """Whether segment ``i`` of ``n_seg`` lies farther than ``min_arc`` along the rod from
    the end whose axis piece ``side`` (0 at s = 0, 1 at s = L) continues."""
    gap = (n_seg - 1 - i) * p.ds if side == 1 else i * p.ds
    return gap > p.min_arc


@jit
def _self_forces(p: LawParams, r, v, pairs, out, touching):
    """Forces of the candidate segment pairs (i < j) on the nodes; the stats of the level."""
    worst, count, energy, power, speed = 0.0, 0, 0.0, 0.0, 0.0
    for m in range(pairs.shape[0]):
        i, j, apart = ordered_apart(p, pairs[m, 0], pairs[m, 1])
        if not apart:
            continue
        delta, s, t, F, pw, en, vn = _pair(
            p, r[i], r[i + 1], v[i : i + 2], r[j], r[j + 1], v[j : j + 2], False
        )
        worst = max(worst, delta)
        if delta > 0.0:
            out[i] += (1.0 - s) * F
            out[i + 1] += s * F
            out[j] -= (1.0 - t) * F
            out[j + 1] -= t * F
            touching[count, 0], touching[count, 1] = i, j
            count += 1
            energy += en
            power += pw
            speed = max(speed, vn)
    return worst, count, energy, power, speed


@jit
def _fixture_forces(p: LawParams, r, v, tails, near, out, touching, count):
    """Forces of the two fixed axis pieces ``tails`` (2, 2, 3) on the rod's segments
    ``near`` them (``near[k, i]``) more than ``min_arc`` from the end each continues."""
    n = r.shape[0] - 1
    worst, energy, power, speed = 0.0, 0.0, 0.0, 0.0
    still = np.zeros((2, 3))
    for k in range(2):
        for i in range(n):
            if not near[k, i]:
                continue
            if not fixture_apart(p, n, i, k):
                continue
            delta, s, _, F, pw, en, vn = _pair(
                p, r[i], r[i + 1], v[i : i + 2], tails[k, 0], tails[k, 1], still, True
            )
            worst = max(worst, delta)
            if delta > 0.0:
                out[i] += (1.0 - s) * F
                out[i + 1] += s * F
                if count < touching.shape[0]:
                    touching[count, 0], touching[count, 1] = i, -1 - k
                count += 1
                energy += en
                power += pw
                speed = max(speed, vn)
    return worst, count, energy, power, speed


#: the law's outcome where no two parts can touch (a nearly straight rod)
NO_CONTACT = ContactForces(np.zeros((0, 3)), 0.0, 0, 0.0, 0.0, np.zeros((0, 2), np.int64))


def contact_forces(
    p: LawParams, r: np.ndarray, v: np.ndarray, fixtures: bool = True
) -> ContactForces:
    """The law (module docstring) at one level: centreline r and inertial velocities v of
    the nodes (N+1, 3)."""
    r = np.ascontiguousarray(r, float)
    v = np.ascontiguousarray(v, float)
    mid = 0.5 * (r[1:] + r[:-1])
    pairs = cKDTree(mid).query_pairs(p.ds + p.diameter, output_type="ndarray").astype(np.int64)
    out = np.zeros_like(r)
    touching = np.zeros((pairs.shape[0] + 2 * r.shape[0], 2), np.int64)
    worst, count, energy, power, speed = _self_forces(p, r, v, pairs, out, touching)
    if fixtures:
        L = p.ds * (r.shape[0] - 1)
        e3 = np.array([0.0, 0.0, 1.0])
        tails = np.array([[r[0], r[0] - L * e3], [r[-1], r[-1] + L * e3]])
        low = np.minimum(r[1:, 2], r[:-1, 2])
        high = np.maximum(r[1:, 2], r[:-1, 2])
        near = np.array([low < r[0, 2] + p.diameter, high > r[-1, 2] - p.diameter])
        w2, count, e2, p2, s2 = _fixture_forces(p, r, v, tails, near, out, touching, count)
        worst, energy, power, speed = max(worst, w2), energy + e2, power + p2, max(speed, s2)
    return ContactForces(
        out, max(worst, 0.0), int(count), energy, power, touching[:count].copy(), speed
    )


def contact_sites(touching: np.ndarray) -> int:
    """Contact sites: touching segment pairs (i, j) grouped when both indices are within 2 of
    a pair already in the group (one site spans a few segments)."""
    if touching.shape[0] == 0:
        return 0
    pairs = sorted(map(tuple, touching.tolist()))
    groups: list[list[tuple[int, int]]] = []
    for i, j in pairs:
        for g in groups:
            if any(abs(i - a) <= 2 and abs(j - b) <= 2 for a, b in g):
                g.append((i, j))
                break
        else:
            groups.append([(i, j)])
    return len(groups)


def lag_cost(rod, stability: float, approach: float) -> dict[str, float | None]:
    """What the lagged penalty costs: the fastest approach of touching parts v [m/s] met
    in a run, the stiffness that holds it to 1 % of D (omega_c >= v / 0.01 D: an undamped
    spring taking the approach's kinetic energy) and the step that stiffness allows lagged
    (omega_c dt <= ``stability``)."""
    if approach <= 0.0:
        return {"max_approach_speed": None, "dt_for_1pct_penetration": None}
    omega = approach / (0.01 * rod.thickness)
    return {
        "max_approach_speed": approach,
        "stiffness_for_1pct_penetration": rod.mass_per_length * omega**2,
        "dt_for_1pct_penetration": stability / omega,
    }
