"""The command line's ``--rtol`` (the onset to a relative tolerance, with its estimated
error: :mod:`dyntorsion.studies.tolerance`) and ``--json`` (one run's result as one JSON
object, :func:`result_json`, for any subcommand that prints one result)."""

from __future__ import annotations

import argparse
import json

import pandas as pd

from ..buckling.scene import Scene
from ..store.results import json_ready
from ..studies.tolerance import DEFAULT_READING, READINGS, check_rtol, onset_within

__all__ = ["RTOL_HELP", "add_rtol_options", "rtol_type", "result_json", "buckle_rtol", "sweep_rtol"]

RTOL_HELP = (
    "relative tolerance of t_c and kappa3 in (0, 1]: run the scene on the rungs of the "
    "fidelity ladder (dyntorsion.studies.tolerance; paced steps) until the estimated "
    "error (the rungs' differences and a solver check) meets R, and print it (overrides "
    "--n-cells, --dt, --fidelity, --paced)"
)


def rtol_type(text: str) -> float:
    """``--rtol``: a relative tolerance in (0, 1]."""
    try:
        return check_rtol(float(text))
    except ValueError as err:
        raise argparse.ArgumentTypeError(str(err).replace("rtol=", "--rtol ")) from None


#: how each reading is said in the text output
READ_AS = {"samples": "off the samples", "continuous": "in continuous time"}


def add_rtol_options(parser: argparse.ArgumentParser) -> None:
    """``--rtol R`` and ``--reading`` (which onset the rungs give) on a subcommand."""
    parser.add_argument("--rtol", type=rtol_type, default=None, metavar="R", help=RTOL_HELP)
    parser.add_argument(
        "--reading",
        choices=tuple(READINGS),
        default=DEFAULT_READING,
        help="with --rtol: the paper's window read in continuous time (default; its error "
        "estimate trusts the scheme's order) or off the samples (the paper's rule, the t_c "
        "of every other command; its estimate is several times too large)",
    )


def result_json(result: dict) -> str:
    """One run's result as one JSON object (numbers as numbers, NaN and infinities as
    null, numpy scalars as Python ones): what ``--json`` prints."""
    return json.dumps(json_ready(result), allow_nan=False)


def buckle_rtol(args: argparse.Namespace, scene: Scene) -> int:
    """``buckle --rtol R``: the onset on the cheapest rung that meets R, with its error."""
    res = onset_within(scene, args.rtol, store=args.store, reading=args.reading)
    grid = {"rung": res.rung, "n_cells": res.n_cells, "dt": res.dt}
    if args.json:
        out = {"scene": scene.label().rsplit(" N=", 1)[0], **res.as_dict(), "grid": grid}
        print(result_json(out))
        return 0 if res.met else 1
    print(f"scene      {scene.label().rsplit(' N=', 1)[0]} (grid chosen for rtol={res.rtol:g})")
    for g in res.grids:
        tc = "-" if g["t_c"] is None else f"{g['t_c']:.5f} s"
        print(
            f"rung       {g['rung']:<9} N={g['n_cells']:<4} dt={g['dt']:.4g} s  {g['status']:<9} t_c = {tc}"
        )
    if res.solver is not None:
        s = res.solver
        tc = "-" if s["t_c"] is None else f"{s['t_c']:.5f} s"
        change = "" if s["t_c_change"] is None else f" (changes t_c by {s['t_c_change']:.2g} s)"
        print(f"solver     Newton tol {s['newton_tol']:.0e} N={s['n_cells']:<4} {s['status']:<9} "
              f"t_c = {tc}{change}")  # fmt: skip
    print(f"status     {res.status} (onset read {READ_AS[res.reading]})")
    if res.t_c_error is None:
        print(res.note)
        return 1
    print(f"t_c        {res.t_c:.5f} +- {res.t_c_error:.2g} s (estimated error: rungs and solver)")
    print(f"kappa3     {res.kappa3:.5f} +- {res.kappa3_error:.2g} 1/m")
    print(
        f"grid       {res.rung}: N = {res.n_cells}, dt = {res.dt:.4g} s (paced by the {res.paced_by})"
    )
    if not res.met:
        print(res.note)
    return 0 if res.met and res.status == "buckled" else 1


def sweep_rtol(args: argparse.Namespace, scenes: list[Scene]) -> int:
    """``sweep --rtol R``: each scene on the cheapest rung that meets R (one after another;
    the rungs are cached in the store like any scene)."""
    if args.jobs != 1 or args.dask_local or args.scheduler:
        raise ValueError(
            "--rtol runs the scenes one after another in this process (each rung decides the "
            "next); drop --jobs/--dask-local/--scheduler"
        )
    rows = []
    for sc in scenes:
        res = onset_within(sc, args.rtol, store=args.store, reading=args.reading)
        rows.append({"a": sc.a, **{k: v for k, v in res.as_dict().items() if k != "grids"}})
    table = pd.DataFrame(rows)
    cols = [
        "a",
        "t_c",
        "t_c_error",
        "kappa3",
        "kappa3_error",
        "rung",
        "n_cells",
        "dt",
        "met",
        "status",
    ]
    print(table[cols].to_string(index=False, float_format=lambda v: f"{v:.5g}"))
    return 0 if table.met.all() else 1
