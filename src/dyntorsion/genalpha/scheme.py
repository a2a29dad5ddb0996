"""The parameters of the generalised-alpha scheme (eq 13) and the constants of one step."""

from __future__ import annotations

import math
import warnings
from dataclasses import asdict, dataclass
from typing import NamedTuple

__all__ = [
    "parameters",
    "QUADRATURES",
    "SchemeWarning",
    "StepControl",
    "LongSteps",
    "Scheme",
    "Coefficients",
]


def parameters(lam: float) -> tuple[float, float, float]:
    """alpha, beta, gamma of eq (13) for a spectral radius at infinity lambda in [-1, 0].

    lambda = -1: alpha = beta = gamma = 1/2 (no numerical damping, the paper's choice);
    lambda = 0: the high-frequency limit is annihilated (alpha = -1/2, beta = 0, gamma = 1).
    """
    lam = float(lam)
    if not (math.isfinite(lam) and -1.0 <= lam <= 0.0):
        raise ValueError(f"lambda_inf={lam!r} is outside the allowed range [-1, 0]")
    alpha = (3.0 * lam + 1.0) / (2.0 * lam - 2.0)
    beta = lam / (lam - 1.0)
    gamma = 1.0 / (1.0 - lam)
    return alpha, beta, gamma


QUADRATURES = ("trapezoidal", "midpoint")


class SchemeWarning(UserWarning):
    """A scheme setting that is allowed but known to be unsound (see the docs)."""


class Coefficients(NamedTuple):
    """The scalars of one step of eq (10)-(12) on a grid (ds, dt), for the kernels.

    abar = c_M (y^i - y^{i-1}) + c_A y_t^{i-1} is the time-averaged rate (eq 11 in eq 10).
    """

    c_M: float  # (1 - a_t) / (g_t dt)
    c_A: float  # a_t - (1 - a_t)(1 - g_t) / g_t
    a_s: float
    b_s: float
    b_t: float
    g_t: float
    inv_ds: float
    dt: float
    trapezoidal: bool


@dataclass(frozen=True)
class StepControl:
    """Step-size control: reject a step whose Newton solve fails and retry it with half
    the step, down to dt_min = dt / 2**max_halvings; grow back (double) after
    ``grow_after`` accepted steps, up to the run's dt (dt_max = dt).

    Steps are dt / 2**m, so every level of the fixed grid t_0 + i dt is landed on
    exactly: the traces, snapshots and stop checks stay on the fixed grid (nothing is
    interpolated).  ``refine`` holds windows (t_start, t_end, m): inside them no step
    is longer than dt / 2**m.  Changing the step costs nothing at lambda_t = -1 (the
    rate history has coefficient c_A = 0 in eq 11-12); for lambda_t > -1 the carried
    rate y_t^{i-1} is a time derivative, valid for any next step, and only c_M = (1 -
    alpha) / (gamma dt) changes with the step.  Variable steps keep the fixed-step order
    (tests/buckling/test_control.py), with one exception at lambda_t = -1: the fields without a
    time derivative that act as multipliers of the constraints (the internal forces n)
    pick up a (-1)^i error at each change of step that the undamped scheme never
    damps, so they do not converge under refinement; the other fields do.
    """

    max_halvings: int = 10
    grow_after: int = 4
    refine: tuple[tuple[float, float, int], ...] = ()

    def __post_init__(self) -> None:
        if not (isinstance(self.max_halvings, int) and 1 <= self.max_halvings <= 30):
            raise ValueError(f"max_halvings={self.max_halvings!r} must be an integer in [1, 30]")
        if not (isinstance(self.grow_after, int) and self.grow_after >= 1):
            raise ValueError(f"grow_after={self.grow_after!r} must be an integer >= 1")
        windows = []
        for w in self.refine:
            try:
                t_a, t_b, m = w
            except (TypeError, ValueError):
                raise ValueError(f"refine: {w!r} must be (t_start, t_end, halvings)") from None
            if not (math.isfinite(t_a) and math.isfinite(t_b) and t_a < t_b):
                raise ValueError(f"refine: window {w!r} needs finite t_start < t_end")
            if not (isinstance(m, int) and 0 <= m <= self.max_halvings):
                raise ValueError(
                    f"refine: halvings={m!r} must be an integer in [0, max_halvings] = "
                    f"[0, {self.max_halvings}]"
                )
            windows.append((float(t_a), float(t_b), int(m)))
        object.__setattr__(self, "refine", tuple(windows))

    def min_halvings(self, t_a: float, t_b: float) -> int:
        """The fewest halvings of dt allowed on the interval (t_a, t_b) by ``refine``."""
        return max((m for lo, hi, m in self.refine if t_a < hi and t_b > lo), default=0)


