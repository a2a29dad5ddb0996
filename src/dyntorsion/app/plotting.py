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
import numpy as np

from ..store.location import checkout

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
    """The figures' look (:data:`STYLE`); tables show a missing value as a dash, not "nan",
    and, in a notebook, no row numbers (:func:`table_html`)."""
    import pandas as pd

    matplotlib.rcParams.update(STYLE)
    pd.set_option("styler.format.na_rep", "–")
    try:
        from IPython import get_ipython
    except ImportError:  # pragma: no cover - IPython comes with the docs extras
        return
    from pandas.io.formats.style import Styler

    shell = get_ipython()
    if shell is not None:
        html = shell.display_formatter.formatters["text/html"]
        html.for_type(pd.DataFrame, table_html)
        html.for_type(Styler, table_html)


def table_html(table) -> str:
    """A data frame or its ``Styler`` as HTML for the site: the index is shown only when
    it says something (not 0, 1, 2, ...), and then as the first column, not as a header
    row of its own; missing values are a dash; numbers without trailing zeros
    (``0.200000`` is ``0.2``, a zero ``0``) and with a minus sign; subscripts and
    superscripts of the headers typeset (``t_c`` as t<sub>c</sub>, ``x^4`` as x<sup>4</sup>)."""
    import pandas as pd

    if isinstance(table, pd.DataFrame):
        frame, styler = table, None
    else:
        frame, styler = table.data, table
    if not _row_numbers(frame.index):  # a meaningful index: a column like the others
        frame = frame.reset_index()
        styler = None if styler is None else _restyle(styler, frame)
    if styler is None:
        html = frame.to_html(index=False, na_rep="–", border=0, float_format=_number)
    else:
        html = styler.hide(axis="index").to_html()
    # a column given its own format shows NaN as "nan" whatever styler.format.na_rep says
    html = re.sub(r">\s*nan\s*</td>", ">–</td>", html)
    html = re.sub(r"(<td[^>]*>)\s*([-+]?[0-9.]+(?:e[-+]?[0-9]+)?)\s*(</td>)", _tidy_cell, html)
    return re.sub(r"(<th[^>]*>)(.*?)(</th>)", _typeset_header, html, flags=re.S)


def _restyle(styler, frame):
    """``styler``'s formats carried over to ``frame`` (its data with the index as columns)."""
    fresh = frame.style
    fresh._display_funcs.update(  # private, but the only way to keep the column formats
        {
            (i, j + frame.shape[1] - styler.data.shape[1]): f
            for (i, j), f in styler._display_funcs.items()
        }
    )
    return fresh


_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def _number(x: float) -> str:
    """A float of a table without a format of its own: six significant figures, no
    trailing zeros, e-notation only for very small or large numbers."""
    from .glance import sci

    return sci(float(x))


def _tidy_cell(m) -> str:
    """A number alone in a table cell: trailing zeros after the point dropped, a zero
    written 0, a minus sign for a hyphen."""
    text = m.group(2)
    if "e" in text:  # 1.50e-03 -> 1.50 × 10⁻³, the digits as formatted
        mant, expo = text.split("e")
        power = "10" + str(int(expo)).translate(_SUPERSCRIPT)
        text = power if mant in ("1", "1.0") else f"{mant} × {power}"
    elif "." in text:
        text = text.rstrip("0").rstrip(".")
        if text in ("", "-", "+", "-0", "+0"):
            text = "0"
    return m.group(1) + text.replace("-", "\u2212", 1 if text.startswith("-") else 0) + m.group(3)


_SUB = re.compile(r"(?<=[A-Za-z\u0391-\u03c9])_(\{[^}]*\}|[A-Za-z0-9]+)")
_SUP = re.compile(r"\^(\([^)]*\)|\{[^}]*\}|-?[0-9]+)")
_GREEK_DIGIT = re.compile(r"(?<=[\u03ba\u03c9])([0-9])\b")  # kappa3, omega3 -> subscript


def _typeset_header(m) -> str:
    """``t_c`` -> t<sub>c</sub>, ``x^4`` -> x<sup>4</sup>, ``κ3`` -> κ<sub>3</sub> in a header."""
    text = _SUB.sub(lambda s: f"<sub>{s.group(1).strip('{}')}</sub>", m.group(2))
    text = _SUP.sub(lambda s: f"<sup>{s.group(1).strip('{}')}</sup>", text)
    text = _GREEK_DIGIT.sub(r"<sub>\1</sub>", text)
    return m.group(1) + text + m.group(3)


