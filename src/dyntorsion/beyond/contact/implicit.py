"""The contact law of :mod:`.law` inside the implicit step: force and Jacobian at the new
level as functions of the new velocity fields.

**Positions at the new level.**  The contact acts on the time route of the centreline
(:mod:`.centreline`, :class:`dyntorsion.shapes.FrameTracker`, eqs 17-21): frames and
positions of every node advanced by its own spin and velocity,

    R^i = exp(-hat(dt (w^{i-1} + w^i) / 2)) R^{i-1},
    r^i = r^{i-1} + dt (V^{i-1} + V^i) / 2,    V = R^T u,                             (C1)

so a contact force depends on the unknowns u^i, w^i of the four nodes of its two
segments only, and the positions the law sees are those the velocities move (the spatial
route, rebuilt from the curvatures, drifts from them by more than a diameter in the whip
at N <= 200: a = 16, N = 200, 2.3 cm at the far end by t = 3.3 s, and a contact held on
one route passed through on the other).  The Jacobian keeps R^i of the iterate fixed
(the rotation's dependence on w^i, O(dt |w|) relative, is left to the iteration).

**Law, linearised in the step.**  For a pair of segments found near at the known level
(a k-d tree of segment midpoints, radius ds + D + travel), the closest points a(s), b(t)
and the unit normal n = (a - b) / |a - b| are those of the known level and stay fixed
during the step; the gap at the new level is n . (a^i - b^i) with a^i, b^i from (C1).
The force on segment a is that of :mod:`.law` on this gap,

    F = w ramp(k delta - c v_n) n,    delta = D - n . (a^i - b^i),   v_n = n . (V_a^i - V_b^i),

shared by the linear weights (1 - s, s) and (-(1 - t), -t) among the four nodes, w the
law's weight (ds, halved at a segment's end node), with the clip max(0, x) of the law
smoothed,

    ramp(x) = 0 (x <= -eps),  (x + eps)^2 / (4 eps) (|x| < eps),  x (x >= eps),     (C3)

eps = k D ``smooth``, the force of an overlap of ``smooth`` D (1e-3): no force at a gap
beyond ``smooth`` D at rest (at a gap below (eps + c |v_n|) / k while approaching; with
k = 5e7 N/m^2, c = 240 N s/m^2 at 1 m/s, 0.6 % of D).  A rounding by
(x + sqrt(x^2 + eps^2)) / 2 reached every candidate pair and did 0.5 % of the work of the
ends before any contact (a = 16, N = 50).  The clip's kink made
Newton cycle between the pressing and the lifting piece (measured: a = 16, N = 200,
t = 3.2 s, 30 iterations alternating).  With the normal fixed the argument x is
linear in V^i and

    dF / dV_b = -w ramp'(x) (k dt / 2 + c) n n^T sigma_b                         (C2)

(sigma_b the weight of node b).  The frames of (C1) turn with the new spins,
dR = -hat(e) R with e = J_l(-phi) dt dw / 2 (phi = dt (w^{i-1} + w^i) / 2, J_l the left
Jacobian of SO(3)), so V_b = R_b^T u_b and the body components of the force move with
w^i too:

    dV_b / dw_b = -R_b^T hat(u_b) (dt / 2) J_l(-phi_b),
    dq_a / dw_a (frame of a) = hat(q_a) (dt / 2) J_l(-phi_a),                      (C4)

and the Jacobian is exact in both u^i and w^i (checked against finite differences).
Measured (a = 16, N = 200): (C4) alone did not cut the Newton iterations of a contact
step (about 24 without, 22.5 with); the failing solves had no active pair -- the frames
turned ~0.8 rad in a substep -- and the step control of :mod:`dyntorsion.genalpha.state_steps` is what brought
them to 8.6.  A normal fixed over the step cannot be crossed: the rod
cannot pass through itself within a step that starts on the right side, whatever the
step, as the spatial normal of the lagged law could (it flips when the centrelines cross).

**Source of eq (7).**  The nodal forces f_a (inertial) enter the linear momentum balance
as q_a = -R_a f_a / w_a (body components per unit length, w_a = ds, ds/2 at the ends) at
the new level, with the box scheme's weights (1 - b_t) and, within a cell,
(1 - b_s, b_s) on its right and left node.  Their Jacobian (C2, C4) has two parts:

    dq = sum_p U_p G_p^T dy + sum_a hat(q_a) turn_a dw_a,                           (C5)

a rank-one term for each pair pressing (its force keeps the direction R n and only its
magnitude ramp(x) moves, with x linear in the velocities and spins of its four nodes:
U_p the rows the unit force reaches, G_p the gradient of the magnitude) and a 3 x 3
block of each node in contact (the frame turning the body components), which couples
a node's spin to the cells beside it only, so lies inside the band.  The blocks go into
the banded Jacobian (with the trapezoidal quadrature, into its nodal dF, where they take
the cells' weights of q_a; with the midpoint one, as three rank-one terms each) and the
rank-one terms to :mod:`.linear` (the Woodbury identity on the banded factors for few,
a sparse LU of the whole matrix for many): one column a pair instead of six for each of
its (up to four) nodes.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from scipy.spatial import cKDTree

from ... import shapes
from ..._numba import IndexMatrix, Matrix, Vector, jit
from .law import LawParams, closest_points, fixture_apart, node_share, ordered_apart

__all__ = ["Known", "Layout", "StepParams", "Pairs", "candidates", "contact_source"]


class StepParams(NamedTuple):
    """What the implicit law of one step reads: the law and the step's scheme numbers."""

    law: LawParams
    dt: float
    g_t: float  # (C1): r^i = r^{i-1} + dt [(1 - g_t) V^{i-1} + g_t V^i], g_t = 1/2
    b_t: float  # weight of the old level in the cell residual
    b_s: float  # weight of the left node in the cell residual
    smooth: float  # (C3): eps = k D smooth


