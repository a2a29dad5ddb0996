"""Ctrl-C and SIGTERM in the serial path (issue 37): one line, exit 130 / 143, no lease
left behind, and the rerun resumes.  Before, a signal during a compiled chunk crashed the
process (signal 11)."""

from __future__ import annotations

import contextlib
import io
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from dyntorsion import _numba

#: a short first scene, then longer ones (the signal lands inside the second's march); a
#: coarse grid, so that the rerun's remaining scenes cost a few seconds
RATES = "3.2,0.8,0.4"
ARGS = ["sweep", "--rates", RATES, "--kappa0", "10", "--n-cells", "100", "--dt", "0.005"]


def _cold_cache_notice() -> str:
    """The line a process prints when it compiles kernels its disk cache lacks (a first
    run after a kernel edit): not part of what a signal makes the sweep say."""
    with contextlib.redirect_stderr(io.StringIO()) as out:
        _numba.announce_cold_cache()
    return out.getvalue().strip()


def _records(store: Path) -> list[Path]:
    return sorted(store.glob("buckling-onset-*.json")) if store.is_dir() else []


@pytest.mark.parametrize(
    ("sig", "status", "word"),
    [(signal.SIGINT, 130, "interrupted"), (signal.SIGTERM, 143, "terminated")],
)
def test_a_serial_sweep_stops_cleanly_on_a_signal_and_resumes(tmp_path, sig, status, word):
    store = tmp_path / "store"
    cmd = [
        sys.executable,
        "-m",
        "dyntorsion",
        *ARGS,
        "--store",
        str(store),
        "--jobs",
        "1",
        "--quiet",
    ]
    env = {k: v for k, v in os.environ.items() if k != "DYNTORSION_DATA"}
    # a test run started as a background job ignores SIGINT, and the sweep would inherit it
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))  # fmt: skip
    deadline = time.monotonic() + 240
    while not _records(store) and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    assert proc.poll() is None, "the sweep ended before the signal: make it longer"
    time.sleep(0.3)  # inside the next scene's compiled march
    proc.send_signal(sig)
    out, err = proc.communicate(timeout=120)
    assert proc.returncode == status, (proc.returncode, err)
    lines = [ln for ln in err.splitlines() if ln.strip() and ln != _cold_cache_notice()]
    assert len(lines) == 1 and word in lines[0], err
    done = len(_records(store))
    assert 1 <= done < len(RATES.split(","))
    assert not list(store.glob("*.lease")) and not list(store.glob("*.tmp")), list(store.iterdir())
    again = subprocess.run(cmd[:-1], capture_output=True, text=True, env=env, timeout=600)
    assert again.returncode == 0, again.stderr
    assert len(_records(store)) == len(RATES.split(","))
    assert again.stdout.count("True") == done  # the finished scenes were read, not rerun
