"""A source that depends on the state goes through integrate() (dyntorsion.genalpha.state):
a viscous force -gamma u per length solved as a state source agrees with the same force
written into the model's F (beyond.contact.damped), a source that couples nothing is the
engine's own run, and what its steps do not support is refused by name."""

from __future__ import annotations

import numpy as np
import pytest

from dyntorsion import Rod
from dyntorsion import genalpha as ga
from dyntorsion.beyond.contact.damped import damped_system
from dyntorsion.buckling.loading import EQ30
from dyntorsion.genalpha.state import StateSource, StateTerms, Substeps
from dyntorsion.model.cosserat import IDX, Cosserat

GAMMA = 2.0e-3  # N s/m^2


class Viscous(StateSource):
    """q_u = gamma u at every node (the sign of F in the residual), coupled every step
    unless ``idle``: its Jacobian, gamma I, as 3 x 3 blocks into the band."""

    substeps = Substeps(1)

    def __init__(self, gamma: float, idle: bool = False):
        self.gamma, self.idle, self.levels = gamma, idle, 0

    def level(self, h, con):
        return h

    def begin(self, level, y_old):
        return None if self.idle else level

    def terms(self, step, y, jacobian, band):
        n1, nf = y.shape
        q = np.zeros((n1, nf))
        q[:, 0:3] = self.gamma * y[:, 0:3]
        nodes = np.arange(n1) if jacobian else np.zeros(0, np.int64)
        blocks = np.tile(self.gamma * np.eye(3), (nodes.size, 1, 1))
        none = np.zeros((0, nf * n1))
        return StateTerms(q, none, none, nodes, blocks, rows=0, cols=0)

    def too_fast(self, h):
        return False

    def level_reached(self, t, y, h, check):
        self.levels += 1
        return None

    def check_every(self, dt):
        return 1


def _scene(n=16, a=12.0, kappa0=10.0):
    rod = Rod()
    model = Cosserat(rod)
    y0 = np.zeros((n + 1, 12))
    y0[:, IDX["k3"]] = kappa0
    fields = ga.Boundary.fields(model.system(), list(EQ30.left))
    left = ga.Boundary(fields.rows, lambda t: np.outer(kappa0 + a * t, [0, 0, 0, 0, 0, 1]))
    right = ga.Boundary.fields(model.system(), list(EQ30.right))
    seed = model.external_force(np.tile([1e-3, 0, 0], (n + 1, 1)))
    return rod, model, y0, left, right, seed


SCHEME = ga.Scheme(quadrature="trapezoidal")
NEWTON = ga.Newton(tol=1e-12)


def _run(system, problem_sources, n=16, t_end=1.0):
    rod, model, y0, left, right, _ = _scene(n)
    grid = ga.Grid(n, rod.L, 0.01, t_end)
    problem = ga.Problem(system, y0, left, right, sources=problem_sources)
    return ga.integrate(problem, grid, scheme=SCHEME, newton=NEWTON)


def test_a_state_source_solves_as_the_same_force_in_the_model():
    rod, model, y0, left, right, seed = _scene()
    inside = _run(damped_system(model, GAMMA, 0.0), ga.Sources(separable=(seed, None)))
    source = Viscous(GAMMA)
    outside = _run(model.system(), ga.Sources(separable=(seed, None), state=source))
    free = _run(model.system(), ga.Sources(separable=(seed, None)))
    # the same discrete equations, solved by two Newton paths to corrections of 1e-12:
    # measured 3e-12 of the force's own effect on the state, 3e-9 of the fields' scales
    effect = np.max(np.abs(free.y - inside.y))
    assert np.max(np.abs(outside.y - inside.y)) < 1e-10 * effect
    scale = np.maximum(np.abs(inside.y), model.scales()[0])
    assert np.max(np.abs(outside.y - inside.y) / scale) < 1e-8
    assert np.max(np.abs(free.y - inside.y) / scale) > 1.0  # the force acts
    state = outside.meta["state"]
    assert state["steps"] == outside.steps == source.levels == 100
    assert state["coupled_steps"] == 100 and state["failed_solves"] == 0
    # Newton with the source's Jacobian converges as the plain one does
    assert state["coupled_iterations"] <= 8 * state["coupled_steps"]


def test_a_source_that_couples_nothing_is_the_engine_s_own_run():
    rod, model, y0, left, right, seed = _scene()
    plain = _run(model.system(), ga.Sources(separable=(seed, None)))
    idle = _run(model.system(), ga.Sources(separable=(seed, None), state=Viscous(GAMMA, True)))
    scale = np.maximum(np.abs(plain.y), model.scales()[0])
    assert np.max(np.abs(idle.y - plain.y) / scale) < 1e-10
    assert idle.meta["state"]["coupled_steps"] == 0


@pytest.mark.parametrize(
    ("part", "name"),
    [
        ({"scheme": ga.Scheme(control=ga.StepControl())}, "scheme.control"),
        ({"output": ga.Output(record={"u3": ("u3", -1)})}, "output.record"),
        ({"output": ga.Output(snapshots=[0.1])}, "output.snapshots"),
        ({"stops": ga.Stops(test=lambda t, y: None, check_every=1)}, "stops.test"),
    ],
)
def test_what_the_state_steps_do_not_support_is_refused_by_name(part, name):
    rod, model, y0, left, right, seed = _scene()
    problem = ga.Problem(model.system(), y0, left, right, ga.Sources(state=Viscous(GAMMA)))
    with pytest.raises(ValueError, match=f"sources.state: .*{name}"):
        ga.integrate(problem, ga.Grid(16, rod.L, 0.01, 0.1), **part)