class Pairs(NamedTuple):
    """The candidate pairs of one step, from the known level.  ``nodes[p]``: the four
    nodes (-1: a fixed point of an end fixture), ``sigma[p]`` their weights, ``n[p]`` the
    normal, ``d[p]`` the closest-point vector a - b at the known level, ``w[p]`` the
    law's weight."""

    nodes: IndexMatrix  # (P, 4)
    sigma: Matrix  # (P, 4)
    n: Matrix  # (P, 3)
    d: Matrix  # (P, 3)
    w: Vector  # (P,)

    @classmethod
    def empty(cls, size: int) -> Pairs:
        """Room for ``size`` pairs (filled by :func:`_gather_kernel`)."""
        return cls(np.empty((size, 4), np.int64), np.empty((size, 4)), np.empty((size, 3)),
                   np.empty((size, 3)), np.empty(size))  # fmt: skip

    def first(self, k: int) -> Pairs:
        """The first k pairs, copied."""
        return Pairs(*(a[:k].copy() for a in self))


#: pairs whose ramp slope (C3) is below this enter the residual only, not the Jacobian (a
#: gap of more than ~50 eps / k: the Newton iteration converges the same, with fewer columns)
SLOPE_MIN = 1e-4

NO_PAIRS = Pairs.empty(0)


@jit
def _gather_kernel(p: LawParams, r, pairs, reach, tails, fixtures, out: Pairs):
    """Fill ``out`` with the candidate pairs (module docstring) among segment pairs
    ``pairs`` and, with ``fixtures``, the segments against the two axis pieces ``tails``:
    closer than ``reach`` at the known level and farther apart along the rod than
    ``min_arc``.  Returns their number."""
    nodes, sigma, normal, dist, weight = out
    n_seg = r.shape[0] - 1
    k = 0
    for m in range(pairs.shape[0]):
        i, j, apart = ordered_apart(p, pairs[m, 0], pairs[m, 1])
        if not apart:
            continue
        s, t, dv = closest_points(r[i], r[i + 1], r[j], r[j + 1])
        d = math.sqrt(dv @ dv)
        if d >= reach or d == 0.0:
            continue
        nodes[k, 0], nodes[k, 1], nodes[k, 2], nodes[k, 3] = i, i + 1, j, j + 1
        sigma[k, 0], sigma[k, 1], sigma[k, 2], sigma[k, 3] = 1.0 - s, s, -(1.0 - t), -t
        normal[k] = dv / d
        dist[k] = dv
        weight[k] = p.ds * node_share(s) * node_share(t)
        k += 1
    if not fixtures:
        return k
    for side in range(2):
        for i in range(n_seg):
            low = min(r[i + 1, 2], r[i, 2])
            high = max(r[i + 1, 2], r[i, 2])
            if side == 0 and not low < r[0, 2] + reach:
                continue
            if side == 1 and not high > r[n_seg, 2] - reach:
                continue
            if not fixture_apart(p, n_seg, i, side):
                continue
            s, _, dv = closest_points(r[i], r[i + 1], tails[side, 0], tails[side, 1])
            d = math.sqrt(dv @ dv)
            if d >= reach or d == 0.0:
                continue
            nodes[k, 0], nodes[k, 1], nodes[k, 2], nodes[k, 3] = i, i + 1, -1, -1
            sigma[k, 0], sigma[k, 1], sigma[k, 2], sigma[k, 3] = 1.0 - s, s, 0.0, 0.0
            normal[k] = dv / d
            dist[k] = dv
            weight[k] = p.ds * node_share(s)
            k += 1
    return k


