"""The solver's share of the onset's error (beyond the paper).

Below a seed of about 1e-13 N/m the Newton solve's tolerance moves the onset more than
the grid does (:mod:`~dyntorsion.studies.tolerance`, module docstring), so the estimate of
:func:`~dyntorsion.studies.tolerance.onset_within` adds the change of the onset in a
solver check, and the hold-out sets are judged against references converged in the
solver too (preset ``tolerance-reference-tight``).  :func:`solver_share` sets both
estimates before and after, per hold-out set and over their union, on the ``fine`` rung.
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from ..store.results import Store
from .presets import preset, solver_scenes
from .sweep import run_sweep
from .tolerance import READINGS, VOUCHED
from .tolerance_study import SETS, chooser, pairs, solver_changes

__all__ = ["VARIANTS", "by_group", "check_cost", "solver_share"]

#: the two ways of judging the estimates: the rules from the rungs alone against the
#: references at the scenes' Newton tolerance (as the first three sets were judged), and
#: with the solver check's share against the references converged in the solver
VARIANTS: dict[str, dict[str, bool]] = {
    "rungs alone, reference at the scene's tol": {"solver": False, "tight": False},
    "with the solver check, converged reference": {"solver": True, "tight": True},
}


def solver_share(
    store: Store | str | Path | None = None, rtol: float = 0.005, sets: tuple[str, ...] = SETS
) -> pd.DataFrame:
    """Per reading, way of judging (:data:`VARIANTS`) and hold-out set, and over all the
    sets: the ``fine`` rung's t_c estimates covered, their median overstatement, the share
    within 3 times the true error, the kappa3 estimates covered; and, judged the second
    way, the chooser at ``rtol`` (met, and met with t_c and kappa3 covered)."""
    rows = []
    for reading in READINGS:
        for variant, how in VARIANTS.items():
            frames = []
            for name in (*sets, "all"):
                if name == "all":
                    fine = pd.concat(frames)
                else:
                    p = pairs(name, store, reading, **how)
                    fine = p[p.buckled & (p.rung == "fine")].assign(set=name)
                    frames.append(fine)
                tc, k3 = fine[fine.quantity == "t_c"], fine[fine.quantity == "kappa3"]
                row = {
                    "reading": reading,
                    "judged": variant,
                    "set": name,
                    "scenes": len(tc),
                    "fine: covered": 100 * tc.covered.mean(),
                    "overstatement, median": float(tc.overstatement.median()),
                    "within 3x": 100 * float((tc.overstatement <= 3).mean()),
                    "kappa3 covered": 100 * k3.covered.mean(),
                    f"rtol {rtol:g}: met": "",
                    "met and covered": "",
                }
                if how["solver"] and name != "all":
                    ch = chooser(rtol, name, store, reading, tight=True)
                    both = ch.t_c_covered & ch.kappa3_covered & ch.met
                    row[f"rtol {rtol:g}: met"] = f"{int(ch.met.sum())}/{len(ch)}"
                    row["met and covered"] = f"{int(both.sum())}/{int(ch.met.sum())}"
                rows.append(row)
    return pd.DataFrame(rows)


def by_group(
    store: Store | str | Path | None = None,
    reading: str = "continuous",
    sets: tuple[str, ...] = SETS[:3],
) -> pd.DataFrame:
    """Per group of scenes (seed, rod, load) of the hold-out sets ``sets`` (default: the
    three looked at when the solver check was added): medians, as % of t_c, of the solver
    check's change, of the ``fine`` rung's estimate from the rungs alone and of its true
    error against the reference at the scenes' tolerance; and the share of scenes whose
    solver change exceeds that estimate."""
    frames = []
    for name in sets:
        p = pairs(name, store, reading)
        fine = p[p.buckled & (p.rung == "fine") & (p.quantity == "t_c")].set_index("scene")
        change = solver_changes(name, store, reading)["t_c"].loc[fine.index]
        frames.append(fine.assign(change=change))
    f = pd.concat(frames)
    rel = 100 / f.reference.abs()
    out = pd.DataFrame({"group": f.group, "change": f.change * rel, "estimate": f.estimate * rel,
                        "true": f.true * rel, "above": f.change > f.estimate})  # fmt: skip
    table = out.groupby("group", sort=False).agg(
        scenes=("change", "size"),
        change=("change", "median"),
        estimate=("estimate", "median"),
        true=("true", "median"),
        above=("above", "mean"),
    )
    table["above"] *= 100
    return table.rename(
        columns={
            "change": "solver change, median [% of t_c]",
            "estimate": "rungs' estimate, median [% of t_c]",
            "true": "true error, median [% of t_c]",
            "above": "change above the estimate [% of scenes]",
        }
    )


def check_cost(store: Store | str | Path | None = None, sets: tuple[str, ...] = SETS) -> float:
    """The recorded wall time of the solver checks of the hold-out sets ``sets`` over that of
    their rungs up to ``fine`` (the ladder a chooser that stops at ``fine`` runs)."""

    def wall(scenes: list) -> pd.DataFrame:
        return run_sweep(scenes, store, compute=False, on_stale="error", progress=False)

    checks = wall(solver_scenes(sets)).wall_time_s.sum()
    ladders = 0.0
    for name in sets:
        t = wall(preset(name))
        ladders += t[t.n_cells <= VOUCHED].wall_time_s.sum()
    return float(checks / ladders)
