"""`make data`'s steps with ``--on-stale error`` (the bench times `make data` so): the
traces and the consistency map, like the sweeps, read a current store without computing
anything and stop at a stale record instead of recomputing it."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from dyntorsion.store.location import default_store

KINDS = {"traces": "onset-trace", "consistency": "onset-rules"}


def _run(module: str, store: Path, choice: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", f"dyntorsion.studies.{module}", "--on-stale", choice],
        capture_output=True, text=True, timeout=600,
        env={**os.environ, "DYNTORSION_DATA": str(store)},
    )  # fmt: skip


@pytest.mark.parametrize("module", sorted(KINDS))
def test_on_stale_error_reads_a_current_store_and_stops_at_a_stale_record(module, tmp_path):
    records = sorted(default_store().glob(f"{KINDS[module]}-*.json"))
    assert records, "the committed records are missing"
    for path in records:
        shutil.copy(path, tmp_path)
    before = {p.name: p.read_bytes() for p in tmp_path.iterdir()}
    done = _run(module, tmp_path, "error")
    assert done.returncode == 0, done.stderr[-400:]
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == before  # nothing computed
    stale = tmp_path / records[0].name
    rec = json.loads(stale.read_text())
    rec["provenance"]["code"] = "0" * 16  # computed by other code: stale
    stale.write_text(json.dumps(rec))
    done = _run(module, tmp_path, "error")
    assert done.returncode != 0 and "stale" in done.stderr, done.stderr[-400:]
    assert json.loads(stale.read_text()) == rec  # refused, not recomputed


def test_on_stale_refuses_an_unknown_choice(tmp_path):
    done = _run("traces", tmp_path, "later")
    assert done.returncode == 2 and "--on-stale" in done.stderr


def test_make_data_runs_every_preset_the_package_defines():
    """``--preset all`` is every preset of the package, so the Makefile keeps no list."""
    from dyntorsion.app.cli import EVERY, _every, parser
    from dyntorsion.studies.linear_predictions import PRESETS as LINEAR
    from dyntorsion.studies.presets import PRESETS

    assert _every(parser().parse_args(["sweep", "--preset", EVERY]).preset, PRESETS) == list(
        PRESETS
    )
    assert _every(parser().parse_args(["linear", "--preset", EVERY]).preset, LINEAR) == list(LINEAR)
    assert _every(["fig10", "tension"], PRESETS) == ["fig10", "tension"]
    makefile = (Path(__file__).resolve().parents[2] / "Makefile").read_text()
    assert "--preset all" in makefile and "_PRESETS :=" not in makefile


def test_make_data_computes_what_the_paper_figures_read():
    """``make data`` is ``--preset paper``: every preset a figure page reads is in
    :data:`~dyntorsion.studies.presets.PAPER`, and ``make data-studies`` covers the rest."""
    import re

    from dyntorsion.app.cli import _every, parser
    from dyntorsion.studies.presets import GROUPS, PAPER, PRESETS

    assert set(PAPER) <= set(PRESETS)
    args = parser().parse_args(["sweep", "--preset", "paper", "--preset", "fig10"])
    assert _every(args.preset, PRESETS, GROUPS) == list(PAPER)  # each once, in order
    assert _every(["all"], PRESETS, GROUPS) == list(PRESETS)
    docs = Path(__file__).resolve().parents[2] / "docs"
    read = {
        name
        for page in (docs / "figures").glob("*.md")
        for name in re.findall(r"(?:cached|preset)\(\"([a-z0-9-]+)\"", page.read_text())
    }
    assert read and read <= set(PAPER), sorted(read - set(PAPER))
    makefile = (docs.parent / "Makefile").read_text()
    data = makefile[makefile.index("\ndata:") : makefile.index("\ndata-studies:")]
    assert "--preset paper" in data and "--preset all" not in data
