"""Linear stability of the twisted, spinning rod (dyntorsion.beyond.linear_stability)."""

import math

import mpmath
import numpy as np
import pytest

from dyntorsion import Rod
from dyntorsion.beyond import linear_stability as LS
from dyntorsion.beyond.predictions import estimate
from dyntorsion.buckling import M_CRI_MP, Perturbation
from dyntorsion.buckling.statics import critical_twist
from dyntorsion.store import results as R
from dyntorsion.studies import linear_predictions as LP
from dyntorsion.studies import presets as P
from dyntorsion.studies import sweep as S
from dyntorsion.waves import linear_loading_dalembert

ROD = Rod()
KC = critical_twist(ROD)


# ------------------------------------------------------------------ the Galerkin basis
def test_beam_roots_match_mpmath():
    """cos(beta) cosh(beta) = 1, the first five roots to 30 digits (mpmath)."""
    _, _, _, _, _, beta = LS._beam_modes(5, 64)
    with mpmath.workdps(30):
        ref = [
            mpmath.findroot(lambda b: mpmath.cos(b) * mpmath.cosh(b) - 1, (j + 0.5) * mpmath.pi)
            for j in range(1, 6)
        ]
    assert np.allclose(beta, [float(r) for r in ref], rtol=1e-14, atol=0)


def test_beam_modes_are_orthonormal_and_diagonalise_bending():
    """int phi_i phi_j = delta_ij and int phi_i'' phi_j'' = beta^4 delta_ij (the modes of
    phi'''' = beta^4 phi with w = w' = 0 at both ends) to round-off, for 40 modes."""
    x, w, phi, d1, d2, beta = LS._beam_modes(40, 256)
    assert np.abs(phi.T @ (w[:, None] * phi) - np.eye(40)).max() < 1e-12
    K = d2.T @ (w[:, None] * d2)
    assert np.abs(K / np.outer(beta**2, beta**2) - np.eye(40)).max() < 1e-11
    # the clamped ends: phi ~ x^2 near x = 0, so phi / x^2 stays bounded at the first node
    assert np.all(np.abs(phi[0] / x[0] ** 2) < 2 * beta**2)


# ------------------------------------------------------------------ frozen spectrum
def test_critical_twist_converges_to_eq32_from_above():
    """The Galerkin (Rayleigh-Ritz) critical twist approaches eq (32) from above, with an
    observed algebraic order of at least 4 in the number of modes."""
    modes = (8, 16, 32)
    err = np.array(
        [LS.LateralModel(ROD, modes=m, quadrature=160).critical_twist() - KC for m in modes]
    )
    assert np.all(err > 0)
    order = np.log(err[:-1] / err[1:]) / np.log(2)
    assert np.all(order > 4.0), order
    assert err[-1] / KC < 1e-6
    assert float(2 * mpmath.pi * M_CRI_MP) * ROD.B1 / (ROD.C * ROD.L) == pytest.approx(
        KC, rel=1e-15
    )


def test_matrices_have_the_structure_of_a_gyroscopic_system():
    """Uniform twist: K Hermitian; spin: G skew-Hermitian; M symmetric positive definite."""
    model = LS.LateralModel(ROD, modes=12)
    K = model.stiffness(15.0)
    G = model.gyroscopic(-3.0 * (ROD.L - model.nodes))
    assert np.abs(K - K.conj().T).max() < 1e-12 * np.abs(K).max()
    assert np.abs(G + G.conj().T).max() < 1e-12 * np.abs(G).max()
    assert np.all(np.linalg.eigvalsh(model.mass_matrix) > 0)