def _gather(p: LawParams, r, pairs, reach, tails, fixtures) -> Pairs:
    """The candidate pairs (:func:`_gather_kernel`) as :class:`Pairs`."""
    out = Pairs.empty(pairs.shape[0] + (2 * (r.shape[0] - 1) if fixtures else 0))
    k = _gather_kernel(p, r, np.ascontiguousarray(pairs, np.int64), float(reach), tails,
                       bool(fixtures), out)  # fmt: skip
    return NO_PAIRS if k == 0 else out.first(k)


def candidates(p: LawParams, r: np.ndarray, V: np.ndarray, dt: float, fixtures: bool) -> Pairs:
    """The pairs that may touch during a step of dt from the known level (r, V): closest
    points nearer than D + travel, travel = 4 dt max|V| + D/2 (twice the largest
    relative displacement at the known speeds, and half a diameter)."""
    reach = p.diameter + 4.0 * dt * float(np.max(np.linalg.norm(V, axis=1))) + 0.5 * p.diameter
    mid = 0.5 * (r[1:] + r[:-1])
    pairs = cKDTree(mid).query_pairs(p.ds + reach, output_type="ndarray")
    pairs = pairs[(np.abs(pairs[:, 1] - pairs[:, 0]) - 1) * p.ds > p.min_arc]
    tails = np.zeros((2, 2, 3))
    if fixtures:
        L = p.ds * (r.shape[0] - 1)
        e3 = np.array([0.0, 0.0, 1.0])
        tails = np.array([[r[0], r[0] - L * e3], [r[-1], r[-1] + L * e3]])
    return _gather(p, np.ascontiguousarray(r), pairs, reach, tails, fixtures)


@jit
def _ramp(x, eps):
    """max(0, x) with its kink rounded over |x| < eps (C3), and its slope."""
    if x <= -eps:
        return 0.0, 0.0
    if x >= eps:
        return x, 1.0
    return (x + eps) * (x + eps) / (4.0 * eps), (x + eps) / (2.0 * eps)


@jit
def _forces(sp: StepParams, pairs: Pairs, V_old, V_new, f, slope):
    """Nodal forces f (N+1, 3, inertial) of the pairs at the new velocities V_new, and each
    pair's slope ramp'(x) (C3).  Returns (largest overlap, energy, dashpot power)."""
    nodes, sigma, normal, dist, weight = pairs
    k, c, D = sp.law.stiffness, sp.law.damping, sp.law.diameter
    eps = k * sp.smooth * D
    worst, energy, power = 0.0, 0.0, 0.0
    for p in range(nodes.shape[0]):
        gap = 0.0
        vn = 0.0
        for a in range(4):
            b = nodes[p, a]
            if b < 0:
                continue
            for x in range(3):
                dr = sp.dt * ((1.0 - sp.g_t) * V_old[b, x] + sp.g_t * V_new[b, x])
                gap += sigma[p, a] * dr * normal[p, x]
                vn += sigma[p, a] * V_new[b, x] * normal[p, x]
        for x in range(3):
            gap += dist[p, x] * normal[p, x]
        delta = D - gap
        worst = max(worst, delta)
        mag, slope[p] = _ramp(k * delta - c * vn, eps)
        w = weight[p]
        if delta > 0.0:
            energy += 0.5 * w * k * delta * delta
        power += -w * c * vn * vn * slope[p]
        for a in range(4):
            b = nodes[p, a]
            if b < 0:
                continue
            for x in range(3):
                f[b, x] += sigma[p, a] * w * mag * normal[p, x]
    return worst, energy, power


class Source(NamedTuple):
    """The contact at one iterate: the source q (N+1, nf) of eq (7) at the new level, and its
    Jacobian in the scaled rows and unknowns as (C5): the sum of the outer products
    ``U[k] G[k]^T`` (one per pair pressing, rank one) and of the blocks ``turn[m]`` =
    dq_a / dw_a of the nodes ``nodes[m]`` (physical units, added to the banded Jacobian);
    the largest predicted overlap, the stored energy and the dashpots' power of the pairs."""

    q: np.ndarray
    U: np.ndarray  # (k, rows of the scaled residual)
    G: np.ndarray  # (k, scaled unknowns)
    nodes: np.ndarray  # (m,)
    turn: np.ndarray  # (m, 3, 3)
    overlap: float
    energy: float
    power: float
    active: int


