"""The one place that sets numba's options for the whole package.

Every compiled kernel is decorated with :func:`jit`.  Kernels are cached on disk
(``cache=True``) so a fresh interpreter does not recompile them, release the GIL
(``nogil=True``) so sweeps can run scenes in threads, and keep strict IEEE
semantics (no ``fastmath``): the onset of a delayed instability is seeded by
numbers of size 1e-8 and we do not want reassociated sums to move it.

Nothing compiles at import: a kernel compiles at its first call (or when a kernel that
calls it compiles), loading its machine code from the disk cache when it is there.  A
kernel with an explicit signature (:func:`jit` ``signature=``) compiles exactly that
signature then, and no other, as an eagerly compiled kernel would
(:class:`DeferredDispatcher`).  The first compilation in a process that misses the disk
cache says so on stderr, once (:func:`announce_cold_cache`); :func:`warmup` compiles every
signed kernel ahead (``dyntorsion warmup``).

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
import importlib
import os
import sys
import tempfile
from functools import cache
from pathlib import Path
from typing import Annotated, get_args, get_origin, get_type_hints

import numba
import numpy as np
from numba.core import caching, event, typeinfer
from numba.core.compiler_lock import global_compiler_lock
from numba.core.registry import CPUDispatcher

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


class DeferredDispatcher(CPUDispatcher):
    """A dispatcher that compiles its one declared signature at first need, then no other.

    Eager ``numba.njit(signature)`` compiles at import; this one waits until it is called
    from Python, typed as the callee of another kernel, or converted to a first-class
    function: then it compiles ``signature`` (from the disk cache when current) and
    disables further compilation, so from there on it behaves exactly as the eagerly
    compiled kernel (same machine code, same conversions, same errors).
    """

    _declared = None  # the signature still to compile; None once compiled

    def compile_declared(self) -> None:
        """Compile the declared signature now, if it is still pending (thread-safe)."""
        if self._declared is None:
            return
        with global_compiler_lock:  # numba's own (reentrant): no second lock to deadlock on
            if self._declared is None:
                return
            with typeinfer.register_dispatcher(self):
                self.compile(self._declared)
            self.disable_compile()
            self._declared = None

    def _compile_for_args(self, *args, **kws):
        if self._declared is None:
            return super()._compile_for_args(*args, **kws)
        self.compile_declared()
        return self  # numba calls what this returns: now the compiled dispatch decides

    def get_call_template(self, args, kws):
        self.compile_declared()
        return super().get_call_template(args, kws)

    def get_compile_result(self, sig):
        self.compile_declared()
        return super().get_compile_result(sig)

    def _reduce_states(self):
        # pickled (to another process): as the eager kernel, its one signature and no other
        self.compile_declared()
        return super()._reduce_states()


#: every kernel with a declared signature, in order of definition (what :func:`warmup` compiles)
DEFERRED: list[DeferredDispatcher] = []


def jit(func=None, signature=None, **overrides):
    """``numba.njit`` with the package's options (see module docstring).

    Use as ``@jit`` or ``@jit(signature=...)``.  Without a signature the kernel compiles
    for the argument types of its first call.  With one, it compiles that signature at
    first need and never another (a :class:`DeferredDispatcher`); kernels that take other
    compiled functions as arguments need one, because only then is their on-disk cache key
    the same in every process.
    """
    options = {**JIT_OPTIONS, **overrides}

    def wrap(f):
        if signature is None or numba.config.DISABLE_JIT:
            return numba.njit(**options)(f)
        cache_on = options.pop("cache")
        targetoptions = {**options, "nopython": True, "boundscheck": None}
        dispatcher = DeferredDispatcher(py_func=f, locals={}, targetoptions=targetoptions)
        if cache_on:
            dispatcher.enable_caching()
        dispatcher._declared = signature
        DEFERRED.append(dispatcher)
        return dispatcher

    return wrap if func is None else wrap(func)


#: rough time a cold cache costs the first run that compiles the engine's kernels (2 cores)
COLD_COMPILE_SECONDS = 25


#: set to ``0`` in the environment to silence the cold-cache notice (the site's notebooks do,
#: so that a page never shows a one-time message of the machine that built it)
NOTICE_VARIABLE = "DYNTORSION_COMPILE_NOTICE"


class _ColdCacheNotice(event.Listener):
    """Says once per process, on stderr, that the package's kernels are being compiled:
    numba fires ``numba:compile`` only for a signature missing from the disk cache.
    Silent where :data:`NOTICE_VARIABLE` is ``0``."""

    said = False

    def on_start(self, ev):
        if self.said or os.environ.get(NOTICE_VARIABLE) == "0":
            return
        dispatcher = ev.data.get("dispatcher")
        py_func = getattr(dispatcher, "py_func", None)
        path = getattr(getattr(py_func, "__code__", None), "co_filename", "")
        try:
            Path(path).resolve().relative_to(PACKAGE_DIR)
        except (ValueError, OSError):
            return  # not one of ours
        type(self).said = True
        announce_cold_cache()

    def on_end(self, ev):
        pass


def announce_cold_cache() -> None:
    """Print the cold-cache notice on stderr (see :class:`_ColdCacheNotice`), as one write:
    the workers of a sweep that compile at once print whole lines."""
    sys.stderr.write(
        f"dyntorsion: compiling the engine's kernels, once: about {COLD_COMPILE_SECONDS} s "
        "(`dyntorsion warmup` compiles all of them ahead)\n"
    )
    sys.stderr.flush()


event.register("numba:compile", _ColdCacheNotice())

#: numba's optimisation level for the package's kernels (numba's own default is 3).  At 1
#: the engine compiles in about three quarters of the time, runs as fast and computes the
#: same numbers bit for bit: without fast-math no level may reorder a floating-point
#: operation (the Benchmarks page has the measurements).  ``NUMBA_OPT`` in the environment
#: overrides it.
KERNEL_OPT = 1


def _ours(ev) -> bool:
    """Whether a ``numba:compile`` event compiles one of the package's kernels."""
    py_func = getattr(ev.data.get("dispatcher"), "py_func", None)
    path = getattr(getattr(py_func, "__code__", None), "co_filename", "")
    try:
        Path(path).resolve().relative_to(PACKAGE_DIR)
    except (ValueError, OSError):
        return False
    return True


