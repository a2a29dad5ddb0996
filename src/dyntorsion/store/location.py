"""Where records are kept: the store used when none is given."""

from __future__ import annotations

import os
from pathlib import Path

__all__ = ["DATA", "default_store"]

#: the source tree's data folder (``data/scenes``)
DATA = Path(__file__).resolve().parents[3] / "data" / "scenes"


def default_store() -> Path:
    """The store used when none is given: ``$DYNTORSION_DATA`` if set, else :data:`DATA`."""
    env = os.environ.get("DYNTORSION_DATA")
    return Path(env) if env else DATA
