"""The command line: ``dyntorsion info``, ``warmup``, ``buckle``, ``sweep``, ``linear``, ``fit``.

``python -m dyntorsion ...`` is the same program.
"""

from __future__ import annotations

import argparse
import os
import re
import signal
import sys
import threading
from collections.abc import Sequence

import numpy as np

from .. import __version__
from ..buckling.scene import Scene, run_scene
from ..store.results import ON_CORRUPT, ON_STALE
from ..studies.presets import GROUPS, PRESETS, preset
from ..studies.sweep import run_sweep
from .cli_fit import fit, fit_rows, print_fit
from .cli_options import add_scene_options, parse_rates, scene_from
from .cli_rtol import add_rtol_options, buckle_rtol, result_json, sweep_rtol
from .contact_cli import add_contact_options, buckle_contact
from .faults import EXIT_INPUT, EXIT_INTERRUPTED, blank_value, describe
from .info import info as _info
from .plugins import PluginError, load_plugins, plugins_in
from .warmup import add_warmup


def _peak_twist(scene: Scene) -> float:
    """The largest |kappa3(0, t)| the scene's history imposes over its run."""
    return float(np.max(np.abs(scene.twist(np.linspace(0.0, scene.duration(), 4001)))))


def _buckle(args: argparse.Namespace) -> int:
    scene = scene_from(args, args.a)
    if args.contact:
        return buckle_contact(args, scene)
    if args.rtol is not None:
        return buckle_rtol(args, scene)
    if args.store:
        table = run_sweep([scene], args.store, on_stale=args.on_stale, progress=False)
        row = table.iloc[0].to_dict()
    else:
        row = run_scene(scene)
    if args.json:
        print(result_json({"scene": scene.label(), **row}))
        return 0 if row["status"] == "buckled" else 1
    try:
        kappa_cri = scene.kappa_cri()
        kc = f"{kappa_cri:.4f}"
    except ValueError:
        kappa_cri, kc = None, "not covered by the static theory"
    print(f"scene      {scene.label()}")
    if row.get("cached"):
        print(
            f"cached     read from {args.store}, not recomputed (--on-stale recompute to redo a stale one)"
        )
    print(f"stopped    {_stopped(row)}")
    print(f"status     {row['status']}")
    if row["status"] == "no-onset" and row["stopped"] == "t_end" and kappa_cri is not None:
        peak = _peak_twist(scene)
        if peak >= kappa_cri and row.get("u3_peak") == 0.0:
            print(
                f"no onset: the end twist passed kappa_cri = {kc} 1/m, yet u3(L, t) stayed exactly "
                f"0: nothing this grid and seed resolve moved the rod (bending time T0 = "
                f"{scene.rod.T0:.3g} s, dt = {scene.dt:g} s); use --fidelity, or a larger --seed"
            )
            return 1
        if peak < kappa_cri:
            print(
                f"no onset: the end twist stays below kappa_cri = {kc} 1/m (at most "
                f"{peak:.4f} 1/m), so the straight rod is stable: no buckling to find"
            )
            return 0
    if row["status"] == "unclassified":
        print(
            f"onset      t_c = {row['t_c']:.4f} s, kappa3 = {row['kappa3']:.4f} 1/m: unclassified, "
            "no static kappa_cri for this scene tells an instability from a rod bent by its seed"
        )
        return 1
    if row["status"] == "failed":  # the onset was never reached: say so, not why none was read
        print("no onset: the run failed (the line 'stopped') before the rod could buckle")
        return 1
    if row["status"] != "buckled":
        why = row.get("onset_error") or "no onset detected before the run ended"
        print(why if row["status"] != "forced" else f"{why} (t_c is no critical time)")
        return 1
    print(f"t_c        {row['t_c']:.4f} +- {row['uncertainty_t']:.4f} s")
    print(
        f"kappa3     {row['kappa3']:.4f} +- {row['uncertainty_kappa3']:.4f} 1/m "
        f"(static kappa_cri = {kc})"
    )
    return 0


