"""Past self-contact (issue 33): topology (Lk = Tw + Wr), the reconstruction of the
centreline, the contact law, and runs through contact (dyntorsion.beyond.contact)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dyntorsion.beyond.contact import topology as T
from dyntorsion.beyond.contact.law import LawParams, contact_forces


def helix(turns: float, a: float = 0.1, b: float = 0.05, per_turn: int = 400) -> np.ndarray:
    """A right-handed helix of radius a and pitch 2 pi b starting on the e3 axis direction."""
    th = np.linspace(0.0, 2 * np.pi * turns, int(per_turn * turns) + 1)
    return np.c_[a * np.cos(th) - a, a * np.sin(th), b * th]


def test_writhe_per_turn_of_a_helix_is_one_minus_cos_of_its_pitch_angle():
    """Fuller (1971): each turn of a helix whose tangent makes the angle alpha with its axis
    adds 1 - cos(alpha) to the writhe; the end effects cancel in the difference."""
    a, b = 0.1, 0.05
    w = [T.writhe_turns(T.closed_polygon(helix(n, a, b))) for n in (4, 5, 6)]
    exact = 1.0 - b / math.hypot(a, b)
    assert np.allclose(np.diff(w), exact, rtol=0, atol=3e-5), (np.diff(w), exact)
    mirrored = helix(5, a, b) * np.array([1.0, -1.0, 1.0])  # a left-handed helix
    assert T.writhe_turns(T.closed_polygon(mirrored)) == pytest.approx(-w[1], abs=1e-12)


def _writhe_numpy(closed: np.ndarray) -> float:
    """Klenin and Langowski's eq 15 over every non-adjacent pair of segments at once (numpy):
    an independent evaluation of what ``topology._writhe`` computes pair by pair."""
    q = np.vstack([closed, closed[:1]])
    m = closed.shape[0]
    i, j = np.triu_indices(m, 2)
    keep = ~((i == 0) & (j == m - 1))
    i, j = i[keep], j[keep]
    x1, x2, x3, x4 = q[i], q[i + 1], q[j], q[j + 1]

    def unit(a, b):
        c = np.cross(a, b)
        n = np.linalg.norm(c, axis=1, keepdims=True)
        return c / np.where(n == 0, 1.0, n), n[:, 0] > 0

    r13, r14, r23, r24 = x3 - x1, x4 - x1, x3 - x2, x4 - x2
    (n1, k1), (n2, k2), (n3, k3), (n4, k4) = (unit(r13, r14), unit(r14, r24), unit(r24, r23),
                                              unit(r23, r13))  # fmt: skip
    dot = lambda a, b: np.arcsin(np.clip(np.sum(a * b, axis=1), -1.0, 1.0))  # noqa: E731
    om = dot(n1, n2) + dot(n2, n3) + dot(n3, n4) + dot(n4, n1)
    sign = np.sign(np.sum(np.cross(x4 - x3, x2 - x1) * r13, axis=1))
    return float(np.sum(np.where(k1 & k2 & k3 & k4, om * sign, 0.0)) / (2 * np.pi))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_compiled_writhe_agrees_with_the_pairs_evaluated_at_once(seed):
    """The compiled kernel (scalar arithmetic, one pair at a time) against the same formula
    over all pairs in numpy, on random walks closed as the rod is closed."""
    rng = np.random.default_rng(seed)
    for n in (3, 40, 300):
        closed = T.closed_polygon(np.cumsum(rng.normal(size=(n, 3)), axis=0))
        ref = _writhe_numpy(closed)
        assert T.writhe_turns(closed) == pytest.approx(ref, rel=1e-12, abs=1e-12)


def test_a_plane_curve_and_the_straight_rod_have_no_writhe():
    th = np.linspace(0, 2 * np.pi, 300, endpoint=False)
    plane = np.c_[np.cos(th) * (1 + 0.3 * np.cos(3 * th)), np.sin(th), 0 * th]
    assert abs(T.writhe_turns(plane)) < 1e-12
    straight = np.c_[np.zeros(51), np.zeros(51), np.linspace(0, 1, 51)]
    assert abs(T.writhe_turns(T.closed_polygon(straight))) < 1e-12
    assert T.twist_turns(np.full(51, 2 * np.pi), 0.02) == pytest.approx(1.0, rel=1e-14)


def _rotate(v, axis, angle):
    axis = axis / np.linalg.norm(axis)
    return (v * math.cos(angle) + np.cross(axis, v) * math.sin(angle)
            + axis * (axis @ v) * (1 - math.cos(angle)))  # fmt: skip


def _ribbon(curve: np.ndarray, extra_turns: int):
    """A closed ribbon on the closed polygon ``curve``: a normal parallel-transported round
    it, then turned about the tangent uniformly so that it closes after ``extra_turns``
    turns beyond the holonomy.  Returns its twist [turns] and the edge curve."""
    M = curve.shape[0]
    t = np.roll(curve, -1, axis=0) - curve
    t /= np.linalg.norm(t, axis=1)[:, None]
    u = np.empty((M + 1, 3))
    u[0] = np.cross(t[0], [0.3, 0.5, 0.8])
    u[0] /= np.linalg.norm(u[0])
    for j in range(M):  # minimal rotation from t_j to t_{j+1}
        a, b = t[j], t[(j + 1) % M]
        ax = np.cross(a, b)
        s = np.linalg.norm(ax)
        u[j + 1] = u[j] if s < 1e-15 else _rotate(u[j], ax, math.atan2(s, a @ b))
    hol = math.atan2(np.cross(u[0], u[M]) @ t[0], u[0] @ u[M])  # angle u_0 -> u_M about t_0
    psi = (hol - 2 * np.pi * extra_turns) * np.arange(M) / M  # d1_M = d1_0
    d1 = np.array([_rotate(u[j], t[j], -psi[j]) for j in range(M)])
    # the edge at each vertex: d1 of the segments either side, made normal to the vertex tangent
    v = d1 + np.roll(d1, 1, axis=0)
    tv = t + np.roll(t, 1, axis=0)
    tv /= np.linalg.norm(tv, axis=1)[:, None]
    v -= tv * np.einsum("ij,ij->i", v, tv)[:, None]
    v /= np.linalg.norm(v, axis=1)[:, None]
    twist = (hol - 2 * np.pi * extra_turns) / (2 * np.pi)
    return -twist, curve + 1e-3 * v


@pytest.mark.parametrize("extra", [0, 2, -3])
def test_calugareanu_on_a_closed_ribbon_with_the_link_from_the_gauss_integral(extra):
    """Lk = Tw + Wr on a trefoil knot, the link of the ribbon's edges counted independently
    (Gauss linking integral of the two closed curves, an integer)."""
    th = np.linspace(0, 2 * np.pi, 1500, endpoint=False)
    knot = np.c_[np.sin(th) + 2 * np.sin(2 * th), np.cos(th) - 2 * np.cos(2 * th), -np.sin(3 * th)]
    tw, edge = _ribbon(knot, extra)
    lk = T.linking_turns(knot, edge)
    assert abs(lk - round(lk)) < 1e-6
    assert abs(tw + T.writhe_turns(knot) - lk) < 0.01, (tw, T.writhe_turns(knot), lk)


def _law(k=1000.0, c=0.0):
    return LawParams(diameter=1e-3, stiffness=k, damping=c, ds=0.02, min_arc=3e-3)


@pytest.mark.parametrize("shift", [0.0, 0.005])
def test_the_contact_force_pushes_two_crossing_parts_apart_and_conserves_momentum(shift):
    """A rod bent back across itself: the two crossing parts overlap by 0.2 D; the force is
    k delta ds along the line of centres, equal and opposite, and the energy k ds delta^2 / 2,
    whether they cross at nodes (shift 0: four segment pairs find the contact) or between."""
    s = np.linspace(0.0, 1.0, 51)
    r = np.c_[np.zeros(51), np.zeros(51), s]
    x = np.linspace(-0.1, 0.1, 21) + shift
    r[30:] = np.c_[x, np.full(21, 0.8e-3), np.full(21, 0.5 + shift)]  # crosses
    law = _law()
    cf = contact_forces(law, r, np.zeros_like(r), fixtures=False)
    assert cf.pairs >= 1
    assert cf.max_overlap == pytest.approx(0.2e-3, rel=1e-9)
    assert np.allclose(cf.force.sum(axis=0), 0.0, atol=1e-15)
    total_on_second = cf.force[30:].sum(axis=0)
    assert total_on_second[1] > 0 and abs(total_on_second[0]) < 1e-12
    assert np.linalg.norm(total_on_second) == pytest.approx(
        law.stiffness * 0.2e-3 * law.ds, rel=1e-9
    )
    assert cf.energy == pytest.approx(0.5 * law.ds * law.stiffness * (0.2e-3) ** 2, rel=1e-9)


def test_contact_sites_group_neighbouring_pairs_and_the_lag_cost_follows_the_approach():
    from dyntorsion import Rod
    from dyntorsion.beyond.contact.law import contact_sites, lag_cost

    assert contact_sites(np.zeros((0, 2), np.int64)) == 0
    assert contact_sites(np.array([[3, 30], [4, 30], [4, 31], [10, 40], [3, -1]])) == 3
    rod = Rod()
    cost = lag_cost(rod, 0.5, 1.0)
    omega = 1.0 / (0.01 * rod.thickness)
    assert cost["dt_for_1pct_penetration"] == pytest.approx(0.5 / omega)
    assert cost["stiffness_for_1pct_penetration"] == pytest.approx(rod.mass_per_length * omega**2)
    assert lag_cost(rod, 0.5, 0.0)["dt_for_1pct_penetration"] is None


def test_near_neighbours_along_the_rod_never_touch_and_fixtures_hold_the_axis():
    s = np.linspace(0.0, 1.0, 51)
    r = np.c_[np.zeros(51), np.zeros(51), s]
    assert contact_forces(_law(), r, np.zeros_like(r)).pairs == 0
    # the free part swung back below the left end, onto the axis beyond it
    r2 = r.copy()
    r2[40:, 2] = -0.05
    r2[40:, 0] = np.linspace(-0.1, 0.1, 11)
    cf = contact_forces(_law(), r2, np.zeros_like(r2))
    assert cf.pairs >= 1 and np.all(cf.touching[:, 1] == -1)
    assert contact_forces(_law(), r2, np.zeros_like(r2), fixtures=False).pairs == 0


# ------------------------------------------------------------------ scenes and runs
from dyntorsion.beyond.contact.run import Contact, ContactScene, run_contact_scene  # noqa: E402
from dyntorsion.buckling.scene import Scene  # noqa: E402


def test_a_contact_scene_keeps_the_scene_key_and_adds_the_contact():
    scene = Scene(a=16.0, kappa0=10.0, t_end=6.0, n_cells=50, dt=0.01)
    before = scene.params()
    cs = ContactScene(scene, Contact(stiffness=500.0, implicit=False))
    assert scene.params() == before and "contact" not in before
    assert cs.params() == {**before, "contact": Contact(stiffness=500.0, implicit=False).params()}
    # implicit (the default): substeps of at most max_step near contact
    imp = ContactScene(scene, Contact(stiffness=500.0, max_step=3e-4))
    assert imp.dt_run <= 3e-4 < scene.dt / (imp.substeps() - 1)
    # the lagged penalty's step: omega_c dt_run <= 0.5
    w = math.sqrt(500.0 / scene.rod.mass_per_length)
    assert w * cs.dt_run <= 0.5 < w * scene.dt / (cs.substeps() - 1)


@pytest.mark.parametrize(
    "kwargs, word",
    [({"stiffness": 0.0}, "stiffness"), ({"damping": -1.0}, "damping"),
     ({"min_arc": 0.5}, "min_arc"), ({"stability": 3.0}, "stability"),
     ({"check": float("nan")}, "check"), ({"max_step": 0.0}, "max_step"),
     ({"smooth": 2.0}, "smooth"), ({"min_step": 0.0}, "min_step"),
     ({"min_step": 1e-3, "max_step": 1e-4}, "min_step"),
     ({"max_cell_bend": 0.0}, "max_cell_bend"), ({"route": "spatial"}, "route")],
)  # fmt: skip
def test_bad_contact_numbers_are_refused_by_name(kwargs, word):
    with pytest.raises(ValueError, match=word):
        Contact(**kwargs)


@pytest.mark.parametrize("implicit", [True, False])
def test_before_contact_link_equals_twist_and_the_shape_stays_consistent(implicit):
    """The straight twisted rod before buckling: Wr = 0, Lk = Tw to round-off, the energy
    budget closed (no contact yet) and the rebuilt centreline on the axis.  The implicit
    route takes the writhe on the time route, whose round-off grows step by step (1.5e-9
    turns measured at 0.2 s)."""
    scene = Scene(a=16.0, kappa0=10.0, t_end=0.2, n_cells=50, dt=0.01)
    res = run_contact_scene(
        ContactScene(scene, Contact(stiffness=200.0, implicit=implicit)), time_route=True
    ).result()
    assert res["stopped"] == "t_end" and res["first_contact_t"] is None
    assert res["twist_turns"] == pytest.approx(
        (10.0 + 16.0 * res["t_last"]) / (2 * np.pi), rel=0.02
    )
    bound = 1e-8 if implicit else 1e-9
    assert abs(res["writhe_turns"]) < bound and res["max_link_gap_turns"] < bound
    # the budget's trapezoidal powers: implicit in the scene's whole steps of 0.01 s
    # (3.2e-4 of the work measured), lagged in steps of 1.2e-3 s (omega_c dt <= 0.5)
    assert abs(res["energy_residual"]) < (1e-3 if implicit else 1e-6)
    assert max(res["drift"].values()) < 1e-6


def test_the_histories_are_the_runs_own_records_as_json_lists():
    """ContactRun.histories: one list per check, read off the run's history (the records of
    data/bench and data/contact are written with it); the far end of a clamped rod stays at
    L, and a straight rod has no plectoneme."""
    import json

    scene = Scene(a=16.0, kappa0=10.0, t_end=0.1, n_cells=20, dt=0.01)
    run = run_contact_scene(ContactScene(scene, Contact(stiffness=200.0, check=0.02)))
    h = run.histories(plectoneme=True)
    json.dumps(h)
    n = len(run.history["t"])
    assert n >= 5 and all(len(v) == n for v in h.values())
    assert h["link_turns"] == run.history["link"].tolist()
    assert h["end_moment"] == run.history["end_moment"].tolist()
    assert h["end_axial_position"] == pytest.approx([scene.rod.L] * n, abs=1e-9)
    assert set(h["plectoneme_pairs"]) == {0} and set(h["plectoneme_turns"]) == {0.0}
    assert "plectoneme_turns" not in run.histories()


def test_cli_buckle_contact_prints_one_json_object(capsys):
    import json

    from dyntorsion.app.cli import main

    argv = ["buckle", "--a", "16", "--kappa0", "10", "--contact", "--t-end", "0.1",
            "--fidelity", "quick", "--contact-stiffness", "200", "--json"]  # fmt: skip
    assert main(argv) == 0
    out = json.loads(capsys.readouterr().out)
    for key in ("first_contact_t", "max_penetration_over_D", "contact_sites", "energy_residual",
                "link_turns", "twist_turns", "writhe_turns", "stopped"):  # fmt: skip
        assert key in out, key
    assert out["stopped"] == "t_end" and out["first_contact_t"] is None
    verdict = out["checks"]
    assert [c["quantity"] for c in verdict["checks"]] == [
        "stopped",
        "max_penetration_over_D",
        "max_link_gap_turns",
        "energy_residual_scheme",
    ]
    for c in verdict["checks"]:
        assert c["reading"] == out[c["quantity"]]
    assert verdict["met"] == all(c["met"] for c in verdict["checks"])


def test_cli_contact_prints_each_check_beside_its_bound(capsys):
    from dyntorsion.app.cli import main

    argv = ["buckle", "--a", "16", "--kappa0", "10", "--contact", "--t-end", "0.05",
            "--fidelity", "quick", "--contact-stiffness", "200"]  # fmt: skip
    assert main(argv) == 0
    lines = [ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("check:")]
    assert len(lines) == 4
    assert "overlap" in lines[1] and "bound 0.01" in lines[1]


def test_cli_contact_needs_an_end_time(capsys):
    from dyntorsion.app.cli import main

    assert main(["buckle", "--a", "16", "--contact", "--fidelity", "quick"]) != 0
    assert "--t-end" in capsys.readouterr().err


@pytest.mark.slow
def test_link_equals_twist_plus_writhe_through_buckling():
    """The paper's a = 16 scene on N = 200 through the onset to t = 2.95 s, just before the
    loop closes: the writhe grows to 0.33 turns and Lk - Tw - Wr stays below 0.01 turns
    (0.0075 measured; it is the drift of the rebuilt shape, 0.03 rad at the far end), the
    energy budget closes to 1e-5 of the work done at the ends.  (About a minute.)"""
    scene = Scene(a=16.0, kappa0=10.0, t_end=2.95, n_cells=200, dt=0.01)
    contact = Contact(stiffness=200.0, implicit=False)
    run = run_contact_scene(ContactScene(scene, contact), time_route=True)
    res = run.result()
    assert res["stopped"] == "t_end" and res["first_contact_t"] is None
    assert res["writhe_turns"] > 0.3
    assert res["max_link_gap_turns"] < 0.01
    assert abs(res["energy_residual"]) < 1e-4
    assert res["drift"]["end_offset_over_L"] < 0.005 and res["drift"]["time_route_over_L"] < 0.005


@pytest.mark.slow
def test_a_passage_through_itself_ends_the_run_with_a_clear_error():
    """The quick grid (N = 50) cannot hold the whip at the first contact (t = 3.26 s): the
    rod passes through itself in the next 0.01 s, Lk - Tw - Wr jumps by ~2, and the run says
    so instead of going on, when the under-resolved stop (1 rad a cell, reached at 3.15 s)
    is lifted.  (About 35 s.)"""
    from dyntorsion.beyond.contact.run import PassageError

    scene = Scene(a=16.0, kappa0=10.0, t_end=3.4, n_cells=50, dt=0.01)
    contact = Contact(stiffness=2000.0, implicit=False, max_cell_bend=10.0)
    run = run_contact_scene(ContactScene(scene, contact))
    res = run.result()
    assert res["stopped"].startswith("passage"), res["stopped"]
    assert 3.2 < res["first_contact_t"] < res["t_last"] < 3.3
    gap = run.history["link"] - run.history["twist"] - run.history["writhe"]
    assert abs(abs(gap[-1] - gap[-2]) - 2.0) < 0.1
    with pytest.raises(PassageError, match="passed through itself"):
        run.check()
    # what the lag costs: the loop closes at ~1 m/s (1.05 measured), which a lagged penalty
    # holds to 1 % of D only with omega_c >= 1e5 rad/s, i.e. dt <= 5e-6 s
    assert res["max_approach_speed"] > 0.5 and res["dt_for_1pct_penetration"] < 1e-5


def _flaky(monkeypatch, fail):
    """Make the state steps' free Newton solve fail where ``fail(call)`` says so."""
    from dyntorsion.genalpha import state_steps

    real_solve, calls = state_steps.free_newton, [0]

    def flaky(*args):
        calls[0] += 1
        return 1 if fail(calls[0]) else real_solve(*args)

    monkeypatch.setattr(state_steps, "free_newton", flaky)
    return calls


