"""A temporary git worktree of this repository, and a measuring subprocess, for the scripts
that measure this checkout against another commit (``bench_targets``,
``bench_contact``)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


@contextmanager
def checkout(commit: str = "HEAD") -> Iterator[Path]:
    """``commit`` checked out into a temporary worktree; yields its folder and removes the
    worktree on exit."""
    with tempfile.TemporaryDirectory() as tmp:
        tree = Path(tmp) / "tree"
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", "-q", str(tree),
                        commit], check=True)  # fmt: skip
        try:
            yield tree
        finally:
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(tree)])


def run_code(code: str, *args: object, env: dict[str, str] | None = None) -> str:
    """``code`` run by this interpreter in a subprocess with ``args`` (and ``env`` added to
    the environment): the last line it printed ("" if none); its stderr in the error if it
    failed."""
    done = subprocess.run([sys.executable, "-c", code, *map(str, args)], capture_output=True,
                          text=True, env=None if env is None else os.environ | env)  # fmt: skip
    if done.returncode:
        raise RuntimeError(f"a measuring subprocess failed:\n{done.stderr}")
    lines = done.stdout.strip().splitlines()
    return lines[-1] if lines else ""


def run_json(code: str, *args: object, env: dict[str, str] | None = None) -> dict:
    """:func:`run_code` whose last line is a JSON object."""
    return json.loads(run_code(code, *args, env=env))
