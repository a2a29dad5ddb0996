"""The replication at a glance: every number the paper states, beside ours.

The paper's values, with where each is stated, live in ``paper/published.json``;
:func:`ours` computes the matching values (cheap ones directly, the buckling
numbers from the cached scenes in ``data/``), and :func:`table` puts them side by
side with the relative difference and a one-line verdict.  :func:`write_numbers`
saves the table as ``paper/numbers.json``.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import Any

import pandas as pd

from . import __version__
from .buckling import critical_twist, fit_power_law, m_cri
from .results import write_json
from .rod import Rod
from .sweep import cached

__all__ = ["PAPER", "published", "ours", "table", "write_numbers"]

PAPER = Path(__file__).resolve().parents[2] / "paper"


def published(path: str | os.PathLike[str] | None = None) -> dict[str, dict[str, Any]]:
    """The paper's stated values by id (``paper/published.json``)."""
    data = json.loads(Path(path or PAPER / "published.json").read_text())
    return {v["id"]: v for v in data["values"]}


def ours() -> dict[str, list[tuple[str, float, str]]]:
    """Our value(s) for each published id: (label, value, where it comes from)."""
    rod = Rod.paper()
    direct = cached("fig08-09").set_index("rho")
    direct_tiny = cached("fig08-09-tiny-seed").set_index("rho")
    sweeps = {"stated seed 1e-8 N/m": cached("fig10"), "seed 1e-17 N/m": cached("fig10-tiny-seed")}
    fits = {k: fit_power_law(t["a"], t["kappa3"], rod, n_boot=0) for k, t in sweeps.items()}
    free = {
        k: fit_power_law(t["a"], t["kappa3"], rod, kappa_cri=None, n_boot=0)
        for k, t in sweeps.items()
    }
    out: dict[str, list[tuple[str, float, str]]] = {
        "c": [("", rod.c, "Rod.c")],
        "m_cri": [("", m_cri, "buckling.m_cri (mpmath root)")],
        "kappa_cri": [("", critical_twist(rod), "buckling.critical_twist, eq (32)")],
        "T1": [("", rod.T1, "Rod.T1")],
        "fig8_tc": [
            ("stated seed 1e-8 N/m", direct.loc[1500.0, "t_c"], "data: fig08-09"),
            ("seed 1e-17 N/m", direct_tiny.loc[1500.0, "t_c"], "data: fig08-09-tiny-seed"),
        ],
        "fig8_kappa3": [
            ("stated seed 1e-8 N/m", direct.loc[1500.0, "kappa3"], "data: fig08-09"),
            ("seed 1e-17 N/m", direct_tiny.loc[1500.0, "kappa3"], "data: fig08-09-tiny-seed"),
        ],
    }
    out["b"] = [(k, f.b, "fit of the Fig 10 sweep") for k, f in fits.items()]
    out["sigma"] = [(k, f.sigma, "fit of the Fig 10 sweep") for k, f in fits.items()]
    out["law_fig8"] = [(k, f.time_to_buckle(1.6), "our fitted law") for k, f in fits.items()]
    out["law_fig9"] = [
        (k, f.time_to_buckle(1.6, rod=rod.with_(rho=5000.0)), "our fitted law")
        for k, f in fits.items()
    ]
    out["kappa_cri_extrapolated"] = [
        (k, f.kappa_cri, "fit with kappa_cri free") for k, f in free.items()
    ]
    return out


def _verdict(rel: float, digits: int, value: float) -> str:
    """'agrees' within the rounding of the paper's stated digits, else how far off."""
    rounding = 0.5 * 10 ** (math.floor(math.log10(abs(value))) - digits + 1) / abs(value)
    if abs(rel) <= rounding + 1e-12:
        return "agrees to the digits stated"
    if abs(rel) < 0.01:
        return "agrees within 1 %"
    if abs(rel) < 0.05:
        return "close (within 5 %)"
    return "differs"


def table() -> pd.DataFrame:
    """One row per (published number, our variant)."""
    pub, mine = published(), ours()
    rows = []
    for pid, p in pub.items():
        for label, value, origin in mine[pid]:
            rel = value / p["value"] - 1
            rows.append(
                {
                    "id": pid,
                    "quantity": p["quantity"],
                    "paper": p["value"],
                    "where (paper)": p["where"],
                    "ours": value,
                    "variant": label,
                    "from": origin,
                    "relative difference": rel,
                    "verdict": _verdict(rel, p["digits"], p["value"]),
                }
            )
    return pd.DataFrame(rows)


def write_numbers(path: str | os.PathLike[str] | None = None) -> Path:
    """Write :func:`table` to ``paper/numbers.json`` (atomically)."""
    payload = {"package_version": __version__, "rows": table().to_dict(orient="records")}
    return write_json(path or PAPER / "numbers.json", payload)
