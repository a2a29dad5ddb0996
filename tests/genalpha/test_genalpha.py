"""The generalised-alpha engine of section 3: parameters, accuracy, stability, errors."""

import numpy as np
import pytest

from dyntorsion import Rod
from dyntorsion import genalpha as ga
from dyntorsion.buckling.loading import EQ30
from dyntorsion.model.cosserat import IDX, Cosserat
from dyntorsion.verification import Manufactured
from dyntorsion.waves import Torsion


def slope(h, err):
    """Least-squares order of convergence over a whole ladder."""
    return float(np.polyfit(np.log(h), np.log(err), 1)[0])


# ------------------------------------------------------------------ eq (13)
@pytest.mark.parametrize("lam", [-1.0, -0.75, -0.5, -0.2, 0.0])
def test_parameters_eq13(lam):
    a, b, g = ga.parameters(lam)
    assert b + g == pytest.approx(1.0, abs=1e-15)  # hence zeta = 0
    # Jansen et al.: gamma = 1/2 + alpha_m - alpha_f with alpha_m = 1 - a, alpha_f = 1 - b
    assert g == pytest.approx(0.5 + (1 - a) - (1 - b), abs=1e-15)


def test_parameters_endpoints():
    assert ga.parameters(-1.0) == (0.5, 0.5, 0.5)
    assert ga.parameters(0.0) == (-0.5, 0.0, 1.0)


@pytest.mark.parametrize("lam", [0.5, -1.0001, 1.0, float("nan")])
def test_parameters_reject_outside_range(lam):
    with pytest.raises(ValueError, match=r"\[-1, 0\]"):
        ga.parameters(lam)


def test_scheme_names_the_bad_parameter():
    with pytest.raises(ValueError, match="lam_t"):
        ga.Scheme(lam_t=0.5)
    with pytest.raises(ValueError, match="quadrature"):
        ga.Scheme(quadrature="simpson")
    with pytest.warns(ga.SchemeWarning, match="lam_s"):
        ga.Scheme(lam_s=-0.5)


# ------------------------------------------------------------------ order of accuracy
@pytest.mark.parametrize("lam_t", [-1.0, -0.5, 0.0])
def test_second_order_in_space_12_fields(lam_t):
    """Manufactured solution of the full 12-field system: error ~ ds^2 (lam_s = -1)."""
    m = Manufactured.random(amplitude=0.1)
    T = 0.25 * m.model.rod.L / m.model.scales()[0][0]
    n = np.array([8, 16, 32, 64])
    err = [m.error(m.solve(int(k), T / 256, T, ga.Scheme(-1.0, lam_t))) for k in n]
    assert slope(1.0 / n, err) == pytest.approx(2.0, abs=0.1)


@pytest.mark.parametrize("lam_t", [-1.0, -0.5, 0.0])
def test_second_order_in_time_12_fields(lam_t):
    """Same system, fixed grid: distance to a dt/16-finer run falls as dt^2 for every lam_t."""
    m = Manufactured.random(amplitude=0.1, frequency=8.0)
    ys = m.model.scales()[0]
    T = 0.25 * m.model.rod.L / ys[0]
    scheme = ga.Scheme(-1.0, lam_t)
    ref = m.solve(32, T / 2048, T, scheme).y
    dts = T / np.array([16, 32, 64, 128])
    err = [np.max(np.abs(m.solve(32, dt, T, scheme).y - ref) / ys) for dt in dts]
    assert slope(dts, err) == pytest.approx(2.0, abs=0.1)


def test_second_order_combined_full_amplitude():
    """ds and dt refined together, large-amplitude nonlinear solution, against the exact one."""
    m = Manufactured.random(amplitude=1.0)
    T = 0.25 * m.model.rod.L / m.model.scales()[0][0]
    n = np.array([8, 16, 32, 64])
    err = [m.error(m.solve(int(k), T / (4 * k), T)) for k in n]
    assert slope(1.0 / n, err) == pytest.approx(2.0, abs=0.1)


