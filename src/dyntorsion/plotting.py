"""Shared look of the figures and where `make paper` puts them.

The plot step only reads results; :func:`save` writes ``paper/figures/<name>.png``
and ``.pdf`` when run inside the source tree (found by walking up to
``pyproject.toml``), and does nothing elsewhere.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import matplotlib

#: 150 dpi and no text under 9 pt, as the figures are read on the site
STYLE = {
    "figure.figsize": (6.0, 3.6),
    "figure.dpi": 150,
    "savefig.dpi": 150,
    "font.size": 10,
    "axes.titlesize": 10,
    "axes.labelsize": 10,
    "xtick.labelsize": 9,
    "ytick.labelsize": 9,
    "legend.fontsize": 9,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "legend.frameon": False,
    "savefig.bbox": "tight",
}


def use_style() -> None:
    """The figures' look (:data:`STYLE`); tables show a missing value as a dash, not "nan"."""
    import pandas as pd

    matplotlib.rcParams.update(STYLE)
    pd.set_option("styler.format.na_rep", "–")


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


#: matplotlib's animation player takes its button icons from a web font on a CDN;
#: these characters need no network
_ICONS = {
    "fa fa-minus": "\u2212",
    "fa fa-fast-backward": "|\u25c0\u25c0",
    "fa fa-step-backward": "|\u25c0",
    "fa fa-play fa-flip-horizontal": "\u25c0",
    "fa fa-pause": "\u275a\u275a",
    "fa fa-play": "\u25b6",
    "fa fa-step-forward": "\u25b6|",
    "fa fa-fast-forward": "\u25b6\u25b6|",
    "fa fa-plus": "+",
}


def offline_jshtml(anim, alt: str, **kwargs) -> str:
    """``anim.to_jshtml(**kwargs)`` without the icon font that it loads from the network,
    its frames described by ``alt``."""
    html = anim.to_jshtml(**kwargs)
    html = html.replace("<img id=", f'<img alt="{alt}" id=', 1)
    html = re.sub(r"<link[^>]*https?://[^>]*>", "", html)
    for cls, text in _ICONS.items():
        html = html.replace(f'<i class="{cls}"></i>', text)
    if re.search(r"https?://", html):
        raise RuntimeError("the animation still references the network")
    return html
