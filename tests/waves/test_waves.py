"""Section 5: exact series, d'Alembert closed forms, transitions and the wave runs."""

import mpmath
import numpy as np
import pytest

from dyntorsion import Rod
from dyntorsion import genalpha as ga
from dyntorsion import waves as w
from dyntorsion.buckling.loading import EQ30
from dyntorsion.model.cosserat import Cosserat
from dyntorsion.verification import observed_orders

ROD = Rod.paper()
C, L = ROD.c, ROD.L


def away_from_fronts(s, fronts, margin=0.02):
    s = np.asarray(s)
    return s[np.all(np.abs(s[:, None] - np.asarray(fronts)[None, :]) > margin, axis=1)]


# ------------------------------------------------------------------ series vs closed form
@pytest.mark.parametrize("t", [0.004, 0.01, 0.025, 0.05])
@pytest.mark.parametrize("kappa0", [0.0, 3.0])
def test_eq25_matches_dalembert_away_from_fronts(t, kappa0):
    """Eq (25) against the travelling ramp a (t - d/c)_+ with its reflections."""
    ct = C * t
    fronts = [ct % (2 * L), 2 * L - ct % (2 * L)]
    s = away_from_fronts(np.linspace(0, L, 41), fronts)
    series = w.linear_loading_exact(
        s, t, a=0.7, kappa0=kappa0, c=C, L=L, series=w.Series(tol=1e-11)
    )
    closed = w.linear_loading_dalembert(s, t, a=0.7, kappa0=kappa0, c=C, L=L)
    assert np.max(np.abs(series - closed)) < 1e-11


def test_dalembert_ramp_is_piecewise_linear_in_time_before_reflection():
    """Before the front reaches s = L: kappa = kappa0 + a (t - s/c) behind it, kappa0 ahead."""
    t = 0.01
    s = np.array([0.0, 0.1, 0.3, 0.5, 0.6, 0.9])
    closed = w.linear_loading_dalembert(s, t, a=0.1, kappa0=2.0, c=C, L=L)
    np.testing.assert_allclose(closed, 2.0 + 0.1 * np.maximum(t - s / C, 0.0), atol=1e-15)


@pytest.mark.parametrize("t", [0.003, 0.01, 0.03])
def test_eq27_matches_dalembert_within_its_bound(t):
    s = np.array([0.05, 0.2, 0.7, 0.95])
    closed = w.instant_release_dalembert(s, t, kappa0=10.0, c=C, L=L)
    for n in (100, 1000, 10000):
        series = w.instant_release_exact(s, t, kappa0=10.0, c=C, L=L, series=w.Series(terms=n))
        bound = w.instant_release_bound(n, s, t, kappa0=10.0, c=C, L=L)
        assert np.all(np.abs(series - closed) <= bound)
    assert np.max(bound) < 2e-3 * 10.0  # informative: 0.2 % of kappa0 at 10^4 terms


@pytest.mark.parametrize("f", [w.ExpQuartic(), w.FlatBlend(1.3)], ids=lambda f: f.name)
@pytest.mark.parametrize("t", [0.005, 0.01, 0.03])
def test_eq29_matches_dalembert(f, t):
    s = np.linspace(0, L, 21)
    closed = w.smooth_release_dalembert(s, t, kappa0=10.0, c=C, L=L, f=f)
    series = w.smooth_release_exact(s, t, kappa0=10.0, c=C, L=L, f=f, series=w.Series(tol=1e-6))
    assert np.max(np.abs(series - closed)) < 1e-6


def test_eq29_truncation_error_falls_within_the_bound():
    s, t = np.linspace(0, L, 21), 0.01
    closed = w.smooth_release_dalembert(s, t, kappa0=10.0, c=C, L=L)
    errors = []
    for n in (10, 30, 100, 300):
        series = w.smooth_release_exact(s, t, kappa0=10.0, c=C, L=L, series=w.Series(terms=n))
        errors.append(np.max(np.abs(series - closed)))
        assert errors[-1] <= w.smooth_release_bound(n, t, kappa0=10.0, c=C, L=L)[0]
    # terms fall like n^-3 at least: the truncation error like N^-2 or faster
    assert np.all(observed_orders(np.array([10, 30, 100, 300.0]) ** -1, np.array(errors)) > 2.0)


def test_tolerance_picks_enough_terms():
    s = np.linspace(0, L, 11)
    for tol in (1e-4, 1e-7):
        series = w.linear_loading_exact(s, 0.02, a=1.0, c=C, L=L, series=w.Series(tol=tol))
        assert np.max(np.abs(series - w.linear_loading_dalembert(s, 0.02, a=1.0, c=C, L=L))) < tol


