"""Cached results in ``data/``, with provenance.

Every expensive scene is stored as one JSON record, named by the hash of its
parameters::

    {"schema": 1, "kind": ..., "key": ..., "params": {...}, "result": {...},
     "provenance": {"package_version", "code", "python", "numpy", "numba",
                    "created", "wall_time_s"},
     "hash": sha256 of the canonical JSON of {kind, params, result}}

``params`` holds everything the numbers depend on (rod, loading, seed, grid,
scheme, Newton options, onset window); ``provenance.code`` is a fingerprint of
the code that computes them (:func:`code_fingerprint`).  Records are written
atomically (a temporary file in the same folder, then ``os.replace``), so a
killed run leaves either the whole record or none.

Reading checks, in order: the content hash (a damaged or hand-edited record is
refused), the parameters (they must equal the request), and then the package
version and the code fingerprint.  A record that fails the last check is
*stale*: :meth:`Store.load` recomputes it (``on_stale="recompute"``, it returns
None), refuses it (``"error"``, :class:`StaleResultError` says what changed), or
takes it anyway (``"accept"``, for reading old data on purpose).
"""

from __future__ import annotations

import ast
import datetime as _dt
import hashlib
import importlib
import inspect
import json
import math
import os
import platform
import tempfile
import textwrap
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import Any

from .leases import TMP_SUFFIX, Lease, _owner, acquire_lease, clean_leftovers

SCHEMA = 1

#: where the computation of each record kind starts: its fingerprint covers every
#: function, class and module-level definition of the package reachable from these
#: (``module:object`` or a whole ``module``), found by walking the code itself
KIND_ROOTS: dict[str, tuple[str, ...]] = {
    "buckling-onset": (
        "dyntorsion.sweep:run_scene",
        "dyntorsion.sweep:Scene",
        "dyntorsion.loading",
    ),
    "linear-onset": (
        "dyntorsion.linear_predictions:run_prediction",
        "dyntorsion.linear_predictions:Prediction",
        "dyntorsion.sweep:Scene",
        "dyntorsion.loading",
    ),
    "onset-trace": ("dyntorsion.traces:compare", "dyntorsion.sweep:Scene", "dyntorsion.loading"),
}
#: the roots of records of any other kind
DEFAULT_ROOTS = KIND_ROOTS["buckling-onset"]
PACKAGE = "dyntorsion"

ON_STALE = ("recompute", "error", "accept")


class StaleResultError(RuntimeError):
    """A cached record no longer matches the code or the request."""


class CorruptResultError(RuntimeError):
    """A cached record whose content hash does not match its content."""


# ----------------------------------------------------------------- hashing
def _strip_docstrings(tree: ast.AST) -> ast.AST:
    for node in ast.walk(tree):
        body = getattr(node, "body", None)
        if (
            isinstance(body, list)
            and body
            and isinstance(body[0], ast.Expr)
            and isinstance(body[0].value, ast.Constant)
            and isinstance(body[0].value.value, str)
        ):
            node.body = body[1:] or [ast.Pass()]
    return tree


def _tree(source: str) -> ast.Module:
    """Syntax tree without docstrings, imports sorted (a linter's reordering is no change)."""
    tree = _strip_docstrings(ast.parse(textwrap.dedent(source)))
    imports = [n for n in tree.body if isinstance(n, ast.Import | ast.ImportFrom)]
    rest = [n for n in tree.body if not isinstance(n, ast.Import | ast.ImportFrom)]
    tree.body = sorted(imports, key=ast.dump) + rest
    return tree


def _source_digest(target: str) -> str:
    """Digest of one ``module`` or ``module:object`` alone (docstrings, comments and
    import order do not count)."""
    module_name, _, attr = target.partition(":")
    obj = importlib.import_module(module_name)
    if attr:
        obj = getattr(obj, attr)
    return hashlib.sha256(ast.dump(_tree(inspect.getsource(obj))).encode()).hexdigest()


