"""A temporary git worktree of this repository, for the scripts that measure this checkout
against another commit or a patch (``bench_targets``, ``bench_contact``,
``bench_fixed_sizes``, ``probe_newton_strategies``)."""

from __future__ import annotations

import subprocess
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


@contextmanager
def checkout(commit: str = "HEAD", patch: Path | None = None) -> Iterator[Path]:
    """``commit`` checked out into a temporary worktree (``patch`` applied to it when
    given); yields its folder and removes the worktree on exit."""
    with tempfile.TemporaryDirectory() as tmp:
        tree = Path(tmp) / "tree"
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", "-q", str(tree),
                        commit], check=True)  # fmt: skip
        try:
            if patch is not None:
                subprocess.run(["git", "-C", str(tree), "apply", str(patch)], check=True)
            yield tree
        finally:
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(tree)])
