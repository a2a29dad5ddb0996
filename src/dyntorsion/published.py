"""The paper's stated values, read from their one place: ``paper/published.json``.

Each entry has an ``id``, the quantity, its ``value``, unit, the digits stated and
where in the paper it stands; :func:`published` gives them by id and :func:`value`
one number (the package uses b and sigma of eq 34 to size its runs).
"""

from __future__ import annotations

import json
import os
from functools import lru_cache
from pathlib import Path
from typing import Any

__all__ = ["PAPER", "published", "value"]

#: the source tree's paper folder (published.json, numbers.json, figures/)
PAPER = Path(__file__).resolve().parents[2] / "paper"


@lru_cache(maxsize=8)
def _read(path: str) -> dict[str, dict[str, Any]]:
    try:
        data = json.loads(Path(path).read_text())
    except FileNotFoundError:
        raise FileNotFoundError(
            f"{path}: the paper's stated values are read from the source tree's "
            "paper/published.json (install the package from a checkout: pip install -e .)"
        ) from None
    return {v["id"]: v for v in data["values"]}


def published(path: str | os.PathLike[str] | None = None) -> dict[str, dict[str, Any]]:
    """The paper's stated values by id (``paper/published.json``)."""
    entries = _read(str(Path(path) if path else PAPER / "published.json"))
    return {k: dict(v) for k, v in entries.items()}


def value(pid: str) -> float:
    """The stated value of ``pid`` (e.g. ``"b"``, ``"sigma"``, ``"kappa_cri"``)."""
    entries = published()
    if pid not in entries:
        raise KeyError(f"pid={pid!r} is not in paper/published.json; known: {', '.join(entries)}")
    return float(entries[pid]["value"])