def _smooth_wave(c, kx=2.3):
    w = c * kx

    def exact(s, t):
        s = np.asarray(s)[:, None]
        return np.concatenate(
            [
                np.sin(kx * s + 0.3) * np.cos(w * t + 0.1),
                c * np.cos(kx * s + 0.3) * np.sin(w * t + 0.1),
            ],
            axis=1,
        )

    return exact


@pytest.mark.parametrize("lam_t", [-1.0, -0.5])
def test_second_order_in_time_wave_exact(lam_t):
    """A travelling torsional wave with exact boundary data, fine grid: error ~ dt^2."""
    model = Torsion()
    system = model.system()
    exact = _smooth_wave(model.rod.c)
    T, n = 3.0 / model.rod.c, 400
    s = np.linspace(0, 1, n + 1)
    left = ga.Boundary.fields(
        system, ["k3"], lambda t: np.array([exact([0.0], x)[0, :1] for x in t])
    )
    right = ga.Boundary.fields(
        system, ["w3"], lambda t: np.array([exact([1.0], x)[0, 1:] for x in t])
    )
    dts = T / np.array([16, 32, 64, 128])
    err = []
    for dt in dts:
        run = ga.integrate(
            ga.Problem(
                system, exact(s, 0.0), left, right, y_t0=(exact(s, 1e-7) - exact(s, -1e-7)) / 2e-7
            ),
            ga.Grid(n_cells=n, length=1.0, dt=dt, t_end=T),
            scheme=ga.Scheme(-1.0, lam_t),
        )
        err.append(np.max(np.abs(run.y - exact(s, T)) / model.scales()[0]))
    assert slope(dts, err) == pytest.approx(2.0, abs=0.1)


# ------------------------------------------------------------------ energy and stability
def _pulse(n, centre=0.4, width=0.08):
    """A twist pulse at rest on a unit rod: y0 (n+1, 2) of the torsion model."""
    s = np.linspace(0, 1, n + 1)
    y0 = np.zeros((n + 1, 2))
    y0[:, 0] = np.exp(-(((s - centre) / width) ** 2))
    return y0


def _pulse_run(lam_t, courant, steps, n=60):
    model = Torsion()
    system = model.system()
    y0 = _pulse(n)
    dt = courant * (1.0 / n) / model.rod.c
    every = steps // 10
    run = ga.integrate(
        ga.Problem(
            system, y0, ga.Boundary.fields(system, ["w3"]), ga.Boundary.fields(system, ["w3"])
        ),
        ga.Grid(n_cells=n, length=1.0, dt=dt, t_end=steps * dt),
        scheme=ga.Scheme(-1.0, lam_t),
        output=ga.Output(snapshots=list(dt * np.arange(0, steps + 1, every))),
    )
    energy = np.array([model.energy(y, 1.0 / n) for y in run.snapshots])
    return run, energy


def test_energy_conserved_to_roundoff_at_lambda_minus_one():
    run, energy = _pulse_run(-1.0, courant=0.8, steps=10_000)
    assert run.steps == 10_000
    assert np.max(np.abs(energy / energy[0] - 1)) < 1e-12


def test_energy_decays_at_lambda_zero():
    _, energy = _pulse_run(0.0, courant=2.0, steps=2_000)
    assert np.all(np.diff(energy) <= 1e-14 * energy[0])
    assert energy[-1] < 0.9 * energy[0]


@pytest.mark.parametrize("lam_t", [-1.0, -0.5, 0.0])
@pytest.mark.parametrize("courant", [0.1, 1.0, 10.0, 100.0])
def test_bounded_over_courant_numbers(lam_t, courant):
    run, energy = _pulse_run(lam_t, courant, steps=1_000)
    assert np.all(np.isfinite(run.y))
    assert np.max(energy) <= energy[0] * (1 + 1e-10)


