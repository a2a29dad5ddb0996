"""The compiled self-contact and crossing tests of :mod:`dyntorsion.shapes` against the
vectorised numpy formulation they replaced (kept here as the reference): same pairs,
same distances, on random curled centrelines and on states of a run past the onset."""

import numpy as np
import pytest

from dyntorsion import shapes
from dyntorsion.buckling.scene import Scene


def _segment_distances(p0, p1, q0, q1):
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


def _candidate_pairs(arc, r, seg, diameter, min_arc, reach):
    i, j = np.triu_indices(seg.size, k=2)
    keep = arc[j] - arc[i + 1] > (2 * diameter if min_arc is None else min_arc)
    i, j = i[keep], j[keep]
    mid = 0.5 * (r[1:] + r[:-1])
    near = np.linalg.norm(mid[i] - mid[j], axis=1) < reach * (seg[i] + seg[j]) + diameter
    return i[near], j[near]


def _segments(r):
    d = np.diff(r, axis=0)
    seg = np.linalg.norm(d, axis=1)
    return r, d, seg, np.concatenate([[0.0], np.cumsum(seg)])


def reference_self_contact(r, diameter, min_arc=None):
    r, _, seg, arc = _segments(r)
    i, j = _candidate_pairs(arc, r, seg, diameter, min_arc, reach=0.5)
    if i.size == 0:
        return None
    d = _segment_distances(r[i], r[i + 1], r[j], r[j + 1])
    m = int(np.argmin(d))
    return (float(d[m]), int(i[m]), int(j[m])) if d[m] < diameter else None


def reference_crossing(r_old, r_new, diameter, min_arc=None):
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
        ok = norm > 0.5 * seg[i] * seg[j]
        nrm = cr / np.where(ok, norm, 1.0)[:, None]
        w = r[j] - r[i]
        dist = np.einsum("ij,ij->i", w, nrm)
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


def curled(rng, n=60, scale=12.0):
    """A centreline of unit length whose curvatures wander enough to loop back on itself."""
    k = np.cumsum(rng.normal(size=(n + 1, 3)) * scale / np.sqrt(n), axis=0)
    return shapes.shape(np.hstack([np.zeros((n + 1, 6)), k, np.zeros((n + 1, 3))]), 1.0 / n)


def test_self_contact_kernel_matches_the_vectorised_reference(rng):
    hits = 0
    for _ in range(300):
        r = curled(rng)
        diameter = 10 ** rng.uniform(-3, -1)
        got, ref = shapes.self_contact(r, diameter), reference_self_contact(r, diameter)
        assert (got is None) == (ref is None)
        if ref is not None:
            hits += 1
            same_pair(r, got, ref)
    assert 30 < hits < 270  # both outcomes are exercised


def same_pair(r, got, ref):
    """The closest pair found, or, where the closest points sit on a node shared by two
    segments (a tie to round-off), its neighbour at the same distance."""
    assert got[0] == pytest.approx(ref[0], rel=1e-12)
    if got[1:] != ref[1:]:
        i, j = got[1], got[2]
        assert abs(i - ref[1]) + abs(j - ref[2]) == 1
        d = _segment_distances(r[[i]], r[[i + 1]], r[[j]], r[[j + 1]])[0]
        assert d == pytest.approx(ref[0], rel=1e-12)


def test_crossing_kernel_matches_the_vectorised_reference(rng):
    """Two strands of one centreline (as in test_shapes) at heights z0, z1 of either sign,
    turned and jittered: crossings where z changes sign, none where it does not."""

    def strands(z, turn, jitter):
        x = np.linspace(-0.5, 0.5, 21)
        a = np.stack([x, 0 * x, 0 * x], 1)
        th = np.linspace(0, np.pi, 21)
        loop = np.stack([0.5 + 0.2 * np.sin(th), 0.2 * (1 - np.cos(th)), z * th / np.pi], 1)
        b = np.stack([0 * x, np.linspace(0.4, -0.5, 21), 0 * x + z], 1)
        return (np.concatenate([a, loop[1:], b[1:]]) + jitter) @ turn.T

    from scipy.spatial.transform import Rotation

    hits = 0
    for _ in range(300):
        turn = Rotation.from_rotvec(rng.normal(size=3)).as_matrix()
        jitter = rng.normal(size=(61, 3)) * 0.003
        z0, z1 = rng.uniform(-0.03, 0.03, size=2)
        r0, r1 = strands(z0, turn, jitter), strands(z1, turn, jitter)
        got, ref = shapes.crossing(r0, r1, 1e-3), reference_crossing(r0, r1, 1e-3)
        assert got == ref
        hits += ref is not None
    assert 20 < hits < 280


def test_kernels_on_a_run_past_the_onset():
    """States of a real whip, level after level: the same contacts and crossings."""
    from dyntorsion import buckling as b
    from dyntorsion.genalpha import Scheme, StepControl

    run = b.simulate(Scene(a=10.0, kappa0=10.0, n_cells=40, dt=0.01, t_end=4.0, seed=1e-4, scheme=Scheme(control=StepControl())), snapshots=list(np.arange(2.0, 4.0, 0.01)), stop_at_contact=False, on_failure="return").run  # fmt: skip
    ds = run.s[1] - run.s[0]
    rs = [shapes.shape(y, ds) for y in run.snapshots]
    hits = 0
    for diameter in (1e-3, 1e-2, 3e-2):
        for old, new in zip(rs[:-1], rs[1:], strict=True):
            got, ref = shapes.self_contact(new, diameter), reference_self_contact(new, diameter)
            assert (got is None) == (ref is None)
            hits += (ref is not None) + (reference_crossing(old, new, diameter) is not None)
            if ref is not None:
                same_pair(new, got, ref)
            assert shapes.crossing(old, new, diameter) == reference_crossing(old, new, diameter)
    assert hits >= 10  # the whip touches and passes through itself
