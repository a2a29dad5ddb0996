"""Cached results in ``data/``, with provenance.

Every expensive scene is stored as one JSON record, named by the hash of its
parameters::

    {"schema": 1, "kind": ..., "key": ..., "params": {...}, "result": {...},
     "provenance": {"package_version", "code", "python", "numpy", "numba",
                    "created", "wall_time_s"},
     "hash": sha256 of the canonical JSON of {kind, params, result}}

``params`` holds everything the numbers depend on (rod, loading, seed, grid,
scheme, Newton options, onset window); ``provenance.code`` is a fingerprint of
the code that computes them (:func:`~dyntorsion.store.fingerprint.code_fingerprint`).  Records are written
atomically (a temporary file in the same folder, then ``os.replace``), so a
killed run leaves either the whole record or none.

Reading checks, in order: the content hash (a damaged or hand-edited record is
refused; the hash is a checksum against damage, not a signature: anyone who edits a
record and recomputes its hash has it served, so a store is only as trustworthy as
whoever can write to it), the result entries its kind must hold
(:func:`require_result`), the parameters (they must equal the request), and then the package
version and the code fingerprint.  A record that fails the last check is
*stale*: :meth:`Store.load` recomputes it (``on_stale="recompute"``, it returns
None), refuses it (``"error"``, :class:`StaleResultError` says what changed), or
takes it anyway (``"accept"``, for reading old data on purpose).
"""

from __future__ import annotations

import datetime as _dt
import hashlib
import json
import math
import os
import platform
import sys
import tempfile
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .fingerprint import code_of
from .leases import TMP_SUFFIX, Lease, acquire_lease, clean_leftovers, this_process
from .location import DATA

SCHEMA = 1


ON_STALE = ("recompute", "error", "accept")
#: what :meth:`Store.load` does with a damaged record: move it aside and recompute, or raise
ON_CORRUPT = ("quarantine", "error")
#: the suffix of a damaged record moved aside
CORRUPT_SUFFIX = ".corrupt"


#: the result entries a record of each kind must hold (:func:`require_result`)
RESULT_KEYS: dict[str, tuple[str, ...]] = {}


def require_result(kind: str, keys: tuple[str, ...]) -> None:
    """Declare the result entries every record of ``kind`` holds: a record without one
    (whatever its hash) is damaged, moved aside and recomputed like any other."""
    RESULT_KEYS[kind] = tuple(keys)


class UnsavedResultError(OSError):
    """A result computed but not written (the store failed): ``result`` holds it."""

    result: Any = None


class StaleResultError(RuntimeError):
    """A cached record no longer matches the code or the request."""


class CorruptResultError(RuntimeError):
    """A cached record whose content hash does not match its content."""


def _plain(obj: Any, where: str = "") -> Any:
    """JSON-ready copy: tuples to lists, numpy scalars and arrays to Python; a
    non-finite number is refused with the entry that holds it."""
    if isinstance(obj, Mapping):
        return {str(k): _plain(v, f"{where}.{k}" if where else str(k)) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_plain(v, f"{where}[{i}]") for i, v in enumerate(obj)]
    if hasattr(obj, "tolist"):
        return _plain(obj.tolist(), where)
    if isinstance(obj, float) and not math.isfinite(obj):
        raise ValueError(f"cannot store the non-finite number {obj!r} (entry {where or '-'})")
    return obj


def json_ready(x: Any) -> Any:
    """``x`` with numpy scalars and arrays as Python numbers and lists, tuples as lists and
    NaN and infinities as None: what a record or ``--json`` can hold."""
    if isinstance(x, dict):
        return {str(k): json_ready(v) for k, v in x.items()}
    if isinstance(x, list | tuple):
        return [json_ready(v) for v in x]
    if isinstance(x, np.ndarray):
        return json_ready(x.tolist())
    if isinstance(x, np.generic):
        x = x.item()
    if isinstance(x, float) and not math.isfinite(x):
        return None
    return x


def canonical(obj: Any) -> str:
    """The canonical JSON text of ``obj`` (sorted keys, no spaces, floats by repr)."""
    return json.dumps(_plain(obj), sort_keys=True, separators=(",", ":"), allow_nan=False)


