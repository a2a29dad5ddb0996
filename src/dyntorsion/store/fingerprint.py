"""Code fingerprints of cached records: which code computed a number.

A record of each kind carries the fingerprint of the code its computation can reach
from its entry points (:data:`KIND_ROOTS`): :func:`reachable` walks the package's own
definitions from those roots (names, attribute chains, module-level assignments, the
Python source of compiled kernels), and :func:`fingerprint_of` hashes their syntax
trees with docstrings and comments removed and imports sorted -- documentation edits,
formatting and import order leave records current; an edit of any function on the path
makes them stale.  The fingerprint does not depend on where a definition lives: each is
named by its qualified name within its module (a function moved to another module, or a
module moved to another folder, keeps its records current), and import statements are left
out (the definitions they bring in are followed and hashed themselves).

The store knows no physics: the roots of each record kind are registered by the layer that
computes them (:func:`register_kind`, called in :mod:`dyntorsion.studies`).
"""

from __future__ import annotations

import ast
import hashlib
import importlib
import inspect
import os
import textwrap
from collections.abc import Mapping
from functools import cache
from pathlib import Path
from typing import Any

from . import fingerprint_cache
from .moved_scripts import MOVED_SCRIPTS

__all__ = [
    "KIND_ROOTS",
    "register_kind",
    "reachable",
    "code_fingerprint",
    "fingerprint_of",
    "code_of",
    "script_provenance",
    "why_stale",
    "MOVED_SCRIPTS",
]

#: where the computation of each record kind starts (``module:object`` or a whole
#: ``module``), registered by the layer that computes it: its fingerprint covers every
#: function, class and module-level definition of the package reachable from these
KIND_ROOTS: dict[str, tuple[str, ...]] = {}


def register_kind(kind: str, roots: tuple[str, ...]) -> None:
    """Declare where the computation of records of ``kind`` starts."""
    if not roots or not all(isinstance(r, str) and r for r in roots):
        raise ValueError(f"roots={roots!r} must be a non-empty tuple of 'module[:object]' strings")
    KIND_ROOTS[kind] = tuple(roots)


PACKAGE = "dyntorsion"


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


class _NoImports(ast.NodeTransformer):
    def visit_Import(self, node: ast.AST) -> None:
        return None

    visit_ImportFrom = visit_Import


def _tree(source: str) -> ast.Module:
    """Syntax tree without docstrings and imports: where a name comes from is no change
    (what it is, is hashed on its own)."""
    tree = _NoImports().visit(_strip_docstrings(ast.parse(textwrap.dedent(source))))
    for node in ast.walk(tree):  # a body left empty by the removal stays valid
        body = getattr(node, "body", None)
        if isinstance(body, list) and not body:
            node.body = [ast.Pass()]
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


#: the package's own layers that keep records but compute no number: a record's
#: fingerprint does not follow into them (a study that caches its runs in the store is
#: not stale when the store's bookkeeping changes)
NOT_COMPUTING = (f"{PACKAGE}.store",)


def _ours(obj: Any) -> bool:
    """Whether ``obj`` is the package's own code that computes numbers."""
    name = getattr(obj, "__name__", "") if inspect.ismodule(obj) else getattr(obj, "__module__", "")
    if not isinstance(name, str) or not (name == PACKAGE or name.startswith(PACKAGE + ".")):
        return False
    return not any(name == m or name.startswith(m + ".") for m in NOT_COMPUTING)


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


def reachable(roots: tuple[str, ...], source=inspect.getsource) -> dict[str, str]:
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
def code_fingerprint(roots: tuple[str, ...]) -> str:
    """Hash of the code that computes cached results: the syntax trees of everything
    :func:`reachable` from ``roots``, with docstrings and comments removed and imports
    sorted, so documentation edits, formatting and import sorting do not invalidate
    data, while an edit of any function on the path does.

    Walking the code takes about a second a kind; the result is kept on disk
    (:mod:`.fingerprint_cache`), keyed by the bytes of every module of the package, so a
    process whose package is byte for byte the same reads it back."""
    name = "|".join((PACKAGE, *roots))
    kept = fingerprint_cache.read(name)
    if kept is not None:
        return kept
    fingerprint = fingerprint_of(reachable(roots))
    fingerprint_cache.write(name, fingerprint)
    return fingerprint


def _local_name(name: str) -> str:
    """``package.module:qualname`` -> ``qualname``; a whole module -> its last component."""
    module, sep, qual = name.partition(":")
    return qual if sep else module.rsplit(".", 1)[-1]


def fingerprint_of(sources: Mapping[str, str]) -> str:
    """Combine the sources of :func:`reachable` into the 16-digit fingerprint (each named
    by :func:`_local_name`, so that moving a definition between modules changes nothing)."""
    entries = sorted(
        f"{_local_name(name)}={hashlib.sha256(ast.dump(_tree(text)).encode()).hexdigest()};"
        for name, text in sources.items()
    )
    return hashlib.sha256("".join(entries).encode()).hexdigest()[:16]


def code_of(kind: str | None) -> str:
    """The code fingerprint that records of ``kind`` carry (see :data:`KIND_ROOTS`)."""
    if kind not in KIND_ROOTS:
        raise LookupError(
            f"kind={kind!r} has no registered code roots (registered: "
            f"{', '.join(sorted(KIND_ROOTS)) or 'none'}): import dyntorsion.studies, which "
            "registers the package's record kinds, or call register_kind for your own"
        )
    return code_fingerprint(KIND_ROOTS[kind])


