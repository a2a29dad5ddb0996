"""The hand-picked probes of the fault classes whose properties are in
tests/app/test_properties_inputs.py: each answer is a correct result or a one-line refusal
naming the parameter, its range and the model's limit (exit 2 for the user's input, 1 for
a failed run or store), and no computed result is lost."""

from __future__ import annotations

import concurrent.futures as cf
import errno
import json
from concurrent.futures.process import BrokenProcessPool

import pytest

import dyntorsion.studies  # noqa: F401  (registers the record kinds)
from dyntorsion import Rod
from dyntorsion.app import cli
from dyntorsion.app.cli import main
from dyntorsion.buckling import Scene, simulate
from dyntorsion.buckling.slender import check_slender
from dyntorsion.genalpha import guard
from dyntorsion.genalpha.guard import BudgetError
from dyntorsion.store import leases, workers
from dyntorsion.store.fingerprint import register_kind
from dyntorsion.store.results import CorruptResultError, Store, UnsavedResultError
from dyntorsion.studies import contact_runs
from dyntorsion.studies.sweep import KIND


def _one_line(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    return err[0]


# ----------------------------------------------------------------- user's input: 2
@pytest.mark.parametrize("extra", [["--rtol", "0.01"], ["--until", "first-peak"]])
def test_contact_refuses_the_options_it_would_ignore(extra, capsys, monkeypatch):
    monkeypatch.setattr(contact_runs, "run_contact_scene", lambda cs: pytest.fail("ran"))
    argv = ["buckle", "--a", "16", "--contact", "--t-end", "3", *extra]
    assert main(argv) == 2
    assert extra[0] in _one_line(capsys)


@pytest.mark.parametrize("command", ["buckle", "sweep"])
@pytest.mark.parametrize(
    "extra", [["--n-cells", "400"], ["--dt", "0.001"], ["--lam-s", "0"], ["--lam-t", "-0.5"]]
)
def test_fidelity_refuses_the_grid_options_it_would_ignore(command, extra, capsys, monkeypatch):
    """``--fidelity`` sets the grid and the scheme: a grid option beside it is refused, not
    silently dropped (its run would be the level's, whatever the option said)."""
    monkeypatch.setattr(cli, "run_scene", lambda *a, **k: pytest.fail("ran"), raising=False)
    rates = ["--a", "16"] if command == "buckle" else ["--rates", "16"]
    assert main([command, *rates, "--fidelity", "quick", *extra]) == 2
    line = _one_line(capsys)
    assert extra[0] in line and "--fidelity quick" in line and "ignored" in line


@pytest.mark.parametrize("D", ["1.5", "0.9999", "0.5"])
def test_a_rod_too_thick_for_the_thin_rod_model_is_refused(D, capsys):
    assert main(["buckle", "--a", "16", "--D", D, "--fidelity", "quick"]) == 2
    line = _one_line(capsys)
    assert f"thickness {float(D):g} m" in line and "allowed range (0, 0.1]" in line
    assert "thin-rod theory" in line
    with pytest.raises(ValueError, match="allowed range"):
        simulate(
            Scene(rod=Rod(D=2.0, L=1.0), a=16.0, n_cells=10, dt=0.01, t_end=0.1), progress=False
        )
    with pytest.raises(ValueError, match="allowed range"):
        check_slender(Rod(D=2.0, L=1.0))
    check_slender(Rod(D=0.1, L=1.0))  # the bound itself is a thin rod


def test_a_contact_min_arc_past_the_rod_is_refused(capsys):
    argv = ["buckle", "--a", "16", "--contact", "--t-end", "3", "--contact-min-arc", "1e300"]
    assert main(argv) == 2
    assert "min_arc=1e+300 diameters: allowed range [1, 1000)" in _one_line(capsys)


# ------------------------------------------------------------ what a run did
@pytest.mark.filterwarnings("ignore")  # the SchemeWarning of lam_s = 0, this test's cause
def test_a_failed_first_step_is_not_a_rod_that_never_moved(capsys):
    argv = ["buckle", "--a", "16", "--kappa0", "10", "--lam-s", "0", "--n-cells", "20"]
    assert main(argv) == 1
    out = capsys.readouterr().out
    assert "status     failed" in out and "the run failed" in out
    assert "never left the straight state" not in out


def test_a_newton_failure_after_a_buckled_onset_is_the_whip():
    row = {"status": "buckled", "stopped": "failed: Newton failed at t=3.49 (step 698)"}
    assert cli._stopped(row).startswith("in the post-buckling whip, after the onset")
    assert cli._stopped({**row, "status": "failed"}) == row["stopped"]


def test_an_interrupted_buckle_without_a_store_says_nothing_was_kept(capsys, monkeypatch):
    def interrupted(args):
        raise KeyboardInterrupt

    monkeypatch.setattr(cli, "_buckle", interrupted)
    monkeypatch.setattr(cli.argparse.ArgumentParser, "set_defaults", _defaults(interrupted))
    assert main(["buckle", "--a", "16"]) == 130
    assert "nothing was kept" in _one_line(capsys)


def _defaults(func):
    original = cli.argparse.ArgumentParser.set_defaults

    def set_defaults(self, **kw):
        if kw.get("func") is not None and kw["func"].__name__ == "_buckle":
            kw["func"] = func
        return original(self, **kw)

    return set_defaults


# ------------------------------------------------------------------- the store: 1
def test_a_store_that_is_a_file_or_a_dangling_link_says_so(tmp_path, capsys):
    afile = tmp_path / "afile"
    afile.write_text("")
    link = tmp_path / "link"
    link.symlink_to(tmp_path / "nowhere")
    for store, what in ((afile, "is a file"), (link, "is a broken symbolic link")):
        assert main(["sweep", "--rates", "16", "--store", str(store), "--quiet"]) == 1
        assert f"{store} {what}, not a folder" in _one_line(capsys)


def test_a_full_disk_names_the_lease_and_leaves_none(tmp_path, monkeypatch):
    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(leases.json, "dump", full)
    with pytest.raises(OSError, match="cannot write the lease") as err:
        leases.acquire_lease(tmp_path / "x.json")
    assert err.value.filename == str(tmp_path / "x.json.lease")
    assert not list(tmp_path.iterdir())  # no empty lease for the next run to wait on


def test_the_memory_refusal_states_its_rule(monkeypatch):
    monkeypatch.setattr(guard, "available_memory", lambda: 2**30)
    with pytest.raises(BudgetError, match=r"over the limit of 50% of the 1 GiB available"):
        guard.check_memory(10**7, 10**3, 12, 10**7, 0)


def test_a_record_with_a_valid_hash_and_no_t_c_is_moved_aside(tmp_path):
    st = Store(tmp_path)
    params = {"x": 1}
    path = st.save(KIND, params, {"status": "buckled", "stopped": "t_end", "steps": 1})
    with pytest.raises(CorruptResultError, match="its result lacks t_c"):
        st.read(path)
    said: list[str] = []
    assert st.load(KIND, params, say=said.append) is None  # to be recomputed
    assert "moved aside" in said[0] and path.with_name(path.name + ".corrupt").exists()


class _Run:
    history = {"r": [[[0.0, 0.0, 0.0]]], "link": [0.0]}

    def result(self):
        return {"stopped": "t_end"}


def test_a_contact_run_checks_the_store_first_and_keeps_a_result_it_cannot_write(
    tmp_path, monkeypatch
):
    from dyntorsion.beyond.contact.run import ContactScene

    cs = ContactScene(Scene(a=16.0, t_end=1.0))

    def unwritable(self, kind, params):
        raise PermissionError(errno.EACCES, "Permission denied", str(tmp_path))

    with monkeypatch.context() as mp:  # an unwritable store: refused before the run
        mp.setattr(Store, "lease", unwritable)
        mp.setattr(contact_runs, "run_contact_scene", lambda cs: pytest.fail("ran"))
        with pytest.raises(PermissionError):
            contact_runs.contact_run(cs, tmp_path)

    def full(self, *args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device", str(tmp_path / "r.json"))

    monkeypatch.setattr(contact_runs, "run_contact_scene", lambda cs: _Run())
    monkeypatch.setattr(Store, "save", full)
    with pytest.raises(UnsavedResultError) as err:
        contact_runs.contact_run(cs, tmp_path)
    assert err.value.result["summary"] == {"stopped": "t_end"}
    assert not list(tmp_path.glob("*.lease"))


# -------------------------------------------------------- a worker killed by the OS
#: a record kind of these tests' own items (their code: the sweep machinery)
ITEMS = "test-items"
register_kind(ITEMS, ("dyntorsion.store.workers:cached_map",))


class _Item:
    def __init__(self, n):
        self.n = n

    def params(self):
        return {"n": self.n}

    def label(self):
        return f"item {self.n}"


def _double(item):
    return {"n": 2 * item.n}


class _BrokenOnce(cf.ThreadPoolExecutor):
    """The first pool breaks as a process pool does when the OS kills a worker."""

    made = 0

    def __init__(self, jobs):
        super().__init__(jobs)
        type(self).made += 1
        self.broken = type(self).made == 1

    def submit(self, fn, *args):
        if not self.broken:
            return super().submit(fn, *args)
        fut = cf.Future()
        fut.set_exception(BrokenProcessPool("a child process terminated abruptly"))
        return fut


def test_a_killed_worker_costs_no_scene(tmp_path, monkeypatch):
    _BrokenOnce.made = 0
    monkeypatch.setattr(workers, "_local_pool", _BrokenOnce)
    said: list[str] = []
    out = workers.cached_map(
        [_Item(1), _Item(2)], _double, ITEMS, tmp_path, jobs=2, progress=False, log=said.append
    )
    assert [rec["result"] for rec, _ in out] == [{"n": 2}, {"n": 4}]
    assert any("worker process died" in s for s in said)


def test_a_worker_killed_twice_is_one_line_exit_1(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(workers, "_local_pool", lambda jobs: _BrokenAlways(jobs))
    with pytest.raises(cf.BrokenExecutor, match="died twice.*rerun with fewer --jobs"):
        workers.cached_map([_Item(1)], _double, ITEMS, tmp_path, jobs=2, progress=False)
    from dyntorsion.app.faults import describe

    assert describe(cf.BrokenExecutor("x"))[1] == 1


class _BrokenAlways(_BrokenOnce):
    def __init__(self, jobs):
        super().__init__(jobs)
        self.broken = True


# ------------------------------------------------------------ advice for a wheel
def test_fit_of_a_missing_preset_names_a_command_a_wheel_has(tmp_path, capsys, monkeypatch):
    from dyntorsion.store import location

    monkeypatch.setattr(location, "checkout", lambda start=None: None)
    assert main(["fit", "--preset", "fig10", "--store", str(tmp_path)]) == 1
    line = _one_line(capsys)
    assert "`dyntorsion sweep --preset fig10`" in line and "make data" not in line
    json.dumps(line)
