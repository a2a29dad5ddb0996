"""One record of a study that a page reads: read it, or compute and save it (``make data-studies``)."""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping
from typing import Any

from ..store.location import default_store
from ..store.results import Store

__all__ = ["read_or_compute"]


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
