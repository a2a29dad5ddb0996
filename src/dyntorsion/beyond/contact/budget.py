"""The energy budget as the scheme keeps it: each line from the discrete equations.

Pair the residual of every cell of eq (10)-(12) with the conjugate of the fields,
z = (u, w, K^k, -n), at the cell's space-time point (the weights a_s = b_s = 1/2 in s,
b_t in time: y* = (1 - b_t) y^i + b_t y^{i-1}, averaged over the cell's two nodes).  The
four rows of eq (7) then give, for one step h (the module docstring of
:mod:`dyntorsion.model.cosserat` for the rows):

* the rate term  h z*.M abar = dE_mid + dG + D  exactly (below), with E_mid the kinetic
  + elastic energy of the cell averages;
* the flux term  h z*.K y*_s = -h [u*.n* + w*.m*]_0^L: the work at the ends, telescoped
  (z.K is symmetric);
* the sources  h z*.<q>*: the work of the contact and of the seed as the scheme applies them;
* the load vector h z*.<F>: zero for the nonlinear terms of eq (7) where F is taken at
  y* itself (each term is skew in this pairing), a residue of second order where it is the
  trapezoidal mean of the corners (the paper's eq 9); the viscous terms of a damped scene
  (:mod:`.damped`, linear: -h (gamma_u |u*|^2 + gamma_w |w*|^2) with either quadrature).

The rate term in time: with abar = (1 - a) v^i + a v^{i-1} and y^i - y^{i-1} =
h [(1 - g) v^{i-1} + g v^i] (eq 11-12, g - 1/2 = b_t - a), for any quadratic energy E,

    h <y*, abar>_E - dE = (1/2 - b)(1/2 - a)(g - 1/2) h^2 |dv|_E^2 + dG,
    G(h; y, v) = (1/2 - b) h <y, v>_E + (1/2)(1/2 - b)(1/2 - a) h^2 |v|_E^2,

the first term the scheme's numerical dissipation D >= 0 (zero at lambda_t = -1, where
also G = 0), G a modified energy that telescopes at a fixed step (Chung-Hulbert's
algorithmic energy for the first-order form).  :class:`SchemeBudget` sums the lines
step by step; what the pairing leaves (the load vector's and the Newton solve's part) is
its ``rest``, so the lines close by construction and the physics is in how each compares
with its counterpart: the contact's work against the law's stored energy and dashpots.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from ...genalpha.scheme import Coefficients
from ...model.cosserat import Params

__all__ = ["Level", "Loads", "SchemeBudget", "energy_weights", "conjugate", "rate_identity", "work_done", "share",
           "nodal_share"]  # fmt: skip


def energy_weights(p: Params) -> np.ndarray:
    """The diagonal of E = 1/2 y.diag(.)y over the 12 fields (rho A, rho I, B; 0 for n)."""
    return np.array([p.rhoA] * 3 + [p.rI1, p.rI2, p.rI3, p.B1, p.B2, p.C] + [0.0] * 3)


def conjugate(p: Params) -> np.ndarray:
    """z = S y: the multipliers that make the rows of eq (7) an energy balance."""
    return np.array([1.0] * 6 + [p.B1, p.B2, p.C] + [-1.0] * 3)


def rate_identity(co: Coefficients, h: float, ew: np.ndarray, y_old, y_new, v_old, v_new):
    """(h <y*, abar>_E, dE, D, dG) of one step for the cell averages y, rates v."""
    b, g = co.b_t, co.g_t
    a = b - g + 0.5
    y_star = (1.0 - b) * y_new + b * y_old
    abar = (1.0 - a) * v_new + a * v_old
    paired = h * float(np.sum(ew * y_star * abar))
    d_e = 0.5 * float(np.sum(ew * (y_new * y_new - y_old * y_old)))
    dv = v_new - v_old
    diss = (0.5 - b) * (0.5 - a) * (g - 0.5) * h * h * float(np.sum(ew * dv * dv))

    def G(y, v):
        return (0.5 - b) * h * float(np.sum(ew * y * v)) + 0.5 * (0.5 - b) * (
            0.5 - a
        ) * h * h * float(np.sum(ew * v * v))

    return paired, d_e, diss, G(y_new, v_new) - G(y_old, v_old)


def _cells(x: np.ndarray) -> np.ndarray:
    """The cell averages of nodal values (eq 12 at lambda_s = -1: both nodes weigh 1/2)."""
    return 0.5 * x[1:] + 0.5 * x[:-1]


class Level(NamedTuple):
    """One time level of a step at the N+1 nodes: the fields ``y`` and their rates ``v``
    (both (N+1, 12))."""

    y: np.ndarray
    v: np.ndarray


class Loads(NamedTuple):
    """The nodal sources q of eq (7) of a step (each (N+1, 12)): the constant ``seed``
    and the contact's at the known (``old``) and the new (``new``) level."""

    seed: np.ndarray
    old: np.ndarray
    new: np.ndarray