def _stopped(row: dict) -> str:
    """The run's end; a Newton failure after a buckled onset is the post-buckling whip."""
    if row["status"] == "buckled" and row["stopped"].startswith("failed"):
        return (
            "in the post-buckling whip, after the onset (a Newton failure there ends the run; "
            f"the onset stands): {row['stopped']}"
        )
    return row["stopped"]


#: the ``--preset`` value that names every preset of a command (``make data-studies`` uses it)
EVERY = "all"


def _every(names: list[str], presets: dict, groups: dict | None = None) -> list[str]:
    """The preset names a ``--preset`` list means, in order and each once: a group name
    (``groups``, e.g. ``paper``) stands for its presets, ``all`` for every one."""
    groups = {EVERY: tuple(presets)} | (groups or {})
    out = [each for name in names for each in groups.get(name, (name,))]
    return list(dict.fromkeys(out))


def _sweep_scenes(args: argparse.Namespace) -> list[Scene]:
    if args.preset:
        if args.rates:
            raise ValueError("--preset and --rates: give one of them, not both")
        return [sc for name in _every(args.preset, PRESETS, GROUPS) for sc in preset(name)]
    if not args.rates:
        raise ValueError(
            "--rates or --preset: give one (e.g. --rates 0.1,0.4,1.6 or geom:0.05:16:12)"
        )
    return [scene_from(args, a) for a in parse_rates(args.rates)]


def _log(message: str) -> None:
    from tqdm.auto import tqdm

    tqdm.write(message, file=sys.stderr)


def _sweep(args: argparse.Namespace) -> int:
    scenes = _sweep_scenes(args)
    if args.rtol is not None:
        return sweep_rtol(args, scenes)
    executor, client, cluster = None, None, None
    if args.dask_local < 0:
        raise ValueError(f"--dask-local={args.dask_local} must be >= 1 workers (or 0: off)")
    if args.scheduler or args.dask_local:
        try:
            from dask.distributed import Client, LocalCluster
        except ImportError as err:
            raise SystemExit(
                "--scheduler/--dask-local need dask.distributed: pip install 'dyntorsion[parallel]'"
            ) from err
        if args.scheduler:
            try:
                client = Client(args.scheduler, timeout="20s")
            except OSError as err:
                raise ConnectionError(
                    f"--scheduler {args.scheduler}: no dask scheduler answered ({err}); check the "
                    "address and that the scheduler is running"
                ) from None
        else:
            cluster = LocalCluster(n_workers=args.dask_local, threads_per_worker=1)
            client = Client(cluster)
        executor = client.get_executor()
    try:
        table = run_sweep(
            scenes,
            args.store,
            executor=executor,
            # dask's futures do not say which run: bound the sweep to its workers, so
            # that an interrupt keeps every scene submitted
            jobs=args.jobs if client is None else sum(client.nthreads().values()),
            on_stale=args.on_stale,
            on_corrupt=args.on_corrupt,
            progress=not args.quiet,
            log=None if args.quiet else _log,
        )
    finally:
        if client is not None:
            client.close()
        if cluster is not None:
            cluster.close()
    cols = [
        "a",
        "kappa0",
        "rod",
        "seed",
        "n_cells",
        "dt",
        "t_c",
        "kappa3",
        "uncertainty_kappa3",
        "status",
        "cached",
    ]
    with np.printoptions(precision=4):
        print(table[cols].to_string(index=False, float_format=lambda v: f"{v:.5g}"))
    if not args.no_fit:
        print_fit(fit_rows(table, scenes))
    return 0


