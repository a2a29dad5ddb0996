"""The numerical environment a record carries (dyntorsion.store.environment) and how the
benchmark scripts resume a record with it (``dyntorsion.studies.contact.records``)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from importlib import metadata
from pathlib import Path

import numpy as np
import pytest

from dyntorsion.store import environment as E
from dyntorsion.store import fingerprint as F
from dyntorsion.studies.contact import records

SHOW = "import json; from dyntorsion.store.environment import numerical_environment as e; print(json.dumps(e()))"


def _in_child(**env: str) -> dict:
    full = {k: v for k, v in os.environ.items()
            if k not in ("OPENBLAS_CORETYPE", "NPY_DISABLE_CPU_FEATURES")} | env  # fmt: skip
    out = subprocess.run([sys.executable, "-c", SHOW], env=full, capture_output=True,
                         text=True, check=True)  # fmt: skip
    return json.loads(out.stdout)


def _cpu_has(flag: str) -> bool:
    path = Path("/proc/cpuinfo")
    return path.exists() and f" {flag} " in path.read_text().replace("\n", " ")


def test_the_environment_names_the_versions_installed():
    env = E.numerical_environment()
    for name in E.LIBRARIES:
        assert env[name] == metadata.version(name)
    assert isinstance(env["numpy_simd"], list) and isinstance(env["blas_kernels"], dict)


@pytest.mark.skipif(not Path("/proc/cpuinfo").exists(), reason="no /proc/cpuinfo to compare with")
def test_avx512_is_the_processors_even_with_numpys_loops_kept_off_it():
    """cpu_has_avx512 (whether contact_roundoff.py runs its native variant) says what the
    kernel's flags say, in a child with NumPy's AVX-512 loops off and in one without."""
    code = "from dyntorsion.store.environment import cpu_has_avx512 as c; print(c())"
    for env in ({}, {"NPY_DISABLE_CPU_FEATURES": E.numpy_avx512_groups()}):
        full = {k: v for k, v in os.environ.items() if k != "NPY_DISABLE_CPU_FEATURES"} | env
        out = subprocess.run([sys.executable, "-c", code], env=full, capture_output=True,
                             text=True, check=True).stdout.strip()  # fmt: skip
        assert out == str(_cpu_has("avx512f")), env


@pytest.mark.skipif(not _cpu_has("avx2"), reason="OpenBLAS's Haswell kernels need AVX2")
def test_the_kernels_asked_for_are_the_kernels_reported():
    """What ``make`` sets (OPENBLAS_CORETYPE=Haswell, NumPy's AVX-512 loops off) is what a
    record then carries, in every OpenBLAS library loaded."""
    native = _in_child()
    if not native["blas_kernels"]:
        pytest.skip("no OpenBLAS found in this process (another BLAS)")
    wide = E.avx512(native["numpy_simd"])
    pinned = _in_child(
        OPENBLAS_CORETYPE="Haswell", NPY_DISABLE_CPU_FEATURES=E.numpy_avx512_groups()
    )
    assert set(pinned["blas_kernels"]) == set(native["blas_kernels"])
    assert set(pinned["blas_kernels"].values()) == {"Haswell"}
    assert not E.avx512(pinned["numpy_simd"])
    if _cpu_has("avx512f"):  # this machine picks other kernels by itself
        assert set(native["blas_kernels"].values()) != {"Haswell"} and wide


def test_the_environment_is_kept_but_does_not_make_a_record_stale(tmp_path):
    script = tmp_path / "bench.py"
    script.write_text("print(1)\n")
    code = F.script_provenance(script, ("dyntorsion.buckling:simulate",))
    assert code["environment"] == E.numerical_environment()
    other = dict(code, environment=dict(code["environment"], blas_kernels={"x": "Zen"}))
    assert F.why_stale(other, script) is None


def test_a_record_is_resumed_only_in_the_environment_it_was_begun_in(tmp_path, capsys):
    out = tmp_path / "record.json"
    script = tmp_path / "bench.py"
    script.write_text("print(1)\n")
    code = F.script_provenance(script, ("dyntorsion.buckling:simulate",))
    fresh = {"params": {"n": 1}, "code": code, "runs": []}
    begun = {"params": {"n": 1}, "code": code, "runs": [{"n": 50}]}
    records.write(out, begun)
    assert records.resume(out, fresh) == begun
    # written before records kept their environment: resumed on the code alone
    legacy = dict(begun, code={k: v for k, v in code.items() if k != "environment"})
    records.write(out, legacy)
    assert records.resume(out, fresh) == legacy
    # begun with other kernels: started over, and said so
    elsewhere = dict(code, environment=dict(code["environment"], blas_kernels={"x": "Zen"}))
    records.write(out, dict(begun, code=elsewhere))
    assert records.resume(out, fresh) == fresh
    assert "another numerical environment" in capsys.readouterr().out
    # other parameters: started over, saying what differs
    records.write(out, dict(begun, params={"n": 2}))
    assert records.resume(out, fresh) == fresh
    said = capsys.readouterr().out
    assert "params differ" in said and "environment" not in said


def test_a_record_is_resumed_with_parameters_as_json_reads_them_back(tmp_path, capsys):
    # tuples come back from JSON as lists and numpy scalars as numbers: still the same run
    out = tmp_path / "record.json"
    script = tmp_path / "bench.py"
    script.write_text("print(1)\n")
    code = F.script_provenance(script, ("dyntorsion.buckling:simulate",))
    params = {"direction": (1.0, 0.0, 0.0), "dt": np.float64(0.02), "n": np.int64(200)}
    begun = {"params": params, "code": code, "runs": [{"n": 200}]}
    out.write_text(json.dumps(begun, default=float))
    fresh = {"params": params, "code": code, "runs": []}
    assert records.resume(out, fresh)["runs"] == [{"n": 200}]
    assert capsys.readouterr().out == ""
