"""The figures' look and the offline animation player."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib import animation  # noqa: E402

from dyntorsion.app import plotting


def test_style_is_readable():
    plotting.use_style()
    rc = matplotlib.rcParams
    assert rc["figure.dpi"] >= 150 and rc["savefig.dpi"] >= 150
    for key in (
        "font.size",
        "axes.labelsize",
        "xtick.labelsize",
        "ytick.labelsize",
        "legend.fontsize",
    ):
        assert float(rc[key]) >= 9, key


def test_animation_player_needs_no_network():
    fig, ax = plt.subplots()
    (line,) = ax.plot([0, 1], [0, 1])
    anim = animation.FuncAnimation(fig, lambda i: (line,), frames=3)
    html = plotting.offline_jshtml(anim, alt="a test frame", default_mode="once")
    plt.close(fig)
    assert "http://" not in html and "https://" not in html
    assert 'class="fa' not in html
    assert 'alt="a test frame"' in html
    assert "\u25b6" in html  # the play button has a label


def test_animation_player_refuses_a_network_reference(monkeypatch):
    fig, ax = plt.subplots()
    anim = animation.FuncAnimation(fig, lambda i: (), frames=2)
    anim._draw_was_started = True  # never drawn here: no "deleted without rendering" warning
    monkeypatch.setattr(
        anim, "to_jshtml", lambda **kw: '<script src="https://cdn.example.org/x.js"></script>'
    )
    with pytest.raises(RuntimeError, match="network"):
        plotting.offline_jshtml(anim, alt="x")
    plt.close(fig)


def test_save_refuses_text_too_small_to_read(tmp_path, monkeypatch):
    monkeypatch.setenv("DYNTORSION_FIGURES", str(tmp_path))
    plotting.use_style()
    fig, ax = plt.subplots()
    ax.set_xlabel("readable")
    plotting.save(fig, "ok")
    assert (tmp_path / "ok.png").is_file()
    ax.annotate("tiny note", (0.5, 0.5), fontsize=7)
    with pytest.raises(ValueError, match=r"'tiny note' \(7 pt\)"):
        plotting.save(fig, "small")
    assert not (tmp_path / "small.png").exists()
    plt.close(fig)


def test_save_refuses_a_legend_entry_that_is_not_drawn(tmp_path, monkeypatch):
    monkeypatch.setenv("DYNTORSION_FIGURES", str(tmp_path))
    plotting.use_style()
    x = np.linspace(0.0, 1.0, 20)
    fig, ax = plt.subplots()
    ax.plot(x, x, label="seen")
    ax.errorbar(x, x, yerr=0.1, fmt="o", label="points")
    ax.axvline(0.5, ls=":", label="a vertical line")
    ax.plot([-1.0, 2.0], [0.2, 0.8], label="crossing the view, no point inside")
    ax.scatter(x, 1 - x, label="scattered")
    ax.fill_between(x, 0.1, 0.2, label="a band")
    ax.set_xlim(0.0, 1.0)
    ax.set_ylim(0.0, 1.0)
    ax.legend()
    plotting.save(fig, "ok")  # every entry is drawn
    ax.plot(x, x + 5.0, label="above the view")
    ax.plot([], [], label="empty")
    ax.scatter(x, x + 3.0, label="scattered above")
    hidden = ax.plot(x, 1 - x, label="invisible")[0]
    hidden.set_visible(False)
    ax.legend()
    with pytest.raises(ValueError, match="above the view, empty, invisible, scattered above"):
        plotting.save(fig, "bad")
    assert not (tmp_path / "bad.png").exists()
    ax.get_legend().remove()  # a figure legend is checked too
    fig.legend(*ax.get_legend_handles_labels())
    with pytest.raises(ValueError, match="above the view"):
        plotting.save(fig, "bad")
    plt.close(fig)


def test_tables_show_no_row_numbers_and_no_nan():
    import pandas as pd

    t = pd.DataFrame({"N": [50, 100], "error": [1e-3, float("nan")]})
    for html in (
        plotting.table_html(t),
        plotting.table_html(t.style.format({"error": "{:.1e}"})),
    ):
        assert "row_heading" not in html and "<th>0</th>" not in html
        assert "nan" not in html and "–" in html
    indexed = plotting.table_html(t.set_index("N"))  # the index as a column, one header row
    assert "<td>50</td>" in indexed and indexed.count("<tr") == 3


def test_tables_show_numbers_and_headers_for_a_reader():
    import pandas as pd

    t = pd.DataFrame({"a": [0.2, 12.8], "t_c [s]": [-1.0, 0.0], "exp(-x^4)": [1.5e-16, 2.0]})
    html = plotting.table_html(t)
    for raw in ("0.200000", "12.800000", "-1.000000", "e-16"):
        assert raw not in html
    assert "<td>0.2</td>" in html and "<td>12.8</td>" in html and "<td>\u22121</td>" in html
    assert "1.5 × 10⁻¹⁶" in html
    assert "t<sub>c</sub> [s]" in html and "x<sup>4</sup>" in html
    styled = plotting.table_html(t.style.format({"a": "{:.4f}", "exp(-x^4)": "{:.2e}"}))
    assert "<td" in styled and ">0.2<" in styled and "1.50 × 10⁻¹⁶" in styled
    assert "0.2000" not in styled and "t<sub>c</sub>" in styled
    pivot = pd.DataFrame({"κ3": [1.25, 2.5]}, index=pd.Index([0.1, 0.2], name="λ∞"))
    html = plotting.table_html(pivot.style.format({"κ3": "{:.3f}"}))
    assert html.count("<tr") == 3 and "κ<sub>3</sub>" in html and ">1.25<" in html
