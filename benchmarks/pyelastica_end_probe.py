"""Probe of why the PyElastica reference (data/bench/pyelastica_plectoneme.json) ends at
link 7 (data/README.md, bench/): PyElastica's plectoneme scene as
benchmarks/pyelastica_plectoneme.py sets it up, with the driven end's rotation recorded.

Run with /work/pe-venv/bin/python:
  pyelastica_end_probe.py --mode as_is     --t-end 0.5   # the script's (and the example's) BC
  pyelastica_end_probe.py --mode no_damper --t-end 0.5   # the same BC, no AnalyticalLinearDamper
  pyelastica_end_probe.py --mode exact     --t-end 0.5   # BC re-imposing the end's directors in
                                                 # constrain_values (what a fix would do)
  pyelastica_end_probe.py --mode as_is --t-end 46.4 --watch-from 46.2   # the passage (long run!)

Prints the end's rotation about the axis (unwrapped, in turns) against the imposed t/5,
the end element's omega_3 after the step against the imposed rate, and PyElastica's link.
With --watch-from, prints every 0.005 s after that time: link, writhe, the smallest
centreline distance between elements the contact checks (|i-j| >= skip) and between
elements it skips (3 <= |i-j| < skip), and the rod's distance from the two closure rays.
"""

import argparse
import sys

import numpy as np

sys.path.insert(0, str(__import__("pathlib").Path(__file__).resolve().parent))
import pyelastica_plectoneme as B  # noqa: E402


def seg_dist(p1, q1, p2, q2):
    """Smallest distance between segments [p1,q1] and [p2,q2]."""
    d1, d2, r = q1 - p1, q2 - p2, p1 - p2
    a, e, f = d1 @ d1, d2 @ d2, d2 @ r
    c, b = d1 @ r, d1 @ d2
    den = a * e - b * b
    s = np.clip((b * f - c * e) / den, 0, 1) if den > 1e-14 else 0.0
    t = (b * s + f) / e
    if t < 0:
        t, s = 0.0, np.clip(-c / a, 0, 1)
    elif t > 1:
        t, s = 1.0, np.clip((b - c) / a, 0, 1)
    return np.linalg.norm(p1 + s * d1 - p2 - t * d2)