def _shape_error_template():
    """numba's CPU overload that formats the message of a slice assignment whose shapes
    differ, or None where numba has none."""
    from numba.core.registry import cpu_target
    from numba.np import arrayobj

    try:
        cpu_target.typing_context.refresh()  # load numba's registrations, as a compile does
        fnty = cpu_target.typing_context.resolve_value_type(arrayobj.raise_with_shape_context)
    except Exception:  # noqa: BLE001 - another numba: keep its own message
        return None
    for template in getattr(fnty, "templates", ()):
        if getattr(template, "_overload_func", None) is arrayobj.ol_raise_with_shape_context_cpu:
            return template
    return None


class _KernelCompilation(event.Listener):
    """How the package's kernels, and what they call, compile: at :data:`KERNEL_OPT`, and
    with numba's generic message for a slice assignment whose shapes differ ("cannot
    assign slice from input of different size") in place of its CPU message, whose string
    formatting costs about 5 s of a first run's compilation.  numba reads ``config.OPT``
    as it optimises each library, so both are set for the outermost compilation of one of
    ours (under numba's compiler lock) and restored after it; other code compiles as numba
    would (except that a slice assignment of the same ranks compiled later in the same
    process reuses numba's cached generic message)."""

    def __init__(self) -> None:
        self.depth, self.saved, self.template = 0, None, None

    def on_start(self, ev):
        if self.depth == 0 and not _ours(ev):
            return
        if self.depth == 0:
            from numba.np import arrayobj

            self.saved = numba.config.OPT
            if "NUMBA_OPT" not in os.environ:
                numba.config.OPT = type(self.saved)(KERNEL_OPT)
            self.template = _shape_error_template()
            if self.template is not None:
                self.template._overload_func = arrayobj.ol_raise_with_shape_context_generic
        self.depth += 1

    def on_end(self, ev):
        if self.depth == 0:
            return
        self.depth -= 1
        if self.depth == 0:
            from numba.np import arrayobj

            numba.config.OPT = self.saved
            if self.template is not None:
                self.template._overload_func = arrayobj.ol_raise_with_shape_context_cpu


event.register("numba:compile", _KernelCompilation())


def kernel_modules(root: Path = PACKAGE_DIR) -> list[str]:
    """Dotted names of the package's modules that define kernels (those using this one)."""
    names = []
    for path in sorted(root.rglob("*.py")):
        if path.name != "_numba.py" and b"_numba" in path.read_bytes():
            parts = path.relative_to(root.parent).with_suffix("").parts
            names.append(".".join(parts[:-1] if parts[-1] == "__init__" else parts))
    return names


def warmup() -> int:
    """Import every module that defines kernels and compile every declared signature now
    (from the disk cache where it is current); returns how many kernels were compiled."""
    for name in kernel_modules():
        importlib.import_module(name)
    for dispatcher in DEFERRED:
        dispatcher.compile_declared()
    return len(DEFERRED)


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