def test_growth_rate_is_zero_below_and_a_square_root_just_above_kappa_cri():
    """Below kappa_cri the straight rod only vibrates (Re lambda = 0); just above it the
    growth rate follows lambda^2 = g (kappa - kappa_cri) (a simple zero of the lowest
    eigenvalue): lambda^2 / delta agrees at delta = 1e-4 and 1e-3 to 1 %."""
    model = LS.LateralModel(ROD)
    kc = model.critical_twist()
    assert model.growth_rate(0.99 * kc) == 0.0
    assert model.growth_rate(10.0) == 0.0
    lam = model.growth_rate(np.array([kc + 1e-4, kc + 1e-3]))
    g = lam**2 / np.array([1e-4, 1e-3])
    assert g[0] == pytest.approx(g[1], rel=0.01)
    assert np.all(np.diff(model.growth_rate(np.linspace(kc + 0.5, 50, 12))) > 0)


def test_spin_barely_changes_the_growth_rate():
    """The gyroscopic coupling rho J omega3 is ~1e-6 of the lateral inertia at the fastest
    rate of Fig 10, so the frozen growth rate with the spin of a = 16 equals the one
    without to 1e-6 (relative)."""
    model = LS.LateralModel(ROD, modes=12)
    for kappa in (14.0, 30.0):
        assert model.growth_rate(kappa, spin_rate=16.0) == pytest.approx(
            model.growth_rate(kappa), rel=1e-6
        )


def test_efolds_follow_the_slow_passage_law_near_kappa_cri():
    """N = (1/a) int lambda dkappa = (2/3) sqrt(g) (kappa - kappa_cri)^{3/2} / a near kappa_cri."""
    model = LS.LateralModel(ROD, modes=12)
    kc = model.critical_twist()
    g = model.growth_rate(kc + 1e-4) ** 2 / 1e-4
    d = 0.02
    n = model.efolds(0.5, kc + d)[0]
    assert n == pytest.approx(2 / 3 * math.sqrt(g) * d**1.5 / 0.5, rel=0.02)


@pytest.fixture(scope="module")
def efold_table():
    model = LS.LateralModel(Rod.paper(), modes=48, quadrature=256)
    return model.efold_table(model.critical_twist() + 150.0)


def test_wkb_exponent_is_two_thirds_under_slow_loading_and_falls_towards_one_third(efold_table):
    """Slow passage: lambda ~ (kappa - kappa_cri)^(1/2) past kappa_cri, so onsets at a
    fixed number of e-foldings give kappa3 - kappa_cri ~ a^(2/3) as a -> 0; far past
    kappa_cri the growth rate steepens and the exponent falls below 1/2 towards 1/3."""
    kappa, integral = efold_table
    a = np.geomspace(1e-3, 1e2, 12)
    kappa3 = np.interp(30.0 * a, integral, kappa)
    rates = np.geomspace(1e-5, 1e2, 300)
    local, valid, n1 = LS.wkb_exponents(a, kappa3, rates, efold_table)
    assert valid.all()
    assert n1 == pytest.approx(0.0, abs=1e-6)
    assert local[0] == pytest.approx(2 / 3, abs=0.01)
    decades = [np.interp(r, rates, local) for r in (1e-3, 1e-2, 1e-1, 1.0, 10.0)]
    assert np.all(np.diff(decades) < -0.01)
    assert 1 / 3 < local[-1] < 0.45


def test_wkb_exponent_grows_with_the_efoldings_per_log_rate(efold_table):
    """N(a) rising with ln a (n1 > 0) steepens the law: 2/3 (1 + dln N / dln a)."""
    kappa, integral = efold_table
    a = np.geomspace(1e-3, 1e-2, 6)
    flat = np.interp(30.0 * a, integral, kappa)
    rising = np.interp((30.0 + 3.0 * np.log(a / a[0])) * a, integral, kappa)
    rates = np.array([1e-3, 2e-3, 5e-3])
    base, _, _ = LS.wkb_exponents(a, flat, rates, efold_table)
    steep, _, n1 = LS.wkb_exponents(a, rising, rates, efold_table)
    assert n1 == pytest.approx(3.0, rel=1e-6)
    assert np.all(steep > base + 0.03)