def _linear(args: argparse.Namespace) -> int:
    from ..studies import linear_predictions as LS

    preds = [p for name in _every(args.preset, LS.PRESETS) for p in LS.preset(name)]
    table = LS.predict(
        preds,
        args.store,
        jobs=args.jobs,
        on_stale=args.on_stale,
        log=None if args.quiet else _log,
    )
    cols = [
        "a",
        "kappa0",
        "seed",
        "waves",
        "spin",
        "rotary_inertia",
        "modes",
        "t_ref",
        "kappa3_ref",
    ]
    print(table[cols].to_string(index=False, float_format=lambda v: f"{v:.5g}"))
    return 0


def _linear_presets() -> list[str]:
    from ..studies.linear_predictions import PRESETS as LINEAR

    return list(LINEAR)


#: the --store option's help, the same for every subcommand
STORE_HELP = "cache folder (default: $DYNTORSION_DATA, else the checkout's data/scenes, else the user cache; `dyntorsion info` names it)"


#: argparse takes "-1e9" or "-inf" for an option; a number in any float notation is a value
_NEGATIVE_NUMBER = re.compile(r"^-((\d+\.?\d*|\.\d+)([eE][-+]?\d+)?|inf(inity)?|nan)$", re.I)


def parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="dyntorsion", description=__doc__.splitlines()[0])
    p.add_argument("--version", action="version", version=f"dyntorsion {__version__}")
    p.add_argument(
        "--debug", action="store_true", help="show the traceback of an error (anywhere on the line)"
    )
    p.add_argument(
        "--max-time",
        type=float,
        default=None,
        metavar="S",
        help="refuse a run estimated longer than S seconds (default: $DYNTORSION_MAX_TIME, else 6 h)",
    )
    sub = p.add_subparsers(dest="command", required=True)

    sub.add_parser(
        "info", help="version, the default store and why, python, numba and the arithmetic"
    ).set_defaults(func=_info)
    add_warmup(sub)

    b = sub.add_parser("buckle", help="one buckling scene: print t_c and kappa3")
    b.add_argument(
        "--a", type=float, default=None, help="loading rate [rad/(m s)] (ramp histories)"
    )
    add_scene_options(b, kappa0=0.0)
    b.add_argument(
        "--store",
        default=None,
        help="cache folder: read the scene from it, or compute and add it (default: none, "
        "the result is printed and not kept)",
    )
    b.add_argument("--on-stale", choices=ON_STALE, default="recompute")
    add_contact_options(b)  # with --json
    add_rtol_options(b)
    b.set_defaults(func=_buckle)

    s = sub.add_parser("sweep", help="a sweep over loading rates (cached, resumable)")
    s.add_argument(
        "--preset",
        action="append",
        choices=[*sorted(PRESETS), *GROUPS],
        help="a named sweep (repeatable; 'paper': those the paper's figures read, 'all': every "
        "one); see dyntorsion.studies.presets.PRESETS",
    )
    s.add_argument("--rates", default=None, help="'0.1,0.4,1.6' or 'geom:LO:HI:N'")
    add_scene_options(s, kappa0=10.0)
    s.add_argument("--store", default=None, help=STORE_HELP)
    s.add_argument("--jobs", type=int, default=1, help="local worker processes")
    s.add_argument(
        "--dask-local",
        type=int,
        default=0,
        metavar="N",
        help="run on a dask.distributed LocalCluster of N workers",
    )
    s.add_argument(
        "--scheduler", default=None, help="address of a running dask.distributed scheduler"
    )
    s.add_argument("--on-stale", choices=ON_STALE, default="recompute")
    s.add_argument(
        "--on-corrupt",
        choices=ON_CORRUPT,
        default="quarantine",
        help="a damaged record: move it aside (.corrupt) and recompute, or stop with an error",
    )
    s.add_argument("--quiet", action="store_true", help="no progress bar or log")
    s.add_argument(
        "--no-fit",
        action="store_true",
        help="do not fit eq (33) to the sweeps (bootstrapped: seconds a sweep); "
        "`dyntorsion fit` fits them from the records later",
    )
    add_rtol_options(s)
    s.set_defaults(func=_sweep)

    lin = sub.add_parser(
        "linear",
        help="linear-stability predictions of the onset (dyntorsion.studies.linear_predictions; cached)",
    )
    lin.add_argument(
        "--preset",
        action="append",
        required=True,
        choices=[*sorted(_linear_presets()), EVERY],
        help="a named set of predictions (repeatable; 'all': every one)",
    )
    lin.add_argument("--store", default=None, help=STORE_HELP)
    lin.add_argument("--jobs", type=int, default=1, help="local worker processes")
    lin.add_argument("--on-stale", choices=ON_STALE, default="recompute")
    lin.add_argument("--quiet", action="store_true", help="no log")
    lin.set_defaults(func=_linear)

    f = sub.add_parser(
        "fit", help="fit eq (33) to cached sweeps: a preset, or every rate sweep in a store"
    )
    f.add_argument("--preset", choices=sorted(PRESETS), default=None)
    f.add_argument("--store", default=None, help=STORE_HELP)
    f.set_defaults(func=fit)
    for each in (p, *sub.choices.values()):
        each._negative_number_matcher = _NEGATIVE_NUMBER
    return p