def digest(obj: Any) -> str:
    return hashlib.sha256(canonical(obj).encode()).hexdigest()


def key(kind: str, params: Mapping[str, Any]) -> str:
    """File name stem of a record: 20 hex digits of the hash of (kind, params).  Params
    that say they are ``unkeyed`` (somewhere inside: a part that cannot be known by value)
    are refused: a record under them could be served for another computation."""
    why = _unkeyed(params)
    if why:
        raise ValueError(f"this {kind} cannot be cached: {why}")
    return digest({"kind": kind, "params": params})[:20]


def _unkeyed(obj: Any) -> str | None:
    if isinstance(obj, Mapping):
        if obj.get("unkeyed"):
            return str(obj["unkeyed"])
        return next((w for w in map(_unkeyed, obj.values()) if w), None)
    if isinstance(obj, list | tuple):
        return next((w for w in map(_unkeyed, obj) if w), None)
    return None


def provenance(wall_time: float | None = None, kind: str | None = None) -> dict[str, Any]:
    import numba
    import numpy

    from .._version import __version__

    return {
        "package_version": __version__,
        "code": code_of(kind),
        "python": platform.python_version(),
        "numpy": numpy.__version__,
        "numba": numba.__version__,
        "created": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        "wall_time_s": wall_time,
    }


def write_text(path: str | os.PathLike[str], text: str) -> Path:
    """Write ``text`` to ``path`` atomically: a temporary file in the same folder, flushed
    to disk, made readable by all (mode 0o644, as a record is shared), then renamed over
    ``path``; on any failure the temporary is removed and ``path`` is untouched."""
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(
        dir=target.parent, prefix=f".{target.stem}.{this_process()}.", suffix=TMP_SUFFIX
    )
    try:
        with os.fdopen(fd, "w") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, 0o644)
        os.replace(tmp, target)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return target


def write_json(path: str | os.PathLike[str], obj: Any) -> Path:
    """Write ``obj`` as JSON (indented by one, keys sorted, no NaN) with :func:`write_text`:
    atomically, ``path`` untouched on any failure."""
    return write_text(path, json.dumps(obj, indent=1, sort_keys=True, allow_nan=False) + "\n")