# ------------------------------------------------------------------ the prebuckling state
def test_prebuckling_state_is_the_exact_solution_of_eq23():
    """kappa3 equals the d'Alembert solution of section 5; kappa3(0, t) = kappa0 + a t;
    omega3(L, t) = 0; compatibility kappa_t = omega_s and theta_t = omega3 hold."""
    pb = LS.Prebuckling(ROD, a=1.6, kappa0=10.0, terms=4000)
    s = np.linspace(0.0, ROD.L, 9)
    for t in (0.013, 0.05, 0.4, 3.0):
        k, w, _, _ = pb(s, t)
        ref = linear_loading_dalembert(s, t, a=1.6, kappa0=10.0, c=ROD.c, L=ROD.L)
        assert np.abs(k - ref).max() < 1e-6
        assert k[0] == pytest.approx(10.0 + 1.6 * t, abs=1e-12)
        assert w[-1] == pytest.approx(0.0, abs=1e-12)
    smooth = LS.Prebuckling(ROD, a=1.6, kappa0=10.0, terms=6)
    s, t, h = np.linspace(0.05, 0.95, 7), 0.71, 1e-6
    k_t = (smooth(s, t + h)[0] - smooth(s, t - h)[0]) / (2 * h)
    w_s = (smooth(s + h, t)[1] - smooth(s - h, t)[1]) / (2 * h)
    th_t = (smooth(s, t + h)[3] - smooth(s, t - h)[3]) / (2 * h)
    w_t = (smooth(s, t + h)[1] - smooth(s, t - h)[1]) / (2 * h)
    assert np.allclose(k_t, w_s, rtol=0, atol=1e-6)
    assert np.allclose(th_t, smooth(s, t)[1], rtol=0, atol=1e-6)
    assert np.allclose(w_t, smooth(s, t)[2], rtol=0, atol=1e-4)


def test_no_spin_and_no_waves_switches():
    s = np.linspace(0, 1, 5)
    k, w, wt, th = LS.Prebuckling(ROD, a=2.0, kappa0=1.0, waves=False, spin=False)(s, 0.5)
    assert np.all(k == 2.0) and np.all(w == 0) and np.all(wt == 0)
    assert np.allclose(th, -2.0 * (1 - s))


# ------------------------------------------------------------------ the slow passage
@pytest.fixture(scope="module")
def fast_model():
    return LS.LateralModel(ROD, modes=8, quadrature=64)


def _reference_passage(model, a, seed, *, waves, spin, terms, dt, t_stop):
    """u3(L) at t_stop by the plain NumPy route: coefficients of (L2) integrated on the
    quadrature points from the prebuckling state at every stage time (no separation of
    the series into fixed matrices), classical Runge-Kutta with the same steps."""
    base = LS.Prebuckling(ROD, a, 10.0, waves=waves, spin=spin, terms=terms)
    rows, points = model.seed_rows(seed)
    at_nodes, at_seed = base.at(model.nodes), base.at(points)
    m = model.modes
    Minv = np.linalg.inv(model.mass_matrix)

    def rhs(t, y):
        kappa, omega, omega_t, _ = at_nodes(t)
        theta = at_seed(t)[3]
        force = rows.T @ np.exp(1j * theta) - model.stiffness(kappa, omega_t) @ y[:m]
        if spin:
            force = force - model.gyroscopic(omega) @ y[m:]
        return np.concatenate([y[m:], Minv @ force])

    y = np.zeros(2 * m, dtype=complex)
    for n in range(round(t_stop / dt)):
        t = n * dt
        k1 = rhs(t, y)
        k2 = rhs(t + dt / 2, y + dt / 2 * k1)
        k3 = rhs(t + dt / 2, y + dt / 2 * k2)
        k4 = rhs(t + dt, y + dt * k3)
        y = y + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return -np.real(np.conj(y[:m]) @ (model.u3_matrix @ y[m:]))


