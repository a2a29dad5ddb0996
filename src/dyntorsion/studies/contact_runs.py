"""Runs past contact cached in the store: record kind ``"contact-run"``.

A :class:`~dyntorsion.beyond.contact.run.ContactScene` is keyed by its whole
:meth:`~dyntorsion.beyond.contact.run.ContactScene.params` (the scene's key plus the
contact's numbers), so a record is never served for another scene or another contact law;
its code fingerprint covers :func:`~dyntorsion.beyond.contact.run.run_contact_scene` and
everything it reaches, so a changed contact code makes it stale.  The result holds the
run's summary (what ``dyntorsion buckle --contact --json`` prints), its histories at the
checks (link, twist, writhe, contact sites, overlap, energies, the twisting moment at
s = 0) and its final centreline; the shapes at every check are not kept.
"""

from __future__ import annotations

import os
import time
from pathlib import Path
from typing import Any

from ..beyond.contact.run import ContactScene, run_contact_scene
from ..store.location import default_store
from ..store.results import Store, UnsavedResultError, json_ready

__all__ = ["KIND", "contact_run"]

#: the record kind of a run past contact (:mod:`dyntorsion.studies.kinds`)
KIND = "contact-run"


def contact_run(
    cs: ContactScene, store: str | os.PathLike[str] | None = None, on_stale: str = "recompute"
) -> tuple[dict[str, Any], bool]:
    """The run of ``cs`` to its scene's ``t_end``, read from ``store`` (default: the
    package's store) or computed and written there; returns (result, whether it was read).
    ``on_stale`` as :meth:`~dyntorsion.store.results.Store.load`."""
    if not isinstance(cs, ContactScene):
        raise TypeError(f"cs={cs!r} must be a ContactScene")
    st = Store(Path(store) if store is not None else default_store())
    params = cs.params()
    record = st.load(KIND, params, on_stale=on_stale)
    if record is not None:
        return record["result"], True
    lease = st.lease(KIND, params)  # before the run: an unwritable store fails now
    try:
        return _computed(cs, st, params), False
    finally:
        if lease is not None:
            lease.release()


def _computed(cs: ContactScene, st: Store, params: dict[str, Any]) -> dict[str, Any]:
    """Run ``cs`` and write its record; a record that cannot be written raises
    :class:`~dyntorsion.store.results.UnsavedResultError` holding the result."""
    tick = time.perf_counter()
    run = run_contact_scene(cs)
    h = run.history
    result = json_ready(
        {
            "summary": run.result(),
            "history": {k: v for k, v in h.items() if k != "r"},
            "final_centreline": h["r"][-1],
        }
    )
    try:
        st.save(KIND, params, result, time.perf_counter() - tick)
    except OSError as err:
        lost = UnsavedResultError(
            err.errno, f"{err.strerror}; the run is printed, not kept", err.filename
        )
        lost.result = result
        raise lost from err
    return result
