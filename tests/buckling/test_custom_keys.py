"""A custom history's cache key holds everything its function computes with (issue 35,
item 10): closure values, globals it names, defaults, the helpers it calls; a function
without readable source runs but is not cached."""

from __future__ import annotations

import functools
import subprocess
import sys

import numpy as np
import pytest

from dyntorsion.buckling.loading import Custom
from dyntorsion.store.results import key

SCALE = 1.5


def _helper(t):
    return SCALE * t


def _closure(s):
    def f(t):
        return 10.0 + s * t

    return f


def _key(func) -> str:
    return key("buckling-onset", {"history": Custom("h", func).params()})


def test_closure_values_give_different_keys():
    assert _key(_closure(1.5)) != _key(_closure(3.0))
    assert _key(_closure(1.5)) == _key(_closure(1.5))


def test_a_global_the_function_reads_is_in_the_key(monkeypatch):
    def f(t):
        return 10.0 + SCALE * t

    before = _key(f)
    monkeypatch.setitem(f.__globals__, "SCALE", 3.0)
    assert _key(f) != before


def test_defaults_are_in_the_key():
    funcs = [lambda t, s=s: 10.0 + s * t for s in (1.0, 2.0)]  # lambdas built in a loop
    assert _key(funcs[0]) != _key(funcs[1])


def test_a_helper_it_calls_is_in_the_key(monkeypatch):
    def f(t):
        return 10.0 + _helper(t)

    before = _key(f)
    monkeypatch.setitem(_helper.__globals__, "SCALE", 2.5)  # the helper's own global
    assert _key(f) != before


def test_partial_is_keyed_by_its_bound_values():
    def f(t, s):
        return 10.0 + s * t

    assert _key(functools.partial(f, s=1.0)) != _key(functools.partial(f, s=2.0))


def test_library_functions_count_by_name():
    def f(t):
        return 10.0 + np.sin(t)

    assert _key(f) == _key(f)


def test_a_function_without_source_runs_but_is_not_cached():
    code = (
        "import numpy as np\n"
        "from dyntorsion.buckling.loading import Custom\n"
        "from dyntorsion.store.results import key\n"
        "h = Custom('h', lambda t: 10.0 + t)\n"
        "assert np.allclose(h(np.array([0.0, 1.0])), [10.0, 11.0])\n"
        "try:\n"
        "    key('buckling-onset', {'history': h.params()})\n"
        "except ValueError as err:\n"
        "    print(err)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert "cannot be cached" in out.stdout and "no readable source" in out.stdout


@pytest.mark.parametrize("s", [1.5, 3.0])
def test_two_closure_values_give_two_results(s):
    """The issue's case: s = 1.5 and s = 3.0 were served the same record."""
    h = Custom("ramp-s", _closure(s))
    assert h(np.array([2.0]))[0] == pytest.approx(10.0 + 2.0 * s)
