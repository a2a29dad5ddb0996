"""What is done to the rod's ends: the end-twist history, the axial end load, and
the end conditions (section 6, eq 30, and the sets a researcher extends it with).

A scene is data: each object here is a frozen dataclass with ``params()`` (its
canonical form, part of the cache key) and is evaluated on arrays of times.

* Twist histories kappa3(0, t): :class:`Ramp` (the paper's kappa0 + a t),
  :class:`SmoothStart` (the ramp from the unstressed rod, kappa0 brought in smoothly),
  :class:`Polynomial`, :class:`RampHold` (a smooth ramp-and-hold), :class:`Tabulated`,
  :class:`Custom` (any named callable with its parameters).
* :class:`AxialLoad`: the axial force n3(L, t) = T + T_rate t at the far end
  (positive = tension); the initial state carries n3 = T(0) along the rod.
* :class:`Ends`: which six fields each end prescribes.  :data:`ENDS` names the sets;
  ``"clamped"`` is the paper's eq (30).  Ill-posed sets are refused on construction.
  They live in :mod:`dyntorsion.model.ends` and are re-exported here.
"""

from __future__ import annotations

import functools
import hashlib
import inspect
import textwrap
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..model.ends import ENDS, EQ30, Ends, IllPosedEndsError, ends, ends_from_params
from .history import HISTORIES, History, finite_value, history_from_params
from .loads import (
    AXIAL_LOADS,
    DISTRIBUTED_LOADS,
    AxialLoad,
    DistributedLoad,
    EndLoad,
    distributed_from_params,
    load_from_params,
)
from .turning import TurnHold  # registers the spin history turn-hold

__all__ = [
    "History",
    "HISTORIES",
    "Ramp",
    "SmoothStart",
    "Polynomial",
    "RampHold",
    "Tabulated",
    "Custom",
    "AxialLoad",
    "EndLoad",
    "DistributedLoad",
    "AXIAL_LOADS",
    "DISTRIBUTED_LOADS",
    "load_from_params",
    "distributed_from_params",
    "TurnHold",
    "Ends",
    "ENDS",
    "EQ30",
    "ends",
    "IllPosedEndsError",
    "history_from_params",
    "ends_from_params",
]


#: t / tau past which exp(-(t / tau)^4) is 0 in floating point (caps x so that x**4 is finite)
_FLAT = 1e10


@dataclass(frozen=True)
class Ramp(History):
    """The paper's history: kappa3(0, t) = kappa0 + a t (eq 30)."""

    a: float
    kappa0: float = 0.0
    kind = "ramp"

    def __post_init__(self) -> None:
        object.__setattr__(self, "a", finite_value("a", self.a))
        object.__setattr__(self, "kappa0", finite_value("kappa0", self.kappa0))

    def __call__(self, t):
        return self.kappa0 + self.a * np.asarray(t, dtype=float)

    @property
    def rate(self) -> float:
        return self.a

    def params(self) -> dict[str, Any]:
        return {"kind": "ramp", "kappa0": self.kappa0, "a": self.a}


@dataclass(frozen=True)
class SmoothStart(History):
    """The paper's ramp started from the unstressed rod, y(s, 0) = 0 (section 6), with the
    pretwist kappa0 brought in by the smooth transition of section 5 (eq 28, Fig 5):
    kappa3(0, t) = kappa0 (1 - f(t / tau)) + a t, f(x) = exp(-x^4), so the end twist
    starts at 0 with its first three time derivatives 0 (of the twist part) and is
    within kappa0 e^-16 (1.1e-7 kappa0) of the ramp kappa0 + a t for t >= 2 tau; ``tau`` [s] is the time at
    which 1 - 1/e of kappa0 is in (section 5's release: tau = 1/50 s)."""

    a: float
    kappa0: float = 0.0
    tau: float = 0.02
    kind = "smooth-start"

    def __post_init__(self) -> None:
        for name in ("a", "kappa0", "tau"):
            object.__setattr__(self, name, finite_value(name, getattr(self, name)))
        if self.tau <= 0:
            raise ValueError(f"smooth start tau={self.tau} must be > 0 s")

    def __call__(self, t):
        t = np.asarray(t, dtype=float)
        # beyond x = 1e10 the transition is 1 to the last bit; the cap keeps x**4 finite
        x = np.clip(t, 0.0, _FLAT * self.tau) / self.tau
        # section 5's f(x) = exp(-x^4) (waves.transitions.smoothing), written out so that
        # the records of this history do not hang on section 5's code (a test ties them)
        return self.kappa0 * -np.expm1(-(x**4)) + self.a * t

    @property
    def rate(self) -> float:
        return self.a

    def params(self) -> dict[str, Any]:
        return {"kind": "smooth-start", "a": self.a, "kappa0": self.kappa0, "tau": self.tau}


