"""Where records are kept: the store used when none is given.

In order: ``$DYNTORSION_DATA`` if set; else, when the package runs from a checkout of its
repository (an editable install or ``PYTHONPATH=src``), the checkout's ``data/scenes``, so
that ``make data`` and ``make paper`` share the committed records; else a per-user cache
folder (``platformdirs.user_cache_dir("dyntorsion")/scenes``), so that an installed wheel
never writes into ``site-packages``.
"""

from __future__ import annotations

import os
from pathlib import Path

from platformdirs import user_cache_dir

__all__ = ["checkout", "DATA", "default_store", "store_origin"]


def checkout(start: Path | None = None) -> Path | None:
    """The root of the repository checkout that holds this package's source, or None for an
    installed package: the first folder above ``start`` (default: this file) with a
    ``pyproject.toml`` naming dyntorsion beside ``src/dyntorsion``."""
    here = (start or Path(__file__)).resolve()
    for d in (here, *here.parents):
        project = d / "pyproject.toml"
        if project.is_file() and (d / "src" / "dyntorsion").is_dir():
            if 'name = "dyntorsion"' in project.read_text(errors="replace"):
                return d
    return None


_ROOT = checkout()
#: the checkout's store (``data/scenes``), or None when the package is installed
DATA = None if _ROOT is None else _ROOT / "data" / "scenes"


def store_origin() -> tuple[Path, str]:
    """The default store and why it was chosen."""
    env = os.environ.get("DYNTORSION_DATA")
    if env:
        return Path(env), "DYNTORSION_DATA is set"
    if DATA is not None:
        return DATA, f"the checkout at {_ROOT}"
    return Path(user_cache_dir("dyntorsion")) / "scenes", "the user cache (installed package)"


def default_store() -> Path:
    """The store used when none is given (see the module docstring)."""
    return store_origin()[0]
