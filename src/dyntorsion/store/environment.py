"""The numerical environment a record was computed in: the versions of the libraries whose
arithmetic enters it and the OpenBLAS kernels of this machine.

The buckling scenes march in the package's compiled kernels (the Fig 8 scene on the quick
grid gave the same bits with either choice of kernels below).  The runs past self-contact also call LAPACK and OpenBLAS (the contact
step's linear solves, the frames' products), whose kernels OpenBLAS picks at start-up by
the processor (``Haswell`` on AVX2 machines, ``SkylakeX`` or ``Cooperlake`` with AVX-512,
...), and NumPy's loops, which it dispatches to AVX2 or AVX-512 code the same way.  Their
rounding differs in the last bit, and the whip of a violent run amplifies that to the
percent: a = 16 rad/(m s), N = 400, lambda_inf = -0.8 touched itself first at t = 3.223 s
with the Haswell kernels and at 3.254 s with SkylakeX's on one machine.  The committed
records were computed with OpenBLAS's Haswell kernels and NumPy's AVX2 loops; ``make``
asks for both (``OPENBLAS_CORETYPE=Haswell``, ``NPY_DISABLE_CPU_FEATURES`` naming NumPy's
AVX-512 groups) wherever the processor has AVX2, and a rerun on another machine then
reproduces them bit for bit (measured: the run above, on an AVX-512 machine).  :func:`numerical_environment` is what a record carries
(:func:`dyntorsion.store.fingerprint.script_provenance`).
"""

from __future__ import annotations

import ctypes
import platform
from importlib import metadata
from pathlib import Path

__all__ = [
    "numerical_environment",
    "numpy_simd",
    "avx512",
    "numpy_avx512_groups",
    "cpu_has_avx512",
    "blas_kernels",
]

#: the libraries whose arithmetic enters a record
LIBRARIES = ("numpy", "scipy", "numba", "llvmlite")

#: how OpenBLAS builds name the function that says which kernels it chose
_CORENAME = (
    "openblas_get_corename",
    "openblas_get_corename64_",
    "scipy_openblas_get_corename",
    "scipy_openblas_get_corename64_",
)


def blas_kernels() -> dict[str, str]:
    """The kernels each OpenBLAS library loaded in this process uses (its folder, e.g.
    ``numpy.libs`` or ``scipy.libs`` for the wheels' copies: kernel family), after loading NumPy's and SciPy's linear algebra; empty where none is found
    (another BLAS, or no ``/proc``)."""
    import numpy  # noqa: F401  (load the libraries whose kernels are asked for)
    import scipy.linalg  # noqa: F401
    import scipy.sparse.linalg  # noqa: F401

    maps = Path("/proc/self/maps")
    if not maps.exists():
        return {}
    paths = sorted({
        line.split()[-1] for line in maps.read_text().splitlines()
        if "openblas" in line.lower() and line.split()[-1].startswith("/")
    })  # fmt: skip
    out: dict[str, str] = {}
    for path in paths:
        try:
            lib = ctypes.CDLL(path)
        except OSError:
            continue
        for symbol in _CORENAME:
            fn = getattr(lib, symbol, None)
            if fn is not None:
                fn.restype = ctypes.c_char_p
                out[Path(path).parent.name] = fn().decode()
                break
    return out


def numpy_simd() -> list[str]:
    """The SIMD extensions NumPy dispatches its loops to in this process, beyond its
    baseline (``NPY_DISABLE_CPU_FEATURES`` removes some: the AVX-512 loops of its
    transcendental functions round differently from the AVX2 ones)."""
    umath = _umath()
    features = getattr(umath, "__cpu_features__", {})
    return [f for f in getattr(umath, "__cpu_dispatch__", []) if features.get(f, False)]


#: the names NumPy gives its AVX-512 dispatch groups (``X86_V4``, ``AVX512_ICL``, ... from
#: NumPy 2.4; ``AVX512F``, ``AVX512_SKX``, ... before)
AVX512_PREFIXES = ("X86_V4", "AVX512")


def avx512(features) -> list[str]:
    """Those of NumPy's SIMD ``features`` that use AVX-512."""
    return [f for f in features if f.startswith(AVX512_PREFIXES)]


def numpy_avx512_groups() -> str:
    """NumPy's AVX-512 dispatch groups, space-separated: what ``NPY_DISABLE_CPU_FEATURES``
    names to keep its loops on AVX2 (the Makefile's pin)."""
    return " ".join(avx512(getattr(_umath(), "__cpu_dispatch__", [])))


def cpu_has_avx512() -> bool:
    """Whether the processor has AVX-512 (its foundation, AVX512F), as NumPy detected it at
    start-up: true even where ``NPY_DISABLE_CPU_FEATURES`` keeps NumPy's loops off it."""
    return bool(getattr(_umath(), "__cpu_features__", {}).get("AVX512F", False))


def _umath():
    """NumPy's compiled core (``numpy._core`` from NumPy 2, ``numpy.core`` before)."""
    import numpy as np

    core = getattr(np, "_core", None)
    if core is None:  # NumPy 1
        core = np.core
    return core._multiarray_umath


def numerical_environment() -> dict:
    """Python, the machine and the versions of :data:`LIBRARIES`, NumPy's SIMD loops
    (:func:`numpy_simd`) and the OpenBLAS kernels (:func:`blas_kernels`): what a record's
    numbers depend on besides the code."""
    versions = {}
    for name in LIBRARIES:
        try:
            versions[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            versions[name] = None
    return {
        "python": platform.python_version(),
        "machine": platform.machine(),
        **versions,
        "numpy_simd": numpy_simd(),
        "blas_kernels": blas_kernels(),
    }
