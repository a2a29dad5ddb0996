"""Sweeps (section 6, Fig 10): scenes, the cache, executors, resuming, the command line."""

import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from dyntorsion import Rod
from dyntorsion import genalpha as ga
from dyntorsion.app.cli import main
from dyntorsion.buckling import Perturbation
from dyntorsion.buckling.delay_law import paper_law
from dyntorsion.buckling.statics import critical_twist
from dyntorsion.store import results as R
from dyntorsion.studies import presets as P
from dyntorsion.studies import sweep as S

COARSE = {"kappa0": 10.0, "n_cells": 40, "dt": 0.01}
COARSE_CLI = ["--kappa0", "10", "--n-cells", "40", "--dt", "0.01"]  # the same, for the CLI
RATES = (10.0, 4.0)


def coarse(rates=RATES):
    return [S.Scene(a=a, **COARSE) for a in rates]


@pytest.fixture(scope="module")
def serial(tmp_path_factory):
    """The two-rate mini sweep, run live in this process."""
    store = R.Store(tmp_path_factory.mktemp("serial"))
    return store, S.run_sweep(coarse(), store, progress=False)


def hashes(store):
    return sorted((rec["key"], rec["hash"]) for rec in store.records(S.KIND))


# ------------------------------------------------------------------ scenes
@pytest.mark.parametrize(
    "kw, name",
    [
        ({"a": 0.0}, "a="),
        ({"a": float("inf")}, "a="),
        ({"a": 1.0, "n_cells": 1}, "n_cells"),
        ({"a": 1.0, "dt": -0.1}, "dt"),
        ({"a": 1.0, "t_end": 0.0}, "t_end"),
        ({"a": 1.0, "horizon": 0.0}, "horizon"),
        ({"a": 1.0, "kappa0": 500.0}, "kappa0"),
    ],
)
def test_scene_rejects_bad_input(kw, name):
    with pytest.raises(ValueError, match=name):
        S.Scene(**kw)


def test_scene_horizon_rule():
    sc = S.Scene(a=1.6, kappa0=0.0)
    kc = critical_twist(sc.rod)
    assert sc.kappa0 + sc.a * sc.duration() == pytest.approx(kc + 3 * (paper_law(1.6, sc.rod) - kc))
    assert S.Scene(a=1.6, t_end=7.0).duration() == 7.0


def _pulse(t, width):
    return 10.0 + np.tanh(t / width)


def _pulse_edited(t, width):
    return 10.0 + 2 * np.tanh(t / width)


