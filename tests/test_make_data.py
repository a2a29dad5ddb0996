"""`make data`'s steps with ``--on-stale error`` (the bench times `make data` so): the
traces and the consistency map refuse a store that lacks their records instead of
computing them, and say what to run."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest


@pytest.mark.parametrize("module", ["traces", "consistency"])
def test_on_stale_error_refuses_a_missing_record(module, tmp_path):
    env = {**os.environ, "DYNTORSION_DATA": str(tmp_path)}
    done = subprocess.run(
        [sys.executable, "-m", f"dyntorsion.studies.{module}", "--on-stale", "error"],
        capture_output=True, text=True, env=env, timeout=300,
    )  # fmt: skip
    assert done.returncode != 0
    assert "make data" in done.stderr, done.stderr[-400:]
    assert not any(tmp_path.rglob("*.json"))  # nothing computed


def test_on_stale_refuses_an_unknown_choice():
    done = subprocess.run(
        [sys.executable, "-m", "dyntorsion.studies.traces", "--on-stale", "later"],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert done.returncode == 2 and "--on-stale" in done.stderr
