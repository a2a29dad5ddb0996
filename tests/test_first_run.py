"""A new installation's first commands: nothing compiles at import, a kernel compiles at its
first use (saying so once when the disk cache is cold), ``warmup`` compiles ahead."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numba
import numpy as np
import pytest

from dyntorsion import _numba

SRC = str(Path(_numba.__file__).resolve().parents[1])
NOTICE = "compiling the engine's kernels, once"


def _python(code: str, cache: Path) -> subprocess.CompletedProcess:
    """Run ``code`` in a new interpreter whose numba cache is the folder ``cache``."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache), "PYTHONPATH": SRC}
    env.pop("NUMBA_DISABLE_JIT", None)
    return subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
    )


def test_importing_the_package_and_its_command_line_compiles_nothing(tmp_path):
    out = _python(
        "from numba.core import event\n"
        "seen = []\n"
        "class L(event.Listener):\n"
        "    def on_start(self, ev): seen.append(ev.data['dispatcher'].py_func.__name__)\n"
        "    def on_end(self, ev): pass\n"
        "event.register('numba:compile', L())\n"
        "import dyntorsion, dyntorsion.app.cli\n"
        "from dyntorsion import _numba\n"
        "import importlib\n"
        "[importlib.import_module(m) for m in _numba.kernel_modules()]\n"
        "pending = sum(d._declared is not None for d in _numba.DEFERRED)\n"
        "print(len(seen), pending, len(_numba.DEFERRED))\n",
        tmp_path,
    )
    compiled, pending, declared = map(int, out.stdout.split())
    assert compiled == 0
    assert declared > 0 and pending == declared
    assert NOTICE not in out.stderr


def test_a_cold_cache_is_announced_once_and_a_warm_one_not(tmp_path):
    code = (
        "import numpy as np\n"
        "from dyntorsion.genalpha.march import norm_sum\n"
        "y = np.ones((3, 2)); f = np.arange(2)\n"
        "print(norm_sum(y, f, 2.0), norm_sum(y, f, 1.0))\n"
    )
    cold = _python(code, tmp_path)
    assert [float(v) for v in cold.stdout.split()] == [6 * np.sqrt(2.0), 3 * np.sqrt(2.0)]
    assert cold.stderr.count(NOTICE) == 1
    warm = _python(code, tmp_path)
    assert warm.stdout == cold.stdout
    assert NOTICE not in warm.stderr


def test_a_declared_signature_compiles_at_first_call_and_no_other():
    def twice(x):
        return 2.0 * x

    kernel = _numba.jit(twice, signature=numba.float64(numba.float64), cache=False)
    try:
        assert isinstance(kernel, _numba.DeferredDispatcher)
        assert kernel.signatures == []  # nothing compiled at definition
        assert kernel(3) == 6.0  # an int converts to the declared float64, as when eager
        assert [tuple(s) for s in kernel.signatures] == [(numba.float64,)]
        with pytest.raises(TypeError):
            kernel(np.ones(2))  # no second signature is compiled
        assert len(kernel.signatures) == 1
    finally:
        _numba.DEFERRED.remove(kernel)


def test_a_declared_kernel_compiles_when_another_kernel_calls_it():
    def inner(x):
        return x + 1.0

    callee = _numba.jit(inner, signature=numba.float64(numba.float64), cache=False)

    @numba.njit
    def outer(x):
        return callee(x) * 2.0

    try:
        assert outer(1.0) == 4.0
        assert callee._declared is None and len(callee.signatures) == 1
    finally:
        _numba.DEFERRED.remove(callee)


def test_kernel_modules_are_the_package_modules_that_define_kernels():
    names = _numba.kernel_modules()
    assert "dyntorsion.genalpha.march" in names
    assert "dyntorsion.model.cosserat" in names
    assert "dyntorsion._numba" not in names and "dyntorsion.store.fingerprint" not in names


def test_the_warmup_command_compiles_every_declared_kernel(monkeypatch, capsys):
    from dyntorsion.app import cli, warmup

    monkeypatch.setattr(_numba, "warmup", lambda: 7)
    args = cli.parser().parse_args(["warmup"])
    assert args.func is warmup.warmup
    assert cli.main(["warmup"]) == 0
    assert "7 kernels compiled or loaded" in capsys.readouterr().out


def test_a_pickled_declared_kernel_keeps_its_one_signature():
    import pickle

    kernel = _numba.jit(_triple, signature=numba.float64(numba.float64), cache=False)
    try:
        clone = pickle.loads(pickle.dumps(kernel))
        assert clone(2) == 6.0
        assert [tuple(s) for s in clone.signatures] == [(numba.float64,)]
        with pytest.raises(TypeError):
            clone(np.ones(2))
    finally:
        _numba.DEFERRED.remove(kernel)


def _triple(x):
    return 3.0 * x


def test_the_notice_is_one_whole_line_in_one_write(monkeypatch):
    """Workers of a sweep that compile at once share stderr: each notice is written in one
    call, so two of them never run together on one line."""

    class Stream:
        def __init__(self):
            self.writes = []

        def write(self, text):
            self.writes.append(text)

        def flush(self):
            pass

    stream = Stream()
    monkeypatch.setattr(sys, "stderr", stream)
    _numba.announce_cold_cache()
    assert len(stream.writes) == 1
    assert stream.writes[0].endswith("\n") and stream.writes[0].count("\n") == 1
    assert NOTICE in stream.writes[0]


def test_the_notice_is_silent_where_the_environment_says_so(tmp_path):
    """The site's notebooks set DYNTORSION_COMPILE_NOTICE=0: a cold cache compiles, silently."""
    code = (
        "import numpy as np\n"
        "from dyntorsion.genalpha.march import norm_sum\n"
        "print(norm_sum(np.ones((3, 2)), np.arange(2), 2.0))\n"
    )
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path), "PYTHONPATH": SRC,
           _numba.NOTICE_VARIABLE: "0"}  # fmt: skip
    env.pop("NUMBA_DISABLE_JIT", None)
    out = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
    )
    assert float(out.stdout) == 6 * np.sqrt(2.0)
    assert NOTICE not in out.stderr