def test_scene_params_name_everything():
    """Each parameter that changes the result, changed alone, gives a new cache key."""
    from dyntorsion.buckling.loading import (
        AxialLoad,
        Custom,
        Polynomial,
        RampHold,
        Tabulated,
    )
    from dyntorsion.model.ends import Ends
    from dyntorsion.model.rod import Section

    T = 5.0  # for scenes with another history or ends, which need an explicit t_end
    props = dict(
        L=1.0, B1=6e-7, B2=7e-7, C=5e-7, mass_per_length=1.2e-3,
        rotary_inertia=(7e-11, 8e-11, 1.5e-10), thickness=1e-3,
    )  # fmt: skip
    base = S.Scene(a=1.6)
    variants = {
        "kappa0": S.Scene(a=1.6, kappa0=0.0),
        "a": S.Scene(a=1.7),
        **{
            f"rod.{k}": S.Scene(a=1.6, rod=Rod().with_(**{k: v}))
            for k, v in dict(E=1.3e7, nu=0.3, D=1.1e-3, L=1.1, rho=5000.0).items()
        },
        "ellipse": S.Scene(a=1.6, rod=Rod.elliptic(a=0.55e-3, b=0.5e-3)),
        "ellipse.a": S.Scene(a=1.6, rod=Rod.elliptic(a=0.56e-3, b=0.5e-3)),
        "ellipse.b": S.Scene(a=1.6, rod=Rod.elliptic(a=0.55e-3, b=0.51e-3)),
        "ellipse turned": S.Scene(a=1.6, rod=Rod.elliptic(a=0.5e-3, b=0.55e-3)),
        "rectangle": S.Scene(a=1.6, rod=Rod.rectangular(w=1e-3, h=0.9e-3)),
        "given": S.Scene(a=1.6, rod=Rod.from_properties(**props)),
        **{
            f"given.{k}": S.Scene(a=1.6, rod=Rod.from_properties(**(props | {k: v})))
            for k, v in dict(
                B1=6.1e-7,
                B2=7.1e-7,
                C=5.1e-7,
                mass_per_length=1.3e-3,
                rotary_inertia=(7e-11, 8e-11, 1.6e-10),
                thickness=2e-3,
            ).items()
        },
        "polynomial": S.Scene(history=Polynomial((10.0, 1.6)), t_end=T),
        "polynomial'": S.Scene(history=Polynomial((10.0, 1.6, 0.1)), t_end=T),
        "ramp-hold": S.Scene(history=RampHold(a=1.6, hold=20.0, kappa0=10.0), t_end=T),
        "ramp-hold.hold": S.Scene(history=RampHold(a=1.6, hold=21.0, kappa0=10.0), t_end=T),
        "ramp-hold.tau": S.Scene(history=RampHold(a=1.6, hold=20.0, kappa0=10.0, tau=1.0), t_end=T),
        "tabulated": S.Scene(history=Tabulated((0.0, 1.0), (10.0, 12.0)), t_end=T),
        "tabulated'": S.Scene(history=Tabulated((0.0, 1.0), (10.0, 12.5)), t_end=T),
        "custom": S.Scene(history=Custom("pulse", _pulse, {"width": 1.0}), t_end=T),
        "custom.param": S.Scene(history=Custom("pulse", _pulse, {"width": 2.0}), t_end=T),
        "custom.name": S.Scene(history=Custom("pulse2", _pulse, {"width": 1.0}), t_end=T),
        "custom.code": S.Scene(history=Custom("pulse", _pulse_edited, {"width": 1.0}), t_end=T),
        "tension": S.Scene(a=1.6, tension=1e-6),
        "compression": S.Scene(a=1.6, tension=-1e-6),
        "tension rate": S.Scene(a=1.6, tension=AxialLoad(0.0, 1e-7), t_end=T),
        "ends": S.Scene(a=1.6, ends="clamped-free-lateral", t_end=T),
        "ends object": S.Scene(
            a=1.6,
            t_end=T,
            ends=Ends(
                "mine", ("u1", "u2", "u3", "w1", "w2", "k3"), ("w1", "w2", "w3", "n1", "u2", "n3")
            ),
        ),  # fmt: skip
        "terms": S.Scene(a=1.6, terms=(("gyro", 0.0),)),
        "terms weight": S.Scene(a=1.6, terms=(("gyro", 0.5),)),
        "rotary": S.Scene(a=1.6, rotary_inertia_scale=0.1),
        "seed": S.Scene(a=1.6, seed=Perturbation(1e-17)),
        "seed form": S.Scene(a=1.6, seed=Perturbation(1e-8, "point")),
        "seed place": S.Scene(a=1.6, seed=Perturbation(1e-8, "point", 0.4)),
        "seed direction": S.Scene(a=1.6, seed=Perturbation(1e-8, direction=(0.0, 1.0, 0.0))),
        "n_cells": S.Scene(a=1.6, n_cells=200),
        "dt": S.Scene(a=1.6, dt=0.0025),
        "t_end": S.Scene(a=1.6, t_end=30.0),
        "horizon": S.Scene(a=1.6, horizon=2.0),
        "quadrature": S.Scene(a=1.6, scheme=ga.Scheme(quadrature="midpoint")),
        "lam_t": S.Scene(a=1.6, scheme=ga.Scheme(lam_t=-0.5)),
        "newton": S.Scene(a=1.6, newton=ga.Newton(tol=1e-8)),
        "window": S.Scene(a=1.6, window=(0.2, 0.5)),
        "variations": S.Scene(a=1.6, variations=((0.05, 0.3),)),
    }
    keys = {name: R.key(S.KIND, sc.params()) for name, sc in variants.items()}
    keys["base"] = R.key(S.KIND, base.params())
    same = [n for n in keys if list(keys.values()).count(keys[n]) > 1]
    assert not same, f"these scenes share a key: {same}"
    assert S.Scene(a=1.6).params() == base.params()
    assert S.Scene(a=2).params()["history"]["a"] == 2.0 and isinstance(S.Scene(a=2).a, float)
    # the same scene spelled two ways has one key
    assert (
        S.Scene(a=1.6, terms={"gyro": 0.0, "wxu": 1.0}).params()
        == S.Scene(a=1.6, terms=(("wxu", 1.0), ("gyro", 0.0))).params()
    )
    assert S.Scene(a=1.6, tension=0.0).params() == base.params()
    assert S.Scene(a=1.6, rod=Rod(section=Section.circle(1e-3), D=None)).params() == base.params()


