"""The layout of the package: every module imports, and the layers the import-linter
contract lists are the package's folders, each with a docstring that names what of the
paper it holds; the tests' folders mirror the package's, and no test imports from
benchmarks/."""

from __future__ import annotations

import ast
import importlib
import pkgutil
import tomllib
from pathlib import Path

import pytest

import dyntorsion

TESTS = Path(__file__).resolve().parents[1]
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


def test_the_test_folders_mirror_the_package():
    """Each folder of tests/ that holds test modules is a folder of the package at the same
    place (or tests/site, for the docs, the install and the layout), and is a package, so
    that two test modules of one name in two folders do not collide."""
    package = Path(dyntorsion.__file__).parent
    folders = {p.parent for p in TESTS.rglob("test_*.py")} - {TESTS}
    assert folders, f"no test folders under {TESTS}"
    for folder in folders:
        rel = folder.relative_to(TESTS)
        assert rel == Path("site") or (package / rel / "__init__.py").is_file(), (
            f"tests/{rel.as_posix()} is no folder of the package {package}"
        )
        assert (folder / "__init__.py").is_file(), f"tests/{rel.as_posix()} has no __init__.py"


def test_no_test_imports_from_benchmarks():
    """The benchmarks are scripts outside the package: a test reaches what it checks through
    dyntorsion, never through benchmarks/."""
    scripts = {p.stem for p in (TESTS.parent / "benchmarks").glob("*.py")} | {"benchmarks"}
    assert len(scripts) > 1, "no benchmarks/ beside tests/"
    found = []
    for path in sorted(TESTS.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom):
                names = [node.module or ""]
            else:
                continue
            where = f"tests/{path.relative_to(TESTS).as_posix()}:{node.lineno}"
            found += [f"{where} imports {n}" for n in names if n.split(".")[0] in scripts]
    assert not found, found
