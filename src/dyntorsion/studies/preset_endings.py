"""How every run of the named sweeps ended, kept as one record for the page "After the
onset".

Every preset's records (:data:`.presets.PRESETS`, thousands of them) are read to list how
each run ended (:func:`ending`: self-contact, the first peak of |u3(L)| for runs asked to
end there, a Newton failure at the smallest step, or t_end).  The record of kind ``preset-endings`` (``make data-studies``) keeps that list, so
the page reads it at once; its fingerprint reaches the presets and the code of the onset
records they read.
"""

from __future__ import annotations

from typing import Any

import pandas as pd

from . import presets as P
from .page_records import table_loader, tables_main

__all__ = ["KIND", "ENDINGS", "ending", "params", "study", "load"]

KIND = "preset-endings"

#: how a run can end, as :func:`ending` names it
ENDINGS = ("self-contact", "first peak", "Newton failure at Δt_min", "t_end")


def ending(stopped: str) -> str:
    """How a run ended (one of :data:`ENDINGS`), from its record's ``stopped``."""
    if stopped.startswith("self-contact"):
        return ENDINGS[0]
    if stopped.startswith("first peak"):
        return ENDINGS[1]  # Scene(until="first-peak") ends the run there
    if stopped.startswith("failed"):
        return ENDINGS[2]
    return ENDINGS[3]


def params() -> dict[str, Any]:
    """What the list is of: the named sweeps."""
    return {"presets": list(P.PRESETS)}


def study(p: dict[str, Any]) -> dict[str, Any]:
    """One row per scene of each preset of ``p``: ``preset``, the record's ``key`` and how
    the run ended, ``end`` (:func:`ending`; a scene in two presets has a row in each)."""
    frames = []
    for name in p["presets"]:
        table = P.cached(name)
        frames.append(
            pd.DataFrame({"preset": name, "key": table.key, "end": table.stopped.map(ending)})
        )
    return {"endings": pd.concat(frames, ignore_index=True)}


def _endings(tables: dict[str, Any]) -> pd.DataFrame:
    return tables["endings"]


#: the list (columns ``preset, key, end``; see :func:`.page_records.table_loader`)
load = table_loader(KIND, params, study, _endings)


def main(argv: list[str] | None = None) -> int:
    """``python -m dyntorsion.studies.preset_endings [--on-stale ...]`` (make data-studies)."""
    return tables_main(
        KIND,
        __doc__.splitlines()[0],
        load,
        lambda e: f"{len(e)} runs of {e.preset.nunique()} presets",
        argv,
    )


if __name__ == "__main__":  # make data-studies
    raise SystemExit(main())
