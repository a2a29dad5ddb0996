"""Leases and leftovers of a store folder (:mod:`dyntorsion.store.results`).

A sweep claims each record it is about to compute with a *lease*: a ``.lease`` file
beside the record, created exclusively and holding ``host-pid``.  A second sweep on the
same store finds the lease and waits for the record instead of computing it again; a
lease whose holder has died (same host: the pid is gone; another host: after
:data:`ABANDONED_AFTER_S`) is taken over.  Temporary files of atomic writes carry the
same ``host-pid``, so those of a killed writer can be told apart and removed.
"""

from __future__ import annotations

import os
import platform
import time
from dataclasses import dataclass
from pathlib import Path

__all__ = ["Lease", "acquire_lease", "clean_leftovers", "TMP_SUFFIX", "LEASE_SUFFIX"]

TMP_SUFFIX = ".tmp"
LEASE_SUFFIX = ".lease"
#: a lease or temporary file of another machine counts as abandoned after this long [s]
ABANDONED_AFTER_S = 24 * 3600.0


def _owner() -> str:
    """host-pid of this process, as written into leases and temporary file names."""
    return f"{platform.node().replace('.', '_') or 'host'}-{os.getpid()}"


def _alive(owner: str, mtime: float) -> bool:
    """Whether the process ``host-pid`` may still be running (another host's: until
    :data:`ABANDONED_AFTER_S` after ``mtime``)."""
    host, _, pid = owner.rpartition("-")
    if host != _owner().rpartition("-")[0]:
        return time.time() - mtime < ABANDONED_AFTER_S
    try:
        os.kill(int(pid), 0)
    except (ValueError, ProcessLookupError):
        return False
    except PermissionError:
        return True
    return True


def clean_leftovers(root: str | os.PathLike[str]) -> list[Path]:
    """Remove the temporary files (``.*.tmp``) that a killed writer left in ``root``
    (their writer is no longer running) and the leases of dead holders; returns them."""
    removed = []
    for path in Path(root).glob(f".*{TMP_SUFFIX}"):
        parts = path.name.split(".")
        owner = parts[2] if len(parts) >= 5 else ""
        try:
            mtime = path.stat().st_mtime
        except FileNotFoundError:
            continue
        if (not owner and time.time() - mtime > 3600.0) or (owner and not _alive(owner, mtime)):
            path.unlink(missing_ok=True)
            removed.append(path)
    for path in Path(root).glob(f"*{LEASE_SUFFIX}"):
        try:
            owner, mtime = path.read_text().strip(), path.stat().st_mtime
        except (FileNotFoundError, OSError):
            continue
        if not _alive(owner, mtime):
            path.unlink(missing_ok=True)
            removed.append(path)
    return removed


@dataclass(frozen=True)
class Lease:
    """A claim on one record: the process that holds it computes the record; another
    sweep on the same store waits for it instead of computing it twice."""

    path: Path

    def release(self) -> None:
        try:
            if self.path.read_text().strip() == _owner():
                self.path.unlink()
        except FileNotFoundError:
            pass


def acquire_lease(record_path: str | os.PathLike[str]) -> Lease | None:
    """Claim the record at ``record_path`` (a ``.lease`` file beside it, created
    exclusively); None while a running process holds it.  A dead holder's lease is
    taken over."""
    path = Path(f"{record_path}{LEASE_SUFFIX}")
    path.parent.mkdir(parents=True, exist_ok=True)
    for _ in range(3):
        try:
            fd = os.open(path, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
        except FileExistsError:
            try:
                owner, mtime = path.read_text().strip(), path.stat().st_mtime
            except FileNotFoundError:
                continue
            if owner == _owner():
                return Lease(path)
            if _alive(owner, mtime):
                return None
            path.unlink(missing_ok=True)
            continue
        with os.fdopen(fd, "w") as fh:
            fh.write(_owner())
        return Lease(path)
    return None
