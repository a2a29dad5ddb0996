"""The named sweeps (section 6): the Fig 10 rate sweeps, the direct runs of Figs 8 and 9
the fitted law is checked against, the accuracy ladders and the studies beyond the paper.
``make data`` computes the paper's (:data:`PAPER`), ``make data-studies`` all of them;
:func:`cached` reads one back, computing nothing."""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import replace
from pathlib import Path
from typing import Any

import pandas as pd

from ..buckling.scene import Scene
from ..buckling.seed import STATED, Perturbation
from ..buckling.statics import critical_twist, euler_load
from ..genalpha import Newton, StepControl
from ..model.ends import EQ30
from ..model.rod import Rod
from ..store.results import Store
from .sweep import run_sweep

#: 16 loading rates, 1.6 x 10^(k/6) for k = -9..6: 0.0506 to 16 rad/(m s), 2.5 decades
FIG10_RATES: tuple[float, ...] = tuple(float(1.6 * 10 ** (k / 6)) for k in range(-9, 7))

#: the seed stated in section 6 (1e-8 N, read as N/m along the rod) and the seed
#: that reproduces the onset times of Figs 8 and 9 (see the Fig 8 page)
SEEDS: dict[str, Perturbation] = {"stated": Perturbation(STATED), "tiny": Perturbation(1e-17)}


def _fig10(seed: str, rates: Iterable[float] = FIG10_RATES, **grid: Any) -> list[Scene]:
    return [Scene(a=a, kappa0=10.0, seed=SEEDS[seed], **grid) for a in rates]


def _fig10_paced() -> list[Scene]:
    """The Fig 10 sweep in paced steps (:func:`~dyntorsion.studies.pacing.paced`), until the
    first peak: the fast setting of the delay law."""
    from .pacing import paced

    return [paced(replace(sc, until="first-peak")) for sc in _fig10("stated")]


def _fig08_09(seed: str) -> list[Scene]:
    return [
        Scene(a=1.6, kappa0=0.0, rod=Rod(rho=rho), seed=SEEDS[seed]) for rho in (1500.0, 5000.0)
    ]


def _grid(seed: str) -> list[Scene]:
    ends = (FIG10_RATES[0], 1.6, FIG10_RATES[-1])
    return [
        sc for n, dt in ((50, 0.01), (200, 0.0025)) for sc in _fig10(seed, ends, n_cells=n, dt=dt)
    ]


#: the grid ladder of the accuracy-and-cost page: N x dt, Courant number 28.9 on the diagonal
LADDER_N: tuple[int, ...] = (25, 50, 100, 200, 400)
LADDER_DT: tuple[float, ...] = (0.02, 0.01, 0.005, 0.0025, 0.00125)
#: Newton tolerances of the sensitivity study
NEWTON_TOLS: tuple[float, ...] = (1e-3, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12)


def _ladder(a: float, kappa0: float) -> list[Scene]:
    return [Scene(a=a, kappa0=kappa0, n_cells=n, dt=dt) for n in LADDER_N for dt in LADDER_DT]


#: the seeds of the Fig 8 page: uniform magnitudes [N/m], then point forces of 1e-8 N
FIG08_SEEDS: tuple[Perturbation, ...] = (
    *(Perturbation(m) for m in (1e-6, 1e-8, 1e-10, 1e-12, 1e-14, 1e-16, 1e-17)),
    *(Perturbation(STATED, "point", x) for x in (0.5, 0.1, 0.9)),
)


def _fig08_seeds() -> list[Scene]:
    return [Scene(a=1.6, kappa0=0.0, seed=seed) for seed in FIG08_SEEDS]


#: imperfection sensitivity ("Why is buckling delayed?"): three rates, uniform seeds
#: 1e-12..1e-4 N/m, point seeds of 1e-8 N at three places, and no seed at all
IMPERFECTION_RATES: tuple[float, ...] = (0.2, 1.6, 12.8)
IMPERFECTION_SEEDS: tuple[Perturbation, ...] = (
    *(Perturbation(10.0**k) for k in range(-12, -3)),
    *(Perturbation(STATED, "point", x) for x in (0.1, 0.5, 0.9)),
    Perturbation(0.0),
)


def _imperfection() -> list[Scene]:
    return [Scene(a=a, kappa0=10.0, seed=p) for a in IMPERFECTION_RATES for p in IMPERFECTION_SEEDS]


