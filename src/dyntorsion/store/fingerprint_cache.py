"""Code fingerprints kept on disk, keyed by the package's bytes.

Walking a record kind's code (:func:`~.fingerprint.reachable`) takes about a second; every
process that reads records needs the fingerprints.  They are a function of the package's
source alone, so they are kept in a file named by the hash of every module of the package
(:func:`package_digest`): a process whose package is byte for byte the same reads them back,
and any edit of any module starts a new file.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import tempfile
from functools import cache
from pathlib import Path
from typing import Any

__all__ = ["package_digest", "cache_file", "read", "write"]

#: the package's source folder
PACKAGE_ROOT = Path(__file__).resolve().parents[1]


@cache
def package_digest(root: Path = PACKAGE_ROOT) -> str:
    """Hash of every module below ``root`` (the package), by relative path and bytes."""
    h = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        h.update(path.relative_to(root).as_posix().encode() + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()[:20]


def cache_file() -> Path | None:
    """Where the fingerprints of this exact package are kept: in the store package's
    ``__pycache__`` or, when that is not writable, the temporary folder (None: neither)."""
    name = f"fingerprints-{package_digest()}.json"
    for folder in (
        Path(__file__).resolve().parent / "__pycache__",
        Path(tempfile.gettempdir()) / f"dyntorsion-fingerprints-{os.getuid()}",
    ):
        try:
            folder.mkdir(parents=True, exist_ok=True)
        except OSError:
            continue
        if os.access(folder, os.W_OK):
            return folder / name
    return None


def _load(path: Path) -> dict[str, Any]:
    try:
        data = json.loads(path.read_text())
    except (OSError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}


def read(name: str) -> str | None:
    """The fingerprint kept under ``name``, or None (none kept, or the file unreadable)."""
    path = cache_file()
    value = _load(path).get(name) if path is not None else None
    return value if isinstance(value, str) else None


def write(name: str, fingerprint: str) -> None:
    """Keep ``fingerprint`` under ``name``, atomically; a failure leaves the file as it was."""
    path = cache_file()
    if path is None:
        return
    data = {**_load(path), name: fingerprint}
    try:
        fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
    except OSError:
        return
    try:
        with os.fdopen(fd, "w") as f:
            json.dump(data, f, sort_keys=True)
        os.replace(tmp, path)
    except OSError:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