@dataclass(frozen=True)
class Polynomial(History):
    """kappa3(0, t) = sum_k coefficients[k] t^k."""

    coefficients: tuple[float, ...]
    kind = "polynomial"

    def __post_init__(self) -> None:
        c = tuple(finite_value(f"coefficients[{i}]", v) for i, v in enumerate(self.coefficients))
        if not c:
            raise ValueError("coefficients must hold at least one number")
        object.__setattr__(self, "coefficients", c)

    def __call__(self, t):
        return np.polynomial.polynomial.polyval(np.asarray(t, dtype=float), self.coefficients)

    def params(self) -> dict[str, Any]:
        return {"kind": "polynomial", "coefficients": list(self.coefficients)}


@dataclass(frozen=True)
class RampHold(History):
    """A ramp kappa0 + a t rounded smoothly into a hold at ``hold``:
    h = hold + a tau (x - log(1 + e^x)), x = (kappa0 + a t - hold) / (a tau),
    ``tau`` [s] the time over which the corner is rounded (C-infinity).  Evaluated as
    kappa0 + a t - a tau log(1 + e^x) for x < 0 and hold - a tau log(1 + e^-x) otherwise,
    the same function without the cancellation of a large ``hold`` against the ramp."""

    a: float
    hold: float
    kappa0: float = 0.0
    tau: float = 0.5
    kind = "ramp-hold"

    def __post_init__(self) -> None:
        for name in ("a", "hold", "kappa0", "tau"):
            object.__setattr__(self, name, finite_value(name, getattr(self, name)))
        if self.a <= 0 or self.tau <= 0:
            raise ValueError(f"ramp-hold needs a > 0 and tau > 0 (got a={self.a}, tau={self.tau})")
        if self.hold <= self.kappa0:
            raise ValueError(f"hold={self.hold} must exceed kappa0={self.kappa0}")

    def __call__(self, t):
        # x - log(1 + e^x) = -log(1 + e^-x), written on each side of the corner so that
        # no large term cancels: the ramp less a tau log(1 + e^x) before it (x < 0), the
        # hold less a tau log(1 + e^-x) after it; exact to round-off for any hold
        ramp = self.kappa0 + self.a * np.asarray(t, dtype=float)
        scale = self.a * self.tau
        x = (ramp - self.hold) / scale
        before = ramp - scale * np.log1p(np.exp(np.minimum(x, 0.0)))
        after = self.hold - scale * np.log1p(np.exp(-np.maximum(x, 0.0)))
        return np.where(x < 0.0, before, after)

    def params(self) -> dict[str, Any]:
        return {
            "kind": "ramp-hold",
            "a": self.a,
            "hold": self.hold,
            "kappa0": self.kappa0,
            "tau": self.tau,
        }


@dataclass(frozen=True)
class Tabulated(History):
    """kappa3(0, t) interpolated (monotone cubic, PCHIP) through the points (t, kappa);
    constant beyond the last point."""

    t: tuple[float, ...]
    kappa: tuple[float, ...]
    kind = "tabulated"

    def __post_init__(self) -> None:
        t = tuple(finite_value(f"t[{i}]", v) for i, v in enumerate(self.t))
        k = tuple(finite_value(f"kappa[{i}]", v) for i, v in enumerate(self.kappa))
        if len(t) != len(k) or len(t) < 2:
            raise ValueError("t and kappa must hold the same number (>= 2) of points")
        if t[0] != 0.0 or np.any(np.diff(t) <= 0):
            raise ValueError("t must start at 0 and increase strictly")
        object.__setattr__(self, "t", t)
        object.__setattr__(self, "kappa", k)

    def __call__(self, t):
        from scipy.interpolate import PchipInterpolator

        tt = np.clip(np.asarray(t, dtype=float), self.t[0], self.t[-1])
        return PchipInterpolator(self.t, self.kappa)(tt)

    def params(self) -> dict[str, Any]:
        return {"kind": "tabulated", "t": list(self.t), "kappa": list(self.kappa)}


_PLAIN = (bool, int, float, complex, str, bytes, type(None))


def function_fingerprint(func: Any, _seen: set[int] | None = None) -> str:
    """Everything a history function computes with, as text: its source; for a
    ``functools.partial`` the function and the bound values; the values in its closure,
    the module globals its code names and its defaults, each by value (numbers, strings,
    arrays, tuples) or, for a function of its own, recursively.  Library modules and
    their functions count by name.  Raises ValueError naming what cannot be fingerprinted
    (a function without readable source, an object without a stable value)."""
    seen = set() if _seen is None else _seen
    if id(func) in seen:
        return "<recursion>"
    seen.add(id(func))
    if isinstance(func, functools.partial):
        bound = (func.args, sorted(func.keywords.items()))
        return f"partial({function_fingerprint(func.func, seen)}, {_value(bound, seen)})"
    code = getattr(func, "__code__", None)
    if code is None:
        raise ValueError(f"func={func!r}: not a Python function, its code cannot be fingerprinted")
    try:
        source = textwrap.dedent(inspect.getsource(func))
    except (OSError, TypeError):
        raise ValueError(
            f"func={getattr(func, '__qualname__', func)!r} has no readable source (defined in "
            "exec or python -c?): it cannot be keyed in the store; define it in a file, or "
            "pass its values as parameters=..."
        ) from None
    parts = [source]
    names = {n for c in _codes(code) for n in c.co_names}
    env = getattr(func, "__globals__", {})
    for name in sorted(names & set(env)):
        parts.append(f"global {name} = {_value(env[name], seen)}")
    for name, cell in zip(code.co_freevars, func.__closure__ or (), strict=True):
        try:
            parts.append(f"closure {name} = {_value(cell.cell_contents, seen)}")
        except ValueError as err:  # an empty cell
            raise ValueError(
                f"func={func.__qualname__!r}: closure {name} is unset ({err})"
            ) from None
    parts.append(f"defaults {_value(func.__defaults__, seen)} {_value(func.__kwdefaults__, seen)}")
    return "\n".join(parts)