#: mechanisms ("Why is buckling delayed?"): the gyroscopic term off, the bending rotary
#: inertia scaled by 0.1 and 10 (torsional wave speed unchanged), and the rotating-frame
#: transport term rho A (w x u) off (not a physical model: a probe of the spin coupling of
#: the lateral motion), at the three rates
MECHANISMS: dict[str, dict[str, Any]] = {
    "gyroscopic term off": {"terms": (("gyro", 0.0),)},
    "rotary inertia x 0.1": {"rotary_inertia_scale": 0.1},
    "rotary inertia x 10": {"rotary_inertia_scale": 10.0},
    "rotating-frame transport off": {"terms": (("wxu", 0.0),)},
}


def _mechanisms() -> list[Scene]:
    return [Scene(a=a, kappa0=10.0, **kw) for a in IMPERFECTION_RATES for kw in MECHANISMS.values()]


#: the delay law under an axial load ("Tension and compression" page): loads as fractions
#: of the clamped Euler load 4 pi^2 B / L^2, every third Fig 10 rate, the stated seed,
#: and the pretwist at the paper's ratio kappa0 / kappa_cri = 10 / 11.2335 of each load
TENSION_FRACTIONS: tuple[float, ...] = (-0.5, -0.25, 0.0, 0.5, 1.0)
TENSION_RATES: tuple[float, ...] = FIG10_RATES[::3]


def tension_scenes(fraction: float, rates: Iterable[float] = TENSION_RATES) -> list[Scene]:
    """The rate sweep at axial load ``fraction`` x the clamped Euler load (Table 1 rod)."""
    rod = Rod()
    T = fraction * euler_load(rod, EQ30.static)
    kappa0 = 10.0 if T == 0.0 else 10.0 * critical_twist(rod, T) / critical_twist(rod)
    return [Scene(a=a, kappa0=kappa0, tension=T, seed=SEEDS["stated"]) for a in rates]


def _newton(a: float, kappa0: float, seed: str = "stated") -> list[Scene]:
    return [
        Scene(a=a, kappa0=kappa0, seed=SEEDS[seed], newton=Newton(tol=tol)) for tol in NEWTON_TOLS
    ]


#: the initial state and the seed's form as a further dimension of the delay law (the
#: "Initial state and seed" page): the Fig 10 sweep from the unstressed rod with
#: kappa0 brought in by section 5's transition in about 0.02 s (its torsional wave needs
#: dt = 0.001 s, so this one runs at five of the rates, every third from 0.16, until the
#: first peak) and in about 0.5 s, and with the stated seed fixed in the lab frame or
#: acting as an impulse for the first IMPULSE_S seconds only
IMPULSE_S = 0.1
STARTS_AND_SEEDS: dict[str, dict[str, Any]] = {
    "start-smooth": {"start": "smooth", "start_tau": 0.02, "dt": 0.001, "until": "first-peak"},
    "start-slow": {"start": "smooth", "start_tau": 0.5},
    "seed-lab": {"seed": Perturbation(STATED, frame="lab")},
    "seed-impulse": {"seed": Perturbation(STATED, duration=IMPULSE_S)},
}
#: the step start (section 6's y(s, 0) = 0 with the end twist jumping to kappa0) on a grid
#: ladder at a = 16: its square wave is discontinuous, so its onset need not converge
STEP_GRIDS: tuple[tuple[int, float], ...] = (
    (100, 0.005), (100, 0.001), (100, 0.0005), (200, 0.0005), (400, 0.00025),
)  # fmt: skip


def _start_or_seed(name: str) -> list[Scene]:
    kw = dict(STARTS_AND_SEEDS[name])
    seed = kw.pop("seed", SEEDS["stated"])
    rates = TENSION_RATES[1:] if name == "start-smooth" else FIG10_RATES
    return [Scene(a=a, kappa0=10.0, seed=seed, **kw) for a in rates]


def _step_grid() -> list[Scene]:
    return [
        Scene(a=16.0, kappa0=10.0, start="step", n_cells=n, dt=dt, until="first-peak")
        for n, dt in STEP_GRIDS
    ]


