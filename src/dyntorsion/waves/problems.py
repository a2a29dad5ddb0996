"""The three initial-boundary-value problems of section 5 (eqs 23, 26, 28) and
:func:`solve`, which runs one on the generalised-alpha engine."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..genalpha import Boundary, Grid, Newton, Output, Run, Scheme, System, integrate
from ..genalpha import Problem as Equations
from ..model.rod import Rod
from .checks import Series, positive_number
from .dalembert import instant_release_dalembert, linear_loading_dalembert, smooth_release_dalembert
from .series import instant_release_exact, linear_loading_exact, smooth_release_exact
from .torsion import Torsion
from .transitions import DEFAULT_TRANSITION, Transition


@dataclass(frozen=True)
class LinearLoading:
    """Eq (23): kappa(0, t) = kappa0 + a t, omega(L, t) = 0; kappa = kappa0, omega = 0 at t = 0."""

    a: float
    kappa0: float = 0.0

    def boundaries(self, system: System) -> tuple[Boundary, Boundary]:
        left = Boundary.fields(system, ["k3"], lambda t: (self.kappa0 + self.a * t)[:, None])
        return left, Boundary.fields(system, ["w3"])

    def exact(self, s, t, *, c, L, series: Series = Series()):
        """Eq (25) at (s, t) (:func:`linear_loading_exact`), summed as ``series`` says."""
        return linear_loading_exact(s, t, a=self.a, kappa0=self.kappa0, c=c, L=L, series=series)

    def dalembert(self, s, t, *, c, L):
        return linear_loading_dalembert(s, t, a=self.a, kappa0=self.kappa0, c=c, L=L)


@dataclass(frozen=True)
class InstantRelease:
    """Eq (26): omega(0, t) = 0 (kappa_s = 0), kappa(L, t) = 0 for t > 0; kappa = kappa0 at t = 0."""

    kappa0: float

    def boundaries(self, system: System) -> tuple[Boundary, Boundary]:
        return Boundary.fields(system, ["w3"]), Boundary.fields(system, ["k3"])

    def exact(self, s, t, *, c, L, series: Series = Series()):
        """Eq (27) at (s, t) (:func:`instant_release_exact`), summed as ``series`` says."""
        return instant_release_exact(s, t, kappa0=self.kappa0, c=c, L=L, series=series)

    def dalembert(self, s, t, *, c, L):
        return instant_release_dalembert(s, t, kappa0=self.kappa0, c=c, L=L)


@dataclass(frozen=True)
class SmoothRelease:
    """Eq (28): omega(0, t) = 0, kappa(L, t) = kappa0 f(rate t); kappa = kappa0 at t = 0."""

    kappa0: float
    rate: float = 50.0
    f: Transition = DEFAULT_TRANSITION

    def boundaries(self, system: System) -> tuple[Boundary, Boundary]:
        right = Boundary.fields(
            system, ["k3"], lambda t: (self.kappa0 * self.f(self.rate * t))[:, None]
        )
        return Boundary.fields(system, ["w3"]), right

    def exact(self, s, t, *, c, L, series: Series = Series()):
        """Eq (29) at (s, t) (:func:`smooth_release_exact`), summed as ``series`` says."""
        return smooth_release_exact(
            s, t, kappa0=self.kappa0, c=c, L=L, rate=self.rate, f=self.f, series=series
        )

    def dalembert(self, s, t, *, c, L):
        return smooth_release_dalembert(
            s, t, kappa0=self.kappa0, c=c, L=L, rate=self.rate, f=self.f
        )


Problem = LinearLoading | InstantRelease | SmoothRelease


@dataclass
class WaveSolution:
    """kappa(s, t) and omega(s, t) of a wave problem on the engine, at the requested times."""

    problem: Any
    rod: Rod
    s: np.ndarray
    t: np.ndarray
    kappa: np.ndarray
    omega: np.ndarray
    run: Run

    def exact(self, kind: str = "dalembert", series: Series = Series()) -> np.ndarray:
        """The exact kappa at the same (s, t): ``"dalembert"`` (closed form) or ``"series"``
        (summed as ``series`` says)."""
        ss, tt = np.meshgrid(self.s, self.t)
        if kind == "dalembert":
            return self.problem.dalembert(ss, tt, c=self.rod.c, L=self.rod.L)
        if kind == "series":
            return self.problem.exact(ss, tt, c=self.rod.c, L=self.rod.L, series=series)
        raise ValueError(f"kind={kind!r}; allowed: 'dalembert', 'series'")

    def errors(self, reference: np.ndarray | None = None) -> dict[str, np.ndarray]:
        """Max, L2 and L1 (trapezoidal in s) norms of kappa - reference, per time."""
        ref = self.exact() if reference is None else np.asarray(reference, dtype=float)
        e = self.kappa - ref
        return {
            "max": np.max(np.abs(e), axis=1),
            "L2": np.sqrt(np.trapezoid(e**2, self.s, axis=1)),
            "L1": np.trapezoid(np.abs(e), self.s, axis=1),
        }


def solve(
    problem: Problem,
    *,
    rod: Rod | None = None,
    n_cells: int,
    dt: float,
    times: Sequence[float] | float,
    lam_t: float = -1.0,
    lam_s: float = -1.0,
    newton: Newton = Newton(),
) -> WaveSolution:
    """Run a wave problem on the generalised-alpha engine with the 2-field model (eq 22).

    ``times`` must be multiples of ``dt``; the run ends at the last of them.  ``lam_t``
    and ``lam_s`` are the spectral radii at infinity of eq (13).  The model has no load
    vector, so the load quadrature of eq (9) has nothing to act on: the run uses the
    paper's trapezoidal rule.
    """
    rod = Rod.paper() if rod is None else rod
    times_arr = np.atleast_1d(np.asarray(times, dtype=float))
    if times_arr.size == 0 or np.any(times_arr <= 0) or not np.all(np.isfinite(times_arr)):
        raise ValueError(f"times={times!r} must be finite and > 0")
    dt = positive_number("dt", dt)
    steps = times_arr / dt
    if np.any(np.abs(steps - np.round(steps)) > 1e-9 * np.maximum(1.0, steps)):
        raise ValueError(f"times={times!r} must be multiples of dt={dt}")
    model = Torsion(rod)
    system = model.system()
    left, right = problem.boundaries(system)
    if not isinstance(n_cells, int | np.integer) or n_cells < 2:
        raise ValueError(f"n_cells={n_cells!r} must be an integer >= 2")
    y0 = np.zeros((n_cells + 1, 2))
    y0[:, 0] = problem.kappa0
    scheme = Scheme(lam_s=lam_s, lam_t=lam_t)
    run = integrate(
        Equations(system, y0, left, right, y_t0="zero"),
        Grid(int(n_cells), rod.L, dt, float(times_arr.max())),
        scheme=scheme,
        newton=newton,
        output=Output(
            snapshots=list(times_arr), meta={"problem": repr(problem), "rod": rod.as_dict()}
        ),
    )
    snaps = np.array([run.snapshot(ti) for ti in times_arr])
    return WaveSolution(
        problem=problem,
        rod=rod,
        s=run.s,
        t=times_arr,
        kappa=snaps[:, :, 0],
        omega=snaps[:, :, 1],
        run=run,
    )