@dataclass
class SchemeBudget:
    """The energy lines of a run summed step by step [J] (module docstring)."""

    params: Params
    ds: float
    gamma_u: float = 0.0  # the viscous damping of the scene (:mod:`.damped`)
    gamma_w: float = 0.0
    energy_mid: float = 0.0  # dE of the cell averages
    dissipation: float = 0.0  # D, the scheme's numerical dissipation (>= 0)
    modified: float = 0.0  # dG, the modified energy's change (step changes included)
    ends: float = 0.0  # work at the ends, h [u*.n* + w*.m*]_0^L
    contact: float = 0.0  # work of the contact source as the scheme applies it
    seed: float = 0.0  # work of the seed force as the scheme applies it
    viscous: float = 0.0  # work of the viscous damping (<= 0)
    rest: float = 0.0  # what the pairing leaves: the load vector's part and the solve's
    _ew: np.ndarray = field(init=False, repr=False)
    _z: np.ndarray = field(init=False, repr=False)

    def __post_init__(self):
        self._ew, self._z = energy_weights(self.params), conjugate(self.params)

    def step(self, co: Coefficients, h: float, old: Level, new: Level, loads: Loads) -> None:
        """Add the step of length ``h`` [s] from the :class:`Level` ``old`` to ``new``,
        with the scheme's coefficients ``co`` and the step's :class:`Loads`; a ValueError
        unless the scheme is the box scheme in space (lam_s = -1)."""
        (y_old, v_old), (y_new, v_new) = old, new
        q_seed, q_old, q_new = loads
        if not (co.a_s == 0.5 and co.b_s == 0.5):
            raise ValueError(
                f"the budget's pairing needs lam_s = -1 (a_s = b_s = 1/2), got a_s={co.a_s}"
            )
        ds, b = self.ds, co.b_t
        cy = [_cells(x) for x in (y_old, y_new, v_old, v_new)]
        paired, d_e, diss, d_g = rate_identity(co, h, self._ew, *cy)
        paired, d_e, diss, d_g = (ds * x for x in (paired, d_e, diss, d_g))
        y_star = (1.0 - b) * y_new + b * y_old
        z_cell = _cells(y_star * self._z)

        def flux(y):  # u.n + w.m at a node
            m = np.array([self.params.B1, self.params.B2, self.params.C]) * y[6:9]
            return float(y[0:3] @ y[9:12] + y[3:6] @ m)

        ends = h * (flux(y_star[-1]) - flux(y_star[0]))

        def work(q):  # -h sum z*.<q>* ds (q already the time combination)
            return -h * ds * float(np.sum(z_cell * _cells(q)))

        contact = work((1.0 - b) * q_new + b * q_old)
        seed = work(q_seed)
        cell = _cells(y_star)
        viscous = -h * ds * float(self.gamma_u * np.sum(cell[:, 0:3] ** 2)
                                  + self.gamma_w * np.sum(cell[:, 3:6] ** 2))  # fmt: skip
        self.energy_mid += d_e
        self.dissipation += diss
        self.modified += d_g
        self.ends += ends
        self.contact += contact
        self.seed += seed
        self.viscous += viscous
        self.rest += paired - ends - contact - seed - viscous

    def as_dict(self) -> dict[str, float]:
        keys = ("energy_mid", "dissipation", "modified", "ends", "contact", "seed", "viscous",
                "rest")  # fmt: skip
        return {k: float(getattr(self, k)) for k in keys}


def work_done(lines: Mapping[str, float]) -> float:
    """The work done on the rod as the scheme applies it, at the ends and by the seed: what
    every line of a run's ``energy_scheme`` is read against."""
    return lines["ends"] + lines["seed"]


def share(lines: Mapping[str, float], key: str) -> float:
    """One line of a run's ``energy_scheme`` over the work done (:func:`work_done`); a run's
    ``energy_residual_scheme`` is ``-share(lines, "rest")``; NaN when no work was done (a
    rod held still, e.g. by a vast viscous damping: no share to read)."""
    work = work_done(lines)
    return lines[key] / work if work != 0.0 else math.nan


def nodal_share(energy: Mapping[str, float], key: str) -> float:
    """One line of a run's nodal ``energy`` (powers at the levels) over the work done at
    the ends and by the seed as the nodes count it."""
    return energy[key] / (energy["work_ends"] + energy["work_seed"])
