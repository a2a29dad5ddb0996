"""Installs anywhere (issue 32): one version, package data, the default store."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

import dyntorsion
from dyntorsion.app.cli import main
from dyntorsion.published import published, value
from dyntorsion.store import location

ROOT = Path(__file__).resolve().parents[2]


def test_one_version_everywhere():
    """The package, its metadata, the CLI and CITATION.cff give the same version."""
    from importlib.metadata import version

    cff = (ROOT / "CITATION.cff").read_text()
    (cited,) = re.findall(r"^version:\s*(\S+)\s*$", cff, re.M)
    assert dyntorsion.__version__ == version("dyntorsion") == cited
    out = subprocess.run(
        [sys.executable, "-m", "dyntorsion", "--version"],
        capture_output=True,
        text=True,
        check=True,
    )
    assert out.stdout.strip() == f"dyntorsion {dyntorsion.__version__}"


def test_the_papers_values_are_package_data():
    """Read through importlib.resources, not a path into the source tree."""
    from importlib.resources import files

    assert files("dyntorsion").joinpath("published.json").is_file()
    assert value("kappa_cri") == pytest.approx(11.2335)
    assert {"b", "sigma", "kappa_cri"} <= set(published())
    assert not (ROOT / "paper" / "published.json").exists()  # one copy


def test_default_store_environment_then_checkout_then_user_cache(monkeypatch, tmp_path):
    monkeypatch.setenv("DYNTORSION_DATA", str(tmp_path / "env"))
    assert location.store_origin() == (tmp_path / "env", "DYNTORSION_DATA is set")
    monkeypatch.delenv("DYNTORSION_DATA")
    store, why = location.store_origin()
    assert store == ROOT / "data" / "scenes" and "checkout" in why
    monkeypatch.setattr(location, "DATA", None)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    store, why = location.store_origin()
    assert store == tmp_path / "cache" / "dyntorsion" / "scenes" and "user cache" in why


def test_a_checkout_is_recognised_by_its_pyproject(tmp_path):
    (tmp_path / "src" / "dyntorsion").mkdir(parents=True)
    (tmp_path / "pyproject.toml").write_text('[project]\nname = "other"\n')
    assert location.checkout(tmp_path / "src" / "dyntorsion") is None
    (tmp_path / "pyproject.toml").write_text('[project]\nname = "dyntorsion"\n')
    assert location.checkout(tmp_path / "src" / "dyntorsion") == tmp_path
    assert location.checkout(ROOT / "src" / "dyntorsion" / "store") == ROOT


def test_info_names_the_version_and_the_store(capsys, monkeypatch, tmp_path):
    monkeypatch.setenv("DYNTORSION_DATA", str(tmp_path))
    assert main(["info"]) == 0
    out = capsys.readouterr().out
    assert dyntorsion.__version__ in out
    assert f"{tmp_path} (DYNTORSION_DATA is set)" in out


def test_info_names_the_arithmetic_the_contact_runs_depend_on(capsys):
    from dyntorsion.store.environment import numerical_environment

    assert main(["info"]) == 0
    out = capsys.readouterr().out
    env = numerical_environment()
    assert f"numpy, scipy      {env['numpy']}, {env['scipy']}" in out
    for lib, kernels in env["blas_kernels"].items():
        assert f"{kernels} ({lib})" in out