#: the hold-out sets of the error estimate of :func:`~dyntorsion.studies.tolerance.onset_within`:
#: Fig 10 rates at three seeds, another rod, and rate sweeps under a tension
#: and a compression (fractions of the clamped Euler load).  The first set was computed
#: with the estimate fixed beforehand; the second (rates half a step of 10^(1/6) between
#: Fig 10's, other seeds, another rod and loads) after the chooser's rule was changed
#: in view of the first ("Accuracy and cost" page); the third (rates a quarter of a step
#: above Fig 10's, other seeds, rod and loads) after the estimate of the continuous reading
#: was fixed, to test it; the fourth (rates three quarters of a step above
#: Fig 10's, other seeds, rod and loads) after the solver check was added to both
#: estimates (:data:`~dyntorsion.studies.tolerance.SOLVER_FACTOR`), to test that
HALF_RATES: tuple[float, ...] = tuple(float(1.6 * 10 ** ((k + 0.5) / 6)) for k in range(-9, 6))
QUARTER_RATES: tuple[float, ...] = tuple(float(1.6 * 10 ** ((k + 0.25) / 6)) for k in range(-9, 6))
THREE_QUARTER_RATES: tuple[float, ...] = tuple(
    float(1.6 * 10 ** ((k + 0.75) / 6)) for k in range(-9, 6)
)
HOLDOUTS: dict[str, dict[str, Any]] = {
    "tolerance-holdout": {
        "rates": FIG10_RATES,
        "seeds": (STATED, 1e-12, 1e-17),
        "rod": Rod(D=1.5e-3, rho=5000.0),
        "rod_rates": TENSION_RATES,
        "loads": (0.5, -0.25),
    },
    "tolerance-holdout-2": {
        "rates": HALF_RATES,
        "seeds": (1e-10, 1e-14, 1e-16),
        "rod": Rod(E=2.5e7, D=0.8e-3, rho=1000.0),
        "rod_rates": HALF_RATES[::3],
        "loads": (0.25, -0.5),
    },
    "tolerance-holdout-3": {
        "rates": QUARTER_RATES,
        "seeds": (1e-9, 1e-13, 1e-15),
        "rod": Rod(E=5e7, D=1.2e-3, rho=2500.0),
        "rod_rates": QUARTER_RATES[1::3],
        "loads": (0.75, -0.4),
    },
    "tolerance-holdout-4": {
        "rates": THREE_QUARTER_RATES,
        "seeds": (1e-11, 1e-15, 1e-17),
        "rod": Rod(E=3.5e7, D=1.0e-3, rho=4000.0),
        "rod_rates": THREE_QUARTER_RATES[2::3],
        "loads": (0.6, -0.3),
    },
}


def holdout_scenes(name: str = "tolerance-holdout") -> list[Scene]:
    """The scenes of a hold-out set (:data:`HOLDOUTS`), with the step-size control of the
    presets; their grids play no part (the rungs set them)."""
    h = HOLDOUTS[name]
    fig10 = [Scene(a=a, kappa0=10.0, seed=Perturbation(m)) for m in h["seeds"] for a in h["rates"]]
    rod = [Scene(a=a, kappa0=10.0, rod=h["rod"], seed=SEEDS["stated"]) for a in h["rod_rates"]]
    loads = [sc for f in h["loads"] for sc in tension_scenes(f, h["rod_rates"])]
    return [
        replace(sc, scheme=replace(sc.scheme, control=PRESET_CONTROL))
        for sc in (*fig10, *rod, *loads)
    ]


def _holdout(name: str) -> list[Scene]:
    """Every scene of a hold-out set on the rungs N = 25..400 of
    :func:`~dyntorsion.studies.tolerance.rungs` (their reference, N = 800, is the preset
    ``tolerance-reference``)."""
    from .tolerance import CELLS, rungs

    scenes = holdout_scenes(name)
    return [r for sc in scenes for r in rungs(sc, len(CELLS))]


def reference_scenes(names: tuple[str, ...] = tuple(HOLDOUTS)) -> list[Scene]:
    """Every scene of the hold-out sets one rung past the ladder, N = 800: the reference
    the rungs' estimates are judged against (:func:`~dyntorsion.studies.tolerance_study.pairs`)."""
    from .tolerance import CELLS, rungs

    return [rungs(sc, len(CELLS) + 1)[-1] for name in names for sc in holdout_scenes(name)]


def tight_reference_scenes(names: tuple[str, ...] = tuple(HOLDOUTS)) -> list[Scene]:
    """The references of :func:`reference_scenes` with the Newton tolerance
    :data:`~dyntorsion.studies.tolerance.REFERENCE_TOL`: converged in the solver too, where
    a tiny seed makes the onset depend on it ("Accuracy and cost", "The solver's share")."""
    from .tolerance import REFERENCE_TOL

    return [
        replace(sc, newton=replace(sc.newton, tol=REFERENCE_TOL)) for sc in reference_scenes(names)
    ]