# ----------------------------------------------------------------- the store
@dataclass(frozen=True)
class Store:
    """A folder of records (default ``data/scenes`` of the source tree)."""

    root: Path

    def __init__(self, root: str | os.PathLike[str]) -> None:
        object.__setattr__(self, "root", Path(root))

    def path(self, kind: str, params: Mapping[str, Any]) -> Path:
        return self.root / f"{kind}-{key(kind, params)}.json"

    def lease(self, kind: str, params: Mapping[str, Any]) -> Lease | None:
        """Claim the record (:func:`acquire_lease`); None while another process holds it."""
        return acquire_lease(self.path(kind, params))

    def clean(self) -> list[Path]:
        """Remove what killed writers left behind (:func:`clean_leftovers`)."""
        return clean_leftovers(self.root) if self.root.is_dir() else []

    def save(
        self,
        kind: str,
        params: Mapping[str, Any],
        result: Mapping[str, Any],
        wall_time: float | None = None,
    ) -> Path:
        """Write one record atomically; returns its path."""
        try:
            record = {
                "schema": SCHEMA,
                "kind": kind,
                "key": key(kind, params),
                "params": _plain(params, "params"),
                "result": _plain(result, "result"),
                "provenance": provenance(wall_time, kind),
            }
        except ValueError as err:
            try:
                where = str(self.path(kind, params))
            except ValueError:
                where = f"a {kind} record in {self.root}"
            raise ValueError(f"{where} not written: {err}") from None
        record["hash"] = digest({"kind": kind, "params": params, "result": result})
        target = self.path(kind, params)
        try:
            write_json(target, record)
        except OSError as err:
            raise OSError(
                err.errno,
                f"cannot write the record ({err.strerror or err})",
                str(target),
            ) from err
        return target

    def read(self, path: str | os.PathLike[str]) -> dict[str, Any]:
        """One record, its content hash checked (:class:`CorruptResultError`)."""
        path = Path(path)
        try:
            record = json.loads(path.read_text())
        except (OSError, ValueError, RecursionError) as err:  # ValueError: also digit limit
            raise CorruptResultError(f"{path}: unreadable record ({err})") from err
        if not isinstance(record, dict) or not isinstance(record.get("params"), dict):
            raise CorruptResultError(
                f"{path}: not a record (a JSON {type(record).__name__} without params)"
            )
        try:
            expected = digest({k: record.get(k) for k in ("kind", "params", "result")})
        except ValueError as err:  # NaN or Infinity: never written by a store
            raise CorruptResultError(f"{path}: not a record ({err})") from err
        if record.get("hash") != expected:
            raise CorruptResultError(
                f"{path}: content hash does not match its content "
                "(damaged or edited by hand); delete it to recompute"
            )
        result = record.get("result")
        needs = RESULT_KEYS.get(record.get("kind"), ())
        missing = [k for k in needs if not isinstance(result, dict) or k not in result]
        if missing:
            raise CorruptResultError(
                f"{path}: its result lacks {', '.join(missing)} (edited by hand, or written "
                "by other code); delete it to recompute"
            )
        return record

    def staleness(self, record: Mapping[str, Any]) -> str | None:
        """Why a record is stale, or None if it matches the current code."""
        from .._version import __version__

        prov = record.get("provenance", {})
        reasons = []
        if record.get("schema") != SCHEMA:
            reasons.append(f"record schema {record.get('schema')} != {SCHEMA}")
        if prov.get("package_version") != __version__:
            reasons.append(f"package version {prov.get('package_version')} != {__version__}")
        code = code_of(record.get("kind"))
        if prov.get("code") != code:
            reasons.append(
                f"code fingerprint {prov.get('code')} != {code} "
                "(the numerical code changed since it was computed)"
            )
        return "; ".join(reasons) or None

    def quarantine(self, path: Path, why: str, say=print) -> Path:
        """Move a damaged record aside (``<name>.corrupt``, kept for inspection), saying so
        in one line; the record is then computed again."""
        aside = path.with_name(path.name + CORRUPT_SUFFIX)
        os.replace(path, aside)
        say(f"damaged record moved aside to {aside.name} and recomputed: {why}")
        return aside

    def load(
        self,
        kind: str,
        params: Mapping[str, Any],
        on_stale: str = "recompute",
        on_corrupt: str = "quarantine",
        say=None,
    ) -> dict[str, Any] | None:
        """The record for (kind, params), or None if it must be computed.  A damaged one is
        moved aside (``on_corrupt="quarantine"``, then None) or raises
        (``"error"``: :class:`CorruptResultError`)."""
        if on_stale not in ON_STALE:
            raise ValueError(f"on_stale={on_stale!r}; allowed: {', '.join(ON_STALE)}")
        if on_corrupt not in ON_CORRUPT:
            raise ValueError(f"on_corrupt={on_corrupt!r}; allowed: {', '.join(ON_CORRUPT)}")
        path = self.path(kind, params)
        if not path.exists():
            return None
        try:
            record = self.read(path)
        except CorruptResultError as err:
            if on_corrupt == "error":
                raise
            self.quarantine(path, str(err), say or (lambda msg: print(msg, file=sys.stderr)))
            return None
        if canonical(record["params"]) != canonical(params):
            raise StaleResultError(
                f"{path}: its parameters differ from the request (hash collision or a renamed file)"
            )
        why = self.staleness(record)
        if why is None or on_stale == "accept":
            return record
        if on_stale == "error":
            how = (
                "`make data-studies` in the checkout"
                if DATA is not None and self.root.resolve() == DATA.resolve()
                else f"the command that wrote it, with --on-stale recompute (store {self.root})"
            )
            raise StaleResultError(f"{path} is stale: {why}. Recompute it with {how}")
        return None

    def records(
        self, kind: str | None = None, skipped: list | None = None
    ) -> Iterator[dict[str, Any]]:
        """Every record in the folder (of one kind), hashes checked; with a list
        ``skipped``, damaged records are left out and their errors appended to it."""
        pattern = f"{kind}-*.json" if kind else "*.json"
        for path in sorted(self.root.glob(pattern)):
            try:
                yield self.read(path)
            except CorruptResultError as err:
                if skipped is None:
                    raise
                skipped.append(err)
