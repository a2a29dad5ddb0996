"""Section 4: Rodrigues' formula, frames in time and space, centrelines, self-contact."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from dyntorsion import buckling as b
from dyntorsion import shapes
from dyntorsion.buckling.scene import Scene


def test_rodrigues_matches_scipy(rng):
    x = np.vstack(
        [
            rng.normal(size=(50, 3)) * 2,
            rng.normal(size=(10, 3)) * 1e-7,
            [[0, 0, 0], [1e-300, 0, 0], [np.pi, 0, 0]],
        ]
    )
    np.testing.assert_allclose(
        shapes.rodrigues(x), Rotation.from_rotvec(-x).as_matrix(), atol=4e-16 * 4
    )


def test_rodrigues_is_orthogonal_and_continuous_at_small_angles():
    th = np.logspace(-9, -2, 40)
    x = np.outer(th, [0.3, -0.4, np.sqrt(0.75)])
    R = shapes.rodrigues(x)
    np.testing.assert_allclose(
        R @ np.swapaxes(R, -1, -2), np.broadcast_to(np.eye(3), R.shape), atol=2e-16 * 4
    )
    np.testing.assert_allclose(R, Rotation.from_rotvec(-x).as_matrix(), atol=1e-16 * 4)


def test_helix_from_constant_curvature():
    """Constant k = (k1, 0, k3): the spatial route gives a helix of the textbook radius."""
    k1, k3, n = 2.0, 3.0, 6000
    length = 3 * 2 * np.pi / np.hypot(k1, k3)  # three full turns
    k = np.tile([k1, 0.0, k3], (n + 1, 1))
    R = shapes.frames_along(k, length / n)
    r = shapes.centreline(R, length / n)[:-1]
    radius = k1 / (k1**2 + k3**2)
    axis = np.array([k1, 0.0, k3]) / np.hypot(k1, k3)  # the Darboux vector in the body = fixed
    # distance of the curve from its axis is constant
    centre = r - np.outer(r @ axis, axis)
    c0 = centre.mean(axis=0)
    dist = np.linalg.norm(centre - c0, axis=1)
    assert np.ptp(dist) < 1e-3 * radius
    assert np.mean(dist) == pytest.approx(radius, rel=1e-3)


def routes_discrepancy(n_cells):
    """Both routes on a run past the onset (every step kept); returns the largest distance
    between their centrelines, the deflection, and the time route's frames."""
    bent = b.simulate(
        Scene(a=10.0, kappa0=10.0, n_cells=n_cells, dt=0.01, t_end=2.0, seed=1e-4),
        snapshots=list(np.arange(0.0, 2.001, 0.01)),
    )
    run = bent.run
    ds = run.s[1] - run.s[0]
    R0 = shapes.frames_along(run.snapshots[0][:, 6:9], ds)
    tracker = shapes.FrameTracker(R0, shapes.centreline(R0, ds))
    for i in range(1, len(run.snapshot_times)):
        old, new = run.snapshots[i - 1], run.snapshots[i]
        tracker.step(
            old[:, 3:6],
            new[:, 3:6],
            old[:, 0:3],
            new[:, 0:3],
            run.snapshot_times[i] - run.snapshot_times[i - 1],
        )
    _, r_space = bent.shape(run.snapshot_times[-1])
    deflection = np.max(np.hypot(r_space[:, 0], r_space[:, 1]))
    return np.max(np.linalg.norm(tracker.r - r_space, axis=1)), deflection, tracker.R


def test_time_and_space_routes_agree():
    """The two routes are different second-order discretisations of the same shape: their
    difference is small and falls like ds^2 (dt fixed, the state resolved in time)."""
    coarse, deflection, R = routes_discrepancy(40)
    fine, _, _ = routes_discrepancy(80)
    assert deflection > 0.05  # the rod has really buckled
    assert fine < 0.1 * deflection
    assert coarse / fine > 3.5
    RtR = R @ np.swapaxes(R, -1, -2)
    assert np.max(np.abs(RtR - np.eye(3))) < 1e-13


def test_frame_tracker_stays_orthogonal_over_a_long_run(rng):
    R = np.broadcast_to(np.eye(3), (5, 3, 3)).copy()
    tracker = shapes.FrameTracker(R, np.zeros((5, 3)))
    w_old = rng.normal(size=(5, 3))
    for _ in range(100_000 // 5):
        w_new = rng.normal(size=(5, 3)) * 50
        tracker.step(w_old, w_new, np.zeros((5, 3)), np.zeros((5, 3)), 1e-3)
        w_old = w_new
    RtR = tracker.R @ np.swapaxes(tracker.R, -1, -2)
    assert np.max(np.abs(RtR - np.eye(3))) < 1e-12


def test_self_contact_finds_a_crossing_and_ignores_neighbours():
    s = np.linspace(0, 1, 101)
    straight = np.stack([0 * s, 0 * s, s], axis=1)
    assert shapes.self_contact(straight, 1e-3) is None
    loop = np.stack(
        [0.1 * np.sin(2 * np.pi * s), 0.1 * (1 - np.cos(2 * np.pi * s)) + 0 * s, 0.3 * s * (s - 1)],
        axis=1,
    )  # a circle whose ends meet up to 1e-4 m
    loop[-1] += [0, 0, 5e-4]
    hit = shapes.self_contact(loop, 1e-3)
    assert hit is not None and hit[0] < 1e-3
    assert {hit[1], hit[2]} & {0, 99}


def test_crossing_between_two_states():
    """Two strands of one centreline, 0.2 apart in arc length, swap sides between the
    states: a crossing; moving closer without swapping, or a rigid rotation, is none."""
    from dyntorsion.shapes import crossing

    def rod(z):
        x = np.linspace(-0.5, 0.5, 21)
        a = np.stack([x, 0 * x, 0 * x], 1)
        th = np.linspace(0, np.pi, 21)
        loop = np.stack([0.5 + 0.2 * np.sin(th), 0.2 * (1 - np.cos(th)), z * th / np.pi], 1)
        b = np.stack([0 * x, np.linspace(0.4, -0.5, 21), 0 * x + z], 1)
        return np.concatenate([a, loop[1:], b[1:]])

    turn = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    assert crossing(rod(0.01), rod(-0.01), 0.001) is not None
    assert crossing(rod(0.01), rod(0.002), 0.001) is None
    assert crossing(rod(0.01), rod(0.01) @ turn.T, 0.001) is None
