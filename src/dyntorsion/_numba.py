"""The one place that sets numba's options for the whole package.

Every compiled kernel is decorated with :func:`jit`.  Kernels are cached on disk
(``cache=True``) so a fresh interpreter does not recompile them, release the GIL
(``nogil=True``) so sweeps can run scenes in threads, and keep strict IEEE
semantics (no ``fastmath``): the onset of a delayed instability is seeded by
numbers of size 1e-8 and we do not want reassociated sums to move it.

Set ``NUMBA_DISABLE_JIT=1`` to run every kernel as plain Python (slow, but
debuggable); that switch is numba's own.
"""

from __future__ import annotations

import numba

JIT_OPTIONS = {"cache": True, "nogil": True, "fastmath": False, "error_model": "numpy"}


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


def named(cls, *field_types):
    """The numba type of the NamedTuple ``cls`` with fields of ``field_types`` (for signatures)."""
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