def test_spatial_damping_is_unstable():
    """lam_s > -1 (eq 13 in space) amplifies: energy grows or the step matrix is singular."""
    model = Torsion()
    system = model.system()
    n = 60
    y0 = _pulse(n)
    with pytest.warns(ga.SchemeWarning):
        scheme = ga.Scheme(-0.5, -1.0)
    bc = ga.Boundary.fields(system, ["w3"])
    dt = 0.1 / n / model.rod.c
    with pytest.raises(ga.ConvergenceError, match="t="):
        ga.integrate(
            ga.Problem(system, y0, bc, bc),
            ga.Grid(n_cells=n, length=1.0, dt=dt, t_end=100 * dt),
            scheme=scheme,
        )
    dt = 100.0 / n / model.rod.c
    run = ga.integrate(
        ga.Problem(system, y0, bc, bc),
        ga.Grid(n_cells=n, length=1.0, dt=dt, t_end=2000 * dt),
        scheme=scheme,
        output=ga.Output(snapshots=[0.0, 2000 * dt]),
    )
    e0, e1 = (model.energy(y, 1.0 / n) for y in run.snapshots)
    assert e1 > 1.05 * e0


# ------------------------------------------------------------------ quadrature rules
def _buckling_like(quadrature, n=16, dt=2e-3, t_end=0.3, scheme=None, newton=None, stops=None):
    """Beyond the critical twist with a large seed: the rod bends within 0.3 s."""
    model = Cosserat(Rod())
    system = model.system()
    kappa0, a = 20.0, 20.0
    y0 = np.zeros((n + 1, 12))
    y0[:, IDX["k3"]] = kappa0
    left = ga.Boundary(
        ga.Boundary.fields(system, list(EQ30.left)).rows,
        lambda t: np.outer(kappa0 + a * t, [0, 0, 0, 0, 0, 1.0]),
    )
    right = ga.Boundary.fields(system, list(EQ30.right))
    f = np.zeros((n + 1, 3))
    f[:, 0] = 1e-4
    times = list(np.arange(0, t_end + 1e-12, 0.05))
    run = ga.integrate(
        ga.Problem(
            system, y0, left, right, sources=ga.Sources(separable=(model.external_force(f), None))
        ),
        ga.Grid(n, 1.0, dt, t_end),
        scheme=scheme or ga.Scheme(quadrature=quadrature),
        newton=newton or ga.Newton(tol=1e-12),
        output=ga.Output(snapshots=times),
        stops=stops or ga.Stops(),
    )
    return model, system, run


def _bent(y, ds=1.0 / 16):
    return ds * np.sum(np.hypot(y[:, IDX["k1"]], y[:, IDX["k2"]]))


@pytest.mark.parametrize("control", [None, ga.StepControl()])
@pytest.mark.parametrize("check_every", [1, 7])
def test_stop_gate_skips_only_the_calls_that_cannot_stop(control, check_every):
    """With ``stop_gate`` the levels, traces and stopping level are those without it,
    and ``stop`` is called only at levels at or past the gate's limit."""
    limit = 0.05
    runs, calls = [], []
    for gate in (None, (("k1", "k2"), limit)):
        seen = []

        def stop(t, y, seen=seen):
            seen.append((t, _bent(y)))
            return "bent" if _bent(y) > 4 * limit else None

        scheme = ga.Scheme(control=control)
        runs.append(
            _buckling_like(
                "trapezoidal",
                scheme=scheme,
                stops=ga.Stops(test=stop, check_every=check_every, gate=gate),
            )[2]
        )
        calls.append(seen)
    plain, gated = runs
    assert plain.stopped == gated.stopped == "bent"
    np.testing.assert_array_equal(plain.t, gated.t)
    np.testing.assert_array_equal(plain.snapshots, gated.snapshots)
    for name in plain.traces:
        np.testing.assert_array_equal(plain[name], gated[name])
    np.testing.assert_array_equal(plain.y, gated.y)
    assert min(g for _, g in calls[1]) >= limit * (1 - 1e-12)
    assert len(calls[1]) < len(calls[0])
    assert [c for c in calls[0] if c[1] >= limit] == calls[1]