def _unwrap(obj: Any) -> Any:
    """The Python function behind a compiled (numba) or wrapped one."""
    for attr in ("py_func", "__wrapped__", "__func__"):
        while hasattr(obj, attr):
            obj = getattr(obj, attr)
    return obj


def _ours(obj: Any) -> bool:
    name = getattr(obj, "__name__", "") if inspect.ismodule(obj) else getattr(obj, "__module__", "")
    return isinstance(name, str) and (name == PACKAGE or name.startswith(PACKAGE + "."))


def _qualname(obj: Any) -> str:
    if inspect.ismodule(obj):
        return obj.__name__
    return f"{obj.__module__}:{obj.__qualname__}"


def _assignment(module: Any, name: str) -> str | None:
    """Source of the module-level statement(s) that bind ``name`` in ``module``."""
    tree = _module_tree(module.__name__)
    found = []
    for node in tree.body:
        targets = []
        if isinstance(node, ast.Assign):
            targets = node.targets
        elif isinstance(node, ast.AnnAssign | ast.AugAssign):
            targets = [node.target]
        names = {n.id for t in targets for n in ast.walk(t) if isinstance(n, ast.Name)}
        if name in names:
            found.append(ast.unparse(node))
    return "\n".join(found) or None


@cache
def _module_tree(name: str) -> ast.Module:
    return ast.parse(inspect.getsource(importlib.import_module(name)))


def _resolve(node: ast.AST, namespace: Mapping[str, Any]) -> Any:
    if isinstance(node, ast.Name):
        return namespace.get(node.id, _MISSING)
    if isinstance(node, ast.Attribute):
        base = _resolve(node.value, namespace)
        if base is _MISSING:
            return _MISSING
        try:
            return inspect.getattr_static(base, node.attr)
        except AttributeError:
            return _MISSING
    return _MISSING


_MISSING = object()


def reachable(roots: tuple[str, ...] = DEFAULT_ROOTS, source=inspect.getsource) -> dict[str, str]:
    """Every definition of the package that the code of ``roots`` can reach, each with
    its source (``qualified name -> source``): functions, classes (with their methods),
    compiled kernels (their Python source) and module-level assignments, following
    names and attribute chains through the modules' namespaces."""
    todo: list[Any] = []
    for target in roots:
        module_name, _, attr = target.partition(":")
        obj = importlib.import_module(module_name)
        todo.append(getattr(obj, attr) if attr else obj)
    seen: dict[str, str] = {}
    while todo:
        obj = _unwrap(todo.pop())
        if isinstance(obj, tuple):  # a module-level assignment: (module, name)
            module, name = obj
            key_ = f"{module.__name__}:{name}="
            if key_ in seen:
                continue
            text = _assignment(module, name)
            if text is None:
                continue
            seen[key_] = text
            namespace = vars(module)
        else:
            if isinstance(obj, property):
                obj = obj.fget
            if not (inspect.ismodule(obj) or inspect.isclass(obj) or inspect.isfunction(obj)):
                continue
            if not _ours(obj):
                continue
            key_ = _qualname(obj)
            if key_ in seen:
                continue
            seen[key_] = text = source(obj)
            module = obj if inspect.ismodule(obj) else importlib.import_module(obj.__module__)
            namespace = vars(module)
        for node in ast.walk(ast.parse(textwrap.dedent(text))):
            if not isinstance(node, ast.Name | ast.Attribute):
                continue
            found = _resolve(node, namespace)
            if found is _MISSING:
                continue
            found = _unwrap(found)
            if inspect.isfunction(found) or inspect.isclass(found) or isinstance(found, property):
                todo.append(found)
            elif inspect.ismodule(found):
                continue  # a module is followed only through the attributes used
            elif isinstance(node, ast.Name) and node.id in namespace:
                todo.append((module, node.id))
    return seen


@cache
def code_fingerprint(roots: tuple[str, ...] = DEFAULT_ROOTS) -> str:
    """Hash of the code that computes cached results: the syntax trees of everything
    :func:`reachable` from ``roots``, with docstrings and comments removed and imports
    sorted, so documentation edits, formatting and import sorting do not invalidate
    data, while an edit of any function on the path does."""
    return fingerprint_of(reachable(roots))