def _codes(code):
    yield code
    for const in code.co_consts:
        if inspect.iscode(const):
            yield from _codes(const)


def _value(obj: Any, seen: set[int]) -> str:
    if isinstance(obj, _PLAIN):
        return repr(obj)
    if isinstance(obj, np.ndarray):
        return f"array{obj.shape}{obj.dtype}:{hashlib.sha256(np.ascontiguousarray(obj).tobytes()).hexdigest()}"
    if isinstance(obj, np.generic):
        return repr(obj.item())
    if isinstance(obj, tuple | list):
        return type(obj).__name__ + "(" + ", ".join(_value(v, seen) for v in obj) + ")"
    if isinstance(obj, dict):
        return (
            "dict("
            + ", ".join(f"{_value(k, seen)}: {_value(v, seen)}" for k, v in obj.items())
            + ")"
        )
    if inspect.ismodule(obj):
        return f"module {obj.__name__}"
    module = getattr(obj, "__module__", None) or ""
    if callable(obj) and not _user_code(obj):
        return f"{module}.{getattr(obj, '__qualname__', type(obj).__name__)}"
    if inspect.isfunction(obj) or isinstance(obj, functools.partial):
        return function_fingerprint(obj, seen)
    if isinstance(obj, History):
        return repr(obj.params())
    text = repr(obj)
    if " at 0x" in text:
        raise ValueError(f"{text}: no stable value to key a custom history by")
    return text


def _user_code(obj: Any) -> bool:
    """A function of the user's own (not of an installed library or of Python)."""
    if isinstance(obj, functools.partial):
        return True
    if not inspect.isfunction(obj):
        return False
    module = inspect.getmodule(obj)
    path = getattr(module, "__file__", None) or ""
    return not any(part in path for part in ("site-packages", "dist-packages", "/lib/python"))


@dataclass(frozen=True)
class Custom(History):
    """Any callable ``func(t, **parameters)`` (vectorised over t), under a ``name``.
    The cache key holds the name, the parameters and a hash of everything the function
    computes with (its source, the values in its closure, the globals it names, its
    default arguments and the functions it calls; :func:`function_fingerprint`), so a
    changed function or value is not served another one's records.  A function that
    cannot be fingerprinted (no readable source) is refused."""

    name: str
    func: Callable[..., np.ndarray] = field(compare=False)
    parameters: tuple[tuple[str, float], ...] = ()
    kind = "custom"

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise ValueError("a custom history needs a non-empty name")
        if not callable(self.func):
            raise TypeError(f"func={self.func!r} must be callable")
        p = self.parameters.items() if isinstance(self.parameters, Mapping) else self.parameters
        object.__setattr__(
            self, "parameters", tuple(sorted((str(k), finite_value(k, v)) for k, v in p))
        )

    def __call__(self, t):
        out = np.asarray(self.func(np.asarray(t, dtype=float), **dict(self.parameters)))
        if out.dtype.kind not in "biuf":  # a string such as "1e7" is not a twist
            raise TypeError(f"the function returned {out.dtype} values, not real numbers")
        return np.broadcast_to(out.astype(float), np.shape(t)).astype(float)

    def source_hash(self) -> str:
        """A hash of everything ``func`` computes with (:func:`function_fingerprint`);
        ValueError when that cannot be known."""
        return hashlib.sha256(function_fingerprint(self.func).encode()).hexdigest()[:16]

    def params(self) -> dict[str, Any]:
        """The history's key.  A function that cannot be fingerprinted still runs, but its
        key says so (``unkeyed``) and the store refuses to cache it."""
        try:
            source, why = self.source_hash(), None
        except ValueError as err:
            source, why = None, str(err)
        out = {"kind": "custom", "name": self.name, "parameters": dict(self.parameters)}
        out["source"] = source
        if why is not None:
            out["unkeyed"] = why
        return out

    @classmethod
    def from_params(cls, params: Mapping[str, Any]) -> Custom:
        """Refused: a custom history's function is code, not data."""
        raise ValueError(
            f"history {params.get('name')!r} is a custom function: rebuild its Scene in Python "
            "with the same Custom(name, func, parameters), or define a History subclass with "
            "a kind (it registers itself and is rebuilt from the store)"
        )