# ------------------------------------------------------------------ mpmath references
def test_precise_series_agree_with_numpy():
    s = np.array([0.0, 0.3, 0.77, 1.0])
    for fn, kw in [
        (w.linear_loading_exact, {"a": 0.1, "kappa0": 1.0}),
        (w.instant_release_exact, {"kappa0": 10.0}),
        (w.smooth_release_exact, {"kappa0": 10.0}),
    ]:
        ref = fn(s, 0.01, c=C, L=L, series=w.Series(terms=20, precise=True), **kw)
        assert isinstance(ref[1], mpmath.mpf)
        np.testing.assert_allclose(
            ref.astype(float),
            fn(s, 0.01, c=C, L=L, series=w.Series(terms=20), **kw),
            rtol=0,
            atol=2e-13,
        )


def test_precise_smooth_release_has_30_digits():
    """The Duhamel quadrature of the reference is good to 30 digits: two precisions agree."""
    s = np.array([0.2, 0.9])
    a = w.smooth_release_exact(
        s, 0.01, kappa0=10.0, c=C, L=L, series=w.Series(terms=8, precise=True, digits=35)
    )
    b = w.smooth_release_exact(
        s, 0.01, kappa0=10.0, c=C, L=L, series=w.Series(terms=8, precise=True, digits=50)
    )
    with mpmath.workdps(50):
        assert max(abs(x - y) for x, y in zip(a, b, strict=True)) < mpmath.mpf(10) ** -30


# ------------------------------------------------------------------ transitions
@pytest.mark.parametrize(
    "f", [w.ExpQuartic(), w.FlatBlend(), w.FlatBlend(0.4)], ids=lambda f: f.name
)
def test_transition_derivatives_are_consistent(f):
    x = np.linspace(0.02, 0.98 * getattr(f, "width", 1.5), 37)
    h = 1e-6
    for k in range(f.max_order):
        fd = (f(x + h, k) - f(x - h, k)) / (2 * h)
        assert np.max(np.abs(fd - f(x, k + 1))) < 1e-6 * (1 + np.max(np.abs(f(x, k + 1))))
        mp_vals = np.array([float(f.mp(xi, k)) for xi in x[::6]])
        np.testing.assert_allclose(mp_vals, f(x[::6], k), rtol=1e-13, atol=1e-13)


def test_paper_facts_about_f():
    """f(0) = 1, f'(0) = f''(0) = f'''(0) = 0, f''''(0) = -24 (section 5); flat blend: all 0."""
    np.testing.assert_allclose(w.ExpQuartic().derivatives_at_zero(), [1, 0, 0, 0, -24], atol=1e-30)
    np.testing.assert_allclose(w.FlatBlend().derivatives_at_zero(), [1, 0, 0, 0, 0], atol=1e-30)
    assert w.smoothing(1.0) == pytest.approx(np.exp(-1.0))  # f(50 t) = 1/e at t = 0.02 s
    assert w.smoothing(-3.0) == 1.0
    assert w.FlatBlend()(np.array([1.0, 2.0]))[0] == 0.0


def test_custom_transition_matches_builtin():
    custom = w.CustomTransition(
        [
            lambda x: np.exp(-(x**4)),
            lambda x: -4 * x**3 * np.exp(-(x**4)),
            lambda x: (16 * x**6 - 12 * x**2) * np.exp(-(x**4)),
        ]
    )
    s = np.linspace(0, L, 7)
    np.testing.assert_allclose(
        w.smooth_release_exact(s, 0.01, kappa0=1.0, c=C, L=L, f=custom, series=w.Series(terms=50)),
        w.smooth_release_exact(s, 0.01, kappa0=1.0, c=C, L=L, series=w.Series(terms=50)),
        atol=1e-15,
    )
    with pytest.raises(ValueError, match="f'''"):
        w.smooth_release_exact(s, 0.01, kappa0=1.0, c=C, L=L, f=custom)
    with pytest.raises(ValueError, match="mpmath"):
        w.smooth_release_exact(
            s, 0.01, kappa0=1.0, c=C, L=L, f=custom, series=w.Series(terms=3, precise=True)
        )


# ------------------------------------------------------------------ runs on the engine
def test_smooth_release_converges_at_second_order():
    """Fig 6 scene, ds and dt halved together (Courant number fixed): order 2 in max and L2."""
    n = np.array([100, 200, 400, 800])
    errs = [
        w.solve(w.SmoothRelease(10.0), n_cells=int(k), dt=0.25 / k, times=[0.01]).errors()
        for k in n
    ]
    for norm in ("max", "L2"):
        e = np.array([x[norm][0] for x in errs])
        assert np.all(observed_orders(1.0 / n, e) > 1.9)


