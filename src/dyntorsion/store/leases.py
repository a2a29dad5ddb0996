"""Leases and leftovers of a store folder (:mod:`dyntorsion.store.results`).

A sweep claims each record it is about to compute with a *lease*: a ``.lease`` file
beside the record, created exclusively and holding what is needed to judge it: the
holder's ``host-pid``, the start time of that process (so that a pid reused by another
process is not taken for the holder) and the time it was taken.  A live holder refreshes
the lease's modification time every :data:`HEARTBEAT_S` (a thread of its own), so a lease
written on another machine is judged by its heartbeat: stale once it is older than
:data:`STALE_AFTER_S`.  A second sweep finds the lease and waits for the record; a lease
whose holder has died, whose pid now belongs to another process, whose heartbeat stopped,
or that cannot be read (empty: the disk filled while it was written) is broken with one
line saying so.  Temporary files of atomic writes carry the same ``host-pid``, so those of
a killed writer can be told apart and removed.
"""

from __future__ import annotations

import json
import os
import platform
import sys
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

__all__ = [
    "Lease",
    "acquire_lease",
    "clean_leftovers",
    "this_process",
    "TMP_SUFFIX",
    "LEASE_SUFFIX",
]

TMP_SUFFIX = ".tmp"
LEASE_SUFFIX = ".lease"
#: a temporary file of another machine counts as abandoned after this long [s]
ABANDONED_AFTER_S = 24 * 3600.0
#: how often a live holder refreshes its lease [s]
HEARTBEAT_S = 30.0
#: a lease whose heartbeat is older than this is stale, whoever holds it [s]
STALE_AFTER_S = 10 * HEARTBEAT_S
#: an unreadable (empty) lease younger than this may be being written [s]
WRITING_S = 5.0


def _started(pid: int) -> float | None:
    """The start time of process ``pid`` in clock ticks since boot (Linux), else None."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    return float(stat.rsplit(")", 1)[1].split()[19])


def _say(message: str) -> None:
    print(f"dyntorsion: {message}", file=sys.stderr)


def this_process() -> str:
    """This process as ``host-pid``, as written into leases and temporary file names."""
    return f"{platform.node().replace('.', '_') or 'host'}-{os.getpid()}"


def _alive(owner: str, mtime: float) -> bool:
    """Whether the process ``host-pid`` may still be running (another host's: until
    :data:`ABANDONED_AFTER_S` after ``mtime``)."""
    host, _, pid = owner.rpartition("-")
    if host != this_process().rpartition("-")[0]:
        return time.time() - mtime < ABANDONED_AFTER_S
    try:
        os.kill(int(pid), 0)
    except (ValueError, ProcessLookupError):
        return False
    except PermissionError:
        return True
    return True


def _holder() -> dict:
    return {"owner": this_process(), "start": _started(os.getpid()), "taken": time.time()}


def stale(path: Path) -> str | None:
    """Why the lease at ``path`` no longer holds its record (None: its holder may be
    running).  Judged by its content and its heartbeat (the file's modification time)."""
    try:
        text, mtime = path.read_bytes(), path.stat().st_mtime
    except FileNotFoundError:
        return None
    age = time.time() - mtime
    try:
        held = json.loads(text)  # bytes: a torn write need not be UTF-8 (a ValueError)
        owner = str(held["owner"])
    except (ValueError, KeyError, TypeError, RecursionError):
        if age < WRITING_S:
            return None
        return f"unreadable lease ({len(text)} bytes; a writer that failed, e.g. on a full disk)"
    if age > STALE_AFTER_S:
        return f"its heartbeat stopped {age:.0f} s ago (holder {owner})"
    host, _, pid = owner.rpartition("-")
    if host != this_process().rpartition("-")[0]:
        return None  # another machine's: judged by the heartbeat alone
    if not _alive(owner, mtime):
        return f"its holder {owner} is no longer running"
    start = held.get("start")
    if start is not None and _started(int(pid)) not in (None, start):
        return f"pid {pid} now belongs to another process (holder {owner} has died)"
    return None


def holder_of(path: Path) -> str:
    """Who holds the lease at ``path`` and since when, for a waiting run's message."""
    try:
        held = json.loads(path.read_bytes())
        since = time.strftime("%H:%M:%S", time.localtime(held["taken"]))
        return f"{held['owner']} since {since}"
    except (OSError, ValueError, KeyError, TypeError, RecursionError):
        return "an unknown holder"


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
        if stale(path) is not None:
            path.unlink(missing_ok=True)
            removed.append(path)
    return removed


@dataclass(frozen=True)
class Lease:
    """A claim on one record: the process that holds it computes the record; another
    sweep on the same store waits for it instead of computing it twice.  While held, a
    thread refreshes its heartbeat every :data:`HEARTBEAT_S`."""

    path: Path
    _stop: threading.Event = field(default_factory=threading.Event, compare=False, repr=False)

    def __post_init__(self) -> None:
        threading.Thread(target=self._beat, name=f"lease {self.path.name}", daemon=True).start()

    def _beat(self) -> None:
        while not self._stop.wait(HEARTBEAT_S):
            try:
                os.utime(self.path)
            except OSError:
                return

    def mine(self) -> bool:
        try:
            return json.loads(self.path.read_text()).get("owner") == this_process()
        except (OSError, ValueError, AttributeError):
            return False

    def release(self) -> None:
        self._stop.set()
        if self.mine():
            self.path.unlink(missing_ok=True)


def acquire_lease(
    record_path: str | os.PathLike[str], say: Callable[[str], None] = _say
) -> Lease | None:
    """Claim the record at ``record_path`` (a ``.lease`` file beside it, created
    exclusively); None while a running process holds it.  A stale or unreadable lease
    (:func:`stale`) is broken, with one line through ``say``."""
    path = Path(f"{record_path}{LEASE_SUFFIX}")
    path.parent.mkdir(parents=True, exist_ok=True)
    for _ in range(3):
        try:
            fd = os.open(path, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
        except FileExistsError:
            probe = Lease.__new__(Lease)
            object.__setattr__(probe, "path", path)
            if probe.mine():
                return Lease(path)
            why = stale(path)
            if why is None:
                return None
            say(f"lease {path.name} broken: {why}")
            path.unlink(missing_ok=True)
            continue
        try:
            with os.fdopen(fd, "w") as fh:
                json.dump(_holder(), fh)
        except OSError as err:  # a full disk: leave no empty lease for the next run to wait on
            path.unlink(missing_ok=True)
            raise OSError(err.errno, f"cannot write the lease ({err.strerror})", str(path)) from err
        return Lease(path)
    return None
