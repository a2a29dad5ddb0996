"""The paper's stated values, read from their one place: ``published.json``, package data
beside this module (read with :mod:`importlib.resources`, so an installed wheel has it).

Each entry has an ``id``, the quantity, its ``value``, unit, the digits stated and
where in the paper it stands; :func:`published` gives them by id and :func:`value`
one number (the package uses b and sigma of eq 34 to size its runs).
"""

from __future__ import annotations

import json
import os
from functools import lru_cache
from importlib.resources import files
from pathlib import Path
from typing import Any

__all__ = ["published", "value"]


@lru_cache(maxsize=8)
def _read(path: str | None) -> dict[str, dict[str, Any]]:
    if path is None:
        text = files("dyntorsion").joinpath("published.json").read_text(encoding="utf-8")
    else:
        try:
            text = Path(path).read_text(encoding="utf-8")
        except FileNotFoundError:
            raise FileNotFoundError(f"path={path!r}: no such file of published values") from None
    return {v["id"]: v for v in json.loads(text)["values"]}


def published(path: str | os.PathLike[str] | None = None) -> dict[str, dict[str, Any]]:
    """The paper's stated values by id (the package's ``published.json``, or ``path``)."""
    entries = _read(None if path is None else str(Path(path)))
    return {k: dict(v) for k, v in entries.items()}


def value(pid: str) -> float:
    """The stated value of ``pid`` (e.g. ``"b"``, ``"sigma"``, ``"kappa_cri"``)."""
    entries = published()
    if pid not in entries:
        raise KeyError(f"pid={pid!r} is not a published value; known: {', '.join(entries)}")
    return float(entries[pid]["value"])
