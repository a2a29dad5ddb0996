"""The stopping tests of the Newton solve (genalpha.newton, Newton.stopping): the
contraction test converges to tol.  That it fails as loudly as the correction test is
tests/genalpha/test_genalpha.py::test_max_iter_failure_raises_convergence_error (both tests), and
that the step-size control still rejects with it (the default) is
tests/buckling/test_control.py::test_rejected_steps_are_retried_with_smaller_steps."""

import numpy as np
import pytest

from dyntorsion import Rod
from dyntorsion import genalpha as ga
from dyntorsion.buckling.loading import EQ30
from dyntorsion.buckling.scene import Scene
from dyntorsion.model.cosserat import IDX, Cosserat

CONTRACTION = ga.Newton(stopping="contraction")
CORRECTION = ga.Newton(stopping="correction")


def _bent_step(newton, n=24, dt=0.05, steps=1):
    """Steps of the twisted rod from a bent, moving state: a nonlinear solve per step."""
    model = Cosserat(Rod())
    system = model.system()
    kappa0, a = 10.0, 1.6
    y0 = np.zeros((n + 1, 12))
    y0[:, IDX["k3"]] = kappa0
    s = np.linspace(0.0, 1.0, n + 1)
    y0[:, IDX["k1"]] = 2.0 * np.sin(np.pi * s)
    left = ga.Boundary(
        ga.Boundary.fields(system, list(EQ30.left)).rows,
        lambda t: np.outer(kappa0 + a * t, [0, 0, 0, 0, 0, 1.0]),
    )
    right = ga.Boundary.fields(system, list(EQ30.right))
    run = ga.integrate(
        ga.Problem(system, y0, left, right, y_t0="zero"),
        ga.Grid(n_cells=n, length=1.0, dt=dt, t_end=steps * dt),
        newton=newton,
    )
    return model.scales()[0], run


def _error(ys, run, ref):
    return float(np.sqrt(np.mean(((run.y - ref.y) / np.maximum(np.abs(ref.y), ys)) ** 2)))


@pytest.mark.parametrize("tol", [1e-4, 1e-6, 1e-8, 1e-10])
def test_contraction_test_converges_a_step_to_tol(tol):
    """One nonlinear step from the constant predictor (a bent rod, 3-9 corrections):
    the contraction test stops within tol of the solution of the discrete equations
    (a full Newton solve to 1e-14), and not later than the correction test."""
    ys, ref = _bent_step(ga.Newton(tol=1e-14, reuse=False, stopping="correction"))
    _, run = _bent_step(ga.Newton(tol=tol, stopping="contraction"))
    _, old = _bent_step(ga.Newton(tol=tol, stopping="correction"))
    assert _error(ys, run, ref) <= tol
    assert run.iterations[0] <= old.iterations[0]


def test_contraction_test_saves_corrections_and_keeps_the_answer():
    """Over a few steps it needs fewer corrections than the correction test, with the
    same answer to tol (the first rate of a step alone is not trusted: from this
    predictor it is 4e-4 and the next 6e-2)."""
    ys, old = _bent_step(ga.Newton(tol=1e-6, stopping="correction"), steps=3)
    _, new = _bent_step(ga.Newton(tol=1e-6, stopping="contraction"), steps=3)
    assert new.iterations.sum() < old.iterations.sum()
    assert _error(ys, new, old) <= 1e-5


def test_stopping_option_is_checked_and_keyed():
    with pytest.raises(ValueError, match="stopping='residual'.*'correction', 'contraction'"):
        ga.Newton(stopping="residual")
    assert ga.Newton().stopping == "contraction"
    old, new = (Scene(a=1.6, newton=n).params() for n in (CORRECTION, ga.Newton()))
    assert old["newton"]["stopping"] == "correction" and new != old


@pytest.mark.parametrize("tol", [1e-6, 1e-8, 1e-10])
def test_factors_kept_across_steps_give_the_solution_within_tol(tol):
    """Three steps that keep the first step's LU factors (one factorisation in the
    last two steps) against a fresh Jacobian at every correction: both within
    tol per step (3 tol after three steps) of the full Newton solution to 1e-14."""
    ys, ref = _bent_step(ga.Newton(tol=1e-14, reuse=False, stopping="correction"), steps=3)
    _, kept = _bent_step(ga.Newton(tol=tol), steps=3)
    _, fresh = _bent_step(ga.Newton(tol=tol, reuse=False), steps=3)
    assert kept.factorisations.sum() < fresh.factorisations.sum()
    assert kept.factorisations[2] == 0  # the third step reuses the factors
    assert _error(ys, kept, ref) <= 3 * tol and _error(ys, fresh, ref) <= 3 * tol
