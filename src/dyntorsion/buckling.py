"""Torsional buckling (section 6): the dynamic buckling scene (boundary conditions of
eq 30, or any end set, twist history and axial load of :mod:`dyntorsion.loading`), the
onset of buckling and the delay law (eqs 33-34).  The static critical twist (eqs 31-32)
lives in :mod:`dyntorsion.statics` and is re-exported here.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from . import shapes
from .genalpha import ConvergenceError, Newton, Run, Scheme, integrate
from .genalpha.guard import check_time_grid, real
from .loading import AxialLoad, Ends, History, Ramp
from .loading import ends as _ends
from .model import Cosserat
from .postbuckling import diagnose
from .rod import Rod
from .statics import (
    M_CRI_MP,
    critical_moment,
    critical_twist,
    critical_twist_numerical,
    m_cri,
)

__all__ = [
    "M_CRI_MP",
    "m_cri",
    "critical_moment",
    "critical_twist",
    "critical_twist_numerical",
    "Perturbation",
    "BucklingRun",
    "simulate",
    "GridWarning",
    "check_grid",
    "Onset",
    "detect_onset",
    "check_window",
    "classify_onset",
    "STATUSES",
    "PowerLawFit",
    "fit_power_law",
]


# ================================================================= the buckling scene
@dataclass(frozen=True)
class Perturbation:
    """The small force that seeds buckling (section 6: "1e-8 N in the d1 direction").

    The paper does not say where it acts.  ``form="uniform"`` (default) applies
    ``magnitude`` N/m along the whole rod; ``form="point"`` applies ``magnitude`` N at
    the node nearest to ``location`` (as magnitude/ds N/m on that node's row).
    ``direction`` is a body-frame unit vector (default d1).  The force acts for all t.
    """

    magnitude: float = 1e-8
    form: str = "uniform"
    location: float = 0.5
    direction: tuple[float, float, float] = (1.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        if not (real("perturbation magnitude", self.magnitude) >= 0):
            raise ValueError(f"perturbation magnitude={self.magnitude!r} must be finite and >= 0")
        if self.form not in ("uniform", "point"):
            raise ValueError(f"perturbation form={self.form!r}; allowed: 'uniform', 'point'")
        d = np.asarray(self.direction, dtype=float)
        if d.shape != (3,) or not np.isclose(np.linalg.norm(d), 1.0):
            raise ValueError(f"perturbation direction={self.direction!r} must be a unit 3-vector")

    def force(self, s: np.ndarray, length: float) -> np.ndarray:
        """Body force per length (N+1, 3) at the nodes s."""
        f = np.zeros((s.size, 3))
        if self.form == "uniform":
            f[:] = self.magnitude * np.asarray(self.direction)
        else:
            if not 0 <= self.location <= length:
                raise ValueError(
                    f"perturbation location={self.location!r} must lie in [0, L] = [0, {length}]"
                )
            j = int(np.argmin(np.abs(s - self.location)))
            ds = s[1] - s[0]
            weight = ds if 0 < j < s.size - 1 else 0.5 * ds
            f[j] = self.magnitude / weight * np.asarray(self.direction)
        return f


@dataclass
class BucklingRun:
    """The buckling scene's outcome: traces every step, snapshots, and the run."""

    t: np.ndarray
    u3_end: np.ndarray
    kappa3_left: np.ndarray
    kappa3_right: np.ndarray
    omega3_left: np.ndarray
    omega3_right: np.ndarray
    theta_left: np.ndarray
    run: Run
    rod: Rod
    params: dict[str, Any] = field(default_factory=dict)
    history: History | None = None
    load: AxialLoad | None = None
    ends: Ends | None = None

    def end_twist(self, t: float | np.ndarray) -> float | np.ndarray:
        """kappa3(0, t) imposed by the run's history (interpolated from the recorded
        kappa3(0, t) when the run carries no history)."""
        if self.history is not None:
            out = self.history(t)
            return float(out) if np.ndim(out) == 0 else out
        return np.interp(t, self.t, self.kappa3_left)

    @property
    def stopped(self) -> str:
        return self.run.stopped

    def shape(self, t: float) -> tuple[float, np.ndarray]:
        """(time, centreline (N+1, 3)) of the snapshot nearest to t (spatial route, the
        left end turned by the integrated end spin)."""
        i = int(np.argmin(np.abs(self.run.snapshot_times - t)))
        ts = float(self.run.snapshot_times[i])
        theta = float(np.interp(ts, self.t, self.theta_left))
        ds = self.run.s[1] - self.run.s[0]
        return ts, shapes.shape(self.run.snapshots[i], ds, theta)


class GridWarning(UserWarning):
    """A time step far outside the range the buckling scene was tested on."""


#: the buckling grids the accuracy ladder tested (Fig 8 and the fast scene): time step
#: over the bending time T0, and Courant number c dt / ds of the torsional waves
TESTED_DT_OVER_T0 = (0.00125 / 43.8178046004133, 0.02 / 43.8178046004133)
TESTED_COURANT = (1.8, 462.0)


def check_grid(rod: Rod, n_cells: int, dt: float) -> None:
    """Warn (:class:`GridWarning`) when dt exceeds ten times the largest tested step, in
    units of the rod's own bending time T0 or of its torsional transit per cell."""
    ratio, courant = dt / rod.T0, rod.c * dt * n_cells / rod.L
    if ratio > 10 * TESTED_DT_OVER_T0[1] or courant > 10 * TESTED_COURANT[1]:
        warnings.warn(
            f"dt={dt:.3g} s is {ratio:.3g} T0 (bending time {rod.T0:.3g} s) at Courant number "
            f"{courant:.3g}: the buckling scene was tested up to {TESTED_DT_OVER_T0[1]:.3g} T0 "
            f"and Courant {TESTED_COURANT[1]:g}; use dyntorsion.fidelity.get('buckling', level, rod)",
            GridWarning,
            stacklevel=3,
        )


def _history(a: float | None, kappa0: float, history: History | None) -> History:
    if history is None:
        if a is None:
            raise ValueError("a=None: give the loading rate a (the paper's ramp) or a history")
        return Ramp(a=real("a", a, " [1/(m s)]"), kappa0=real("kappa0", kappa0, " [1/m]"))
    if not isinstance(history, History):
        raise TypeError(f"history={history!r} must be a dyntorsion.loading.History")
    if a is not None or kappa0 != 0.0:
        raise ValueError("give either a (and kappa0) or a history, not both")
    return history


def _load(tension: float | AxialLoad) -> AxialLoad:
    return tension if isinstance(tension, AxialLoad) else AxialLoad(T=tension)


def simulate(
    rod: Rod | None = None,
    *,
    a: float | None = None,
    kappa0: float = 0.0,
    n_cells: int,
    dt: float,
    t_end: float,
    history: History | None = None,
    tension: float | AxialLoad = 0.0,
    ends: str | Ends = "clamped",
    perturbation: float | Perturbation = 1e-8,
    scheme: Scheme = Scheme(),
    newton: Newton = Newton(),
    snapshots: Sequence[float] = (),
    stop_at_contact: bool = True,
    check_every: int | None = None,
    progress: bool | None = None,
    on_failure: str = "raise",
    terms: Mapping[str, float] | None = None,
    rotary_inertia_scale: float = 1.0,
) -> BucklingRun:
    """Run the buckling scene of section 6, or any extension of it.

    Table 1 rod (or ``rod``, any section), end conditions ``ends`` (default
    ``"clamped"``: eq 30; see :data:`dyntorsion.loading.ENDS`), end twist
    kappa3(0, t) = kappa0 + a t (the paper) or ``history`` (a
    :class:`~dyntorsion.loading.History`), axial end load ``tension`` [N] (a number or
    an :class:`~dyntorsion.loading.AxialLoad`; positive = tension), initial state y = 0
    except k3 = kappa3(0, 0) and n3 = T(0) (a straight rod pretwisted without stress in
    bending, in equilibrium under the axial load), and a constant seed force
    ``perturbation`` (N/m along the rod in d1, or a :class:`Perturbation`).  With no
    seed (magnitude 0) the straight rod is an exact solution of the discrete equations
    and the run stays straight to round-off.

    The run ends at ``t_end`` or, with ``stop_at_contact``, at the first check
    (every ``check_every`` steps, default about every 0.1 s of simulated time, or every
    step with step-size control: between checks 0.1 s apart the whipping rod can pass
    through itself unseen; checked every step, a pair of segments that crossed between two
    levels counts as contact too)
    at which two non-neighbouring parts of the centreline come closer than the
    rod's thickness; ``result.stopped`` says which ("t_end" or "self-contact ...").

    Past the onset the rod whips round violently; a Newton failure there raises
    :class:`~dyntorsion.postbuckling.PostBucklingError`, one in the first steps
    :class:`~dyntorsion.postbuckling.GridTooCoarseError` (both are
    :class:`~dyntorsion.genalpha.ConvergenceError`; ``on_failure="raise"``), or, with
    ``on_failure="return"``, ends the run at the last completed step with
    ``stopped = "failed: ..."`` (the traces up to it are what the onset needs).

    ``terms`` and ``rotary_inertia_scale`` are passed to
    :class:`~dyntorsion.model.Cosserat`: switch single mechanisms off (e.g.
    ``{"gyro": 0.0}``) or scale the bending rotary inertia.  A time step far outside
    the tested range for this rod warns (:class:`GridWarning`).
    """
    if on_failure not in ("raise", "return"):
        raise ValueError(f"on_failure={on_failure!r}; allowed: 'raise', 'return'")
    rod = Rod.paper() if rod is None else rod
    if not isinstance(rod, Rod):
        raise TypeError(f"rod={rod!r} must be a dyntorsion.Rod")
    check_time_grid(dt, t_end, 0.0, snapshots, check_every)
    hist = _history(a, kappa0, history)
    load = _load(tension)
    end_set = _ends(ends)
    if not isinstance(perturbation, Perturbation):
        perturbation = Perturbation(magnitude=real("perturbation", perturbation, " [N/m]"))
    model = Cosserat(rod, terms=dict(terms or {}), rotary_inertia_scale=rotary_inertia_scale)
    system = model.system()
    if not isinstance(n_cells, int | np.integer) or n_cells < 2:
        raise ValueError(f"n_cells={n_cells!r} must be an integer >= 2")
    n_cells = int(n_cells)
    check_grid(rod, n_cells, dt)
    s = np.linspace(0.0, rod.L, n_cells + 1)
    ds = rod.L / n_cells
    y0 = np.zeros((n_cells + 1, 12))
    y0[:, system.index("k3")] = hist(np.zeros(1))[0]
    y0[:, system.index("n3")] = load(np.zeros(1))[0]
    left, right = end_set.rows(system, hist, load)
    q = model.external_force(perturbation.force(s, rod.L))

    i_k1, i_k2 = system.index("k1"), system.index("k2")
    if check_every is None:
        check_every = 1 if scheme.control is not None else max(1, int(round(0.1 / dt)))
    previous: list[np.ndarray] = []  # the last centreline checked (every level: crossings)

    def contact(t, y):
        # a centreline whose tangent turns by less than pi/3 in all keeps points an arc
        # length l apart at least l cos(pi/6) > l/2 apart: no contact (min_arc = 2 d)
        if np.sum(np.hypot(y[:, i_k1], y[:, i_k2])) * ds < np.pi / 3:
            previous.clear()
            return None
        r = shapes.shape(y, ds)
        hit = shapes.self_contact(r, rod.thickness)
        if hit is not None:
            d, i, j = hit
            return f"self-contact at t = {t:.6g} s (segments {i} and {j}, distance {d:.3g} m)"
        crossed = shapes.crossing(previous[0], r, rod.thickness) if previous else None
        previous[:] = [r] if check_every == 1 else []
        if crossed is not None:
            i, j = crossed
            return (
                f"self-contact at t = {t:.6g} s (segments {i} and {j} passed through each "
                "other since the previous level)"
            )
        return None

    try:
        run = integrate(
            system,
            n_cells=n_cells,
            length=rod.L,
            dt=dt,
            t_end=t_end,
            y0=y0,
            left=left,
            right=right,
            scheme=scheme,
            source=(q, None),
            record={
                "u3_end": ("u3", -1),
                "k3_left": ("k3", 0),
                "k3_right": ("k3", -1),
                "w3_left": ("w3", 0),
                "w3_right": ("w3", -1),
            },
            snapshots=snapshots,
            newton=newton,
            stop=contact if stop_at_contact else None,
            check_every=check_every,
            progress=progress,
        )
    except ConvergenceError as raw:
        u3 = raw.run["u3_end"] if raw.run is not None else np.zeros(0)
        t_run = raw.run.t if raw.run is not None else np.zeros(0)
        err = diagnose(raw, rod, n_cells, dt, u3, t_run)
        if on_failure == "raise" or err.run is None:
            raise err from None
        run = err.run
        run.stopped = f"failed: {err}"
    t = run.t
    w0 = run["w3_left"]
    theta = np.concatenate([[0.0], np.cumsum(0.5 * np.diff(t) * (w0[1:] + w0[:-1]))])
    params = {
        "rod": rod.as_dict(),
        "a": hist.rate,
        "kappa0": hist.kappa0,
        "history": hist.params(),
        "load": load.params(),
        "ends": end_set.params(),
        "n_cells": n_cells,
        "dt": dt,
        "t_end": t_end,
        "perturbation": asdict(perturbation),
        "scheme": run.meta["scheme"],
        "check_every": check_every,
        "terms": dict(terms or {}),
        "rotary_inertia_scale": rotary_inertia_scale,
    }
    return BucklingRun(
        t=t,
        u3_end=run["u3_end"],
        kappa3_left=run["k3_left"],
        kappa3_right=run["k3_right"],
        omega3_left=w0,
        omega3_right=run["w3_right"],
        theta_left=theta,
        run=run,
        rod=rod,
        params=params,
        history=hist,
        load=load,
        ends=end_set,
    )


# ================================================================= onset of buckling
@dataclass(frozen=True)
class Onset:
    """Critical time and twist from the linear fit of u3(L, t) (section 6)."""

    t_c: float
    kappa3: float
    uncertainty_t: float
    uncertainty_kappa3: float
    slope: float
    intercept: float
    window: tuple[float, float]
    variations: dict[tuple[float, float], float]
    t_ref: float = math.nan
    u_ref: float = math.nan


def check_window(window, variations=()) -> None:
    """Refuse an onset window (or a variation) that is not two finite fractions
    0 < lo < hi < 1 of the first peak of ``|u3(L, t)|``."""
    for name, w in (("window", window), *(("variations", v) for v in variations)):
        try:
            lo, hi = (float(v) for v in w)
        except (TypeError, ValueError):
            raise ValueError(f"{name}={w!r} must be a pair (lo, hi) with 0 < lo < hi < 1") from None
        if not 0 < lo < hi < 1:
            raise ValueError(f"{name}={tuple(w)!r} must satisfy 0 < lo < hi < 1")


#: what an onset record says happened (:func:`classify_onset`)
STATUSES = ("buckled", "forced", "no-onset", "failed")


def classify_onset(run: BucklingRun, onset: Onset | None, kappa_cri: float | None) -> str:
    """What the run shows: ``"buckled"`` (an onset after the end twist has passed the
    static critical twist ``kappa_cri``), ``"forced"`` (an onset before t = 0 or before
    ``|kappa3(0, t)|`` reaches kappa_cri: the seed bent the rod, not the instability),
    ``"no-onset"`` (the run ended, at t_end or self-contact, without one) or ``"failed"``
    (a Newton failure ended it without one).  With ``kappa_cri=None`` (no static theory
    for the scene) an onset at t_c >= 0 counts as buckled."""
    if onset is None:
        return "failed" if run.stopped.startswith("failed") else "no-onset"
    if onset.t_c < run.t[0]:
        return "forced"
    if kappa_cri is None:
        return "buckled"
    upto = np.abs(run.kappa3_left[run.t <= onset.t_c])
    passed = max(float(upto.max(initial=0.0)), abs(float(run.end_twist(onset.t_c))))
    return "buckled" if passed >= kappa_cri else "forced"


def detect_onset(
    run: BucklingRun,
    window: tuple[float, float] = (0.1, 0.5),
    variations: Sequence[tuple[float, float]] = ((0.05, 0.3), (0.2, 0.7)),
    u_ref: float | None = None,
) -> Onset:
    """Fit a straight line to the initial dramatic variation of u3(L, t), extrapolate
    to u3 = 0: t_c and the end twist kappa3 = kappa3(0, t_c) of the run's history
    (kappa0 + a t_c for the paper's ramp).

    Window rule (deterministic): ``U = |u3(L, t)|``.  The rise starts when U first
    exceeds ``u_ref`` (default L / T0, T0 = L^2 sqrt(rho A / B1) the bending time
    scale: 0.023 m/s for Table 1, far above the prebuckling level and far below
    the first peak); its peak U_peak is the running maximum of U at the first
    later sample where U has fallen below 0.7 of that running maximum (so the
    small torsional-wave ripples on the rise do not count as a peak).  The fit
    uses the samples from the first time U exceeds ``window[0] * U_peak`` to the
    first time it exceeds ``window[1] * U_peak``.  The same fit with each of
    ``variations`` gives the method's uncertainty: the largest ``|t_c - t_c(variation)|``.

    ``t_ref`` is the time at which U first reaches ``u_ref`` (linear interpolation
    between samples): the level a linear theory can be compared with (see
    :mod:`dyntorsion.linear_stability`), where ``t_c`` is an extrapolation from the
    nonlinear rise.
    """
    check_window(window, variations)
    t, u = np.asarray(run.t), np.asarray(run.u3_end)
    U = np.abs(u)
    if not np.any(U > 0):
        raise ValueError("u3(L, t) is identically zero: the rod never left the straight state")
    if u_ref is None:
        u_ref = run.rod.L / run.rod.T0
    above = np.nonzero(U >= u_ref)[0]
    if above.size == 0:
        if run.stopped.startswith("failed"):
            advice = (
                f"the run ended on a Newton failure at t = {run.t[-1]:.6g} s before buckling "
                "(refine dt or change the Newton options; a longer t_end does not help)"
            )
        elif run.stopped != "t_end":
            advice = f"the run stopped before buckling ({run.stopped})"
        else:
            advice = "the run ends before buckling; increase t_end"
        raise ValueError(f"|u3(L, t)| never reaches u_ref = {u_ref:.3g} m/s: {advice}")
    i_start = int(above[0])
    if i_start == 0:
        t_ref = float(t[0])
    else:
        u0, u1 = U[i_start - 1], U[i_start]
        t_ref = float(t[i_start - 1] + (u_ref - u0) / (u1 - u0) * (t[i_start] - t[i_start - 1]))
    running = np.maximum.accumulate(U[i_start:])
    drop = np.nonzero(U[i_start:] < 0.7 * running)[0]
    end = i_start + (int(drop[0]) if drop.size else U.size - i_start)
    i_peak = i_start + int(np.argmax(U[i_start:end]))
    U_peak, sign = U[i_peak], np.sign(u[i_peak])

    def fit(lo: float, hi: float):
        if not 0 < lo < hi < 1:
            raise ValueError(f"window=({lo}, {hi}) must satisfy 0 < lo < hi < 1")
        head = U[: i_peak + 1]
        i0 = int(np.argmax(head >= lo * U_peak))
        i1 = int(np.argmax(head >= hi * U_peak))
        if i1 - i0 < 2:
            raise ValueError(
                f"window=({lo}, {hi}) holds fewer than 3 samples: refine dt or widen the window"
            )
        slope, intercept = np.polyfit(t[i0 : i1 + 1], sign * U[i0 : i1 + 1], 1)
        return -intercept / slope, slope * sign, intercept * sign

    t_c, slope, intercept = fit(*window)
    var = {tuple(v): fit(*v)[0] for v in variations}
    unc = max((abs(v - t_c) for v in var.values()), default=0.0)
    a = run.params.get("a")
    if a is not None and run.history is None:
        kappa3 = run.params["kappa0"] + a * t_c
    else:
        kappa3 = run.end_twist(t_c)
    if a is not None:
        unc_k = abs(a) * unc
    else:
        unc_k = max((abs(run.end_twist(v) - kappa3) for v in var.values()), default=0.0)
    return Onset(
        t_c=float(t_c),
        kappa3=float(kappa3),
        uncertainty_t=float(unc),
        uncertainty_kappa3=float(unc_k),
        slope=float(slope),
        intercept=float(intercept),
        window=tuple(window),
        variations={k: float(v) for k, v in var.items()},
        t_ref=t_ref,
        u_ref=float(u_ref),
    )


# ================================================================= the delay law
@dataclass(frozen=True)
class PowerLawFit:
    """Least-squares fit of eq (33): kappa3 = kappa_cri + (b / L) (a L / c)^sigma.

    ``*_err`` are standard errors from the fit covariance (0 for a fixed
    kappa_cri); ``bootstrap`` holds (low, high) percentile intervals at
    ``confidence`` from refits of ``n_boot`` resamples (pairs drawn with
    replacement; ``n_boot_failed`` refits that did not converge are dropped).
    """

    b: float
    sigma: float
    kappa_cri: float
    b_err: float
    sigma_err: float
    kappa_cri_err: float
    kappa_cri_free: bool
    covariance: np.ndarray
    bootstrap: dict[str, tuple[float, float]]
    confidence: float
    n_boot: int
    n_boot_failed: int
    residual_rms: float
    n_points: int
    rod: Rod

    def kappa3(self, a: float | np.ndarray, rod: Rod | None = None) -> float | np.ndarray:
        """The fitted critical twist at loading rate ``a`` (L and c of ``rod``, default
        the fitted rod's: eq 33 carries the density only through c)."""
        rod = self.rod if rod is None else rod
        return self.kappa_cri + self.b / rod.L * (np.asarray(a) * rod.L / rod.c) ** self.sigma

    def time_to_buckle(self, a: float, kappa0: float = 0.0, rod: Rod | None = None) -> float:
        """(kappa3(a) - kappa0) / a: the paper's 'time until buckling' (20.11 s and
        25.45 s for Figs 8 and 9)."""
        return float((self.kappa3(a, rod) - kappa0) / a)


def _power_law(x: np.ndarray, kc: float, b_over_L: float, sigma: float) -> np.ndarray:
    return kc + b_over_L * x**sigma


def _numbers(name: str, values) -> np.ndarray:
    try:
        return np.asarray(values, dtype=float)
    except (TypeError, ValueError) as err:
        raise ValueError(f"{name} must be numbers ({err})") from None


def _determined(a: np.ndarray, k: np.ndarray, kappa_cri: float | None, n_par: int) -> None:
    """Refuse data that cannot determine eq (33), naming the reason."""
    rates = np.unique(a)
    if rates.size < n_par:
        raise ValueError(
            f"a holds {rates.size} distinct rate(s); fitting {n_par} parameters needs at least "
            f"{n_par} (eq 33 is a law in the rate)"
        )
    if kappa_cri is None:
        if np.ptp(k) == 0:
            raise ValueError("kappa3 is the same at every rate: sigma and b are undetermined")
        return
    if not (
        isinstance(kappa_cri, int | float | np.integer | np.floating) and math.isfinite(kappa_cri)
    ):
        raise ValueError(f"kappa_cri={kappa_cri!r} must be a finite number, 'static' or None")
    below = k <= kappa_cri
    if np.any(below):
        raise ValueError(
            f"{int(below.sum())} of {k.size} kappa3 value(s) lie at or below kappa_cri = "
            f"{kappa_cri:.6g} (min {k.min():.6g}): eq (33) needs kappa3 > kappa_cri; fit only "
            'onsets with status "buckled" (a forced onset precedes the critical twist)'
        )


def fit_power_law(
    a: Sequence[float],
    kappa3: Sequence[float],
    rod: Rod | None = None,
    *,
    kappa_cri: float | str | None = "static",
    uncertainty: Sequence[float] | None = None,
    n_boot: int = 2000,
    confidence: float = 0.95,
    seed: int = 0,
) -> PowerLawFit:
    """Fit eq (33) to critical twists ``kappa3`` measured at loading rates ``a``.

    ``kappa_cri="static"`` fixes kappa_cri at eq (32) for ``rod`` (the paper's
    fit); a number fixes it there; ``None`` fits it too (the extrapolation to
    a = 0 that the paper checks against eq 32).  Unweighted least squares in
    kappa3, as the paper; ``uncertainty`` (one standard deviation per point)
    weights the points instead.  ``seed`` fixes the bootstrap's resampling.
    """
    import scipy.optimize

    rod = Rod.paper() if rod is None else rod
    a, k = _numbers("a", a), _numbers("kappa3", kappa3)
    if a.ndim != 1 or a.shape != k.shape:
        raise ValueError(f"a and kappa3 must be 1-D of one length (got {a.shape}, {k.shape})")
    if not (np.all(np.isfinite(a)) and np.all(np.isfinite(k))):
        raise ValueError("a and kappa3 must be finite (drop scenes without an onset)")
    if np.any(a <= 0):
        raise ValueError(f"a must be > 0 (got min {a.min()!r})")
    free = kappa_cri is None
    if isinstance(kappa_cri, str):
        if kappa_cri != "static":
            raise ValueError(f"kappa_cri={kappa_cri!r}; allowed: 'static', a number, None")
        kappa_cri = critical_twist(rod)
    n_par = 3 if free else 2
    if a.size < n_par + 1:
        raise ValueError(
            f"need at least {n_par + 1} points to fit {n_par} parameters (got {a.size})"
        )
    _determined(a, k, kappa_cri, n_par)
    if not 0 < confidence < 1:
        raise ValueError(f"confidence={confidence!r} must lie in (0, 1)")
    if not isinstance(n_boot, int) or n_boot < 0:
        raise ValueError(f"n_boot={n_boot!r} must be an integer >= 0")
    w = None
    if uncertainty is not None:
        w = np.asarray(uncertainty, dtype=float)
        if w.shape != a.shape or not np.all(w > 0):
            raise ValueError("uncertainty must be one positive number per point")
    x = a * rod.L / rod.c

    def solve(xs: np.ndarray, ks: np.ndarray, ws: np.ndarray | None, quiet: bool = False):
        kc0 = float(kappa_cri) if not free else float(ks.min()) - 0.1 * float(np.ptp(ks))
        dk = np.maximum(ks - kc0, 1e-12 * max(1.0, abs(kc0)))
        sig0, logb0 = np.polyfit(np.log(xs), np.log(dk), 1)
        if free:
            f, p0 = _power_law, [kc0, math.exp(logb0), sig0]
        else:

            def f(xx, bl, sg):
                return _power_law(xx, kappa_cri, bl, sg)

            p0 = [math.exp(logb0), sig0]
        with np.errstate(all="ignore"), warnings.catch_warnings():
            if quiet:
                warnings.simplefilter("ignore", scipy.optimize.OptimizeWarning)
            p, cov = scipy.optimize.curve_fit(
                f, xs, ks, p0=p0, sigma=ws, absolute_sigma=ws is not None, maxfev=20000
            )
        return (p if free else np.r_[kappa_cri, p]), cov, f

    with warnings.catch_warnings():
        warnings.simplefilter("error", scipy.optimize.OptimizeWarning)
        try:
            p, cov, f = solve(x, k, w)
        except (RuntimeError, scipy.optimize.OptimizeWarning) as err:
            raise ValueError(f"the data cannot determine eq (33): the fit failed ({err})") from None
    if not (np.all(np.isfinite(p)) and np.all(np.isfinite(cov))):
        raise ValueError(
            "the data cannot determine eq (33): the fitted parameters or their covariance "
            "are not finite (add rates, or fix kappa_cri)"
        )
    kc, bl, sg = (float(v) for v in p)
    err = (
        np.sqrt(np.clip(np.diag(cov), 0, None))
        if np.all(np.isfinite(cov))
        else np.full(n_par, np.nan)
    )
    if not free:
        err = np.r_[0.0, err]
    resid = k - _power_law(x, kc, bl, sg)

    rng = np.random.default_rng(seed)
    samples, failed = [], 0
    for _ in range(n_boot):
        idx = rng.integers(0, a.size, a.size)
        if np.unique(x[idx]).size < n_par:
            failed += 1
            continue
        try:
            pb, _, _ = solve(x[idx], k[idx], None if w is None else w[idx], quiet=True)
        except (RuntimeError, ValueError, np.linalg.LinAlgError):
            failed += 1
            continue
        samples.append(pb)
    lo, hi = 50 * (1 - confidence), 50 * (1 + confidence)
    boot: dict[str, tuple[float, float]] = {}
    if samples:
        S = np.array(samples)
        S[:, 1] *= rod.L
        names = ("kappa_cri", "b", "sigma") if free else ("b", "sigma")
        cols = (0, 1, 2) if free else (1, 2)
        for name, c in zip(names, cols, strict=True):
            boot[name] = (float(np.percentile(S[:, c], lo)), float(np.percentile(S[:, c], hi)))
    return PowerLawFit(
        b=bl * rod.L,
        sigma=sg,
        kappa_cri=kc,
        b_err=float(err[1]) * rod.L,
        sigma_err=float(err[2]),
        kappa_cri_err=float(err[0]),
        kappa_cri_free=free,
        covariance=cov,
        bootstrap=boot,
        confidence=confidence,
        n_boot=n_boot,
        n_boot_failed=failed,
        residual_rms=float(np.sqrt(np.mean(resid**2))),
        n_points=int(a.size),
        rod=rod,
    )