class _Terminated(KeyboardInterrupt):
    """SIGTERM, raised where the run stands: an interrupt (so that a sweep keeps its
    running scenes as on Ctrl-C, and no handler of ordinary errors on the way takes it
    for a failed run)."""


def _kept(args: argparse.Namespace) -> str:
    """What an interrupted command kept: ``buckle`` keeps its result only with --store."""
    if args.command == "buckle" and not args.store:
        return "nothing was kept (buckle keeps its result only with --store)"
    return "finished results are kept in the store"


def _terminate(signum, frame) -> None:
    raise _Terminated(signum)


def main(argv: Sequence[str] | None = None) -> int:
    """Run a subcommand; a package error prints one line and a non-zero status
    (``--debug``: the traceback instead)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in argv
    blank = blank_value(argv)
    if blank:
        print(f"dyntorsion: error: {blank}", file=sys.stderr)
        return EXIT_INPUT
    try:  # before the options are read: a plugin's kinds and end sets become choices
        load_plugins(plugins_in(argv))
    except PluginError as err:
        if debug:
            raise
        print(f"dyntorsion: error: {err}", file=sys.stderr)
        return EXIT_INPUT
    args = parser().parse_args([a for a in argv if a != "--debug"])
    if args.max_time is not None and not args.max_time > 0:
        print(f"dyntorsion: error: --max-time={args.max_time} must be > 0 seconds", file=sys.stderr)
        return 2
    budget = os.environ.get("DYNTORSION_MAX_TIME")
    if args.max_time is not None:
        os.environ["DYNTORSION_MAX_TIME"] = repr(args.max_time)  # worker processes inherit it
    main_thread = threading.current_thread() is threading.main_thread()
    old = signal.signal(signal.SIGTERM, _terminate) if main_thread else None
    try:
        return args.func(args)
    except _Terminated as stop:
        if debug:
            raise
        print(f"dyntorsion: terminated (SIGTERM); {_kept(args)}", file=sys.stderr)
        return 128 + stop.args[0]
    except KeyboardInterrupt:
        if debug:
            raise
        print(f"dyntorsion: interrupted; {_kept(args)}", file=sys.stderr)
        return EXIT_INTERRUPTED
    except Exception as err:
        if debug:
            raise
        line, status = describe(err)
        print(f"dyntorsion: error: {line}", file=sys.stderr)
        return status
    finally:
        if main_thread:
            signal.signal(signal.SIGTERM, old)
        if args.max_time is not None:  # a caller in this process keeps its own budget
            if budget is None:
                os.environ.pop("DYNTORSION_MAX_TIME", None)
            else:
                os.environ["DYNTORSION_MAX_TIME"] = budget


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
