"""One record of a study that a page reads: read it, or compute and save it (``make data-studies``).

Tables a page derives from many other records (:func:`read_or_compute_frames`) are kept
the same way, as pandas DataFrames written by :func:`frame_to_json` and read back by
:func:`frame_from_json` with their index, columns, dtypes and infinities intact."""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
import pandas as pd

from ..store.location import default_store
from ..store.results import ON_STALE, Store
from . import fidelity

__all__ = [
    "read_or_compute",
    "read_or_compute_at",
    "level_loader",
    "read_or_compute_frames",
    "table_loader",
    "tables_main",
    "frame_to_json",
    "frame_from_json",
    "main_by_level",
]

#: the layout :func:`frame_to_json` writes; part of every table record's key, so that a
#: record written in another layout is missing, never misread
FRAME_FORMAT = 2

#: how a non-finite float is written (JSON has no NaN or infinity): {"float": name}
_NON_FINITE = {"nan": math.nan, "inf": math.inf, "-inf": -math.inf}


def _cell(v: Any) -> Any:
    """One value of a frame as JSON holds it: numpy scalars as Python ones, a non-finite
    float as ``{"float": "nan" | "inf" | "-inf"}``."""
    if isinstance(v, np.generic):
        v = v.item()
    if isinstance(v, float) and not math.isfinite(v):
        return {"float": "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf")}
    if isinstance(v, dict | list | tuple):
        raise TypeError(f"value {v!r}: a page record's frame holds numbers, booleans and strings")
    return v


def _uncell(v: Any) -> Any:
    return _NON_FINITE[v["float"]] if isinstance(v, dict) else v


def _axis_to_json(axis: pd.Index) -> dict[str, Any]:
    if isinstance(axis, pd.RangeIndex):
        return {"range": [axis.start, axis.stop, axis.step], "names": [axis.name]}
    levels = [axis.get_level_values(i) for i in range(axis.nlevels)]
    return {
        "levels": [[_cell(v) for v in level.tolist()] for level in levels],
        "dtypes": [str(level.dtype) for level in levels],
        "names": list(axis.names),
    }


def _axis_from_json(d: Mapping[str, Any]) -> pd.Index:
    if "range" in d:
        return pd.RangeIndex(*d["range"], name=d["names"][0])
    arrays = [
        pd.Index([_uncell(v) for v in values], dtype=dtype)
        for values, dtype in zip(d["levels"], d["dtypes"], strict=True)
    ]
    if len(arrays) > 1:
        return pd.MultiIndex.from_arrays(arrays, names=d["names"])
    return arrays[0].rename(d["names"][0])


def frame_to_json(frame: pd.DataFrame) -> dict[str, Any]:
    """``frame`` as JSON-ready lists: its index and columns (each level's values, dtype and
    name), the values row by row and each column's dtype.  Raises a TypeError for what
    :func:`frame_from_json` cannot restore (a column of another dtype than numbers,
    booleans and strings, or a cell holding a container)."""
    for col, dtype in frame.dtypes.items():
        if dtype.kind not in "fiubO" and not isinstance(dtype, pd.StringDtype):
            raise TypeError(f"column {col!r} has dtype {dtype}: not kept in a page record")
    return {
        "index": _axis_to_json(frame.index),
        "columns": _axis_to_json(frame.columns),
        "data": [[_cell(v) for v in row] for row in frame.itertuples(index=False, name=None)],
        "dtypes": [str(d) for d in frame.dtypes],
    }


def frame_from_json(d: Mapping[str, Any]) -> pd.DataFrame:
    """The DataFrame :func:`frame_to_json` wrote (equal to the original, dtypes and all)."""
    data = [[_uncell(v) for v in row] for row in d["data"]]
    index, columns = _axis_from_json(d["index"]), _axis_from_json(d["columns"])
    frame = pd.DataFrame(data or None, index=index, columns=columns, dtype=object)
    for j, dtype in enumerate(d["dtypes"]):
        frame.isetitem(j, frame.iloc[:, j].astype(dtype))
    return frame


def read_or_compute_frames(
    kind: str,
    params: Mapping[str, Any],
    make: Callable[[], Mapping[str, Any]],
    store: Store | str | None = None,
    *,
    compute: bool = False,
    on_stale: str = "recompute",
) -> dict[str, Any]:
    """:func:`read_or_compute` of a record of named tables: ``make()`` returns a mapping of
    names to DataFrames or JSON-ready values; the same mapping comes back, the frames as
    they were made.  The record is keyed by ``params`` and :data:`FRAME_FORMAT`."""
    params = {**params, "frame_format": FRAME_FORMAT}

    def encoded() -> dict[str, Any]:
        out = {}
        for name, value in make().items():
            is_frame = isinstance(value, pd.DataFrame)
            out[name] = {"frame": frame_to_json(value)} if is_frame else {"value": value}
        return out

    rec = read_or_compute(kind, params, encoded, store, compute=compute, on_stale=on_stale)
    return {
        name: frame_from_json(v["frame"]) if "frame" in v else v["value"] for name, v in rec.items()
    }