def test_incompatible_scenes_converge_only_in_weak_norms():
    """Fig 3 (kink) converges in max and L1; Fig 4 (jump) only in L1, the max error stays O(kappa0)."""
    n = np.array([100, 200, 400, 800])
    lin = [
        w.solve(w.LinearLoading(0.1), n_cells=int(k), dt=0.2 / k, times=[0.01]).errors() for k in n
    ]
    rel = [
        w.solve(w.InstantRelease(10.0), n_cells=int(k), dt=0.2 / k, times=[0.01]).errors()
        for k in n
    ]
    assert np.all(observed_orders(1.0 / n, np.array([e["max"][0] for e in lin])) > 0.5)
    assert np.all(observed_orders(1.0 / n, np.array([e["L1"][0] for e in lin])) > 1.0)
    assert np.all(observed_orders(1.0 / n, np.array([e["L1"][0] for e in rel])) > 0.3)
    assert min(e["max"][0] for e in rel) > 5.0


def test_twelve_field_model_gives_the_same_wave():
    """The Cosserat system on the linear-loading scene (rod stays straight) = reduced model."""
    n, dt, a = 100, 1e-3, 0.1
    reduced = w.solve(w.LinearLoading(a), n_cells=n, dt=dt, times=[0.005, 0.01])
    system = Cosserat(ROD).system()
    left = ga.Boundary.fields(
        system, list(EQ30.left), lambda t: np.outer(a * t, [0, 0, 0, 0, 0, 1])
    )
    right = ga.Boundary.fields(system, list(EQ30.right))
    run = ga.integrate(
        ga.Problem(system, np.zeros((n + 1, 12)), left, right),
        ga.Grid(n_cells=n, length=L, dt=dt, t_end=0.01),
        output=ga.Output(snapshots=[0.005, 0.01]),
    )
    for i, t in enumerate((0.005, 0.01)):
        scale_k, scale_w = np.max(np.abs(reduced.kappa[i])), np.max(np.abs(reduced.omega[i]))
        assert np.max(np.abs(run.field("k3", t) - reduced.kappa[i])) < 1e-9 * scale_k
        assert np.max(np.abs(run.field("w3", t) - reduced.omega[i])) < 1e-9 * scale_w
        others = np.delete(run.snapshot(t), [5, 8], axis=1)
        assert np.max(np.abs(others)) == 0.0


def test_energy_of_release_is_conserved_until_the_front_arrives():
    """Instant release: no work crosses s = 0 (omega = 0) and kappa(L) = 0 after t = 0, so
    the box energy stays at its value after the first step."""
    sol = w.solve(w.InstantRelease(10.0), n_cells=200, dt=1e-3, times=[0.001, 0.01, 0.05])
    energy = [
        w.Torsion(ROD).energy(np.stack([k, o], axis=1), L / 200)
        for k, o in zip(sol.kappa, sol.omega, strict=True)
    ]
    np.testing.assert_allclose(energy[1:], energy[0], rtol=1e-9)


# ------------------------------------------------------------------ regression
def test_series_values_regression(num_regression):
    """The series of eqs (25), (27), (29) at five points and three times, pinned, and each
    value checked against the independent d'Alembert solution (within the series' own
    truncation bound for eq 29)."""
    s = np.array([0.0, 0.25, 0.5, 0.75, 1.0])
    out = {}
    for t in (0.005, 0.01, 0.02):
        out[f"eq25_t{t}"] = w.linear_loading_exact(
            s, t, a=0.1, c=C, L=L, series=w.Series(terms=1000)
        )
        out[f"eq27_t{t}"] = w.instant_release_exact(
            s, t, kappa0=10.0, c=C, L=L, series=w.Series(terms=1000)
        )
        out[f"eq29_t{t}"] = w.smooth_release_exact(
            s, t, kappa0=10.0, c=C, L=L, series=w.Series(terms=100)
        )
        exact = {
            "eq25": w.linear_loading_dalembert(s, t, a=0.1, c=C, L=L),
            "eq27": w.instant_release_dalembert(s, t, kappa0=10.0, c=C, L=L),
            "eq29": w.smooth_release_dalembert(s, t, kappa0=10.0, c=C, L=L),
        }
        bound = float(np.max(w.smooth_release_bound(100, t, kappa0=10.0, c=C, L=L)))
        np.testing.assert_allclose(out[f"eq29_t{t}"], exact["eq29"], rtol=0, atol=bound + 1e-12)
        # eq (25) converges fast (1e-9 at 1000 terms); eq (27) carries a jump of kappa0 and
        # its series converges like 1/terms (measured 1.2e-2 at worst, kappa0 = 10)
        np.testing.assert_allclose(out[f"eq25_t{t}"], exact["eq25"], rtol=0, atol=1e-8)
        np.testing.assert_allclose(out[f"eq27_t{t}"], exact["eq27"], rtol=0, atol=2e-3 * 10.0)
    num_regression.check(out, default_tolerance={"atol": 1e-12, "rtol": 1e-10})


