"""What the benchmark scripts that write a record to ``data/bench`` share: the record's
provenance (package version, the script's sha256, the code fingerprint of what computed
it: ``tests/test_plectoneme_records.py`` checks both) and the atomic write (a temporary
file in the same folder renamed over the record, so a run cut short loses nothing
already written)."""

from __future__ import annotations

import hashlib
import json
import os
import tempfile
from pathlib import Path

from dyntorsion import __version__
from dyntorsion.store.fingerprint import code_fingerprint

__all__ = ["provenance", "write"]


def provenance(script: str | os.PathLike[str], roots: tuple[str, ...]) -> dict:
    """The ``code`` part of a record written by ``script`` with the code reachable from
    ``roots`` (:func:`dyntorsion.store.fingerprint.code_fingerprint`)."""
    return {"dyntorsion": __version__,
            "script_sha256": hashlib.sha256(Path(script).read_bytes()).hexdigest(),
            "code_fingerprint": code_fingerprint(roots)}  # fmt: skip


def write(out: Path, record: dict, indent: int | None = None) -> None:
    """Write ``record`` to ``out`` as JSON (indented by ``indent``), atomically."""
    out.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.NamedTemporaryFile(
        "w", dir=out.parent, prefix=f".{out.stem}.", delete=False
    ) as f:
        json.dump(record, f, indent=indent)
    os.replace(f.name, out)