def test_a_switch_given_twice_is_refused_not_keyed_as_another():
    with pytest.raises(ValueError, match="gyro.*more than once"):
        S.Scene(a=1.6, terms=(("gyro", 2.0), ("gyro", 0.0)))


def test_presets():
    assert len(P.FIG10_RATES) >= 12
    assert P.FIG10_RATES[-1] / P.FIG10_RATES[0] >= 100
    assert any(abs(a - 1.6) < 1e-12 for a in P.FIG10_RATES)
    assert np.all(np.diff(np.log(P.FIG10_RATES)) == pytest.approx(np.log(10) / 6))
    fig10 = P.preset("fig10")
    assert {sc.kappa0 for sc in fig10} == {10.0}
    assert {sc.seed.magnitude for sc in fig10} == {1e-8}
    assert {sc.seed.magnitude for sc in P.preset("fig10-tiny-seed")} == {1e-17}
    assert [sc.rod.rho for sc in P.preset("fig08-09")] == [1500.0, 5000.0]
    with pytest.raises(ValueError, match="preset="):
        P.preset("fig11")


# ------------------------------------------------------------------ the mini sweep
def test_mini_sweep_pin_of_our_output(serial, num_regression):
    """A pin of our own output: the mini sweep's numbers, to catch any change; the onsets' accuracy is checked against converged grids elsewhere."""
    _, table = serial
    assert list(table["a"]) == list(RATES)  # rows in the order of the scenes
    assert not table["cached"].any()
    assert table["kappa3"].notna().all()
    assert (table["kappa3"] > critical_twist(Rod())).all()
    num_regression.check(
        {c: table[c].to_numpy(float) for c in ("a", "t_c", "kappa3", "uncertainty_kappa3")},
        default_tolerance={"rtol": 1e-6},
    )


def test_second_run_reads_the_cache(serial, monkeypatch):
    store, table = serial

    def no(*args):
        raise AssertionError("a cached scene was recomputed")

    monkeypatch.setattr(S, "run_scene", no)
    again = S.run_sweep(coarse(), store, progress=False)
    assert again["cached"].all()
    cols = ["t_c", "kappa3", "uncertainty_t", "key"]
    assert again[cols].equals(table[cols])
    only = S.run_sweep(coarse(), store, compute=False, on_stale="error", progress=False)
    assert only[cols].equals(table[cols])


def test_read_only_sweep_names_missing_scenes(tmp_path):
    with pytest.raises(S.MissingResultError, match=r"(?s)a=3\.2 .*make data"):
        S.run_sweep(coarse((3.2,)), tmp_path, compute=False, progress=False)


def test_stale_scene_is_recomputed_or_refused(serial, tmp_path, monkeypatch):
    store, table = serial
    copy = R.Store(tmp_path)
    for rec in store.records(S.KIND):
        (tmp_path / f"{S.KIND}-{rec['key']}.json").write_text(
            (store.root / f"{S.KIND}-{rec['key']}.json").read_text()
        )
    monkeypatch.setattr(R, "code_of", lambda *a: "changed-code")
    with pytest.raises(R.StaleResultError, match="code fingerprint"):
        S.run_sweep(coarse(), copy, on_stale="error", progress=False)
    log = []
    fresh = S.run_sweep(coarse(), copy, on_stale="recompute", progress=False, log=log.append)
    assert not fresh["cached"].any()
    assert sum("stale" in m for m in log) == 2
    assert np.array_equal(fresh["kappa3"], table["kappa3"])
    assert {r["provenance"]["code"] for r in copy.records()} == {"changed-code"}