def test_fig6_numerical_kappa_pin_of_our_output(num_regression):
    """The paper's Fig 6 grid: ds = 0.01 m, dt = 0.005 s, t = 0.01 s.  A pin of our own
    output (it catches any change of the discrete solution); its error against the exact
    solution is tested in tests/waves/test_waves.py's convergence tests."""
    sol = w.solve(w.SmoothRelease(10.0), n_cells=100, dt=0.005, times=[0.01])
    num_regression.check(
        {"s": sol.s[::10], "kappa": sol.kappa[0, ::10]},
        default_tolerance={"atol": 1e-10, "rtol": 1e-9},
    )


# ------------------------------------------------------------------ bad input
@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"c": 0.0}, "c="),
        ({"c": -1.0}, "c="),
        ({"L": 0.0}, "L="),
        ({"t": -0.1}, "t must"),
        ({"s": 1.5}, r"s must lie in \[0, L\]"),
        ({"s": -0.1}, "s must"),
    ],
)
def test_bad_input(kwargs, match):
    args = {"s": 0.5, "t": 0.01, "c": C, "L": L, "series": w.Series(terms=10)}
    args.update(kwargs)
    s, t = args.pop("s"), args.pop("t")
    for fn, extra in [
        (w.linear_loading_exact, {"a": 0.1}),
        (w.instant_release_exact, {"kappa0": 1}),
        (w.smooth_release_exact, {"kappa0": 1}),
    ]:
        with pytest.raises(ValueError, match=match):
            fn(s, t, **args, **extra)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"terms": 0}, r"series\.terms=0 must be an integer >= 1"),
        ({"terms": 2.5}, r"series\.terms=2\.5 must be an integer >= 1"),
        ({"terms": True}, r"series\.terms=True"),
        ({"tol": 0.0}, r"series\.tol=0\.0 must be a finite number > 0"),
        ({"tol": float("nan")}, r"series\.tol=nan"),
        ({"precise": "yes"}, r"series\.precise='yes' must be True or False"),
        ({"digits": 4}, r"series\.digits=4 must be an integer >= 5"),
        ({"digits": 35.0}, r"series\.digits=35\.0"),
        ({"budget": -1.0}, r"series\.budget=-1\.0 must be a finite number > 0"),
    ],
)
def test_bad_series_options_are_named(kwargs, match):
    with pytest.raises(ValueError, match=match):
        w.Series(**kwargs)


def test_series_options_are_normalised():
    opts = w.Series(terms=np.int64(7), tol=1, digits=np.int64(40), budget=None)
    assert (opts.terms, opts.tol, opts.digits, opts.budget) == (7, 1.0, 40, None)
    assert type(opts.terms) is int and type(opts.tol) is float and type(opts.digits) is int


def test_dalembert_digits_choose_the_arithmetic():
    s = np.array([0.1, 0.6])
    fast = w.smooth_release_dalembert(s, 0.01, kappa0=10.0, c=C, L=L)
    slow = w.smooth_release_dalembert(s, 0.01, kappa0=10.0, c=C, L=L, digits=30)
    assert fast.dtype == float and isinstance(slow[0], mpmath.mpf)
    np.testing.assert_allclose(slow.astype(float), fast, rtol=0, atol=1e-13)
    with pytest.raises(ValueError, match=r"digits=4 must be an integer >= 5 or None"):
        w.instant_release_dalembert(s, 0.01, kappa0=1.0, c=C, L=L, digits=4)


def test_bad_solve_input():
    with pytest.raises(ValueError, match="multiples of dt"):
        w.solve(w.SmoothRelease(10.0), n_cells=10, dt=0.003, times=[0.01])
    with pytest.raises(ValueError, match="n_cells"):
        w.solve(w.SmoothRelease(10.0), n_cells=1, dt=0.005, times=[0.01])
    with pytest.raises(ValueError, match="width"):
        w.FlatBlend(0.0)
    with pytest.raises(ValueError, match="derivative order"):
        w.ExpQuartic()(0.5, 7)
    with pytest.raises(ValueError, match="needs .* series terms"):
        w.instant_release_exact(
            np.array([0.5]), 0.01, kappa0=1.0, c=C, L=L, series=w.Series(tol=1e-12)
        )