def watch(ea, pos, dirs, rad, skip):
    n = pos.shape[1] - 1
    checked, skipped = np.inf, np.inf
    mid = 0.5 * (pos[:, 1:] + pos[:, :-1])
    for i in range(n):
        for j in range(i - 3, -1, -1):
            if np.linalg.norm(mid[:, i] - mid[:, j]) > 0.1:
                continue
            dd = seg_dist(pos[:, i], pos[:, i + 1], pos[:, j], pos[:, j + 1])
            if i - j >= skip:
                checked = min(checked, dd)
            else:
                skipped = min(skipped, dd)
    # closure rays (next_tangent): from each end along its end tangent
    ray = []
    for end, nb in ((0, 1), (-1, -2)):
        o = pos[:, end]
        u = (pos[:, end] - pos[:, nb]) / np.linalg.norm(pos[:, end] - pos[:, nb])
        rel = pos - o[:, None]
        along = u @ rel
        perp = np.linalg.norm(rel - np.outer(u, along), axis=0)
        far = np.abs(np.arange(pos.shape[1]) - (end % pos.shape[1])) > 3
        m = far & (along > 0)
        ray.append(perp[m].min() if m.any() else np.inf)
    P, D, R = pos[None], dirs[None, 0], rad[None]
    lk = ea.compute_link(P, D, R, 10 * B.LENGTH, "next_tangent")[0]
    wr = ea.compute_writhe(P, 10 * B.LENGTH, "next_tangent")[0]
    return lk, wr, checked, skipped, ray


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--mode", choices=["as_is", "no_damper", "exact"], default="as_is")
    ap.add_argument("--t-end", type=float, default=0.5)
    ap.add_argument("--watch-from", type=float, default=None)
    a = ap.parse_args()

    import elastica as ea
    from elastica._rotations import _get_rotation_matrix

    class Case(ea.BaseSystemCollection, ea.Constraints, ea.Contact, ea.CallBacks, ea.Damping):
        pass

    N, DT, TURNS, T_TWIST = B.N_ELEM, B.DT, B.TURNS, B.T_TWIST
    area = np.pi * B.RADIUS**2
    rho = B.MASS / (area * B.LENGTH)
    sim = Case()
    rod = ea.CosseratRod.straight_rod(
        N,
        np.zeros(3),
        np.array([0.0, 1, 0]),
        np.array([0.0, 0, 1]),
        B.LENGTH,
        B.RADIUS,
        rho,
        youngs_modulus=B.E,
        shear_modulus=B.SHEAR,
    )
    rod.velocity_collection[2, N // 2] -= B.KICK
    sim.append(rod)
    if a.mode != "no_damper":
        sim.dampen(rod).using(
            ea.AnalyticalLinearDamper, damping_constant=2.0 / rho / area, time_step=DT
        )
    mode = a.mode

    class BC(ea.ConstraintBase):
        def __init__(self, p_start, p_end, d_start, d_end, **kw):
            super().__init__(**kw)
            theta = 2.0 * np.pi * TURNS
            local = d_end @ (-(p_end - p_start) / np.linalg.norm(p_end - p_start))
            local /= np.linalg.norm(local)
            self.local, self.d_end = local, d_end.copy()
            self.final = _get_rotation_matrix(-theta, local.reshape(3, 1)).reshape(3, 3) @ d_end
            self.spin = theta / T_TWIST * local
            self.p0, self.d0 = p_start.copy(), d_start.copy()

        def constrain_values(self, system, time):
            if time > T_TWIST:
                system.position_collection[..., 0] = self.p0
                system.position_collection[0, -1] = 0.0
                system.position_collection[2, -1] = 0.0
                system.director_collection[..., 0] = self.d0
                system.director_collection[..., -1] = self.final
            elif mode == "exact":
                ang = 2.0 * np.pi * TURNS * time / T_TWIST
                system.director_collection[..., -1] = (
                    _get_rotation_matrix(-ang, self.local.reshape(3, 1)).reshape(3, 3) @ self.d_end
                )
                system.director_collection[..., 0] = self.d0

        def constrain_rates(self, system, time):
            system.velocity_collection[..., 0] = 0.0
            system.omega_collection[..., 0] = 0.0
            if time > T_TWIST:
                system.velocity_collection[..., -1] = 0.0
                system.omega_collection[..., -1] = 0.0
            else:
                system.velocity_collection[0, -1] = 0.0
                system.velocity_collection[2, -1] = 0.0
                system.omega_collection[..., -1] = -self.spin
                system.velocity_collection[2, N // 2] -= B.KICK

    sim.constrain(rod).using(BC, constrained_position_idx=(0, -1), constrained_director_idx=(0, -1))
    sim.detect_contact_between(rod, rod).using(ea.RodSelfContact, k=B.CONTACT_K, nu=B.CONTACT_NU)
    sim.finalize()

    # the damper's per-step factor on the end element's omega_3, from the rod's own arrays
    nm = rod.mass
    em = 0.5 * (nm[1:] + nm[:-1])
    em[0] += 0.5 * nm[0]
    em[-1] += 0.5 * nm[-1]
    invJ = np.diagonal(rod.inv_mass_second_moment_of_inertia).T  # (3, n_elem)
    fac = np.exp(-2.0 / rho / area * DT * em * invJ[2])
    print(
        f"mode {mode}: damper factor on omega_3 per step (end element) {fac[-1]:.6f}; "
        f"bending {np.exp(-2.0 / rho / area * DT * em[-1] * invJ[0, -1]):.6f}; "
        f"|R(-20 pi) d_end - d_end| = {np.abs(_get_rotation_matrix(-2 * np.pi * TURNS, np.array([[0.0], [0.0], [1.0]])).reshape(3, 3) - np.eye(3)).max():.1e}",
        flush=True,
    )

    d10 = rod.director_collection[..., -1].copy()
    prev, unwrapped = 0.0, 0.0
    steps = int(round(a.t_end / DT))
    rep = max(1, int(round(0.1 / DT)))
    wat = int(round(0.005 / DT))
    skip = int(1 + np.ceil(0.8 * np.pi * B.RADIUS / (B.LENGTH / N)))
    stepper, t = ea.PositionVerlet(), 0.0
    for i in range(1, steps + 1):
        t = stepper.step(sim, t, DT)
        d1 = rod.director_collection[0, :, -1]
        # rotation of d1 about the axis: components on the initial d1 (z) and d2 (x)
        ang = np.arctan2(d1 @ d10[1], d1 @ d10[0])
        dang = (ang - prev + np.pi) % (2 * np.pi) - np.pi
        unwrapped += dang
        prev = ang
        if i % rep == 0 or i == steps:
            om3 = rod.omega_collection[2, -1]
            imposed = min(t, T_TWIST) / 5.0
            line = (
                f"t {t:8.4f} end rotation {unwrapped / 2 / np.pi:+.6f} turns "
                f"(imposed {imposed:.6f}, ratio {unwrapped / 2 / np.pi / max(imposed, 1e-12):.6f})"
                f"  omega3(end) {om3:+.6f} (imposed {2 * np.pi / 5:+.6f}, "
                f"ratio {om3 / (2 * np.pi / 5):.6f}) dil {rod.dilatation[-1]:.6f}"
            )
            if i % (10 * rep) == 0 or i == steps:
                lk = ea.compute_link(
                    rod.position_collection[None],
                    rod.director_collection[None, 0],
                    rod.radius[None],
                    10 * B.LENGTH,
                    "next_tangent",
                )[0]
                line += f"  link {lk:+.6f}"
            print(line, flush=True)
        if a.watch_from is not None and t >= a.watch_from and i % wat == 0:
            lk, wr, chk, skp, ray = watch(
                ea, rod.position_collection, rod.director_collection, rod.radius, skip
            )
            print(
                f"W t {t:8.4f} link {lk:+.4f} writhe {wr:+.4f} y_end {rod.position_collection[1, -1]:.4f}"
                f" min dist checked {chk:.4f} skipped(<{skip}) {skp:.4f} rays {ray[0]:.4f} {ray[1]:.4f}",
                flush=True,
            )


if __name__ == "__main__":
    main()
