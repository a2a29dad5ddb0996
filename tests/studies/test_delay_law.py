"""The delay law of section 6 (eqs 33-34): the power-law fit and the committed Fig 10 sweep."""

import numpy as np
import pytest

from dyntorsion import Rod
from dyntorsion.buckling.delay_law import fit_power_law, paper_law
from dyntorsion.buckling.statics import critical_twist
from dyntorsion.store import location as L
from dyntorsion.studies import presets as P
from dyntorsion.studies import sweep as S

ROD = Rod()
A = np.array(P.FIG10_RATES)


# ------------------------------------------------------------------ the fit itself
def test_paper_law_predicts_the_paper_times_until_buckling():
    """Section 6: b = 160.60, sigma = 0.5680 give 20.11 s (Fig 8) and 25.45 s (Fig 9)."""
    exact = fit_power_law(A, paper_law(A, ROD), ROD, n_boot=0)
    assert exact.time_to_buckle(1.6) == pytest.approx(20.11, abs=0.005)
    assert exact.time_to_buckle(1.6, rod=ROD.with_(rho=5000.0)) == pytest.approx(25.45, abs=0.005)


@pytest.mark.parametrize("kappa_cri", ["static", None])
def test_fit_recovers_an_exact_power_law(kappa_cri):
    b, sigma = 123.4, 0.61
    k = critical_twist(ROD) + b / ROD.L * (A * ROD.L / ROD.c) ** sigma
    fit = fit_power_law(A, k, ROD, kappa_cri=kappa_cri, n_boot=50)
    assert fit.b == pytest.approx(b, rel=1e-8)
    assert fit.sigma == pytest.approx(sigma, rel=1e-8)
    assert fit.kappa_cri == pytest.approx(critical_twist(ROD), rel=1e-8)
    assert fit.kappa_cri_free is (kappa_cri is None)
    assert fit.residual_rms < 1e-8


def test_fit_uncertainties_cover_the_truth(rng):
    """Noisy synthetic sweeps: the 95 % intervals hold the true b, sigma and kappa_cri in
    most of 40 repetitions, and the covariance errors match the scatter of the estimates."""
    b, sigma, noise = 160.6, 0.568, 0.5
    truth = paper_law(A, ROD)
    est, inside, inside_cov = [], 0, 0
    for _ in range(40):
        k = truth + rng.normal(0.0, noise, A.size)
        f = fit_power_law(A, k, ROD, kappa_cri=None, n_boot=200, seed=int(rng.integers(1 << 30)))
        est.append((f.b, f.sigma, f.kappa_cri, f.b_err, f.sigma_err, f.kappa_cri_err))
        lo, hi = f.bootstrap["sigma"]
        inside += lo <= sigma <= hi
        inside_cov += abs(f.b - b) < 1.96 * f.b_err
    est = np.array(est)
    assert inside >= 30 and inside_cov >= 32
    for col in range(3):
        assert np.std(est[:, col]) == pytest.approx(np.median(est[:, col + 3]), rel=0.5)
    assert abs(np.mean(est[:, 2]) - critical_twist(ROD)) < 3 * np.std(est[:, 2]) / np.sqrt(40)


def test_fit_is_reproducible():
    k = paper_law(A, ROD) + np.linspace(-0.3, 0.3, A.size)
    f1, f2 = (fit_power_law(A, k, ROD, kappa_cri=None, n_boot=100, seed=7) for _ in range(2))
    assert f1.bootstrap == f2.bootstrap and f1.b == f2.b


@pytest.mark.parametrize(
    "kw, msg",
    [
        ({"a": [1.0, 2.0], "kappa3": [20.0]}, "one length"),
        ({"a": [0.0, 1.0, 2.0, 3.0], "kappa3": [12, 13, 14, 15]}, "a must be > 0"),
        ({"a": [1.0, 2.0, 3.0], "kappa3": [12, 13, 14], "kappa_cri": None}, "at least 4"),
        ({"a": [1.0, 2.0, 3.0], "kappa3": [12, np.nan, 14]}, "finite"),
        ({"a": [1.0, 2.0, 3.0], "kappa3": [12, 13, 14], "kappa_cri": "paper"}, "kappa_cri="),
        ({"a": [1.0, 2.0, 3.0], "kappa3": [12, 13, 14], "confidence": 1.0}, "confidence"),
    ],
)
def test_fit_rejects_bad_input(kw, msg):
    with pytest.raises(ValueError, match=msg):
        fit_power_law(rod=ROD, **kw)


