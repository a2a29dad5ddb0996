"""Manufactured solutions of the 12-field system, for measuring the order of accuracy.

A smooth y*(s, t) is chosen for all twelve fields; the source that makes it an
exact solution, q = -(M y*_t + K y*_s + F(y*)), is handed to the engine, and the
boundary rows take their values from y*.  The error of the discrete solution
against y* then shows the observed order in ds and dt (scikit-fem style: the
tests pin rates, not only values).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from . import genalpha as ga
from .model.cosserat import Cosserat
from .model.ends import EQ30
from .model.rod import Rod

#: the boundary rows of eq (30): prescribed fields at s = 0 and s = L
LEFT_FIELDS, RIGHT_FIELDS = EQ30.left, EQ30.right


@dataclass(frozen=True)
class Manufactured:
    """y*_f(s, t) = B_f + A_f sin(om_f t + ph_f) cos(ka_f s + ps_f), field by field."""

    model: Cosserat
    A: np.ndarray
    B: np.ndarray
    om: np.ndarray
    ph: np.ndarray
    ka: np.ndarray
    ps: np.ndarray

    @classmethod
    def random(
        cls, seed: int = 1, rod: Rod | None = None, amplitude: float = 1.0, frequency: float = 1.0
    ) -> Manufactured:
        """A solution whose fields are ``amplitude`` x their characteristic scale and vary
        on O(L) in space and O(T0 / frequency) in time (T0 the bending time)."""
        rod = rod or Rod(E=100.0, nu=0.3, D=0.3, L=1.0, rho=1.0)
        model = Cosserat(rod)
        ys, _ = model.scales()
        T0 = rod.L / ys[0]
        g = np.random.default_rng(seed)
        return cls(
            model=model,
            A=amplitude * ys * g.uniform(0.3, 1.0, 12),
            B=amplitude * ys * g.uniform(-0.5, 0.5, 12),
            om=frequency * g.uniform(1.0, 3.0, 12) / T0,
            ph=g.uniform(0, 2 * np.pi, 12),
            ka=g.uniform(1.0, 3.0, 12) / rod.L,
            ps=g.uniform(0, 2 * np.pi, 12),
        )

    def y(self, s, t):
        s = np.asarray(s, float)[:, None]
        return self.B + self.A * np.sin(self.om * t + self.ph) * np.cos(self.ka * s + self.ps)

    def y_t(self, s, t):
        s = np.asarray(s, float)[:, None]
        return self.A * self.om * np.cos(self.om * t + self.ph) * np.cos(self.ka * s + self.ps)

    def y_s(self, s, t):
        s = np.asarray(s, float)[:, None]
        return -self.A * self.ka * np.sin(self.om * t + self.ph) * np.sin(self.ka * s + self.ps)

    def source(self, s, t):
        system = self.model.system()
        y = self.y(s, t)
        return -(self.y_t(s, t) @ system.M.T + self.y_s(s, t) @ system.K.T + system.load(y))

    def solve(
        self,
        n_cells: int,
        dt: float,
        t_end: float,
        scheme: ga.Scheme = ga.Scheme(),
        newton: ga.Newton = ga.Newton(tol=1e-12),
        project: bool = True,
    ) -> ga.Run:
        """Discrete solution.  y*(s, 0) satisfies the discrete constraint rows only to
        O(ds^2), so by default it is first projected onto them
        (:func:`~dyntorsion.genalpha.consistent_initial_state`)."""
        system = self.model.system()
        L = self.model.rod.L
        s = np.linspace(0.0, L, n_cells + 1)
        li = [system.index(f) for f in LEFT_FIELDS]
        ri = [system.index(f) for f in RIGHT_FIELDS]
        left = ga.Boundary.fields(
            system, LEFT_FIELDS, lambda t: np.array([self.y([0.0], ti)[0][li] for ti in t])
        )
        right = ga.Boundary.fields(
            system, RIGHT_FIELDS, lambda t: np.array([self.y([L], ti)[0][ri] for ti in t])
        )
        problem = ga.Problem(
            system,
            self.y(s, 0.0),
            left,
            right,
            sources=ga.Sources(field=self.source),
            y_t0=self.y_t(s, 0.0),
        )
        grid = ga.Grid(n_cells, L, dt, t_end)
        if project:
            projected = ga.consistent_initial_state(problem, grid, scheme=scheme)
            problem = dataclasses.replace(problem, y0=projected)
        return ga.integrate(problem, grid, scheme=scheme, newton=newton)

    def error(self, run: ga.Run) -> float:
        """Max over nodes and fields of |y - y*| / yscale at the final time."""
        ys, _ = self.model.scales()
        return float(np.max(np.abs(run.y - self.y(run.s, run.t_final)) / ys))


def observed_orders(h, err) -> np.ndarray:
    """log2-type rates between successive levels of a ladder h (any ratio)."""
    h, err = np.asarray(h, float), np.asarray(err, float)
    return np.log(err[:-1] / err[1:]) / np.log(h[:-1] / h[1:])


def richardson(h, values) -> tuple[float, float] | None:
    """The limit h -> 0 and the observed order p of ``values`` on a ladder of steps ``h``
    (any ratios, any order), from its three finest levels: v(h) = v0 + C h^p through them.
    None when the two differences do not shrink in one direction (no order to observe) or
    need an order outside [1/4, 8]."""
    h, v = np.asarray(h, float), np.asarray(values, float)
    if h.size < 3 or h.size != v.size:
        raise ValueError(
            f"richardson needs at least three levels of h and values (got {h.size}, {v.size})"
        )
    order = np.argsort(h)[:3][::-1]
    (h1, h2, h3), (v1, v2, v3) = h[order], v[order]
    if not (h1 > h2 > h3 > 0):
        raise ValueError(f"richardson needs three distinct positive steps (got {h1}, {h2}, {h3})")
    if v2 == v3 or (v1 - v2) / (v2 - v3) <= 0:
        return None
    target = (v1 - v2) / (v2 - v3)

    def ratio(p: float) -> float:  # increasing in p for h1 > h2 > h3
        return (h1**p - h2**p) / (h2**p - h3**p)

    lo, hi = 0.25, 8.0
    if not ratio(lo) <= target <= ratio(hi):
        return None
    p = brentq(lambda q: ratio(q) - target, lo, hi, xtol=1e-14)
    return float(v3 - (v2 - v3) * h3**p / (h2**p - h3**p)), float(p)