def fingerprint_of(sources: Mapping[str, str]) -> str:
    """Combine the sources of :func:`reachable` into the 16-digit fingerprint."""
    h = hashlib.sha256()
    for name in sorted(sources):
        digest_ = hashlib.sha256(ast.dump(_tree(sources[name])).encode()).hexdigest()
        h.update(f"{name}={digest_};".encode())
    return h.hexdigest()[:16]


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


def canonical(obj: Any) -> str:
    """The canonical JSON text of ``obj`` (sorted keys, no spaces, floats by repr)."""
    return json.dumps(_plain(obj), sort_keys=True, separators=(",", ":"), allow_nan=False)


def digest(obj: Any) -> str:
    return hashlib.sha256(canonical(obj).encode()).hexdigest()


def key(kind: str, params: Mapping[str, Any]) -> str:
    """File name stem of a record: 20 hex digits of the hash of (kind, params)."""
    return digest({"kind": kind, "params": params})[:20]


def code_of(kind: str | None) -> str:
    """The code fingerprint that records of ``kind`` carry (see :data:`KIND_ROOTS`)."""
    return code_fingerprint(KIND_ROOTS.get(kind, DEFAULT_ROOTS))


def provenance(wall_time: float | None = None, kind: str | None = None) -> dict[str, Any]:
    import numba
    import numpy

    from . import __version__

    return {
        "package_version": __version__,
        "code": code_of(kind),
        "python": platform.python_version(),
        "numpy": numpy.__version__,
        "numba": numba.__version__,
        "created": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        "wall_time_s": wall_time,
    }


def write_json(path: str | os.PathLike[str], obj: Any) -> Path:
    """Write ``obj`` as JSON atomically: a temporary file in the same folder, flushed
    to disk, then renamed over ``path``; on any failure the temporary is removed and
    ``path`` is untouched."""
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(
        dir=target.parent, prefix=f".{target.stem}.{_owner()}.", suffix=TMP_SUFFIX
    )
    try:
        with os.fdopen(fd, "w") as fh:
            json.dump(obj, fh, indent=1, sort_keys=True, allow_nan=False)
            fh.write("\n")
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, 0o644)
        os.replace(tmp, target)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return target


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
        except (OSError, json.JSONDecodeError) as err:
            raise CorruptResultError(f"{path}: unreadable record ({err})") from err
        expected = digest({k: record.get(k) for k in ("kind", "params", "result")})
        if record.get("hash") != expected:
            raise CorruptResultError(
                f"{path}: content hash does not match its content "
                "(damaged or edited by hand); delete it to recompute"
            )
        return record

    def staleness(self, record: Mapping[str, Any]) -> str | None:
        """Why a record is stale, or None if it matches the current code."""
        from . import __version__

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

    def load(
        self, kind: str, params: Mapping[str, Any], on_stale: str = "recompute"
    ) -> dict[str, Any] | None:
        """The record for (kind, params), or None if it must be computed."""
        if on_stale not in ON_STALE:
            raise ValueError(f"on_stale={on_stale!r}; allowed: {', '.join(ON_STALE)}")
        path = self.path(kind, params)
        if not path.exists():
            return None
        record = self.read(path)
        if canonical(record["params"]) != canonical(params):
            raise StaleResultError(
                f"{path}: its parameters differ from the request (hash collision or a renamed file)"
            )
        why = self.staleness(record)
        if why is None or on_stale == "accept":
            return record
        if on_stale == "error":
            raise StaleResultError(
                f"{path} is stale: {why}. Recompute it with `make data` "
                "(or the sweep command with --on-stale recompute)"
            )
        return None

    def records(self, kind: str | None = None) -> Iterator[dict[str, Any]]:
        """Every record in the folder (of one kind), hashes checked."""
        pattern = f"{kind}-*.json" if kind else "*.json"
        for path in sorted(self.root.glob(pattern)):
            yield self.read(path)