def _sha256(path: str | os.PathLike[str]) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def _is_module(source: str | os.PathLike[str]) -> bool:
    """Whether ``source`` names a module of the package (else it is a script's path)."""
    return (
        isinstance(source, str) and source.startswith(PACKAGE + ".") and not source.endswith(".py")
    )


def _digest(source: str | os.PathLike[str]) -> str:
    """Digest of a module of the package or of a script's file: its syntax tree with
    docstrings, comments and imports left out (as :func:`code_fingerprint` hashes each
    definition)."""
    if _is_module(source):
        return _source_digest(str(source))
    return hashlib.sha256(ast.dump(_tree(Path(source).read_text())).encode()).hexdigest()


def _where(target: str) -> str | Path:
    """A :data:`MOVED_SCRIPTS` target: a module name, or a path in the checkout."""
    from .location import checkout

    return target if _is_module(target) else (checkout() or Path.cwd()) / target


def script_provenance(
    script: str | os.PathLike[str],
    roots: tuple[str, ...],
    imports: tuple[str | os.PathLike[str], ...] = (),
) -> dict:
    """The ``code`` part of a record written to ``data/`` by a module of the package
    (``script`` its name, e.g. ``"dyntorsion.studies.contact.contact_budget"``) or by a
    script (``script`` its path), computed with the package's code reachable from
    ``roots``.

    Holds the package version; the module's digest (its code without docstrings and
    imports, :func:`_digest`) or the script's sha256; those of the modules or sibling
    scripts it ``imports``; the roots and their :func:`code_fingerprint`; and the numerical
    environment (:func:`dyntorsion.store.environment.numerical_environment`: a resumed
    record is completed only in the environment it was begun in).  :func:`why_stale`
    reads it back; the environment does not make a record stale (the same code gives the
    same numbers to round-off in any of them).
    """
    from .._version import __version__
    from .environment import numerical_environment

    out: dict[str, Any] = {"dyntorsion": __version__}
    if _is_module(script):
        out["module"] = str(script)
        out["module_digest"] = _digest(script)
    else:
        out["script_sha256"] = _sha256(script)
    out["roots"] = list(roots)
    out["code_fingerprint"] = code_fingerprint(tuple(roots))
    files = [p for p in imports if not _is_module(p)]
    modules = [m for m in imports if _is_module(m)]
    if files:
        out["imports_sha256"] = {Path(p).name: _sha256(p) for p in files}
    if modules:
        out["imports_digest"] = {str(m): _digest(m) for m in modules}
    out["environment"] = numerical_environment()
    return out


def _moved_to(script: str | os.PathLike[str]) -> str | os.PathLike[str]:
    """Where the code of ``script`` lives now: a moved script's path gives its module."""
    if _is_module(script) or Path(script).exists() or Path(script).name not in MOVED_SCRIPTS:
        return script
    return _where(MOVED_SCRIPTS[Path(script).name][0])


def _old_name(source: str | os.PathLike[str]) -> str:
    """The file name a module had as a script (its own name for a script)."""
    if not _is_module(source):
        return Path(source).name
    return next((old for old, (m, *_) in MOVED_SCRIPTS.items() if m == source), str(source))


def _same_script(sha: str, old: str, here: Path | None) -> bool:
    """Whether a record's ``sha`` of the script ``old`` (found ``here`` if it is beside the
    record's script) names the code of today: the same file, or the script's last
    version whose code is unchanged where it lives now (:data:`MOVED_SCRIPTS`)."""
    if here is not None and here.exists() and _sha256(here) == sha:
        return True
    entry = MOVED_SCRIPTS.get(old)
    if entry is None or entry[1] != sha:
        return False
    target = _where(entry[0])
    return (_is_module(target) or Path(target).exists()) and _digest(target) == entry[2]


def why_stale(code: Mapping[str, Any], script: str | os.PathLike[str]) -> str | None:
    """Why a record whose ``code`` part is :func:`script_provenance`'s is no longer what
    ``script`` (a module name or a script's path; the path of a script since moved into
    the package names its module, :data:`MOVED_SCRIPTS`) and today's package would
    compute, or None if it is current.

    Stale when the module or script, or one it imports, changed (its code: a docstring
    edit of a module is no change), or code reachable from the record's roots changed.
    """
    script = _moved_to(script)
    name = str(script) if _is_module(script) else Path(script).name
    if "roots" not in code or not ({"script_sha256", "module_digest"} & set(code)):
        return f"the record carries no roots or script hash: rerun {name}"
    if "module_digest" in code:
        if code.get("module") != script or _digest(script) != code["module_digest"]:
            return f"{name} changed since the record was written: rerun it"
    elif not _same_script(
        code["script_sha256"], _old_name(script), None if _is_module(script) else Path(script)
    ):
        return f"{name} changed since the record was written: rerun it"
    for other, sha in code.get("imports_sha256", {}).items():
        here = None if _is_module(script) else Path(script).with_name(other)
        if not _same_script(sha, other, here):
            return f"{other}, which {name} imports, changed since the record: rerun {name}"
    for module, digest in code.get("imports_digest", {}).items():
        if _digest(module) != digest:
            return f"{module}, which {name} imports, changed since the record: rerun {name}"
    now = code_fingerprint(tuple(code["roots"]))
    if code.get("code_fingerprint") != now:
        return (
            f"the code reachable from {', '.join(code['roots'])} changed since the record "
            f"(fingerprint {code.get('code_fingerprint')} then, {now} now): rerun {name}"
        )
    return None