class Known(NamedTuple):
    """The known level of a step, at the N+1 nodes: the frames ``R`` (N+1, 3, 3), the lab
    velocities ``V`` (N+1, 3) [m/s] and the spins ``w`` (N+1, 3) [rad/s]."""

    R: np.ndarray
    V: np.ndarray
    w: np.ndarray


class Layout(NamedTuple):
    """The layout of the step's scaled residual and unknowns: ``nf`` fields a node, the
    ``nbl`` boundary rows at s = 0 first, the scales of the rows ``rscale`` (nf,) and of
    the unknowns ``yscale`` (nf,) (:class:`~dyntorsion.genalpha.discrete.Constants`)."""

    nf: int
    nbl: int
    rscale: np.ndarray
    yscale: np.ndarray


def contact_source(sp: StepParams, pairs: Pairs, known: Known, y_new, weights, layout: Layout,
                   want_jac: bool = True, band: bool = True) -> Source:  # fmt: skip
    """The contact source and its Jacobian (module docstring, C1-C5) at the iterate
    ``y_new`` (N+1, nf) (body velocities u = y[:, 0:3], spins w = y[:, 3:6]), the step
    from the :class:`Known` level ``known``; ``weights`` (N+1,) the nodes' lengths
    [m]; ``layout`` the residual's :class:`Layout`.  ``want_jac`` False: the source
    alone (empty terms).  ``band``: the frames' blocks (C4, second line) as ``turn`` for
    the banded Jacobian (a trapezoidal quadrature adds them to its nodal dF); else as
    three more rank-one terms a node in ``U``, ``G``."""
    R_old, V_old, w_old = known
    nf, nbl, rscale, yscale = layout
    n1 = R_old.shape[0]
    R = shapes.rodrigues(0.5 * sp.dt * (y_new[:, 3:6] + w_old)) @ R_old  # (C1)
    V_new = np.einsum("nji,nj->ni", R, y_new[:, 0:3])
    f = np.zeros((n1, 3))
    slope = np.zeros(pairs.nodes.shape[0])
    worst, energy, power = _forces(sp, pairs, V_old, V_new, f, slope)
    q = np.zeros((n1, nf))
    q[:, 0:3] = -np.einsum("nij,nj->ni", R, f) / weights[:, None]
    on = np.flatnonzero(slope > SLOPE_MIN)
    if not want_jac or on.size == 0:
        none = np.zeros((0, nf * n1))
        return Source(q, none, none, NO_NODES, NO_BLOCKS, worst, energy, power, int(on.size))
    nodes = np.unique(pairs.nodes[on][pairs.nodes[on] >= 0])
    turn = 0.5 * sp.dt * left_jacobian(-0.5 * sp.dt * (y_new[:, 3:6] + w_old))  # (C4)
    blocks = np.empty((nodes.size, 3, 3))
    _frame_blocks(nodes, np.ascontiguousarray(q[:, 0:3]), turn, blocks)
    k = on.size + (0 if band else 3 * nodes.size)
    U, G = np.zeros((k, nf * n1)), np.zeros((k, nf * n1))
    stiff = sp.law.stiffness * sp.g_t * sp.dt + sp.law.damping
    _pair_terms(sp, pairs, on, slope, stiff, R, np.ascontiguousarray(y_new[:, 0:3]), turn,
                weights, nbl, rscale, yscale, U, G)  # fmt: skip
    if band:
        return Source(q, U, G, nodes, blocks, worst, energy, power, int(on.size))
    _block_terms(sp, nodes, blocks, on.size, nbl, rscale, yscale, U, G)
    return Source(q, U, G, NO_NODES, NO_BLOCKS, worst, energy, power, int(on.size))


NO_NODES, NO_BLOCKS = np.zeros(0, np.int64), np.zeros((0, 3, 3))


def left_jacobian(x: np.ndarray) -> np.ndarray:
    """J_l(x) = E + (1 - cos t) / t^2 hat(x) + (t - sin t) / t^3 hat(x)^2, t = |x|, for x of
    shape (n, 3): d exp(hat(x)) = hat(J_l(x) dx) exp(hat(x)) (series below t = 1e-4)."""
    t = np.linalg.norm(x, axis=1)
    small = t < 1e-4
    ts = np.where(small, 1.0, t)
    a = np.where(small, 0.5 - t**2 / 24.0, (1.0 - np.cos(ts)) / ts**2)
    b = np.where(small, 1.0 / 6.0 - t**2 / 120.0, (ts - np.sin(ts)) / ts**3)
    H = shapes.hat(x)
    return np.eye(3) + a[:, None, None] * H + b[:, None, None] * (H @ H)


