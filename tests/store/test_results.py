"""The data/ cache: provenance, content hashes, atomic writes, stale detection."""

import ast
import json

import pytest

import dyntorsion.studies  # noqa: F401  (registers the package's record kinds)
from dyntorsion import __version__
from dyntorsion.store import fingerprint as F
from dyntorsion.store import fingerprint_cache
from dyntorsion.store import results as R

#: the demo records' kind, computed by this module's own code
F.register_kind("demo", ("dyntorsion.store.results",))

PARAMS = {"a": 1.6, "grid": {"n_cells": 100, "dt": 0.005}, "window": (0.1, 0.5)}
RESULT = {"t_c": 14.7, "kappa3": 23.52, "stopped": "self-contact"}


@pytest.fixture
def store(tmp_path):
    return R.Store(tmp_path / "scenes")


def test_roundtrip_with_provenance(store):
    path = store.save("demo", PARAMS, RESULT, wall_time=1.25)
    rec = store.load("demo", PARAMS, on_stale="error")
    assert rec["result"] == RESULT
    assert rec["params"]["window"] == [0.1, 0.5]
    prov = rec["provenance"]
    assert prov["package_version"] == __version__
    assert prov["code"] == F.code_of("demo")
    assert prov["wall_time_s"] == 1.25
    assert {"python", "numpy", "numba", "created"} <= set(prov)
    assert path.name == f"demo-{R.key('demo', PARAMS)}.json"
    assert rec["hash"] == R.digest({"kind": "demo", "params": PARAMS, "result": RESULT})


def test_missing_record_is_none(store):
    assert store.load("demo", PARAMS) is None


def test_key_depends_on_every_parameter():
    keys = {
        R.key("demo", PARAMS),
        R.key("other", PARAMS),
        R.key("demo", {**PARAMS, "a": 1.6000000000000003}),
        R.key("demo", {**PARAMS, "grid": {"n_cells": 100, "dt": 0.0025}}),
    }
    assert len(keys) == 4
    assert R.key("demo", dict(reversed(list(PARAMS.items())))) == R.key("demo", PARAMS)


def test_write_is_atomic_and_leaves_no_temporary(store, monkeypatch):
    store.save("demo", PARAMS, RESULT)
    assert [p.name for p in store.root.iterdir()] == [store.path("demo", PARAMS).name]

    def boom(*args, **kwargs):
        raise KeyboardInterrupt  # the process is stopped in the middle of the write

    monkeypatch.setattr(R.os, "fsync", boom)
    with pytest.raises(KeyboardInterrupt):
        store.save("demo", {**PARAMS, "a": 3.2}, RESULT)
    assert len(list(store.root.iterdir())) == 1  # neither the record nor its temporary
    assert store.load("demo", {**PARAMS, "a": 3.2}) is None