def test_trapezoidal_rule_keeps_inextensibility_at_every_level():
    model, system, run = _buckling_like("trapezoidal")
    ds = 1.0 / 16
    worst = max(np.max(np.abs(ga.algebraic_residual(system, y, ds))) for y in run.snapshots)
    scale = model.scales()[1][9]
    assert worst / scale < 1e-9


def test_midpoint_rule_keeps_inextensibility_only_on_average():
    model, system, run = _buckling_like("midpoint")
    ds = 1.0 / 16
    worst = max(
        np.max(np.abs(ga.algebraic_residual(system, y, ds, ga.Scheme(quadrature="midpoint"))))
        for y in run.snapshots
    )
    assert worst / model.scales()[1][9] > 1e-6  # not satisfied at the levels themselves
    assert np.max(np.abs(run.snapshots[-1][:, :3])) > 1e-2  # the rod is really moving


# ------------------------------------------------------------------ bad input
def _tiny_problem():
    system = Torsion().system()
    n = 4
    return system, dict(
        grid=dict(n_cells=n, length=1.0, dt=1e-3, t_end=1e-2),
        y0=np.zeros((n + 1, 2)),
        left=ga.Boundary.fields(system, ["w3"]),
        right=ga.Boundary.fields(system, ["w3"]),
    )


def _integrate(system, grid, y0, left, right):
    return ga.integrate(ga.Problem(system, y0, left, right), ga.Grid(**grid))


@pytest.mark.parametrize(
    "change,match",
    [
        ({"dt": 0.0}, "dt="),
        ({"dt": -1.0}, "dt="),
        ({"n_cells": 1}, "n_cells="),
        ({"t_end": 0.0}, "t_end="),
        ({"length": float("nan")}, "length="),
    ],
)
def test_bad_input_is_named(change, match):
    system, kw = _tiny_problem()
    kw["grid"].update(change)
    if "n_cells" in change:
        kw["y0"] = np.zeros((change["n_cells"] + 1, 2))
    with pytest.raises(ValueError, match=match):
        _integrate(system, **kw)


def test_bad_record_every_is_named():
    with pytest.raises(ValueError, match="record_every=0 must be an integer >= 1"):
        ga.Output(every=0)


def test_nan_initial_state_is_rejected():
    system, kw = _tiny_problem()
    kw["y0"][2, 0] = np.nan
    with pytest.raises(ValueError, match="y0 contains NaN"):
        _integrate(system, **kw)


def test_wrong_shapes_are_rejected():
    system, kw = _tiny_problem()
    kw["y0"] = np.zeros((3, 2))
    with pytest.raises(ValueError, match="y0 has shape"):
        _integrate(system, **kw)
    system, kw = _tiny_problem()
    kw["right"] = ga.Boundary.fields(system, ["w3", "k3"])
    with pytest.raises(ValueError, match="nb_left \\+ nb_right"):
        _integrate(system, **kw)


def test_newton_options_are_checked():
    with pytest.raises(ValueError, match="tol"):
        ga.Newton(tol=0.0)
    with pytest.raises(ValueError, match="max_iter"):
        ga.Newton(max_iter=0)
    with pytest.raises(ValueError, match="predictor"):
        ga.Newton(predictor="quadratic")


def test_failed_newton_reports_time_step_iterations_residual():
    system, kw = _tiny_problem()
    kw["left"] = ga.Boundary(kw["left"].rows, lambda t: np.where(t > 4.5e-3, np.nan, 0.0)[:, None])
    with pytest.raises(ValueError, match="not finite"):
        _integrate(system, **kw)
    err = ga.ConvergenceError(0.25, 250, 7, 3.5e-2, "damping")
    assert (err.t, err.step, err.iterations, err.residual) == (0.25, 250, 7, 3.5e-2)
    assert "t=0.25" in str(err) and "step 250" in str(err) and "7 iterations" in str(err)