# ------------------------------------------------------------------ the committed sweep
def committed(name):
    """A preset read from data/scenes: missing or stale records fail with `make data`."""
    return P.cached(name)


@pytest.fixture(scope="module", params=["fig10", "fig10-tiny-seed"])
def sweep(request):
    return request.param, committed(request.param)


def test_every_scene_of_the_sweep_buckled(sweep):
    _, table = sweep
    assert table["kappa3"].notna().all()
    assert (table["kappa3"] > critical_twist(ROD)).all()
    assert np.all(np.diff(table["kappa3"]) > 0)  # the delay grows with the loading rate
    assert (table["uncertainty_kappa3"] < 0.1 * (table["kappa3"] - critical_twist(ROD))).all()


def test_committed_fit_pin_of_our_output(sweep, num_regression):
    """A pin of our own output: the fit of the committed sweeps; the fit itself is checked against the exact law in test_paper_law_predicts_the_paper_times_until_buckling."""
    name, table = sweep
    fixed = fit_power_law(table["a"], table["kappa3"], ROD, n_boot=500)
    free = fit_power_law(table["a"], table["kappa3"], ROD, kappa_cri=None, n_boot=500)
    num_regression.check(
        {
            "b": fixed.b,
            "sigma": fixed.sigma,
            "b_err": fixed.b_err,
            "sigma_err": fixed.sigma_err,
            "b_free": free.b,
            "sigma_free": free.sigma,
            "kappa_cri_free": free.kappa_cri,
            "kappa_cri_free_err": free.kappa_cri_err,
        },
        default_tolerance={"rtol": 1e-6},
        basename=f"fit_{name}",
    )


def test_free_fit_misses_the_static_twist_by_the_power_laws_curvature(sweep):
    """The paper's check (kappa_cri free extrapolates to eq 32) does not hold over our
    2.5 decades: the free fit lands below 11.2335 (see the Fig 10 page).  The cause is
    that the local exponent d ln(kappa3 - kappa_cri) / d ln a is not constant, and a
    free kappa_cri absorbs the curvature: fitted on the slowest half of the rates only,
    the extrapolation comes closer to eq (32)."""
    _, table = sweep
    kc = critical_twist(ROD)
    a, k = table["a"].to_numpy(), table["kappa3"].to_numpy()
    full = fit_power_law(a, k, ROD, kappa_cri=None, n_boot=0)
    slow = fit_power_law(a[:8], k[:8], ROD, kappa_cri=None, n_boot=0)
    assert full.kappa_cri < kc - 3 * full.kappa_cri_err
    assert abs(slow.kappa_cri - kc) < abs(full.kappa_cri - kc)
    local = np.diff(np.log(k - kc)) / np.diff(np.log(a))
    assert np.ptp(local) > 10 * full.sigma_err


@pytest.mark.parametrize("seed", ["fig10-grid", "fig10-grid-tiny-seed"])
def test_committed_sweep_is_grid_independent(seed):
    """kappa3 at N = 50/dt = 0.01 and N = 200/dt = 0.0025 against the sweep's N = 100,
    dt = 0.005, at the slowest, the paper's and the fastest rate: within 1 %."""
    base = committed("fig10" if seed == "fig10-grid" else "fig10-tiny-seed").set_index("a")
    for _, row in committed(seed).iterrows():
        assert row["kappa3"] == pytest.approx(base.loc[row["a"], "kappa3"], rel=0.01)


# ------------------------------------------------------------------ imperfection sensitivity
def test_onset_is_later_the_smaller_the_seed_and_never_without_one():
    scenes = P.preset("imperfection")
    table = committed("imperfection")
    store = S.Store(L.DATA)
    for a in P.IMPERFECTION_RATES:
        rows = [
            (sc.seed.magnitude, k)
            for sc, k in zip(scenes, table["kappa3"], strict=True)
            if sc.a == a and sc.seed.form == "uniform" and sc.seed.magnitude > 0
        ]
        mags, kappas = np.array(rows).T
        order = np.argsort(mags)
        assert np.all(np.diff(kappas[order]) < 0)  # more seed, earlier onset
    for sc in scenes:
        if sc.seed.magnitude == 0:
            res = store.load(S.KIND, sc.params(), on_stale="error")["result"]
            assert res["t_c"] is None and "identically zero" in res["onset_error"]
            assert res["u3_peak"] == 0.0
            assert sc.kappa0 + sc.a * res["t_last"] > 2 * critical_twist(ROD)
