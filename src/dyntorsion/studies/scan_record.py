"""The consistency scan as a record: every triple of the consistency map judged at the
seeds of a scan (:func:`dyntorsion.studies.readings.scan`), computed once by ``make data``
and read by the Consistency page.

The scan is computed from other records (the map, the direct runs, the Fig 8 grid error),
so a record of kind ``readings-scan`` is keyed by the scan's settings *and* a digest of
those inputs: recomputed inputs that differ leave no record to read (the page then asks
for ``make data``), and its code fingerprint covers the scan and the reading of its inputs.
"""

from __future__ import annotations

import hashlib
import math
from typing import Any

import numpy as np
import pandas as pd

from ..store.results import Store
from . import claims, consistency, readings
from .page_records import read_or_compute

__all__ = ["KIND", "STEP", "BAND", "inputs_digest", "scan_table", "load", "compute"]

KIND = "readings-scan"

#: the scan's step in seed [decades] and the band of claim 1 (relative) the page reads
STEP, BAND = 0.25, 0.05


def inputs_digest(map_table: pd.DataFrame, direct: pd.DataFrame, grid_error: float) -> str:
    """20 hex digits of a hash of the scan's inputs (every value, index and column name)."""
    h = hashlib.sha256()
    for table in (map_table, direct):
        h.update(",".join(map(str, table.columns)).encode())
        h.update(pd.util.hash_pandas_object(table, index=True).to_numpy().tobytes())
    h.update(repr(float(grid_error)).encode())
    return h.hexdigest()[:20]


def _column(values: pd.Series) -> list:
    """JSON-ready values; in a float column NaN as None and infinities as "inf"/"-inf"."""
    if values.dtype.kind != "f":
        return [v.item() if isinstance(v, np.generic) else v for v in values]
    return [
        None if math.isnan(v) else (("inf" if v > 0 else "-inf") if math.isinf(v) else v)
        for v in values.tolist()
    ]


def scan_table(
    map_table: pd.DataFrame, direct: pd.DataFrame, grid_error: float, step: float, band: float
) -> dict[str, Any]:
    """:func:`~dyntorsion.studies.readings.scan` as a record's result: its columns, their
    order and their dtypes."""
    df = readings.scan(map_table, direct, grid_error, step=step, band=band)
    return {
        "columns": {c: _column(df[c]) for c in df.columns},
        "order": list(map(str, df.columns)),
        "dtypes": {c: str(t) for c, t in df.dtypes.items()},
    }


def _frame(result: dict[str, Any]) -> pd.DataFrame:
    df = pd.DataFrame(result["columns"])[result["order"]]
    return df.astype(result["dtypes"])


def load(
    map_table: pd.DataFrame,
    direct: pd.DataFrame,
    grid_error: float,
    step: float = STEP,
    band: float = BAND,
    store: Store | str | None = None,
    *,
    compute: bool = False,
    on_stale: str = "recompute",
) -> pd.DataFrame:
    """The scan of these inputs at ``step`` [decades] and ``band`` from ``store`` (default
    data/scenes): computed when missing or stale with ``compute=True`` (a stale one refused
    with ``on_stale="error"``), refused otherwise (:class:`LookupError` naming ``make data``)."""
    params = {"step": step, "band": band, "inputs": inputs_digest(map_table, direct, grid_error)}
    result = read_or_compute(
        KIND,
        params,
        lambda: scan_table(map_table, direct, grid_error, step, band),
        store,
        compute=compute,
        on_stale=on_stale,
        what=" for these map and direct runs",
    )
    return _frame(result)


def compute(on_stale: str = "recompute") -> pd.DataFrame:
    """The page's scan from the committed map and direct runs (``make data``)."""
    maps, direct = consistency.table("map"), consistency.table("direct")
    return load(maps, direct, claims.fig8_grid_error(), compute=True, on_stale=on_stale)


if __name__ == "__main__":  # make data
    import argparse

    from ..store.results import ON_STALE

    parser = argparse.ArgumentParser(description="compute the consistency scan")
    parser.add_argument("--on-stale", choices=ON_STALE, default="recompute")
    args = parser.parse_args()
    print(f"{KIND}: {len(compute(args.on_stale))} rows")