@dataclass(frozen=True)
class LongSteps:
    """Steps of ``factor * dt`` while the solution is quiet: from t_0 on the levels
    t_0 + i factor dt, until the first such level at which

    * the gauge G = ``ds * sum_j norm(y_j[fields])`` reaches ``limit`` (for the rod:
      the total bending turn in rad, so ``limit = 0.3`` means "straight to 17
      degrees"), or
    * the estimated local error of the long step h in G, ``|h^3 G_ttt| / 12`` from the
      third difference of G at the last four levels (the level t_0, where the load
      starts with a kink, is not used), exceeds ``tol`` times the largest G so far (a
      relative error (s h)^3 / 12 for a growth e^{st}), or
    * a long step's Newton solve fails (the level before it is kept), or a level that
      must be landed on (a snapshot, t_end) is not a whole number of long steps away,

    and at dt from there on (:mod:`.long`).  The long steps record only their own
    levels; a stop check falls on the first long level at or after it.  The step
    that first exceeds ``tol`` is kept.  Changing the step once is free at
    lambda_t = -1 (c_A = 0 in eq 11-12) and keeps the order otherwise (see
    :class:`StepControl`).  ``Run.meta["long_steps"]`` says how many long steps were
    taken, until when, and why they ended.  The defaults are those measured on the
    Fig 10 sweep ("Accuracy and cost" page).
    """

    factor: int = 8
    limit: float = 0.3
    tol: float = 1e-3
    fields: tuple[str, ...] = ("k1", "k2")

    def __post_init__(self) -> None:
        if not (isinstance(self.factor, int) and 2 <= self.factor <= 4096):
            raise ValueError(f"long_steps factor={self.factor!r} must be an integer in [2, 4096]")
        if not (
            isinstance(self.limit, int | float) and math.isfinite(self.limit) and self.limit > 0
        ):
            raise ValueError(f"long_steps limit={self.limit!r} must be a finite number > 0")
        if not (isinstance(self.tol, int | float) and 0 < self.tol < 1):
            raise ValueError(f"long_steps tol={self.tol!r} must be a number in (0, 1)")
        fields = (self.fields,) if isinstance(self.fields, str) else tuple(self.fields)
        if not fields or not all(isinstance(f, str) for f in fields):
            raise ValueError(f"long_steps fields={self.fields!r} must be field names")
        object.__setattr__(self, "fields", fields)
        object.__setattr__(self, "limit", float(self.limit))
        object.__setattr__(self, "tol", float(self.tol))


@dataclass(frozen=True)
class Scheme:
    """Generalised-alpha parameters in space and time and the load-vector quadrature.

    lam_s, lam_t : spectral radius at infinity in space and in time, each in [-1, 0]
        (eq 13).  The paper uses -1 for both.
    quadrature : "trapezoidal" (eq 9: average of F at the corners; the paper's)
        or "midpoint" (F at the averaged state).
    control : a :class:`StepControl` (or its fields as a dict), or None for fixed steps
        (the default: the paper's grid).
    long_steps : a :class:`LongSteps` (or its fields as a dict): steps of a multiple
        of dt while the solution is quiet; None (the default) for none.
    """

    lam_s: float = -1.0
    lam_t: float = -1.0
    quadrature: str = "trapezoidal"
    control: StepControl | None = None
    long_steps: LongSteps | None = None

    def __post_init__(self) -> None:
        if isinstance(self.long_steps, dict):
            object.__setattr__(self, "long_steps", LongSteps(**self.long_steps))
        if self.long_steps is not None and not isinstance(self.long_steps, LongSteps):
            raise TypeError(f"long_steps={self.long_steps!r} must be a LongSteps, a dict or None")
        if isinstance(self.control, dict):
            control = dict(self.control)
            control["refine"] = tuple(tuple(w) for w in control.get("refine", ()))
            object.__setattr__(self, "control", StepControl(**control))
        if self.control is not None and not isinstance(self.control, StepControl):
            raise TypeError(f"control={self.control!r} must be a StepControl, a dict or None")
        for name in ("lam_s", "lam_t"):
            try:
                parameters(getattr(self, name))
            except ValueError as err:
                raise ValueError(f"{name}: {err}") from None
        if self.quadrature not in QUADRATURES:
            raise ValueError(f"quadrature={self.quadrature!r}; allowed: {QUADRATURES}")
        if self.lam_s != -1.0:
            warnings.warn(
                f"lam_s={self.lam_s}: with eq (13) in space the scheme is a theta-method in s "
                "that is only first order and, for the hyperbolic torsion rows, unstable "
                "(spectral radius > 1) and ill-conditioned at small Courant numbers; "
                "lam_s = -1 (the paper's choice) is the sound one",
                SchemeWarning,
                stacklevel=3,
            )

    def params(self) -> dict:
        """The scheme as data (the cache key's part); ``control`` and ``long_steps`` only
        when set, so fixed-step schemes keep the keys they always had."""
        out = {"lam_s": self.lam_s, "lam_t": self.lam_t, "quadrature": self.quadrature}
        if self.control is not None:
            out["control"] = asdict(self.control)
            out["control"]["refine"] = [list(w) for w in self.control.refine]
        if self.long_steps is not None:
            out["long_steps"] = asdict(self.long_steps)
            out["long_steps"]["fields"] = list(self.long_steps.fields)
        return out

    @property
    def space(self) -> tuple[float, float, float]:
        return parameters(self.lam_s)

    @property
    def time(self) -> tuple[float, float, float]:
        return parameters(self.lam_t)

    def coefficients(self, ds: float, dt: float) -> Coefficients:
        """The constants of one step on the grid (ds, dt)."""
        a_s, b_s, _ = self.space
        a_t, b_t, g_t = self.time
        return Coefficients(
            c_M=(1.0 - a_t) / (g_t * dt),
            c_A=a_t - (1.0 - a_t) * (1.0 - g_t) / g_t,
            a_s=a_s,
            b_s=b_s,
            b_t=b_t,
            g_t=g_t,
            inv_ds=1.0 / ds,
            dt=float(dt),
            trapezoidal=self.quadrature == "trapezoidal",
        )