@pytest.mark.parametrize(
    "newton",
    [
        ga.Newton(max_iter=1, reuse=False, stopping="correction"),
        ga.Newton(max_iter=1, reuse=False, stopping="contraction"),
        ga.Newton(max_iter=2, stopping="contraction"),
    ],
    ids=["correction", "contraction", "contraction-2"],
)
def test_max_iter_failure_raises_convergence_error(newton):
    """Too few corrections cannot converge a nonlinear step from a poor predictor: the
    error names the time, the step, the corrections and the residual, with either
    stopping test."""
    model = Cosserat(Rod())
    system = model.system()
    n = 8
    y0 = np.zeros((n + 1, 12))
    left = ga.Boundary(
        ga.Boundary.fields(system, list(EQ30.left)).rows,
        lambda t: np.outer(500.0 * t, [1e-3, 0, 0, 0, 0, 1.0]),
    )
    right = ga.Boundary.fields(system, list(EQ30.right))
    with pytest.raises(ga.ConvergenceError) as info:
        ga.integrate(
            ga.Problem(system, y0, left, right),
            ga.Grid(n_cells=n, length=1.0, dt=1e-2, t_end=0.1),
            newton=newton,
        )
    e = info.value
    assert e.step >= 1 and e.t == pytest.approx(e.step * 1e-2) and e.iterations >= 1
    assert np.isfinite(e.residual) and e.residual > 0
    assert f"t={e.t:.10g}" in str(e) and f"step {e.step}" in str(e)


# ------------------------------------------------------------------ run bookkeeping
def test_records_snapshots_and_stop():
    system = Torsion().system()
    n = 20
    y0 = _pulse(n, centre=0.5, width=0.1)
    dt = 1e-4
    problem = ga.Problem(
        system, y0, ga.Boundary.fields(system, ["w3"]), ga.Boundary.fields(system, ["w3"])
    )
    grid = ga.Grid(n, 1.0, dt, 100 * dt)
    full = ga.integrate(problem, grid, output=ga.Output(record={"k_mid": ("k3", 10)}))
    sparse = ga.integrate(
        problem,
        grid,
        output=ga.Output(record={"k_mid": ("k3", 10)}, every=7, snapshots=[0.0, 50 * dt]),
        stops=ga.Stops(check_every=13),
    )
    assert full.t.size == 101 and np.allclose(full.t, dt * np.arange(101))
    assert np.allclose(sparse.t, dt * np.r_[0, np.arange(7, 101, 7)])
    assert np.array_equal(sparse["k_mid"], full["k_mid"][np.r_[0, np.arange(7, 101, 7)]])
    assert np.array_equal(sparse.y, full.y)  # chunking does not change the numbers
    assert sparse.snapshot(50 * dt)[10, 0] == full["k_mid"][50]
    stopped = ga.integrate(
        problem,
        grid,
        stops=ga.Stops(test=lambda t, y: "half" if t >= 50 * dt else None, check_every=10),
    )
    assert stopped.stopped == "half" and stopped.steps == 50


def test_failed_step_is_retried_and_gives_the_same_answer():
    """A step the first Newton solve gives up on is retried; the result does not move."""
    _, _, run = _buckling_like("trapezoidal")
    _, _, again = _buckling_like("trapezoidal")
    assert np.array_equal(run.y, again.y)  # deterministic
    scheme = ga.Scheme(-1.0, -0.9)
    model, _, reuse = _buckling_like("trapezoidal", t_end=0.4, scheme=scheme)
    _, _, full = _buckling_like(
        "trapezoidal", t_end=0.4, scheme=scheme, newton=ga.Newton(tol=1e-12, reuse=False)
    )
    assert reuse.retries.sum() >= 1  # this scene needs the fallback at dt = 2e-3
    assert np.max(np.abs(reuse.y - full.y) / model.scales()[0]) < 1e-8
