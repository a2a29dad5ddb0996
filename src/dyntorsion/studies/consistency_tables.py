"""The consistency study's derived tables on the page "Are the paper's numbers
consistent?", kept as one record.

What the page reads of the scan of every (seed, form, rule, rate range) triple
(:func:`.readings.scan`), the fit of every cell of the map (:func:`.claims.fits`) and the
cell closest to holding the four claims (:func:`.claims.closest`) takes tens of thousands
of least-squares fits.  The record
of kind ``consistency-tables`` (``make data-studies``) keeps them, so the page reads them
at once; its fingerprint reaches the functions that compute them and the code of the
``onset-rules`` records they read.
"""

from __future__ import annotations

from typing import Any

import pandas as pd

from . import claims, consistency
from . import readings as R
from .page_records import table_loader, tables_main

__all__ = ["KIND", "SCAN_STEP", "BAND", "Tables", "params", "study", "load"]

KIND = "consistency-tables"
#: the scan's seeds: every SCAN_STEP decades of the map's range
SCAN_STEP = 0.25
#: the fits are made where claim 1 could hold within BAND (relative)
BAND = 0.05


def params() -> dict[str, Any]:
    """What the tables are of: the scan's step in decades of seed and claim 1's band."""
    return {"scan_step": SCAN_STEP, "band": BAND}


def study(p: dict[str, Any]) -> dict[str, Any]:
    """The tables of :func:`params` ``p`` (see :class:`Tables`), from the scan of every
    triple at every seed (:func:`.readings.scan`, 20,000 rows, not kept itself)."""
    maps, direct = consistency.table("map"), consistency.table("direct")
    grid_error = claims.fig8_grid_error()
    scan = R.scan(maps, direct, grid_error, step=p["scan_step"], band=p["band"])
    held = R.held(scan, grid_error)
    where = []
    for tol in R.CLAIM3:
        for form in ("uniform", "point"):
            g = scan[(scan.c3_rms <= tol) & (scan.form == form)]
            where.append({"claim3": tol, "form": form, "cells": len(g),
                          "seed_min": g.seed.min(), "seed_max": g.seed.max(),
                          "fig8_min": g.direct_fig8.min(), "fig8_max": g.direct_fig8.max(),
                          "c1_min": g.c1.min()})  # fmt: skip
    counts = {
        "triples": int(scan.groupby(["form", "rule", "a_lo", "a_hi"]).ngroups),
        "3": R.count(scan, held["3"]),
        "3 and 4": R.count(scan, held["3"] & held["4"]),
        "2 and 3": R.count(scan, held["2"] & held["3"]),
        "2 and 4": R.count(scan, held["2"] & held["4"]),
    }
    return {
        "at claim 1": scan[scan.claim1_seed].reset_index(drop=True),
        "tolerance table": R.tolerance_table(scan, grid_error),
        "claim 3 where": pd.DataFrame(where),
        "counts": counts,
        "fits": claims.fits(maps)[["seed", "b", "sigma"]],
        "closest": claims.closest().to_frame().T.reset_index(drop=True),
    }


class Tables:
    """The tables of one record."""

    def __init__(self, tables: dict[str, Any]) -> None:
        self._t = tables

    def at_claim1_seed(self) -> pd.DataFrame:
        """The rows of :func:`.readings.scan` at the seed of claim 1 of each form and rule."""
        return self._t["at claim 1"].copy()

    def tolerance_table(self) -> pd.DataFrame:
        """:func:`.readings.tolerance_table` of the whole scan."""
        return self._t["tolerance table"].copy()

    def claim3_where(self) -> pd.DataFrame:
        """Per tolerance of claim 3 (``claim3``) and seed ``form``: the scan's ``cells``
        that hold it, their range of seeds, of the direct Fig 8 run's t_c [s] and the
        smallest miss of claim 1 ``c1_min`` [s] (NaN where none holds)."""
        return self._t["claim 3 where"].copy()

    def counts(self) -> dict[str, int]:
        """The scan's ``triples`` (form, rule, rate range) and how many hold claim 3, and
        the pairs of claims, at some seed (default readings, :func:`.readings.held`)."""
        return dict(self._t["counts"])

    def fits(self) -> pd.DataFrame:
        """:func:`.claims.fits` of the map: each cell's ``seed``, ``b`` and ``sigma``."""
        return self._t["fits"].copy()

    def closest(self) -> pd.Series:
        """:func:`.claims.closest`: the cell closest to holding the four claims."""
        return self._t["closest"].iloc[0].copy()


#: the record's tables as :class:`Tables` (see :func:`.page_records.table_loader`)
load = table_loader(KIND, params, study, Tables)


def main(argv: list[str] | None = None) -> int:
    """``python -m dyntorsion.studies.consistency_tables [--on-stale ...]`` (make data-studies)."""
    return tables_main(
        KIND,
        __doc__.splitlines()[0],
        load,
        lambda t: f"{t.counts()['triples']} triples, fits {len(t.fits())} cells",
        argv,
    )


if __name__ == "__main__":  # make data-studies
    raise SystemExit(main())
