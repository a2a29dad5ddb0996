"""One record of a study that a page reads: read it, or compute and save it (``make data-studies``)."""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping
from typing import Any

from ..store.location import default_store
from ..store.results import ON_STALE, Store
from . import fidelity

__all__ = ["read_or_compute", "read_or_compute_at", "main_by_level"]


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
