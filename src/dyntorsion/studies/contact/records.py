"""What the modules that write a record to ``data/contact`` and ``data/bench`` share: the
record's provenance (:func:`dyntorsion.store.fingerprint.script_provenance`: package version, the
script's sha256, the roots of the code that computed it and their fingerprint, which
:func:`~dyntorsion.store.fingerprint.why_stale` checks on the pages and in the tests), the
atomic write (a temporary file in the same folder renamed over the record, so a run cut
short loses nothing already written) and the resume-and-run loop of a record made of
independent runs (runs already in a current record are kept; the rest run, finest grid
first, each written as it ends)."""

from __future__ import annotations

import argparse
import json
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

from ...store.fingerprint import script_provenance, why_stale
from ...store.location import checkout
from ...store.results import json_ready, write_text

__all__ = ["DATA", "provenance", "result_json", "write", "resume", "run_missing", "run_script",
           "summary"]  # fmt: skip

#: the checkout's ``data/`` folder (the working directory's for an installed package)
DATA = (checkout() or Path.cwd()) / "data"

provenance = script_provenance


def result_json(result: dict) -> str:
    """One run's result as one JSON object (numbers as numbers, NaN and infinities as
    null, numpy scalars as Python ones), as ``dyntorsion buckle --json`` prints it."""
    return json.dumps(json_ready(result), allow_nan=False)


def write(out: Path, record: dict, indent: int | None = None) -> None:
    """Write ``record`` to ``out`` as JSON (indented by ``indent``), atomically
    (:func:`dyntorsion.store.results.write_text`: ``out`` untouched on any failure)."""
    write_text(out, json.dumps(record, indent=indent))


def resume(out: Path, record: dict, keys: Sequence[str] = ("params", "code")) -> dict:
    """The record at ``out`` if its ``keys`` equal ``record``'s (same parameters, script
    and code: what it holds is what this run would compute), else ``record``.  The
    ``code`` parts are compared with their numerical environment
    (:func:`dyntorsion.store.environment.numerical_environment`) where the record on disk
    has one: runs made with other kernels are not mixed into it (a record written before
    the environment was kept is resumed on the code alone)."""
    if out.exists():
        old = json.loads(out.read_text())
        if all(_same(k, old.get(k), _as_stored(record[k])) for k in keys):
            return old
        was = (old.get("code") or {}).get("environment")
        if was is not None and all(
            _same(k, old.get(k), _as_stored(record[k]), environment=False) for k in keys
        ):
            print(f"{out.name}: begun in another numerical environment "
                  f"({was}); starting over", flush=True)  # fmt: skip
        else:
            differ = [k for k in keys if not _same(k, old.get(k), _as_stored(record[k]))]
            print(f"{out.name}: its {' and '.join(differ)} differ from this run's; "
                  "starting over", flush=True)  # fmt: skip
    return record


def _as_stored(value):
    """``value`` as it reads back from the record's JSON (tuples as lists, numpy scalars as
    numbers), so that a record on disk compares equal to the one this run would write."""
    return json.loads(json.dumps(json_ready(value), allow_nan=False))


def _same(key: str, old, new, environment: bool = True) -> bool:
    """Whether the ``key`` parts of two records agree (module docstring); a record written
    by a script since moved into the package agrees with its module while
    :func:`~dyntorsion.store.fingerprint.why_stale` finds it current."""
    if key != "code" or not isinstance(old, dict) or not isinstance(new, dict):
        return old == new
    if "script_sha256" in old and "module" in new:
        same_env = not environment or old.get("environment") in (None, new.get("environment"))
        return same_env and why_stale(old, new["module"]) is None
    if environment and "environment" in old:
        return old == new
    return {k: v for k, v in old.items() if k != "environment"} == {
        k: v for k, v in new.items() if k != "environment"
    }


def run_missing(
    out: Path,
    record: dict,
    jobs: Mapping[str, Sequence[tuple]],
    compute: Mapping[str, Callable[..., dict]],
    key: Mapping[str, Callable[[dict], tuple]],
    report: Callable[[str, tuple, dict], str],
    processes: int = 1,
    indent: int | None = None,
) -> dict:
    """Complete ``record`` (resumed from ``out``, :func:`resume`): for each part (a list
    in the record) the runs ``jobs[part]`` (argument tuples, the first the number of
    cells) not yet in it by ``key[part](row)``, each ``compute[part](*args)`` in one of
    ``processes`` processes, the finest first.  Each finished run is put in its part in
    the order of ``jobs`` and the record written; ``report(part, args, row)`` is printed."""
    record = resume(out, record)
    done = {(part, key[part](row)) for part in jobs for row in record[part]}
    order = {(part, tuple(a)): i for part, runs in jobs.items() for i, a in enumerate(runs)}
    todo = [(part, tuple(a)) for part, runs in jobs.items() for a in runs
            if (part, tuple(a)) not in done]  # fmt: skip
    todo.sort(key=lambda job: -job[1][0])
    with ProcessPoolExecutor(max_workers=max(1, processes)) as pool:
        futures = {pool.submit(compute[part], *args): (part, args) for part, args in todo}
        for fut in as_completed(futures):
            part, args = futures[fut]
            row = fut.result()
            record[part].append(row)
            record[part].sort(key=lambda r, p=part: order[(p, key[p](r))])
            write(out, record, indent)
            print(report(part, args, row), flush=True)
    return record


def summary(grid: str, res: Mapping, **numbers: str) -> str:
    """One printed line for a finished run past contact: its grid, how and when it ended,
    the ``numbers`` (label: formatted value) and its wall time."""
    said = ", ".join(f"{label.replace('_', ' ')} {value}" for label, value in numbers.items())
    return f"{grid}: {res['stopped'][:70]} at {res['t_last']} s; {said} ({res['wall_time']:.0f} s)"


def run_script(
    argv: Sequence[str] | None,
    doc: str,
    out: Path,
    record: dict,
    runs: Sequence[tuple],
    compute: Callable[..., dict],
    key: Callable[[dict], tuple],
    report: Callable[[dict], str],
) -> int:
    """The command line of a script whose record is one list of runs (``record["runs"]``):
    ``--jobs J`` runs at once, the missing ones computed by :func:`run_missing`,
    ``report(row)`` printed as each ends."""
    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    ap.add_argument("--jobs", type=int, default=1, help="runs at once (processes)")
    processes = ap.parse_args(argv).jobs
    run_missing(out, record, {"runs": runs}, {"runs": compute}, {"runs": key},
                lambda part, args, row: report(row), processes)  # fmt: skip
    return 0