def table_loader(
    kind: str,
    params: Callable[[], Mapping[str, Any]],
    study: Callable[[Mapping[str, Any]], Mapping[str, Any]],
    wrap: Callable[[dict[str, Any]], Any] = dict,
) -> Callable[..., Any]:
    """The ``load(store=None, *, compute=False, on_stale="recompute")`` of a table record
    of ``kind``, keyed by ``params()`` and made by ``study``: its tables (through ``wrap``)
    from ``store`` (default data/scenes), computed when missing or stale with
    ``compute=True`` (a stale one refused with ``on_stale="error"``), refused otherwise
    (:class:`LookupError` naming ``make data-studies``)."""

    def load(store: Store | str | None = None, *, compute: bool = False,
             on_stale: str = "recompute") -> Any:  # fmt: skip
        """The record's tables from ``store``: computed when missing or stale with
        ``compute=True``, else refused with a LookupError (:func:`table_loader`)."""
        p = params()
        tables = read_or_compute_frames(
            kind, p, lambda: study(p), store, compute=compute, on_stale=on_stale
        )
        return wrap(tables)

    return load


def tables_main(
    kind: str,
    description: str,
    load: Callable[..., Any],
    summary: Callable[[Any], str],
    argv: list[str] | None = None,
) -> int:
    """The command line of a table record (``make data-studies``): ``--on-stale`` and
    ``--store``; ``load(store, compute=True, on_stale=...)`` and one line, ``kind`` and
    ``summary`` of what it loaded."""
    import argparse

    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--on-stale", choices=ON_STALE, default="recompute")
    parser.add_argument("--store", default=None)
    args = parser.parse_args(argv)
    print(f"{kind}: {summary(load(args.store, compute=True, on_stale=args.on_stale))}")
    return 0


def read_or_compute(
    kind: str,
    params: Mapping[str, Any],
    make: Callable[[], Mapping[str, Any]],
    store: Store | str | None = None,
    *,
    compute: bool = False,
    on_stale: str = "recompute",
    what: str = "",
) -> dict[str, Any]:
    """The result of the ``kind`` record of ``params`` in ``store`` (default data/scenes).
    Missing or stale: with ``compute=True`` ``make()`` computes it and it is saved with its
    wall time (a stale one is refused with ``on_stale="error"``); without, a
    :class:`LookupError` names the record (``what``) and ``make data-studies``."""
    if not isinstance(store, Store):
        store = Store(default_store() if store is None else store)
    rec = store.load(kind, params, on_stale=on_stale if compute else "error")
    if rec is None:
        if not compute:
            raise LookupError(f"no {kind} record{what} in {store.root}: run `make data-studies`")
        start = time.perf_counter()
        result = make()
        rec = store.read(store.save(kind, params, result, time.perf_counter() - start))
    return rec["result"]


def read_or_compute_at(
    kind: str,
    level: str | None,
    params: Callable[[str], Mapping[str, Any]],
    study: Callable[[Mapping[str, Any]], Mapping[str, Any]],
    store: Store | str | None = None,
    *,
    compute: bool = False,
    on_stale: str = "recompute",
) -> dict[str, Any]:
    """:func:`read_or_compute` of the record keyed by ``params(level)`` and computed by
    ``study`` on it, at fidelity ``level`` (default :func:`~.fidelity.level`; another
    name raises a ValueError naming the allowed levels)."""
    level = fidelity.check_level(level or fidelity.level())
    p = params(level)
    return read_or_compute(
        kind, p, lambda: study(p), store, compute=compute, on_stale=on_stale, what=f" at {level}"
    )


def level_loader(
    kind: str,
    params: Callable[[str], Mapping[str, Any]],
    study: Callable[[Mapping[str, Any]], Mapping[str, Any]],
) -> Callable[..., dict[str, Any]]:
    """The ``load(level=None, store=None, *, compute=False, on_stale="recompute")`` of a page
    record kept per fidelity level (:func:`read_or_compute_at` of ``kind``, ``params`` and
    ``study``)."""

    def load(level: str | None = None, store: Store | str | None = None, *,
             compute: bool = False, on_stale: str = "recompute") -> dict[str, Any]:  # fmt: skip
        """The record at fidelity ``level`` (default :func:`~.fidelity.level`) from ``store``
        (default data/scenes): computed when missing or stale with ``compute=True`` (a stale
        one refused with ``on_stale="error"``), refused otherwise (:class:`LookupError`)."""
        return read_or_compute_at(kind, level, params, study, store, compute=compute,
                                  on_stale=on_stale)  # fmt: skip

    return load


def main_by_level(
    kind: str,
    description: str,
    load: Callable[..., Mapping[str, Any]],
    summary: Callable[[Mapping[str, Any]], str],
    levels: tuple[str, ...] = ("quick", "standard"),
) -> None:
    """The command line of a page record kept per level (``make data-studies``):
    ``--on-stale`` and ``--level`` (repeatable, default ``levels``); for each level,
    ``load(level, compute=True, on_stale=...)`` and one line: ``kind``, the level and
    ``summary`` of the record's result."""
    import argparse

    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--on-stale", choices=ON_STALE, default="recompute")
    parser.add_argument("--level", choices=fidelity.LEVELS, action="append")
    args = parser.parse_args()
    for lvl in args.level or list(levels):
        print(f"{kind} [{lvl}]: {summary(load(lvl, compute=True, on_stale=args.on_stale))}")
