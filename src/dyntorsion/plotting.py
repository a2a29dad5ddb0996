"""Shared look of the figures and where `make paper` puts them.

The plot step only reads results; :func:`save` writes ``paper/figures/<name>.png``
and ``.pdf`` when run inside the source tree (found by walking up to
``pyproject.toml``), and does nothing elsewhere.
"""

from __future__ import annotations

import os
from pathlib import Path

import matplotlib

STYLE = {
    "figure.figsize": (6.0, 3.6),
    "figure.dpi": 110,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "legend.frameon": False,
    "savefig.bbox": "tight",
}


def use_style() -> None:
    matplotlib.rcParams.update(STYLE)


def project_root(start: Path | None = None) -> Path | None:
    here = (start or Path.cwd()).resolve()
    for d in (here, *here.parents):
        if (d / "pyproject.toml").is_file() and (d / "src" / "dyntorsion").is_dir():
            return d
    return None


def figure_dir() -> Path | None:
    env = os.environ.get("DYNTORSION_FIGURES")
    if env:
        return Path(env)
    root = project_root()
    return None if root is None else root / "paper" / "figures"


def save(fig, name: str) -> None:
    """Write ``name``.png and ``name``.pdf to the figure directory (if there is one)."""
    out = figure_dir()
    if out is None:
        return
    out.mkdir(parents=True, exist_ok=True)
    paths = [out / f"{name}.{ext}" for ext in ("png", "pdf")]
    for p in paths:
        tmp = p.with_name(p.stem + ".tmp" + p.suffix)
        fig.savefig(tmp)
        os.replace(tmp, p)