@pytest.mark.parametrize(
    "waves, spin, seed",
    [
        (True, True, Perturbation(1e-8)),
        (True, False, Perturbation(1e-8)),
        (False, True, Perturbation(1e-8, "point", 0.3, (0.6, 0.8, 0.0))),
    ],
)
def test_compiled_passage_matches_the_plain_route(fast_model, waves, spin, seed):
    """The compiled march over separated coefficient matrices (dyntorsion.beyond.passage) gives
    the u3(L) trace of the plain NumPy evaluation of (L2) to round-off."""
    a, dt, t_stop = 12.8, 2e-3, 2.0
    p = fast_model.passage(
        a, 10.0, seed, waves=waves, spin=spin, terms=4,
        steps=LS.PassageSteps(dt=dt, t_end=t_stop, samples=1),
    )  # fmt: skip
    assert not p.reached and p.t[-1] == pytest.approx(t_stop)
    ref = _reference_passage(
        fast_model, a, seed, waves=waves, spin=spin, terms=4, dt=dt, t_stop=t_stop
    )
    assert ref != 0.0
    assert p.u3[-1] == pytest.approx(ref, rel=1e-10)


def test_passage_converges_at_fourth_order_in_dt(fast_model):
    """Runge-Kutta 4: the crossing time for dt, dt/2, dt/4 converges with observed order ~4."""
    t = [
        fast_model.passage(12.8, 10.0, 1e-8, waves=False, steps=LS.PassageSteps(dt=dt)).t_ref
        for dt in (0.01, 0.005, 0.0025)
    ]
    order = math.log2(abs(t[0] - t[1]) / abs(t[1] - t[2]))
    assert 3.7 < order < 4.3, (t, order)


def test_passage_is_linear_in_the_seed(fast_model):
    """u3 is quadratic in the lateral motion: seed x 10 reaches u_ref x 100 at the same time."""
    p1 = fast_model.passage(12.8, 10.0, 1e-8, waves=False, steps=LS.PassageSteps(dt=0.005))
    p2 = fast_model.passage(
        12.8, 10.0, 1e-7, waves=False, steps=LS.PassageSteps(dt=0.005, u_ref=100 * p1.u_ref)
    )
    assert p2.t_ref == pytest.approx(p1.t_ref, rel=1e-9)
    assert np.allclose(p2.u3, 100 * p1.u3, rtol=1e-9, atol=0)


def test_smaller_seed_and_faster_loading_buckle_later_in_twist(fast_model):
    k = {
        (a, e): fast_model.passage(a, 10.0, e, waves=False).kappa3_ref
        for a in (3.2, 12.8)
        for e in (1e-6, 1e-10)
    }
    assert k[(3.2, 1e-10)] > k[(3.2, 1e-6)] > KC
    assert k[(12.8, 1e-6)] > k[(3.2, 1e-6)]


def test_waves_change_the_prediction_little(fast_model):
    """The torsional oscillation averages out over the bending time scale."""
    kw = dict(a=12.8, kappa0=10.0, seed=1e-8)
    ramp = fast_model.passage(**kw, waves=False).kappa3_ref
    waves = fast_model.passage(**kw, waves=True, terms=4).kappa3_ref
    assert abs(waves - ramp) < 1e-3 * (ramp - KC)


def test_point_seed_and_bad_input(fast_model):
    p = fast_model.passage(12.8, 10.0, Perturbation(1e-8, "point", 0.5), waves=False)
    assert p.reached and p.kappa3_ref > KC
    with pytest.raises(ValueError, match="location"):
        fast_model.passage(12.8, 10.0, Perturbation(1e-8, "point", 2.0), waves=False)
    with pytest.raises(ValueError, match="a=-1"):
        fast_model.passage(-1.0)
    with pytest.raises(ValueError, match="u_ref"):
        fast_model.passage(1.0, steps=LS.PassageSteps(u_ref=0.0))
    with pytest.raises(ValueError, match="dt"):
        fast_model.passage(1.0, steps=LS.PassageSteps(dt=-1.0))
    with pytest.raises(ValueError, match="modes"):
        LS.LateralModel(ROD, modes=0)
    with pytest.raises(ValueError, match="quadrature"):
        LS.LateralModel(ROD, modes=20, quadrature=50)
    with pytest.raises(ValueError, match="preset"):
        LP.preset("nope")


