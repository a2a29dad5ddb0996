"""The delay law (section 6, eqs 33-34): kappa3 = kappa_cri + (b / L) (a L / c)^sigma
fitted to the critical twists of a rate sweep, with kappa_cri fixed at the static value
of eq (32) (the paper's fit) or free (its extrapolation to a = 0).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..model.rod import Rod
from ..published import value
from .statics import critical_twist

__all__ = [
    "PowerLawFit",
    "fit_power_law",
    "eq33",
    "rate_number",
    "paper_law",
    "FIT_SPACES",
    "fit_in_space",
]


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
        return eq33(rate_number(a, rod), self.kappa_cri, self.b / rod.L, self.sigma)

    def time_to_buckle(self, a: float, kappa0: float = 0.0, rod: Rod | None = None) -> float:
        """(kappa3(a) - kappa0) / a: the paper's 'time until buckling' (20.11 s and
        25.45 s for Figs 8 and 9)."""
        return float((self.kappa3(a, rod) - kappa0) / a)


def rate_number(a: float | np.ndarray, rod: Rod) -> np.ndarray:
    """The dimensionless loading rate a L / c of eq (33)."""
    return np.asarray(a) * rod.L / rod.c


def eq33(x: np.ndarray, kappa_cri: float, b_over_L: float, sigma: float) -> np.ndarray:
    """Eq (33) in the rate number x = a L / c: kappa3 = kappa_cri + (b / L) x^sigma."""
    return kappa_cri + b_over_L * x**sigma


def paper_law(a: float | np.ndarray, rod: Rod, kappa_cri: float | None = None) -> np.ndarray:
    """kappa3 of eq (33) with the paper's b and sigma (eq 34, the paper's stated values);
    used to choose how long a run may last."""
    kc = critical_twist(rod) if kappa_cri is None else kappa_cri
    return eq33(rate_number(a, rod), kc, value("b") / rod.L, value("sigma"))


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
            f"a must hold at least {n_par} distinct rates to fit {n_par} parameters "
            f"(eq 33 is a law in the rate); it holds {rates.size}"
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


def _static_or_given(kappa_cri: float | str | None, rod: Rod) -> float | None:
    """``kappa_cri`` of a fit: ``"static"`` (this rod's, eq 32), a number, or None (free)."""
    if isinstance(kappa_cri, str):
        if kappa_cri != "static":
            raise ValueError(f"kappa_cri={kappa_cri!r}; allowed: 'static', a number, None")
        return critical_twist(rod)
    return kappa_cri


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
    kappa_cri = _static_or_given(kappa_cri, rod)
    n_par = 3 if free else 2
    if a.size < n_par + 1:
        raise ValueError(
            f"a and kappa3 must hold at least {n_par + 1} points to fit {n_par} parameters "
            f"(got {a.size})"
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
    x = rate_number(a, rod)

    def solve(xs: np.ndarray, ks: np.ndarray, ws: np.ndarray | None, quiet: bool = False):
        kc0 = float(kappa_cri) if not free else float(ks.min()) - 0.1 * float(np.ptp(ks))
        dk = np.maximum(ks - kc0, 1e-12 * max(1.0, abs(kc0)))
        sig0, logb0 = np.polyfit(np.log(xs), np.log(dk), 1)
        if free:
            f, p0 = eq33, [kc0, math.exp(logb0), sig0]
        else:

            def f(xx, bl, sg):
                return eq33(xx, kappa_cri, bl, sg)

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
            raise ValueError(
                f"a and kappa3 cannot determine eq (33): the fit failed ({err})"
            ) from None
    if not (np.all(np.isfinite(p)) and np.all(np.isfinite(cov))):
        raise ValueError(
            "a and kappa3 cannot determine eq (33): the fitted parameters or their covariance "
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
    resid = k - eq33(x, kc, bl, sg)

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


#: the spaces eq (33) can be fitted in (least squares of the residual in): the twist
#: kappa3 (the paper's Fig 10 plots it), the log of the delay kappa3 - kappa_cri (a
#: straight line on log-log axes), the time to buckle t = (kappa3 - kappa0) / a (Figs 8,
#: 9 report it) and its log
FIT_SPACES: tuple[str, ...] = ("kappa3", "log delay", "t", "log t")


def fit_in_space(
    a: Sequence[float],
    kappa3: Sequence[float],
    rod: Rod | None = None,
    *,
    space: str = "kappa3",
    kappa_cri: float | str | None = "static",
    kappa0: float = 0.0,
) -> tuple[float, float, float]:
    """(kappa_cri, b, sigma) of eq (33) fitted by unweighted least squares in ``space``
    (:data:`FIT_SPACES`): the residual of kappa3, of ln(kappa3 - kappa_cri), of the time
    to buckle t = (kappa3 - kappa0) / a, or of ln t.  ``kappa_cri`` as in
    :func:`fit_power_law` ("static": eq 32; None: fitted too).  In ``"kappa3"`` with
    kappa_cri fixed this is :func:`fit_power_law`'s fit (the paper's eq 34 reading); the
    others are the readings the paper leaves open.  Raises ``ValueError`` if the fit
    does not converge."""
    import scipy.optimize

    if space not in FIT_SPACES:
        raise ValueError(f"space={space!r}; allowed: {', '.join(map(repr, FIT_SPACES))}")
    rod = Rod.paper() if rod is None else rod
    a, k = _numbers("a", a), _numbers("kappa3", kappa3)
    if a.ndim != 1 or a.shape != k.shape or a.size < 4:
        raise ValueError(f"a and kappa3 must be 1-D of one length >= 4 (got {a.shape}, {k.shape})")
    if np.any(a <= 0) or not np.all(np.isfinite(k)):
        raise ValueError("a must be > 0 and kappa3 finite")
    if space in ("t", "log t") and np.any(k <= kappa0):
        raise ValueError(f"kappa3 must exceed kappa0 = {kappa0:g} to fit the time to buckle")
    free = kappa_cri is None
    kappa_cri = _static_or_given(kappa_cri, rod)
    x = rate_number(a, rod)
    # start from the paper's fit (linear in kappa3), in the parameters ln(b / L) and sigma
    start = fit_power_law(a, k, rod, kappa_cri=kappa_cri, n_boot=0)
    p0 = [math.log(start.b / rod.L), start.sigma]
    lo, hi = [-np.inf, 0.0], [np.inf, 3.0]
    if free:
        p0, lo, hi = [start.kappa_cri, *p0], [-np.inf, *lo], [float(k.min()), *hi]
        if space == "log delay":
            p0[0] = min(p0[0], float(k.min()) - 1e-6 * float(np.ptp(k)))
            hi[0] = float(k.min()) - 1e-9 * float(np.ptp(k))

    def parts(p):
        kc, lb, sg = p if free else (kappa_cri, *p)
        return kc, lb, sg

    def residual(p):
        kc, lb, sg = parts(p)
        model = eq33(x, kc, math.exp(lb), sg)
        if space == "kappa3":
            return model - k
        if space == "log delay":
            return (lb + sg * np.log(x)) - np.log(np.maximum(k - kc, 1e-300))
        if space == "t":
            return (model - k) / a
        return np.log(np.maximum(model - kappa0, 1e-300)) - np.log(k - kappa0)

    if not free and space == "log delay" and np.any(k <= kappa_cri):
        raise ValueError(
            f"kappa3 must exceed kappa_cri = {kappa_cri:.6g} to fit ln(kappa3 - kappa_cri)"
        )
    with np.errstate(all="ignore"):
        sol = scipy.optimize.least_squares(residual, p0, bounds=(lo, hi), xtol=1e-14, ftol=1e-14)
    if not sol.success or not np.all(np.isfinite(sol.x)):
        raise ValueError(f"eq (33) in space {space!r} did not converge ({sol.message})")
    kc, lb, sg = parts(sol.x)
    return float(kc), float(math.exp(lb) * rod.L), float(sg)