@jit
def _rows(sp: StepParams, na, v, nbl, rscale, out):
    """out[rows] += a source v of node na in the linear momentum rows (3 values) as the
    cells a - 1 (weight 1 - b_s) and a (b_s) take it, with 1 - b_t, scaled."""
    nf = rscale.shape[0]
    n1 = out.shape[0] // nf
    for side in range(2):
        cell = na - 1 + side
        if cell < 0 or cell >= n1 - 1:
            continue
        wt = (1.0 - sp.b_t) * ((1.0 - sp.b_s) if side == 0 else sp.b_s)
        row = nbl + nf * cell
        for x in range(3):
            out[row + x] += wt * v[x] / rscale[x]


@jit
def _pair_terms(sp: StepParams, pairs: Pairs, on, slope, stiff, R, u, turn, weights, nbl,
                rscale, yscale, U, G):  # fmt: skip
    """(C5): the pressing pair p = on[k] adds U[k] G[k]^T, U[k] the rows its unit force
    reaches, sigma_a R_a n / w_a at each node a, and G[k] the derivative of its force's
    magnitude, -d ramp / d(u_b, w_b) = ramp' (k g_t dt + c) w sigma_b (R_b n, -(R_b n x u_b)
    turn_b) (C2, C4), in the scaled rows and unknowns."""
    nodes, sigma, normal, weight = pairs.nodes, pairs.sigma, pairs.n, pairs.w
    nf = rscale.shape[0]
    for k in range(on.shape[0]):
        p = on[k]
        coef = weight[p] * slope[p] * stiff
        for a in range(4):
            na = nodes[p, a]
            if na < 0:
                continue
            Rn = R[na] @ normal[p]
            _rows(sp, na, sigma[p, a] / weights[na] * Rn, nbl, rscale, U[k])
            cr = np.cross(Rn, u[na]) @ turn[na]
            for y in range(3):
                G[k, nf * na + y] += coef * sigma[p, a] * Rn[y] * yscale[y]
                G[k, nf * na + 3 + y] -= coef * sigma[p, a] * cr[y] * yscale[3 + y]


@jit
def _frame_blocks(nodes, q, turn, out):
    """(C4), second line: the body components q_a of the force turn with the frame of a,
    dq_a / dw_a = hat(q_a) turn_a, for each node of ``nodes``."""
    Q = np.zeros((3, 3))
    for m in range(nodes.shape[0]):
        na = nodes[m]
        Q[0, 1], Q[0, 2], Q[1, 2] = -q[na, 2], q[na, 1], -q[na, 0]
        Q[1, 0], Q[2, 0], Q[2, 1] = q[na, 2], -q[na, 1], q[na, 0]
        out[m] = Q @ turn[na]


@jit
def _block_terms(sp: StepParams, nodes, blocks, k0, nbl, rscale, yscale, U, G):
    """The blocks dq_a / dw_a as rank-one terms: U[k] the rows of column y of the block,
    G[k] the unit on w_y of node a (scaled), from k = k0 on."""
    nf = rscale.shape[0]
    k = k0
    for m in range(nodes.shape[0]):
        na = nodes[m]
        for y in range(3):
            _rows(sp, na, np.ascontiguousarray(blocks[m, :, y]), nbl, rscale, U[k])
            G[k, nf * na + 3 + y] = yscale[3 + y]
            k += 1


@jit
def add_blocks(nodes, blocks, dF):
    """dF[a][u rows, w columns] += the blocks of ``nodes`` (the trapezoidal quadrature's
    nodal Jacobian of F: the cells beside a take it with the same weights as q_a)."""
    for m in range(nodes.shape[0]):
        na = nodes[m]
        for x in range(3):
            for y in range(3):
                dF[na, x, 3 + y] += blocks[m, x, y]


def add_to_residual(r, q_new, sp: StepParams, nf, nbl, rscale) -> None:
    """r += the new level's contact source in every cell: (1 - b_t) [(1 - b_s) q_j +
    b_s q_{j-1}] / rscale (the rows of prepare_step / residual)."""
    cell = (1.0 - sp.b_t) * ((1.0 - sp.b_s) * q_new[1:] + sp.b_s * q_new[:-1]) / rscale
    r[nbl : nbl + cell.size] += cell.ravel()