def test_unreached_threshold_gives_nan(fast_model):
    p = fast_model.passage(1.0, 10.0, 1e-8, waves=False, steps=LS.PassageSteps(t_end=1.0))
    assert not p.reached and math.isnan(p.kappa3_ref)


# ------------------------------------------------------------------ cache and findings
def test_prediction_cache_round_trip(tmp_path, monkeypatch):
    pred = LP.Prediction(S.Scene(a=12.8), waves=False, modes=4)
    table = LP.predict([pred], tmp_path)
    rec = next(R.Store(tmp_path).records(LP.KIND))
    assert rec["provenance"]["code"] == R.code_of(LP.KIND) != R.code_of(S.KIND)
    monkeypatch.setattr(LP, "run_prediction", lambda p: pytest.fail("recomputed"))
    again = LP.predict([pred], tmp_path, compute=False)
    assert again["kappa3_ref"].iloc[0] == table["kappa3_ref"].iloc[0]
    with pytest.raises(S.MissingResultError, match="make data"):
        LP.predict([LP.Prediction(S.Scene(a=1.0), modes=4)], tmp_path, compute=False)


@pytest.mark.parametrize("seed", ["", "-tiny-seed"])
def test_linear_theory_predicts_the_simulated_onset_over_fig10(seed):
    """The finding of "Why is buckling delayed? (2)": with no fitted parameter the linear
    prediction of the time |u3(L)| reaches u_ref lies within 3 % of the simulated one at
    every rate of Fig 10 (stated and tiny seed), and is never later."""
    sim = P.cached("fig10" + seed)
    lin = LP.cached("linear-fig10" + seed)
    ratio = lin["t_ref"].to_numpy() / sim["t_ref"].to_numpy()
    assert np.all(ratio < 1.0) and np.all(ratio > 0.97), ratio


def test_cli_reads_the_committed_predictions(capsys):
    from dyntorsion.app.cli import main

    assert main(["linear", "--preset", "linear-variants", "--on-stale", "error", "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "kappa3_ref" in out and len(out.strip().splitlines()) == 1 + len(
        LP.preset("linear-variants")
    )


def test_a_committed_prediction_is_reproduced():
    """Recomputing the cheapest committed prediction (a = 12.8, no waves) gives the cached
    numbers (to 1e-9: a different BLAS may reorder sums)."""
    pred = LP.Prediction(S.Scene(a=12.8), waves=False)
    cached = LP.predict([pred], compute=False, on_stale="error").iloc[0]
    fresh = LP.run_prediction(pred)
    assert fresh["kappa3_ref"] == pytest.approx(cached["kappa3_ref"], rel=1e-9)
    assert fresh["t_ref"] == pytest.approx(cached["t_ref"], rel=1e-9)


def test_fast_estimate_is_within_3_percent_of_the_simulated_onsets():
    """beyond.predictions.estimate against the committed Fig 10 sweeps (stated and tiny
    seed): the threshold time within 3 % of the simulation's at every rate."""
    for name in ("fig10", "fig10-tiny-seed"):
        sim = P.cached(name)
        for sc, t_ref in zip(P.preset(name), sim.t_ref, strict=True):
            e = estimate(sc)
            assert 6 <= e.modes <= 24
            assert e.t_ref == pytest.approx(t_ref, rel=0.03), (name, sc.a)
    with pytest.raises(ValueError, match="axial load"):
        estimate(S.Scene(a=1.6, tension=0.01, t_end=10.0))