def test_a_script_record_is_written_whole_and_readable_by_all(tmp_path, monkeypatch):
    """The records of data/contact and data/bench are written as the store's are: mode
    0o644 whatever the temporary's, and a write cut short leaves the old record and no
    temporary."""
    from dyntorsion.studies.contact.records import write

    out = tmp_path / "bench" / "scene.json"
    write(out, {"runs": [1.5, 2.5]})
    assert out.stat().st_mode & 0o777 == 0o644
    assert json.loads(out.read_text()) == {"runs": [1.5, 2.5]}

    def boom(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(R.os, "fsync", boom)
    with pytest.raises(KeyboardInterrupt):
        write(out, {"runs": [9.0]})
    assert json.loads(out.read_text()) == {"runs": [1.5, 2.5]}
    assert [p.name for p in out.parent.iterdir()] == ["scene.json"]


def test_leftover_temporary_is_ignored(store):
    store.save("demo", PARAMS, RESULT)
    (store.root / ".demo-x.abc.tmp").write_text('{"half": ')  # as a SIGKILL would leave it
    assert len(list(store.records("demo"))) == 1


def test_edited_record_is_refused(store):
    path = store.save("demo", PARAMS, RESULT)
    rec = json.loads(path.read_text())
    rec["result"]["kappa3"] = 33.38
    path.write_text(json.dumps(rec))
    with pytest.raises(R.CorruptResultError, match="content hash"):
        store.load("demo", PARAMS, on_corrupt="error")
    said = []
    assert store.load("demo", PARAMS, say=said.append) is None  # moved aside, to recompute
    assert not path.exists() and path.with_name(path.name + ".corrupt").exists()
    assert len(said) == 1 and "moved aside" in said[0] and "content hash" in said[0]


@pytest.mark.parametrize(
    "field, value, reason",
    [("code", "0000000000000000", "fingerprint"), ("package_version", "0.0.1", "version")],
)
def test_stale_record(store, field, value, reason):
    path = store.save("demo", PARAMS, RESULT)
    rec = json.loads(path.read_text())
    rec["provenance"][field] = value
    path.write_text(json.dumps(rec))
    assert store.load("demo", PARAMS, on_stale="recompute") is None
    with pytest.raises(R.StaleResultError, match=reason) as err:
        store.load("demo", PARAMS, on_stale="error")
    # a user's own store is not the checkout's: `make data` would not recompute it
    assert "make data" not in str(err.value) and "--on-stale recompute" in str(err.value)
    assert store.load("demo", PARAMS, on_stale="accept")["result"] == RESULT


def test_record_under_another_name_is_refused(store):
    path = store.save("demo", PARAMS, RESULT)
    path.rename(store.path("demo", {**PARAMS, "a": 2.0}))
    with pytest.raises(R.StaleResultError, match="parameters differ"):
        store.load("demo", {**PARAMS, "a": 2.0})


def test_bad_on_stale(store):
    with pytest.raises(ValueError, match="on_stale"):
        store.load("demo", PARAMS, on_stale="ignore")


def test_non_finite_numbers_are_not_stored(store):
    with pytest.raises(ValueError, match="non-finite"):
        store.save("demo", PARAMS, {"t_c": float("nan")})


def test_fingerprint_ignores_docstrings_and_comments_but_not_code():
    def dump(src):
        return ast.dump(F._strip_docstrings(ast.parse(src)))

    base = 'def f(x):\n    """Eq (33)."""\n    return 2 * x\n'
    assert dump(base) == dump(
        'def f(x):\n    """Other words."""\n    # a comment\n    return 2 * x\n'
    )
    assert dump(base) != dump('def f(x):\n    """Eq (33)."""\n    return 3 * x\n')
    assert F._source_digest("dyntorsion.store.results") == F._source_digest(
        "dyntorsion.store.results"
    )
    roots = F.KIND_ROOTS["buckling-onset"]
    assert F.code_fingerprint(roots) == F.code_of("buckling-onset")
    assert F.code_fingerprint(roots[:-1]) != F.code_of("buckling-onset")


def test_fingerprint_reaches_what_the_old_hand_list_missed():
    """The functions issue 14 found outside the hand-kept list are on the derived path."""
    reached = F.reachable(F.KIND_ROOTS["buckling-onset"])
    for name in (
        "dyntorsion.buckling.scene:simulate_scene",
        "dyntorsion.buckling.statics:critical_moment",
        "dyntorsion.buckling.statics:critical_twist",
        "dyntorsion.buckling.onset:detect_onset",
        "dyntorsion.published:value",  # the paper's b and sigma size the runs
        "dyntorsion.genalpha.integrate:integrate",
        "dyntorsion.genalpha.march:march",  # the compiled march and what it calls
        "dyntorsion.genalpha.newton:solve_step",
        "dyntorsion.model.cosserat:load_vector",  # a compiled kernel, by its Python source
        "dyntorsion.genalpha.abd:factor",
        "dyntorsion.buckling.loading",
    ):
        assert name in reached, name
    assert not any(n.startswith("dyntorsion.store.results") for n in reached)
    assert not any(n.startswith("dyntorsion.app.cli") for n in reached)


def test_fingerprint_covers_every_function_a_record_runs():
    """Trace a small buckling record's computation: every package function executed is
    inside a definition the fingerprint covers."""
    import sys

    from dyntorsion.buckling.scene import Scene, run_scene

    scene = Scene(a=16.0, kappa0=10.0, n_cells=8, dt=0.02, t_end=0.4)
    run_scene(scene)  # compiled first: the numba compilation hooks are not the record's work
    executed: set[tuple[str, str]] = set()

    def tracer(frame, event, arg):
        if event == "call":
            mod = frame.f_globals.get("__name__", "")
            generated = not frame.f_code.co_filename.endswith(".py")  # dataclass methods
            kept = any(mod == m or mod.startswith(m + ".") for m in F.NOT_COMPUTING)
            if mod.startswith("dyntorsion") and not kept and not generated:
                executed.add((mod, frame.f_code.co_qualname))

    sys.setprofile(tracer)
    try:
        run_scene(scene)
    finally:
        sys.setprofile(None)
    reached = F.reachable(F.KIND_ROOTS["buckling-onset"])
    modules = {n for n in reached if ":" not in n}
    assert executed
    for mod, qual in executed:
        parts = qual.replace(".<locals>", "").split(".")
        prefixes = {f"{mod}:{'.'.join(parts[:i])}" for i in range(1, len(parts) + 1)}
        assert mod in modules or prefixes & set(reached), f"{mod}:{qual} is not fingerprinted"


def test_editing_any_function_on_the_path_changes_the_fingerprint(tmp_path, monkeypatch):
    """A package of three modules: the root calls a helper in another module, which reads
    a module constant; an unrelated function sits beside them.  Editing the helper or the
    constant changes the fingerprint; editing the unrelated function does not."""
    import importlib
    import sys

    pkg = tmp_path / "fp_walk"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    files = {
        "a.py": "from .b import helper\n\n\ndef root(x):\n    return helper(x) + 1\n",
        "b.py": "SCALE = 2.0\n\n\ndef helper(x):\n    return SCALE * x\n\n\n"
        "def unrelated(x):\n    return x\n",
    }
    for name, text in files.items():
        (pkg / name).write_text(text)
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setattr(F, "PACKAGE", "fp_walk")

    def fingerprint():
        for m in ("fp_walk.a", "fp_walk.b"):
            sys.modules.pop(m, None)
        F._module_tree.cache_clear()
        importlib.invalidate_caches()
        return F.fingerprint_of(F.reachable(("fp_walk.a:root",)))

    base = fingerprint()
    assert set(F.reachable(("fp_walk.a:root",))) == {
        "fp_walk.a:root",
        "fp_walk.b:helper",
        "fp_walk.b:SCALE=",
    }
    (pkg / "b.py").write_text(files["b.py"].replace("return x\n", "return -x\n"))
    assert fingerprint() == base
    for old, new in (("return SCALE * x", "return SCALE * x * x"), ("SCALE = 2.0", "SCALE = 3.0")):
        (pkg / "b.py").write_text(files["b.py"].replace(old, new))
        assert fingerprint() != base, old


def test_fingerprint_ignores_import_order(tmp_path, monkeypatch):
    pkg = tmp_path / "fp_demo"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("import math\nimport os\n\n\ndef f():\n    return math.pi\n")
    (pkg / "b.py").write_text(
        "import os\nimport math\n\n\ndef f():\n    # same code\n    return math.pi\n"
    )
    (pkg / "c.py").write_text("import os\nimport math\n\n\ndef f():\n    return math.e\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    da, db, dc = (F._source_digest(f"fp_demo.{m}") for m in "abc")
    assert da == db != dc


def test_moving_a_definition_to_another_module_keeps_the_fingerprint(tmp_path, monkeypatch):
    """Issue 31: records survive a change of layout.  The helper moves from b.py into a
    folder (sub/c.py) with the same code: same fingerprint; its code edited: another."""
    import importlib
    import sys

    def package(helper_module: str, helper_code: str) -> str:
        name = f"fp_move_{abs(hash((helper_module, helper_code))) % 10**8}"
        pkg = tmp_path / name
        (pkg / "sub").mkdir(parents=True)
        (pkg / "__init__.py").write_text("")
        (pkg / "sub" / "__init__.py").write_text("")
        rel = "." + helper_module.replace("/", ".")
        (pkg / "a.py").write_text(
            f"from {rel} import helper\n\n\ndef root(x):\n    return helper(x)\n"
        )
        (pkg / f"{helper_module}.py").write_text(f"def helper(x):\n    return {helper_code}\n")
        monkeypatch.syspath_prepend(str(tmp_path))
        importlib.invalidate_caches()
        monkeypatch.setattr(F, "PACKAGE", name)
        sys.modules.pop(f"{name}.a", None)
        return F.fingerprint_of(F.reachable((f"{name}.a:root",)))

    here = package("b", "2 * x")
    assert package("sub/c", "2 * x") == here
    assert package("sub/c", "3 * x") != here


def test_every_registered_kind_is_a_record_kind_of_the_studies():
    """The store knows no physics: the kinds' roots come from the studies layer."""
    from dyntorsion.studies.kinds import KINDS

    assert set(KINDS) <= set(F.KIND_ROOTS)
    for roots in KINDS.values():
        assert F.reachable(roots), roots


def test_an_unregistered_kind_is_refused_with_the_fix():
    with pytest.raises(LookupError, match="register_kind"):
        F.code_of("nobody-registered-this")


def test_a_script_record_is_stale_when_its_script_or_its_code_changes(tmp_path, monkeypatch):
    """``script_provenance`` written, ``why_stale`` read back: current as written; stale
    (with the reason) when the script is edited, when the fingerprint differs from what
    the roots reach today, and when the record predates the roots."""
    import dyntorsion

    script = tmp_path / "bench.py"
    script.write_text("print(1)\n")
    roots = ("dyntorsion.buckling:simulate",)
    code = F.script_provenance(script, roots)
    assert code["roots"] == list(roots) and code["dyntorsion"] == dyntorsion.__version__
    assert code["code_fingerprint"] == F.code_fingerprint(roots)
    assert F.why_stale(code, script) is None
    script.write_text("print(2)\n")
    assert "bench.py changed" in F.why_stale(code, script)
    script.write_text("print(1)\n")
    then = dict(code, code_fingerprint="0" * 16)
    reason = F.why_stale(then, script)
    assert "dyntorsion.buckling:simulate changed" in reason and "0" * 16 in reason
    old = {k: v for k, v in code.items() if k != "roots"}
    assert "no roots" in F.why_stale(old, script)
    helper = tmp_path / "scene.py"
    helper.write_text("X = 1\n")
    code = F.script_provenance(script, roots, (helper,))
    assert code["imports_sha256"] == {"scene.py": F._sha256(helper)}
    assert F.why_stale(code, script) is None
    helper.write_text("X = 2\n")
    assert "scene.py, which bench.py imports, changed" in F.why_stale(code, script)


def test_a_record_of_a_moved_script_follows_its_code(tmp_path, monkeypatch):
    """A record written by a script that has since moved into the package (its sha256 in
    ``MOVED_SCRIPTS``) is current while the module's code is what the table pins, by the
    script's old path or by the module's name; stale when the code or the hash differs.
    A record written by a module names it and its digest."""
    module, roots = "dyntorsion.studies.contact.plectoneme_scene", ("dyntorsion.buckling:simulate",)
    sha = "ab" * 32
    monkeypatch.setitem(F.MOVED_SCRIPTS, "scene_script.py", (module, sha, F._digest(module)))
    code = {
        "script_sha256": sha,
        "roots": list(roots),
        "code_fingerprint": F.code_fingerprint(roots),
    }
    old_path = tmp_path / "benchmarks" / "scene_script.py"  # no longer there
    assert F.why_stale(code, old_path) is None
    assert F.why_stale(code, module) is None
    assert "changed" in F.why_stale(dict(code, script_sha256="cd" * 32), module)
    monkeypatch.setitem(F.MOVED_SCRIPTS, "scene_script.py", (module, sha, "0" * 64))
    assert "changed" in F.why_stale(code, old_path)
    new = F.script_provenance(module, roots, ("dyntorsion.studies.contact.records",))
    assert new["module"] == module and "script_sha256" not in new
    assert F.why_stale(new, module) is None
    assert "changed" in F.why_stale(dict(new, module_digest="0" * 64), module)
    moved = dict(new, imports_digest={"dyntorsion.studies.contact.records": "0" * 64})
    assert "which" in F.why_stale(moved, module)


def test_the_moved_scripts_table_pins_todays_code():
    """Every entry of ``MOVED_SCRIPTS`` names a module or a file of the checkout whose
    code is the digest pinned (an edit of that code must make its records stale, so the
    entry cannot be refreshed without recomputing them)."""
    for old, (target, sha, digest) in F.MOVED_SCRIPTS.items():
        assert len(sha) == 64 and old.endswith(".py")
        assert F._digest(F._where(target)) == digest, f"{old}: {target}'s code changed"


def test_fingerprints_kept_on_disk_are_the_ones_computed(tmp_path, monkeypatch):
    """A process reads back the fingerprints of a byte-identical package; a cache file that
    cannot be read is recomputed over, never trusted."""
    roots = F.KIND_ROOTS["wave-convergence"]
    computed = F.fingerprint_of(F.reachable(roots))
    cache = tmp_path / "fingerprints.json"
    monkeypatch.setattr(fingerprint_cache, "cache_file", lambda: cache)
    F.code_fingerprint.cache_clear()
    try:
        assert F.code_fingerprint(roots) == computed
        kept = json.loads(cache.read_text())
        assert list(kept.values()) == [computed]
        F.code_fingerprint.cache_clear()
        cache.write_text("{not json")
        assert F.code_fingerprint(roots) == computed
        F.code_fingerprint.cache_clear()
        cache.write_text(json.dumps({next(iter(kept)): "0123456789abcdef"}))
        assert F.code_fingerprint(roots) == "0123456789abcdef"  # read back, as written
    finally:
        F.code_fingerprint.cache_clear()


def test_the_package_digest_names_the_cache_and_follows_every_byte(tmp_path):
    digest = fingerprint_cache.package_digest
    assert digest() in fingerprint_cache.cache_file().name
    (tmp_path / "sub").mkdir()
    (tmp_path / "a.py").write_text("X = 1\n")
    (tmp_path / "sub" / "b.py").write_text("def f():\n    return 2\n")
    before = digest(tmp_path)
    digest.cache_clear()
    (tmp_path / "sub" / "b.py").write_text("def f():\n    return 3\n")
    assert digest(tmp_path) != before
    digest.cache_clear()


def test_a_study_that_caches_its_runs_is_not_fingerprinted_by_the_store():
    """The store keeps records and computes no number: a study reading its runs through it
    (accuracy-runs) does not reach it."""
    reached = F.reachable(F.KIND_ROOTS["accuracy-runs"])
    assert "dyntorsion.studies.sweep:run_sweep" in reached
    assert not any(name.startswith("dyntorsion.store") for name in reached)
