"""The layout of the package (issue 31): every module imports, and the layers the
import-linter contract lists are the package's folders, each with a docstring that names
what of the paper it holds."""

from __future__ import annotations

import importlib
import pkgutil
import tomllib
from pathlib import Path

import pytest

import dyntorsion

MODULES = sorted(m.name for m in pkgutil.walk_packages(dyntorsion.__path__, "dyntorsion."))


@pytest.mark.parametrize("name", MODULES)
def test_every_module_imports(name):
    importlib.import_module(name)


def test_the_layers_contract_names_every_folder_once():
    project = tomllib.loads((Path(__file__).parents[2] / "pyproject.toml").read_text())
    contracts = project["tool"]["importlinter"]["contracts"]
    (layers,) = [c["layers"] for c in contracts if c["type"] == "layers"]
    listed = [p.strip() for entry in layers for p in entry.split("|")]
    assert len(listed) == len(set(listed))
    folders = {f"dyntorsion.{m.name}" for m in pkgutil.iter_modules(dyntorsion.__path__) if m.ispkg}
    assert folders <= set(listed), folders - set(listed)
    for name in folders:
        assert importlib.import_module(name).__doc__, f"{name} has no docstring"
