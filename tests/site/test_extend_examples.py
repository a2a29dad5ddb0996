"""The three worked examples of the Extend page (docs/examples/*.py, files outside the
package): each runs through a Scene, the store, a sweep and the command line with
--plugin, and is checked against a closed form."""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

import numpy as np
import pytest

from dyntorsion.buckling.scene import Scene
from dyntorsion.store.results import key
from dyntorsion.studies import kinds  # noqa: F401  (registers the record kinds)

EXAMPLES = Path(__file__).resolve().parents[2] / "docs" / "examples"


def _example(name: str):
    if str(EXAMPLES) not in sys.path:
        sys.path.insert(0, str(EXAMPLES))
    return importlib.import_module(name)


def _round_trip(out: dict, scene: Scene) -> None:
    """The record read back is the scene; the command line found it in the store."""
    assert out["back"] == scene and out["back"].params() == scene.params()
    assert key("buckling-onset", scene.params()) in set(out["table"]["key"])


def test_a_sine_modulated_ramp(tmp_path, capsys):
    ex = _example("sine_ramp")
    out = ex.demo(tmp_path)
    # amp = 0 is the paper's ramp: the same onset to the last digit
    assert out["same"]["t_c"] == out["plain"]["t_c"] is not None
    assert out["same"]["kappa3"] == out["plain"]["kappa3"]
    _round_trip(out, out["wavy"])
    assert out["cli"] == 0 and "cached" in capsys.readouterr().out
    assert out["table"]["status"][0] == "buckled"


def test_a_distributed_load_bends_the_rod_as_the_clamped_beam(tmp_path, capsys):
    ex = _example("foundation")
    out = ex.demo(tmp_path)
    # second order in the cell length: halving it quarters the error, and Richardson's
    # value is the beam's q0 L^4 / (384 B)
    err_coarse, err_fine = (abs(out[k] / out["beam"] - 1) for k in ("coarse", "fine"))
    assert 3.0 < err_coarse / err_fine < 5.0
    assert out["richardson"] == pytest.approx(out["beam"], rel=1e-3)
    _round_trip(out, out["scene"])
    assert out["cli"] == 1 and "cached" in capsys.readouterr().out  # no onset: no seed


def test_an_end_set_with_a_matched_torsional_dashpot(tmp_path, capsys):
    ex = _example("dashpot_end")
    out = ex.demo(tmp_path)
    assert out["error"] < 1e-9  # the twist wave leaves s = L without a reflection
    _round_trip(out, out["scene"])
    assert out["cli"] == 1 and "cached" in capsys.readouterr().out  # no seed: no onset
    assert "'clamped-dashpot' do not support a static critical twist" in out["refused"]
    assert np.isfinite(out["table"]["steps"]).all()


def test_a_plugin_that_fails_names_itself_and_the_option(tmp_path, capsys):
    from dyntorsion.app.cli import main

    bad = tmp_path / "broken_plugin.py"
    bad.write_text("raise RuntimeError('not today')\n")
    assert main(["buckle", "--plugin", str(bad), "--a", "1"]) == 2
    err = capsys.readouterr().err
    assert f"--plugin {bad}: cannot import it (RuntimeError: not today)" in err
    assert main(["sweep", "--plugin", "no_such_module_here", "--rates", "1"]) == 2
    assert "--plugin no_such_module_here" in capsys.readouterr().err
    with pytest.raises(SystemExit) as usage:  # argparse's refusal of an option
        main(["buckle", "--a", "1", "--ends", "nope"])
    assert usage.value.code == 2
    assert "--ends 'nope'; registered: clamped" in capsys.readouterr().err
