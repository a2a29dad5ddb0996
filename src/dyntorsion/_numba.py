"""The one place that sets numba's options for the whole package.

Every compiled kernel is decorated with :func:`jit`.  Kernels are cached on disk
(``cache=True``) so a fresh interpreter does not recompile them, release the GIL
(``nogil=True``) so sweeps can run scenes in threads, and keep strict IEEE
semantics (no ``fastmath``): the onset of a delayed instability is seeded by
numbers of size 1e-8 and we do not want reassociated sums to move it.

Set ``NUMBA_DISABLE_JIT=1`` to run every kernel as plain Python (slow, but
debuggable); that switch is numba's own.

The on-disk cache of the package's kernels lives in a folder named by the hash of
every module that defines kernels (:func:`kernel_sources_digest`), in the module's
``__pycache__`` (or under ``NUMBA_CACHE_DIR`` when set, or the temporary folder when
neither is writable).  Numba by itself notices a change of a kernel's own file only:
a kernel whose callee in another file changed would load its old compiled code and
run the old callee.  Keyed by the sources of all kernels, any such edit recompiles.
"""

from __future__ import annotations

import hashlib
import os
import tempfile
from functools import cache
from pathlib import Path
from typing import Annotated, get_args, get_origin, get_type_hints

import numba
import numpy as np
from numba.core import caching

JIT_OPTIONS = {"cache": True, "nogil": True, "fastmath": False, "error_model": "numpy"}

#: the package's source folder: kernels defined below it use :class:`SourceKeyedLocator`
PACKAGE_DIR = Path(__file__).resolve().parent


def kernel_sources_digest(root: Path = PACKAGE_DIR) -> str:
    """Hash of every module below ``root`` that uses this module (the ones defining
    kernels), by relative path and content."""
    h = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        text = path.read_bytes()
        if b"_numba" in text and path.name != "_numba.py":
            h.update(path.relative_to(root).as_posix().encode() + b"\0" + text + b"\0")
    h.update(Path(__file__).read_bytes())
    return h.hexdigest()[:16]


@cache
def _digest() -> str:
    return kernel_sources_digest()


class SourceKeyedLocator(caching._SourceFileBackedLocatorMixin, caching._CacheLocator):
    """Numba cache locator for the package's kernels: a folder per
    :func:`kernel_sources_digest` (see the module docstring)."""

    def __init__(self, py_func, py_file: str, base: Path):
        self._py_file = py_file
        self._lineno = py_func.__code__.co_firstlineno
        self._cache_path = str(base)

    def get_cache_path(self) -> str:
        return self._cache_path

    @classmethod
    def from_function(cls, py_func, py_file):
        try:
            Path(py_file).resolve().relative_to(PACKAGE_DIR)
        except (ValueError, OSError):
            return None  # not ours: numba's own locators decide
        name = f"numba-{_digest()}"
        sub = cls.get_suitable_cache_subpath(py_file)
        bases = [Path(py_file).parent / "__pycache__" / name]
        if numba.config.CACHE_DIR:
            bases.insert(0, Path(numba.config.CACHE_DIR) / name / sub)
        bases.append(Path(tempfile.gettempdir()) / f"dyntorsion-numba-{os.getuid()}" / name / sub)
        for base in bases:
            locator = cls(py_func, py_file, base)
            try:
                locator.ensure_cache_path()
            except OSError:
                continue
            return locator
        return None


if SourceKeyedLocator not in caching.CacheImpl._locator_classes:
    caching.CacheImpl._locator_classes.insert(0, SourceKeyedLocator)


def jit(func=None, signature=None, **overrides):
    """``numba.njit`` with the package's options (see module docstring).

    Use as ``@jit`` or ``@jit(signature=...)``.  An explicit signature compiles
    eagerly; kernels that take other compiled functions as arguments need one,
    because only then is their on-disk cache key the same in every process.
    """
    options = {**JIT_OPTIONS, **overrides}

    def wrap(f):
        if signature is None:
            return numba.njit(**options)(f)
        return numba.njit(signature, **options)(f)

    return wrap if func is None else wrap(func)


# Array types of the engine's compiled interface (all float64/int64, C-contiguous).
A1 = numba.types.float64[::1]
A2 = numba.types.float64[:, ::1]
A3 = numba.types.float64[:, :, ::1]
I1 = numba.types.int64[::1]
I2 = numba.types.int64[:, ::1]

#: annotations of the array fields of the kernels' NamedTuples: the array and its compiled type
Vector = Annotated[np.ndarray, A1]
Matrix = Annotated[np.ndarray, A2]
Stack = Annotated[np.ndarray, A3]
Indices = Annotated[np.ndarray, I1]
IndexMatrix = Annotated[np.ndarray, I2]

_SCALARS = {float: numba.float64, int: numba.int64, bool: numba.boolean}


def named(cls):
    """The numba type of the NamedTuple ``cls``, read from its annotations: ``float``,
    ``int`` and ``bool`` fields are float64, int64 and boolean, array fields are annotated
    with :data:`Vector`, :data:`Matrix`, :data:`Stack`, :data:`Indices` or
    :data:`IndexMatrix`, and a NamedTuple field is typed the same way (for signatures)."""
    hints = get_type_hints(cls, include_extras=True)
    field_types = []
    for name in cls._fields:
        hint = hints[name]
        if get_origin(hint) is Annotated:
            field_types.append(get_args(hint)[1])
        elif hint in _SCALARS:
            field_types.append(_SCALARS[hint])
        elif isinstance(hint, type) and issubclass(hint, tuple) and hasattr(hint, "_fields"):
            field_types.append(named(hint))
        else:
            raise TypeError(
                f"{cls.__name__}.{name}: annotation {hint!r} has no compiled type; use float, "
                "int, bool, a NamedTuple, or one of Vector, Matrix, Stack, Indices, IndexMatrix"
            )
    if all(t == field_types[0] for t in field_types):
        return numba.types.NamedUniTuple(field_types[0], len(field_types), cls)
    return numba.types.NamedTuple(field_types, cls)


#: signature of a model's load vector  F(y, params, out)
LOAD_SIGNATURE = numba.types.void(A1, A1, A1)
#: signature of a model's load Jacobian  dF(y, params, out)
JACOBIAN_SIGNATURE = numba.types.void(A1, A1, A2)


def load_kernel(func):
    """Compile a model's load vector F(y, p, out) with the engine's signature."""
    return jit(func, signature=LOAD_SIGNATURE)


def jacobian_kernel(func):
    """Compile a model's load Jacobian dF(y, p, out) with the engine's signature."""
    return jit(func, signature=JACOBIAN_SIGNATURE)