def test_a_failed_step_is_retried_in_shorter_substeps(monkeypatch):
    """A whole step whose Newton solve fails (both predictors) is crossed again in
    substeps from the same level, and the run goes on to its end unchanged in substance."""
    scene = Scene(a=16.0, kappa0=10.0, t_end=0.03, n_cells=20, dt=0.01)
    cs = ContactScene(scene, Contact(stiffness=200.0))
    plain = run_contact_scene(cs).result()
    _flaky(monkeypatch, lambda call: call in (2, 3))  # the second whole step, both tries
    res = run_contact_scene(cs).result()
    assert res["stopped"] == "t_end" and res["t_last"] == pytest.approx(0.03)
    imp = res["implicit"]
    assert imp["failed_solves_retried_shorter"] == 1
    assert imp["shortest_step"] == pytest.approx(scene.dt / cs.substeps())
    # one step of 0.01 s crossed in 40 substeps instead of whole (the torsional waves at a
    # Courant number of 11 in whole steps): 4.1e-4 relative measured
    assert res["twist_turns"] == pytest.approx(plain["twist_turns"], rel=1e-3)
    assert res["twist_turns"] != plain["twist_turns"]


def test_a_step_failing_at_the_shortest_substep_ends_the_run_saying_so(monkeypatch):
    scene = Scene(a=16.0, kappa0=10.0, t_end=0.05, n_cells=20, dt=0.01)
    cs = ContactScene(scene, Contact(stiffness=200.0, max_step=2.5e-3, min_step=1e-3))
    _flaky(monkeypatch, lambda call: call > 2)
    res = run_contact_scene(cs).result()
    assert res["stopped"].startswith("failed:") and "shortest substep" in res["stopped"]
    assert "t=0.02125" in res["stopped"] and res["t_last"] == pytest.approx(0.02)
    # the end turning at 16 rad/s is fast for whole steps (0.16 rad a step): substeps of
    # 2.5e-3 s, then 1.25e-3 s (min_step 1e-3), each failing
    assert res["implicit"]["failed_solves_retried_shorter"] == 2


