"""The tolerance study's tables on the page "Accuracy and cost", kept as one record.

Each table is derived from the hold-out sets' onset records (:mod:`.tolerance_study`,
:mod:`.solver_share`): thousands of records, read in about a minute.  The record of kind
``tolerance-tables`` (``make data-studies``) keeps the tables so the page reads them at
once; its fingerprint reaches every function that computes them and, through
:func:`~.sweep.run_sweep`, the code of the onset records they read, so a change of either
makes it stale.
"""

from __future__ import annotations

from typing import Any

import pandas as pd

from . import solver_share as SS
from . import tolerance_study as TS
from .page_records import table_loader, tables_main
from .tolerance import READINGS

__all__ = ["KIND", "RTOL", "Tables", "params", "study", "load"]

KIND = "tolerance-tables"
#: the tolerance the chooser is judged at
RTOL = 0.005
#: the sets judged before the solver check, and of those the first two (the sample rule's)
JUDGED_SETS, SAMPLE_SETS = 3, 2


def params() -> dict[str, Any]:
    """What the tables are of: the hold-out sets, the readings and the chooser's rtol."""
    return {"sets": list(TS.SETS), "readings": list(READINGS), "rtol": RTOL}


def study(p: dict[str, Any]) -> dict[str, Any]:
    """The tables of :func:`params` ``p``, by name (see :class:`Tables` for each)."""
    sets, rtol = tuple(p["sets"]), p["rtol"]
    out: dict[str, Any] = {}
    for reading in p["readings"]:
        for name in sets[:JUDGED_SETS]:
            out[f"pairs {name} {reading}"] = TS.pairs(name, reading=reading)
            out[f"chooser {name} {reading}"] = TS.chooser(rtol, name, reading=reading)
        out[f"spread {reading}"] = TS.spread(reading=reading)
        out[f"multiples {reading}"] = TS.multiples(reading=reading)
    for name in sets[:SAMPLE_SETS]:
        out[f"coverage {name}"] = TS.coverage(
            name,
            rtol=rtol,
            pairs_=out[f"pairs {name} samples"],
            chosen=out[f"chooser {name} samples"],
        )
    out["reference error"] = TS.reference_error()
    out["alternatives"] = TS.alternatives()
    out["solver by group"] = SS.by_group(reading="continuous")
    out["solver share"] = SS.solver_share(rtol=rtol, sets=sets)
    out["solver check cost"] = float(SS.check_cost(sets=sets))
    return out


class Tables:
    """The tables of one record, named as the functions that computed them."""

    def __init__(self, tables: dict[str, Any]) -> None:
        self._t = tables

    @property
    def names(self) -> list[str]:
        """The names of the tables held."""
        return list(self._t)

    def pairs(self, name: str, reading: str = "samples") -> pd.DataFrame:
        """:func:`.tolerance_study.pairs` of the set ``name`` (one of the first three)."""
        return self._t[f"pairs {name} {reading}"].copy()

    def chooser(self, name: str, reading: str = "samples") -> pd.DataFrame:
        """:func:`.tolerance_study.chooser` at :data:`RTOL` (one of the first three sets)."""
        return self._t[f"chooser {name} {reading}"].copy()

    def coverage(self, name: str) -> pd.DataFrame:
        """:func:`.tolerance_study.coverage` off the samples (one of the first two sets)."""
        return self._t[f"coverage {name}"].copy()

    def spread(self, reading: str = "samples") -> pd.DataFrame:
        return self._t[f"spread {reading}"].copy()

    def multiples(self, reading: str = "samples") -> pd.DataFrame:
        return self._t[f"multiples {reading}"].copy()

    def reference_error(self) -> pd.DataFrame:
        return self._t["reference error"].copy()

    def alternatives(self) -> pd.DataFrame:
        return self._t["alternatives"].copy()

    def solver_by_group(self) -> pd.DataFrame:
        """:func:`.solver_share.by_group`, read in continuous time."""
        return self._t["solver by group"].copy()

    def solver_share(self) -> pd.DataFrame:
        return self._t["solver share"].copy()

    def solver_check_cost(self) -> float:
        """:func:`.solver_share.check_cost`: the solver check's extra time, a fraction."""
        return self._t["solver check cost"]


#: the record's tables as :class:`Tables` (see :func:`.page_records.table_loader`)
load = table_loader(KIND, params, study, Tables)


def main(argv: list[str] | None = None) -> int:
    """``python -m dyntorsion.studies.tolerance_tables [--on-stale ...]`` (make data-studies)."""
    return tables_main(
        KIND, __doc__.splitlines()[0], load, lambda t: f"{len(t.names)} tables", argv
    )


if __name__ == "__main__":  # make data-studies
    raise SystemExit(main())