def solver_scenes(names: tuple[str, ...] = tuple(HOLDOUTS)) -> list[Scene]:
    """The solver check of every scene of the hold-out sets
    (:func:`~dyntorsion.studies.tolerance.solver_check`)."""
    from .tolerance import solver_check

    return [solver_check(sc) for name in names for sc in holdout_scenes(name)]


#: name -> function returning the scenes; ``make data-studies`` runs them all
PRESETS: dict[str, Callable[[], list[Scene]]] = {
    "fig10": lambda: _fig10("stated"),
    "fig10-tiny-seed": lambda: _fig10("tiny"),
    "fig10-paced": _fig10_paced,
    "fig08-09": lambda: _fig08_09("stated"),
    "fig08-09-tiny-seed": lambda: _fig08_09("tiny"),
    "fig10-grid": lambda: _grid("stated"),
    "fig10-grid-tiny-seed": lambda: _grid("tiny"),
    "accuracy-fig08": lambda: _ladder(1.6, 0.0),
    "accuracy-fast": lambda: _ladder(16.0, 10.0),
    "newton-fig08": lambda: _newton(1.6, 0.0),
    "newton-fast": lambda: _newton(16.0, 10.0),
    "newton-fast-tiny-seed": lambda: _newton(16.0, 10.0, "tiny"),
    "fig08-seeds": _fig08_seeds,
    "imperfection": _imperfection,
    "mechanisms": _mechanisms,
    "tension": lambda: [sc for f in TENSION_FRACTIONS for sc in tension_scenes(f)],
    **{name: (lambda name=name: _start_or_seed(name)) for name in STARTS_AND_SEEDS},
    "start-step-grid": _step_grid,
    "tolerance-holdout": lambda: _holdout("tolerance-holdout"),
    "tolerance-holdout-2": lambda: _holdout("tolerance-holdout-2"),
    "tolerance-holdout-3": lambda: _holdout("tolerance-holdout-3"),
    "tolerance-holdout-4": lambda: _holdout("tolerance-holdout-4"),
    "tolerance-reference": reference_scenes,
    "tolerance-reference-tight": tight_reference_scenes,
    "tolerance-solver": solver_scenes,
}


#: the presets the paper's figures read (Figs 8, 9 and 10 and their grid check):
#: ``make data`` computes these, and ``dyntorsion sweep --preset paper`` names them
PAPER: tuple[str, ...] = (
    "fig10",
    "fig10-tiny-seed",
    "fig08-09",
    "fig08-09-tiny-seed",
    "fig10-grid",
    "fig10-grid-tiny-seed",
    "fig08-seeds",
    "accuracy-fig08",
)

#: a ``--preset`` value that stands for several presets: the paper's, or every one
GROUPS: dict[str, tuple[str, ...]] = {"paper": PAPER, "all": tuple(PRESETS)}


def cached(name: str, store: Store | str | Path | None = None) -> pd.DataFrame:
    """The table of a named preset read from ``store`` (default :func:`~dyntorsion.store.location.default_store`), computing
    nothing: a missing scene raises :class:`MissingResultError`, a stale one
    :class:`~dyntorsion.store.results.StaleResultError`, each naming the command that
    computes it (``dyntorsion sweep --preset NAME``; in a checkout also ``make data-studies``)."""
    return run_sweep(
        preset(name),
        store,
        command=f"dyntorsion sweep --preset {name}",
        compute=False,
        on_stale="error",
        progress=False,
    )


#: the step-size control every preset runs with: identical to fixed steps
#: until the first rejected step, so the onsets do not move, and the runs go on past the
#: post-buckling whip to self-contact or t_end instead of stopping on a Newton failure
PRESET_CONTROL = StepControl()


def preset(name: str) -> list[Scene]:
    """The scenes of a named sweep (see :data:`PRESETS`), each with the step-size
    control :data:`PRESET_CONTROL`."""
    if name not in PRESETS:
        raise ValueError(f"preset={name!r}; allowed: {', '.join(PRESETS)}")
    return [
        replace(sc, scheme=replace(sc.scheme, control=PRESET_CONTROL)) for sc in PRESETS[name]()
    ]
