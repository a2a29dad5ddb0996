"""The command line for rods, loads, histories and ends other than the paper's."""

from __future__ import annotations

import re

import pytest

from dyntorsion import Rod
from dyntorsion.app.cli import main
from dyntorsion.buckling.delay_law import fit_power_law
from dyntorsion.buckling.statics import critical_twist
from dyntorsion.store import location as L
from dyntorsion.studies import sweep as S

STEEL_CLI = ["--E", "2e11", "--nu", "0.3", "--rho", "7850", "--n-cells", "20", "--dt", "2e-4"]
STEEL = Rod(E=2e11, nu=0.3, rho=7850.0)


def test_sweep_and_fit_of_a_steel_rod_use_the_steel_rod(tmp_path, capsys):
    store = str(tmp_path / "steel")
    rates = "2,4,8,16"
    assert (
        main(["sweep", "--rates", rates, "--kappa0", "10", *STEEL_CLI, "--store", store, "--quiet"])
        == 0
    )
    swept = capsys.readouterr().out
    assert main(["fit", "--store", store]) == 0
    fitted = capsys.readouterr().out
    table = S.run_sweep(
        [S.Scene(a=a, kappa0=10.0, rod=STEEL, n_cells=20, dt=2e-4) for a in (2.0, 4.0, 8.0, 16.0)],
        store,
        compute=False,
    )
    own = fit_power_law(table["a"], table["kappa3"], STEEL, n_boot=0)
    table1 = fit_power_law(table["a"], table["kappa3"], Rod(), n_boot=0)
    line = next(ln for ln in fitted.splitlines() if "kappa_cri fixed" in ln)
    b = float(re.search(r"b = ([\d.]+)", line).group(1))
    assert b == pytest.approx(own.b, abs=0.01)
    assert abs(b - table1.b) > 0.1 * b  # what the old CLI printed (Table 1's c and kappa_cri)
    assert f"kappa_cri = {critical_twist(STEEL):.4f}" in line
    assert fitted.splitlines()[0] in swept  # sweep prints the same fit
    # --no-fit (make data): the same table from the records, no fit
    assert main(["sweep", "--rates", rates, "--kappa0", "10", *STEEL_CLI, "--store", store,
                 "--quiet", "--no-fit"]) == 0  # fmt: skip
    quiet = capsys.readouterr().out
    assert "fit " not in quiet and quiet.splitlines()[0] in swept
    rows = quiet.splitlines()[1:]
    assert len(rows) == 4 and all(r.endswith("buckled    True") for r in rows)  # cached
    assert [r.rsplit(None, 1)[0] for r in rows] == [
        r.rsplit(None, 1)[0] for r in swept.splitlines()[1:5]
    ]


def test_fit_says_why_below_four_rates(tmp_path, capsys):
    store = str(tmp_path / "few")
    assert (
        main(
            ["sweep", "--rates", "8,16", "--kappa0", "10", *STEEL_CLI, "--store", store, "--quiet"]
        )
        == 0
    )
    capsys.readouterr()
    assert main(["fit", "--store", store]) == 0
    assert "2 rate(s) with an onset; eq (33) needs at least 4" in capsys.readouterr().out


def test_the_store_can_be_set_by_the_environment(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("DYNTORSION_DATA", str(tmp_path / "env-store"))
    assert L.default_store() == tmp_path / "env-store"
    assert main(["sweep", "--rates", "16", "--kappa0", "10", *STEEL_CLI, "--quiet"]) == 0
    assert len(list((tmp_path / "env-store").glob("buckling-onset-*.json"))) == 1


def test_buckle_with_an_elliptic_section_a_load_and_a_history(capsys):
    rc = main(
        ["buckle", "--a", "1.6", "--kappa0", "10", "--ellipse", "0.55e-3,0.5e-3", "--tension", "2e-6",
         "--history", "ramp-hold:30,0.5", "--t-end", "12", "--n-cells", "30", "--dt", "0.02"]
    )  # fmt: skip
    out = capsys.readouterr().out
    assert rc == 0, out
    assert "ellipse a=0.00055 b=0.0005" in out and "T=2e-06" in out
    kc = critical_twist(Rod.elliptic(a=0.55e-3, b=0.5e-3), 2e-6)
    assert f"static kappa_cri = {kc:.4f}" in out


@pytest.mark.parametrize(
    "argv, message",
    [
        (["sweep", "--rates", ","], "holds no rate"),
        (["sweep", "--rates", "geom:0.1:1"], "geom:LO:HI:N"),
        (["buckle", "--history", "poly:10,x", "--t-end", "1"], "comma-separated numbers"),
        (["buckle", "--a", "1", "--ellipse", "1e-3"], "must hold 2 numbers"),
        (["buckle", "--history", "spline:1"], "no history of kind 'spline'; registered: custom"),
        (["buckle", "--a", "1.6", "--ends", "pinned-follower"], "give t_end"),
        (["buckle", "--a", "1.6", "--paced", "8"], "steps=8 must be an integer in [16"),
        (
            ["buckle", "--a", "1.6", "--paced", "--tension", "0.01", "--t-end", "5"],
            "paced steps need the fast onset estimate",
        ),
    ],
)
def test_bad_scene_options_say_what_is_wrong(argv, message, capsys):
    assert main(argv) == 2
    assert message in capsys.readouterr().err


def test_a_paced_sweep_from_the_command_line_is_the_paced_scenes(tmp_path, capsys):
    from dyntorsion.studies.pacing import paced

    store = str(tmp_path / "paced")
    argv = ["sweep", "--rates", "4,16", "--n-cells", "40", "--until", "first-peak"]
    assert main([*argv, "--paced", "--store", store, "--quiet"]) == 0
    capsys.readouterr()
    scenes = [paced(S.Scene(a=a, n_cells=40, until="first-peak")) for a in (4.0, 16.0)]
    table = S.run_sweep(scenes, store, compute=False)  # every record is there, keyed so
    assert list(table["dt"]) == [sc.dt for sc in scenes]
    assert scenes[0].dt > scenes[1].dt and scenes[1].dt != 0.005


def test_fit_takes_a_paced_sweep_as_one_sweep_and_splits_one_at_two_steps(tmp_path, capsys):
    """The family of a scene leaves out its time step, so a paced sweep (one step per
    rate) is fitted as one sweep; the same rates at two fixed steps are two sweeps."""
    store = str(tmp_path / "mixed")
    base = ["sweep", "--rates", "4,8,16,32", "--kappa0", "10", "--n-cells", "20"]
    base += ["--until", "first-peak", "--store", store, "--quiet"]
    for extra in (["--dt", "0.01"], ["--dt", "0.02"], ["--paced", "64"]):
        assert main([*base, *extra]) == 0
    capsys.readouterr()
    assert main(["fit", "--store", store]) == 0
    lines = [ln for ln in capsys.readouterr().out.splitlines() if "kappa_cri fixed" in ln]
    labels = sorted(re.search(r"dt=(\S+)", ln).group(1) for ln in lines)
    assert len(lines) == 3 and labels[:2] == ["0.01", "0.02"]
    lo, hi = map(float, labels[2].split("-"))  # the paced sweep: its steps follow the rate
    assert hi > 2 * lo
    # the same rates again at dt = 0.01 with another t_end: one record a rate is fitted
    assert main([*base, "--dt", "0.01", "--t-end", "40"]) == 0
    capsys.readouterr()
    assert main(["fit", "--store", store]) == 0
    again = [ln for ln in capsys.readouterr().out.splitlines() if "kappa_cri fixed" in ln]
    assert sorted(again) == sorted(lines)