@pytest.mark.parametrize("how", ["processes", "dask"])
def test_executors_give_the_same_records(serial, tmp_path, how):
    store, _ = serial
    other = R.Store(tmp_path)
    if how == "processes":
        S.run_sweep(coarse(), other, jobs=2, progress=False)
    else:
        distributed = pytest.importorskip("dask.distributed")
        with (
            distributed.LocalCluster(
                n_workers=2, threads_per_worker=1, dashboard_address=None
            ) as cluster,
            distributed.Client(cluster) as client,
        ):
            S.run_sweep(coarse(), other, executor=client.get_executor(), progress=False)
    assert hashes(other) == hashes(store)


def test_killed_sweep_resumes_to_the_same_table(serial, tmp_path):
    """SIGKILL a command-line sweep after its first scene is written, then resume."""
    store, _ = serial
    rates = (10.0, 4.0, 7.0)
    cmd = [
        sys.executable,
        "-m",
        "dyntorsion",
        "sweep",
        "--rates",
        ",".join(map(str, rates)),
        *COARSE_CLI,
        "--store",
        str(tmp_path),
        "--quiet",
    ]
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 120
    while not list(tmp_path.glob("*.json")) and time.monotonic() < deadline:
        if proc.poll() is not None:
            break
        time.sleep(0.02)
    if proc.poll() is None:
        os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    done_before = len(list(tmp_path.glob("*.json")))
    assert done_before >= 1
    resumed = S.run_sweep(coarse(rates), tmp_path, progress=False)
    assert resumed["cached"].sum() == done_before
    full = S.run_sweep(coarse(rates), store, progress=False)  # 10 and 4 cached, 7 computed
    cols = ["a", "t_c", "kappa3", "uncertainty_kappa3", "key"]
    assert resumed[cols].equals(full[cols])
    assert not list(tmp_path.glob("*.tmp"))


# ------------------------------------------------------------------ command line
def test_cli_buckle_prints_the_onset(serial, capsys):
    _, table = serial
    assert main(["buckle", "--a", "10", *COARSE_CLI]) == 0
    out = capsys.readouterr().out
    assert f"{table['kappa3'][0]:.4f}" in out and "t_c" in out


def test_cli_sweep_reads_the_cache(serial, capsys):
    store, table = serial
    assert (
        main(
            [
                "sweep",
                "--rates",
                "10,4",
                *COARSE_CLI,
                "--store",
                str(store.root),
                "--quiet",
            ]
        )
        == 0
    )
    out = capsys.readouterr().out
    assert out.count("True") == 2 and f"{table['kappa3'][1]:.5g}" in out


def test_cli_bad_input_names_the_parameter(capsys):
    assert main(["buckle", "--a", "-1"]) == 2
    assert "a=-1.0" in capsys.readouterr().err


def test_python_m_entry_point():
    out = subprocess.run(
        [sys.executable, "-m", "dyntorsion", "--version"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    assert out.startswith("dyntorsion ")


def test_model_switches_name_the_scene_and_reach_the_model():
    base = S.Scene(a=10.0, **COARSE)
    assert base.params()["model"] == {"terms": {}, "rotary_inertia_scale": 1.0}
    gyro = S.Scene(a=10.0, terms=(("gyro", 0.0),), **COARSE)
    heavy = S.Scene(a=10.0, rotary_inertia_scale=10.0, **COARSE)
    assert gyro.params()["model"] == {"terms": {"gyro": 0.0}, "rotary_inertia_scale": 1.0}
    assert heavy.params()["model"] == {"terms": {}, "rotary_inertia_scale": 10.0}
    assert len({R.key(S.KIND, sc.params()) for sc in (base, gyro, heavy)}) == 3
    with pytest.raises(ValueError, match="terms"):
        S.Scene(a=10.0, terms=(("spin", 0.0),))
    with pytest.raises(ValueError, match="rotary_inertia_scale"):
        S.Scene(a=10.0, rotary_inertia_scale=-1.0)
    t_c = {
        name: S.run_scene(sc)["t_c"]
        for name, sc in (("base", base), ("gyro", gyro), ("heavy", heavy))
    }
    assert t_c["gyro"] != t_c["base"] and t_c["heavy"] != t_c["base"]


def test_cached_map_names_an_unknown_option(tmp_path):
    """The options of cached_map are MapOptions, named once; a misspelt one is refused."""
    from dyntorsion.store.workers import cached_map

    with pytest.raises(TypeError, match=r"unknown option\(s\) \['job'\]; allowed: .*'jobs'"):
        cached_map([], lambda item: {}, "buckling-onset", tmp_path, job=2)