def _row_numbers(index) -> bool:
    """An unnamed integer index numbers rows (a meaningful one has a name)."""
    return index.nlevels == 1 and index.name is None and index.dtype.kind in "iu"


def project_root(start: Path | None = None) -> Path | None:
    """The checkout the current folder (or ``start``) lies in, or None."""
    return checkout(start or Path.cwd())


def figure_dir() -> Path | None:
    env = os.environ.get("DYNTORSION_FIGURES")
    if env:
        return Path(env)
    root = project_root()
    return None if root is None else root / "paper" / "figures"


#: the smallest text a figure may carry [pt]
MIN_FONT_PT = 9.0


def check_text_size(fig, name: str = "figure") -> None:
    """Raise ``ValueError`` naming each visible text of ``fig`` smaller than
    :data:`MIN_FONT_PT`."""
    from matplotlib.text import Text

    small = sorted(
        {
            f"{t.get_text()!r} ({t.get_fontsize():g} pt)"
            for t in fig.findobj(Text)
            if t.get_visible() and t.get_text().strip() and t.get_fontsize() < MIN_FONT_PT
        }
    )
    if small:
        raise ValueError(
            f"{name}: text under {MIN_FONT_PT:g} pt, too small to read on the site: "
            + ", ".join(small[:8])
        )


def _drawn(artist, ax, renderer) -> bool:
    """Whether ``artist`` (a legend entry of ``ax``) leaves a mark inside ``ax``."""
    from matplotlib.collections import Collection, PathCollection
    from matplotlib.container import Container
    from matplotlib.lines import Line2D
    from matplotlib.path import Path as MplPath

    if isinstance(artist, Container):  # errorbar, bar: drawn if any part is
        return any(_drawn(a, ax, renderer) for a in artist.get_children() if a is not None)
    if not artist.get_visible():
        return False
    if ax.name == "3d":  # projected on drawing: only an empty artist is known not to show
        segments = getattr(artist, "_segments3d", None)
        data = artist.get_data_3d() if hasattr(artist, "get_data_3d") else None
        return (segments is None or len(segments) > 0) and (data is None or len(data[0]) > 0)
    box = ax.get_window_extent(renderer)
    if isinstance(artist, Line2D):
        xy = artist.get_transform().transform(artist.get_xydata())
        xy = xy[np.isfinite(xy).all(axis=1)]
        if len(xy) == 0:
            return False
        if box.count_contains(xy) > 0:
            return True
        return (
            len(xy) > 1
            and artist.get_linestyle() not in ("None", " ", "")
            and (MplPath(xy).intersects_bbox(box, filled=False))
        )
    if isinstance(artist, PathCollection):  # scatter: its points, in display units
        xy = artist.get_offset_transform().transform(np.asarray(artist.get_offsets(), float))
        return box.count_contains(xy[np.isfinite(xy).all(axis=1)]) > 0
    if isinstance(artist, Collection):  # bands, polygons: their data limits
        limits = artist.get_datalim(ax.transData)
        return bool(np.isfinite(limits.get_points()).all()) and limits.transformed(
            ax.transData
        ).overlaps(box)
    extent = artist.get_window_extent(renderer)
    return extent.width >= 0 and extent.height >= 0 and extent.overlaps(box)


def check_legend(fig, name: str = "figure") -> None:
    """Raise ``ValueError`` naming each legend entry of ``fig`` whose artist leaves no mark
    in its axes (invisible, empty, or wholly outside the axis limits): a reader would look
    for a curve that is not there."""
    renderer = fig.canvas.get_renderer()
    legends = [ax.get_legend() for ax in fig.axes] + list(fig.legends)
    shown = {t.get_text() for lg in legends if lg is not None for t in lg.get_texts()}
    if not shown:
        return
    missing = set()
    for ax in fig.axes:
        for artist, label in zip(*ax.get_legend_handles_labels(), strict=True):
            if label in shown and not _drawn(artist, ax, renderer):
                missing.add(label)
    if missing:
        raise ValueError(
            f"{name}: the legend lists what the axes do not show: " + ", ".join(sorted(missing))
        )


def save(fig, name: str) -> None:
    """Check the text size (:func:`check_text_size`) and the legend (:func:`check_legend`),
    then write ``name``.png and ``name``.pdf to the figure directory (if there is one)."""
    check_text_size(fig, name)
    check_legend(fig, name)
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
