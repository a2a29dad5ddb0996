"""The 12-field Cosserat model of section 2."""

import numpy as np
import pytest

from dyntorsion import Rod
from dyntorsion import genalpha as ga
from dyntorsion.buckling.loading import EQ30
from dyntorsion.model.cosserat import FIELDS, IDX, TERMS, Cosserat


def _fd_jacobian(system, y, h=1e-7):
    J = np.zeros((12, 12))
    for k in range(12):
        step = h * max(1.0, abs(y[k]))
        yp, ym = y.copy(), y.copy()
        yp[k] += step
        ym[k] -= step
        J[:, k] = (system.load(yp) - system.load(ym)) / (2 * step)
    return J


@pytest.mark.parametrize("switches", ["all on", "random weights"])
def test_jacobian_matches_finite_differences(rng, switches):
    terms = {} if switches == "all on" else {t: float(rng.uniform(0.2, 2)) for t in TERMS}
    # a rod with O(1) coefficients so that every term is visible at O(1) states
    model = Cosserat(Rod(E=100.0, nu=0.3, D=0.5, L=1.0, rho=2.0), terms=terms)
    system = model.system()
    for _ in range(5):
        y = rng.normal(size=12)
        assert np.all(y != 0)
        J = system.load_jacobian(y)
        J_fd = _fd_jacobian(system, y)
        assert np.max(np.abs(J - J_fd)) <= 1e-7 * max(1.0, np.max(np.abs(J)))


def test_each_switch_removes_its_term(rng):
    rod = Rod(E=100.0, nu=0.3, D=0.5, L=1.0, rho=2.0)
    y = rng.normal(size=12)
    full = Cosserat(rod).system().load(y)
    for term in TERMS:
        off = Cosserat(rod, terms={term: 0.0}).system().load(y)
        assert np.any(off != full), term


def test_gyroscopic_term_is_w_cross_rhoI_w(rng):
    rod = Rod(E=100.0, nu=0.3, D=0.5, L=1.0, rho=2.0)
    y = np.zeros(12)
    y[3:6] = rng.normal(size=3)
    model = Cosserat(rod)
    rhoI = model.params[1:4]
    expected = np.cross(y[3:6], rhoI * y[3:6])
    assert np.allclose(model.system().load(y)[3:6], expected, rtol=1e-14, atol=0)


def test_rotary_inertia_scale_keeps_torsion():
    rod = Rod()
    p1 = Cosserat(rod).params
    p2 = Cosserat(rod, rotary_inertia_scale=10.0).params
    assert p2[1] == pytest.approx(10 * p1[1]) and p2[2] == pytest.approx(10 * p1[2])
    assert p2[3] == p1[3]


def test_bad_switch_names():
    with pytest.raises(ValueError, match="terms"):
        Cosserat(terms={"gyroscopic": 0.0})
    with pytest.raises(ValueError, match="rotary_inertia_scale"):
        Cosserat(rotary_inertia_scale=-1.0)


def test_uniform_twist_is_an_exact_discrete_equilibrium():
    """k3 = kappa0 everywhere, all else 0: residual ~ round-off, nothing moves in 10^4 steps."""
    model = Cosserat(Rod())
    system = model.system()
    n, kappa0 = 20, 7.3
    y0 = np.zeros((n + 1, 12))
    y0[:, IDX["k3"]] = kappa0
    left = ga.Boundary.fields(system, list(EQ30.left), [0, 0, 0, 0, 0, kappa0])
    right = ga.Boundary.fields(system, list(EQ30.right))
    run = ga.integrate(
        ga.Problem(system, y0, left, right),
        ga.Grid(n_cells=n, length=1.0, dt=1e-3, t_end=10.0),
        output=ga.Output(record={"u3": ("u3", -1)}),
    )
    assert run.steps == 10_000
    assert np.max(run.residuals) <= 1e-14
    others = np.delete(run.y, IDX["k3"], axis=1)
    assert np.max(np.abs(others)) <= 1e-14
    assert np.max(np.abs(run.y[:, IDX["k3"]] - kappa0)) <= 1e-12
    assert np.max(np.abs(run["u3"])) <= 1e-14


def test_field_names():
    assert FIELDS[IDX["n3"]] == "n3" and len(FIELDS) == 12