def test_a_grid_too_coarse_for_the_loop_stops_the_run_saying_what_to_refine():
    """The run stops once a cell holds more bending than max_cell_bend (here set below the
    seed's own bending), naming the curvature, the loop's radius in diameters and the grid
    that would resolve it."""
    scene = Scene(a=16.0, kappa0=10.0, t_end=0.1, n_cells=20, dt=0.01)
    res = run_contact_scene(ContactScene(scene, Contact(max_cell_bend=1e-12))).result()
    assert res["stopped"].startswith("under-resolved:")
    for word in ("max_cell_bend is 1e-12 rad", "n_cells >=", "radius", " D on cells of 50 D"):
        assert word in res["stopped"], (word, res["stopped"])
    assert res["max_cell_bend"] > 1e-12 and res["t_last"] < 0.1


@pytest.mark.parametrize("anchor", [False, True])
def test_the_anchored_time_route_carries_one_step_and_its_drift_cannot_accumulate(anchor):
    """A level whose velocities disagree with its curvatures (the rod straight, every node
    moving sideways at 1 m/s): the time route moves dt a step while the rebuilt shape stays.
    Anchored, the time route is set back onto the rebuilt shape after each step and the
    drift is that of one step; left to run, it grows by dt every step."""
    from dyntorsion.beyond.contact.centreline import Reconstruction

    n, L, dt = 20, 1.0, 1e-3
    y = np.zeros((n + 1, 12))
    y[:, 8] = 10.0  # twisted, straight
    moving = y.copy()
    moving[1:-1, 0] = 1.0  # u1 at the inner nodes, body frame
    rec = Reconstruction(y, L / n, L, anchor=anchor)
    for k in range(1, 4):
        rec.update(moving, dt)
        gap = np.max(np.linalg.norm(rec.tracker.r - rec.r, axis=1))  # u = 0 at the start
        assert gap == pytest.approx(0.0 if anchor else (k - 0.5) * dt, abs=1e-15)
    assert rec.drift.anchored is anchor
    assert rec.drift.time_route == pytest.approx((1.0 if anchor else 2.5) * dt / L, rel=1e-12)
