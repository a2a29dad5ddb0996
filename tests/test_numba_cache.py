"""The kernels' disk cache follows the sources of every kernel, not just its own file."""

from __future__ import annotations

from pathlib import Path
from typing import NamedTuple

import numba
import numpy as np
import pytest

from dyntorsion import _numba
from dyntorsion._numba import Matrix, Vector, named
from dyntorsion.genalpha import march


def _package(root: Path) -> None:
    (root / "callee.py").write_text("from ._numba import jit\n\n\n@jit\ndef f(x):\n    return x\n")
    (root / "caller.py").write_text(
        "from ._numba import jit\nfrom .callee import f\n\n\n@jit\ndef g(x):\n    return f(x)\n"
    )
    (root / "plain.py").write_text("def h(x):\n    return x\n")


def test_editing_a_callee_changes_the_cache_folder_of_every_kernel(tmp_path):
    _package(tmp_path)
    before = _numba.kernel_sources_digest(tmp_path)
    assert _numba.kernel_sources_digest(tmp_path) == before
    (tmp_path / "callee.py").write_text(
        "from ._numba import jit\n\n\n@jit\ndef f(x):\n    return 2 * x\n"
    )
    assert _numba.kernel_sources_digest(tmp_path) != before


def test_a_module_without_kernels_does_not_move_the_cache(tmp_path):
    _package(tmp_path)
    before = _numba.kernel_sources_digest(tmp_path)
    (tmp_path / "plain.py").write_text("def h(x):\n    return 3 * x\n")
    assert _numba.kernel_sources_digest(tmp_path) == before


def test_the_package_kernels_are_cached_under_the_digest():
    locator = _numba.SourceKeyedLocator.from_function(march.march.py_func, march.__file__)
    assert locator is not None
    assert f"numba-{_numba.kernel_sources_digest()}" in locator.get_cache_path()
    assert _numba.SourceKeyedLocator.from_function(len, __file__) is None  # not ours


class _Inner(NamedTuple):
    a: float
    b: int


class _Outer(NamedTuple):
    x: Vector
    m: Matrix
    flag: bool
    inner: _Inner


class _Bad(NamedTuple):
    x: np.ndarray


def test_named_reads_compiled_types_from_annotations():
    """A kernel structure's numba type comes from its field annotations (one place for each
    field's type); a field without a compiled type is refused, naming it."""
    t = named(_Outer)
    assert t.types[0] == numba.types.float64[::1]
    assert t.types[1] == numba.types.float64[:, ::1]
    assert t.types[2] == numba.boolean
    assert t.types[3].types == (numba.float64, numba.int64)
    with pytest.raises(TypeError, match=r"_Bad\.x: annotation .* has no compiled type"):
        named(_Bad)


class _Event:
    """A stand-in for numba's ``numba:compile`` event of a dispatcher of ``func``."""

    def __init__(self, func):
        self.data = {"dispatcher": type("D", (), {"py_func": staticmethod(func)})()}


def _foreign(x):
    return x


def test_the_package_s_kernels_compile_at_their_level_and_others_at_numba_s(monkeypatch):
    from numba.np import arrayobj

    monkeypatch.delenv("NUMBA_OPT", raising=False)
    listener, before = _numba._KernelCompilation(), numba.config.OPT
    ours = _Event(march.march.py_func)
    template = _numba._shape_error_template()
    assert template is not None  # numba still has the overload this swaps
    listener.on_start(_Event(_foreign))
    assert numba.config.OPT == before and listener.depth == 0
    listener.on_start(ours)
    listener.on_start(_Event(_foreign))  # a callee compiled inside one of ours
    assert numba.config.OPT == _numba.KERNEL_OPT
    assert template._overload_func is arrayobj.ol_raise_with_shape_context_generic
    listener.on_end(None)
    assert numba.config.OPT == _numba.KERNEL_OPT
    listener.on_end(None)
    assert numba.config.OPT == before and type(numba.config.OPT) is type(before)
    assert template._overload_func is arrayobj.ol_raise_with_shape_context_cpu


def test_numba_opt_in_the_environment_wins(monkeypatch):
    monkeypatch.setenv("NUMBA_OPT", "3")
    listener, before = _numba._KernelCompilation(), numba.config.OPT
    listener.on_start(_Event(march.march.py_func))
    assert numba.config.OPT == before
    listener.on_end(None)
    assert numba.config.OPT == before
