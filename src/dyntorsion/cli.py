"""The command line: ``dyntorsion buckle``, ``sweep``, ``linear``, ``fit``.

``python -m dyntorsion ...`` is the same program.
"""

from __future__ import annotations

import argparse
import signal
import sys
import threading
from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from . import __version__, fidelity
from .buckling import Perturbation, fit_power_law
from .faults import EXIT_INTERRUPTED, describe
from .fidelity import LEVELS
from .loading import ENDS, AxialLoad, Polynomial, RampHold, Tabulated
from .results import ON_STALE, Store
from .rod import Rod
from .sweep import (
    KIND,
    PRESET_CONTROL,
    PRESETS,
    Scene,
    cached,
    default_store,
    preset,
    run_scene,
    run_sweep,
)


def _numbers(text: str, n: int | None, what: str) -> list[float]:
    try:
        vals = [float(v) for v in text.split(",")]
    except ValueError:
        raise ValueError(f"{what}={text!r} must be comma-separated numbers") from None
    if n is not None and len(vals) != n:
        raise ValueError(f"{what}={text!r} must hold {n} numbers (got {len(vals)})")
    return vals


def _level(name: str) -> str:
    try:
        return fidelity.check_level(name)
    except ValueError as err:
        raise argparse.ArgumentTypeError(str(err)) from None


def _scene_options(p: argparse.ArgumentParser, kappa0: float) -> None:
    g = p.add_argument_group("rod (default: Table 1)")
    g.add_argument("--rho", type=float, default=1500.0, help="density [kg/m^3] (Table 1: 1500)")
    g.add_argument("--E", type=float, default=1.25e7, help="Young's modulus [Pa]")
    g.add_argument("--nu", type=float, default=0.25, help="Poisson's ratio")
    g.add_argument("--L", type=float, default=1.0, help="length [m]")
    sec = g.add_mutually_exclusive_group()
    sec.add_argument("--D", type=float, default=None, help="diameter of a circle [m] (1e-3)")
    sec.add_argument(
        "--ellipse", metavar="A,B", help="elliptic section: semi-axes along d1, d2 [m]"
    )
    sec.add_argument(
        "--rectangle", metavar="W,H", help="rectangular section: width (d1), height (d2) [m]"
    )
    sec.add_argument(
        "--properties",
        metavar="B1,B2,C,RHOA,RHOI1,RHOI2,RHOI3,THICKNESS",
        help="a rod given by its stiffnesses [N m^2], mass per length [kg/m], rotary inertias "
        "[kg m] and contact thickness [m] (E, nu, rho are then unused)",
    )
    g = p.add_argument_group("loading and ends")
    g.add_argument("--kappa0", type=float, default=kappa0, help="initial twist [1/m]")
    g.add_argument(
        "--history",
        default="ramp",
        help="end twist kappa3(0, t): 'ramp' (kappa0 + a t, the paper), 'ramp-hold:HOLD[:TAU]' "
        "(ramp at --a rounded into a hold at HOLD 1/m over TAU s), 'poly:C0,C1,...' "
        "(sum C_k t^k), 'table:FILE' (two columns t, kappa; t from 0)",
    )
    g.add_argument("--tension", type=float, default=0.0, help="axial end load [N], > 0 tension")
    g.add_argument("--tension-rate", type=float, default=0.0, help="its rate [N/s]")
    g.add_argument(
        "--ends", choices=sorted(ENDS), default="clamped", help="end conditions (clamped: eq 30)"
    )
    g = p.add_argument_group("seed and grid")
    g.add_argument(
        "--seed",
        type=float,
        default=1e-8,
        help="perturbation magnitude (N/m uniform, N for --seed-form point)",
    )
    g.add_argument("--seed-form", choices=("uniform", "point"), default="uniform")
    g.add_argument("--seed-location", type=float, default=0.5, help="point seed position [m]")
    g.add_argument(
        "--fidelity",
        type=_level,
        default=None,
        help=f"grid preset ({', '.join(LEVELS)}; dyntorsion.fidelity), its time step scaled to the rod; "
        "overrides --n-cells/--dt/--lam-*",
    )
    g.add_argument("--n-cells", type=int, default=100, help="cells along the rod")
    g.add_argument("--dt", type=float, default=0.005, help="time step [s]")
    g.add_argument("--lam-s", type=float, default=-1.0, help="lambda_inf in space, [-1, 0]")
    g.add_argument("--lam-t", type=float, default=-1.0, help="lambda_inf in time, [-1, 0]")
    g.add_argument(
        "--control",
        action="store_true",
        help="step-size control: retry a failed step with smaller ones and follow the rod to "
        "self-contact (genalpha.StepControl; the presets always use it)",
    )
    g.add_argument(
        "--t-end",
        type=float,
        default=None,
        help="end time [s] (default for the ramp at clamped ends: 3x the paper's delay, eqs 33-34)",
    )


def _rod(args: argparse.Namespace) -> Rod:
    if args.properties:
        B1, B2, C, rhoA, r1, r2, r3, t = _numbers(args.properties, 8, "--properties")
        return Rod.from_properties(
            L=args.L,
            B1=B1,
            B2=B2,
            C=C,
            mass_per_length=rhoA,
            rotary_inertia=(r1, r2, r3),
            thickness=t,
        )
    mat = dict(E=args.E, nu=args.nu, L=args.L, rho=args.rho)
    if args.ellipse:
        a, b = _numbers(args.ellipse, 2, "--ellipse")
        return Rod.elliptic(a=a, b=b, **mat)
    if args.rectangle:
        w, h = _numbers(args.rectangle, 2, "--rectangle")
        return Rod.rectangular(w=w, h=h, **mat)
    return Rod(D=1e-3 if args.D is None else args.D, **mat)


def _history(args: argparse.Namespace, a: float | None) -> dict:
    """Scene keywords for the end twist: a and kappa0 (the ramp) or a history."""
    kind, _, rest = args.history.partition(":")
    if kind == "ramp":
        if a is None:
            raise ValueError("--history ramp needs the loading rate --a")
        return {"a": a, "kappa0": args.kappa0}
    if kind == "ramp-hold":
        if a is None:
            raise ValueError("--history ramp-hold needs the loading rate --a")
        vals = _numbers(rest, None, "--history ramp-hold:HOLD[:TAU]".replace(":TAU]", "]"))
        if len(vals) not in (1, 2):
            raise ValueError("--history ramp-hold:HOLD[,TAU] takes one or two numbers")
        return {"history": RampHold(a, vals[0], args.kappa0, *vals[1:])}
    if kind == "poly":
        return {"history": Polynomial(tuple(_numbers(rest, None, "--history poly")))}
    if kind == "table":
        try:
            t, k = np.loadtxt(rest, delimiter=None, unpack=True, ndmin=2)
        except (OSError, ValueError) as err:
            raise ValueError(
                f"--history table:{rest}: cannot read two columns t, kappa ({err})"
            ) from None
        return {"history": Tabulated(tuple(t), tuple(k))}
    raise ValueError(
        f"--history={args.history!r}; allowed: ramp, ramp-hold:HOLD[,TAU], poly:C0,C1,..., table:FILE"
    )


def _scene(args: argparse.Namespace, a: float | None) -> Scene:
    rod = _rod(args)
    seed = Perturbation(magnitude=args.seed, form=args.seed_form, location=args.seed_location)
    grid = fidelity.get(
        "buckling",
        args.fidelity
        or fidelity.Fidelity(args.n_cells, args.dt, lam_s=args.lam_s, lam_t=args.lam_t),
        rod=rod,
    )
    kwargs = grid.simulate_kwargs()
    if args.control:
        kwargs["scheme"] = replace(kwargs["scheme"], control=PRESET_CONTROL)
    return Scene(
        rod=rod,
        seed=seed,
        t_end=args.t_end,
        tension=AxialLoad(args.tension, args.tension_rate),
        ends=args.ends,
        **_history(args, a),
        **kwargs,
    )


def _rates(text: str) -> list[float]:
    """'0.1,0.4,1.6' or 'geom:0.05:16:12' (12 rates spaced logarithmically)."""
    if text.startswith("geom:"):
        parts = text[5:].split(":")
        try:
            lo, hi, n = float(parts[0]), float(parts[1]), int(parts[2])
            if len(parts) != 3:
                raise IndexError
        except (IndexError, ValueError):
            raise ValueError(
                f"--rates {text!r}: write geom:LO:HI:N (e.g. geom:0.05:16:12)"
            ) from None
        if not (0 < lo < hi and n >= 2):
            raise ValueError(f"--rates {text!r}: need 0 < LO < HI and N >= 2")
        return [float(v) for v in np.geomspace(lo, hi, n)]
    rates = _numbers(text, None, "--rates") if text.strip(", ") else []
    if not rates:
        raise ValueError(f"--rates {text!r} holds no rate (e.g. 0.1,0.4,1.6 or geom:0.05:16:12)")
    return rates


def _buckle(args: argparse.Namespace) -> int:
    scene = _scene(args, args.a)
    if args.store:
        table = run_sweep([scene], args.store, on_stale=args.on_stale, progress=False)
        row = table.iloc[0].to_dict()
    else:
        row = run_scene(scene)
    try:
        kc = f"{scene.kappa_cri():.4f}"
    except ValueError:
        kc = "not covered by the static theory"
    print(f"scene      {scene.label()}")
    print(f"stopped    {row['stopped']}")
    print(f"status     {row['status']}")
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


def _sweep_scenes(args: argparse.Namespace) -> list[Scene]:
    if args.preset:
        if args.rates:
            raise SystemExit("give either --preset or --rates, not both")
        return [sc for name in args.preset for sc in preset(name)]
    if not args.rates:
        raise SystemExit("give --rates (e.g. 0.1,0.4,1.6 or geom:0.05:16:12) or --preset")
    return [_scene(args, a) for a in _rates(args.rates)]


def _print_fit(rows: list[dict]) -> None:
    """Fit eq (33) to each family of scenes (same everything but the rate), with each
    family's own rod, axial load and static critical twist."""
    families: dict[str, list[dict]] = {}
    for r in rows:
        if r["a"] is not None and r["kappa3"] is not None:
            families.setdefault(r["family"], []).append(r)
    if not families:
        print('fit: no scene with a loading rate and a "buckled" onset to fit')
    for grp in families.values():
        seen, pts = set(), []
        for r in grp:
            if round(r["a"], 9) not in seen:
                seen.add(round(r["a"], 9))
                pts.append(r)
        head = pts[0]
        name = head["label"]
        if len(pts) == 1:
            continue  # a single scene, not a rate sweep
        if len(pts) < 4:
            print(
                f"fit {name}: {len(pts)} rate(s) with an onset; eq (33) needs at least 4 "
                "(3 parameters with kappa_cri free, plus one) -- add rates to this sweep"
            )
            continue
        a = [r["a"] for r in pts]
        k = [r["kappa3"] for r in pts]
        rod = head["rod"]
        try:
            kc = head["scene"].kappa_cri()
            modes = (kc, None)
        except ValueError as err:
            print(f"fit {name}: kappa_cri fixed skipped ({err})")
            modes = (None,)
        for mode in modes:
            try:
                f = fit_power_law(a, k, rod, kappa_cri=mode, n_boot=500)
            except ValueError as err:
                print(f"fit {name}: not fitted ({err})")
                continue
            tag = "kappa_cri fixed" if mode is not None else "kappa_cri free "
            print(
                f"fit {name} {tag}: b = {f.b:.2f} +- {f.b_err:.2f}, "
                f"sigma = {f.sigma:.4f} +- {f.sigma_err:.4f}, "
                f"kappa_cri = {f.kappa_cri:.4f} +- {f.kappa_cri_err:.4f} "
                "(paper, Table 1 rod: b = 160.60, sigma = 0.5680)"
            )


def _fit_rows(table, scenes: list[Scene]) -> list[dict]:
    rows = []
    for (_, r), sc in zip(table.iterrows(), scenes, strict=True):
        label = sc.label().split(" ", 1)[1] if sc.history is None else sc.label()  # drop a=
        rows.append(
            {
                "a": sc.twist.rate,
                "kappa3": r["kappa3"] if r["status"] == "buckled" else None,
                "family": r["family"],
                "rod": sc.rod,
                "scene": sc,
                "label": f"[{label}]",
            }
        )
    return rows


def _log(message: str) -> None:
    from tqdm.auto import tqdm

    tqdm.write(message, file=sys.stderr)


def _sweep(args: argparse.Namespace) -> int:
    scenes = _sweep_scenes(args)
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
            client = Client(args.scheduler)
        else:
            cluster = LocalCluster(n_workers=args.dask_local, threads_per_worker=1)
            client = Client(cluster)
        executor = client.get_executor()
    try:
        table = run_sweep(
            scenes,
            args.store,
            executor=executor,
            jobs=args.jobs,
            on_stale=args.on_stale,
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
    _print_fit(_fit_rows(table, scenes))
    return 0


def _linear(args: argparse.Namespace) -> int:
    from . import linear_predictions as LS

    preds = [p for name in args.preset for p in LS.preset(name)]
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


def _fit(args: argparse.Namespace) -> int:
    if args.preset:
        scenes = preset(args.preset)
        table = cached(args.preset, args.store)
    else:
        store = Store(args.store or default_store())
        scenes = [Scene.from_params(rec["params"]) for rec in store.records(KIND)]
        if not scenes:
            raise ValueError(f"--store {args.store}: no {KIND} records to fit")
        table = run_sweep(scenes, args.store, compute=False, on_stale="error", progress=False)
    _print_fit(_fit_rows(table, scenes))
    return 0


def _linear_presets() -> list[str]:
    from .linear_predictions import PRESETS as LINEAR

    return list(LINEAR)


def parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="dyntorsion", description=__doc__.splitlines()[0])
    p.add_argument("--version", action="version", version=f"dyntorsion {__version__}")
    p.add_argument(
        "--debug", action="store_true", help="show the traceback of an error (anywhere on the line)"
    )
    sub = p.add_subparsers(dest="command", required=True)

    b = sub.add_parser("buckle", help="one buckling scene: print t_c and kappa3")
    b.add_argument(
        "--a", type=float, default=None, help="loading rate [rad/(m s)] (ramp histories)"
    )
    _scene_options(b, kappa0=0.0)
    b.add_argument(
        "--store", default=None, help="cache folder: read the scene from it, or compute and add it"
    )
    b.add_argument("--on-stale", choices=ON_STALE, default="recompute")
    b.set_defaults(func=_buckle)

    s = sub.add_parser("sweep", help="a sweep over loading rates (cached, resumable)")
    s.add_argument(
        "--preset",
        action="append",
        choices=sorted(PRESETS),
        help="a named sweep (repeatable); see dyntorsion.sweep.PRESETS",
    )
    s.add_argument("--rates", default=None, help="'0.1,0.4,1.6' or 'geom:LO:HI:N'")
    _scene_options(s, kappa0=10.0)
    s.add_argument(
        "--store", default=None, help="cache folder (default: $DYNTORSION_DATA, else data/scenes)"
    )
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
    s.add_argument("--quiet", action="store_true", help="no progress bar or log")
    s.set_defaults(func=_sweep)

    lin = sub.add_parser(
        "linear",
        help="linear-stability predictions of the onset (dyntorsion.linear_predictions; cached)",
    )
    lin.add_argument(
        "--preset",
        action="append",
        required=True,
        choices=sorted(_linear_presets()),
        help="a named set of predictions (repeatable)",
    )
    lin.add_argument(
        "--store", default=None, help="cache folder (default: $DYNTORSION_DATA, else data/scenes)"
    )
    lin.add_argument("--jobs", type=int, default=1, help="local worker processes")
    lin.add_argument("--on-stale", choices=ON_STALE, default="recompute")
    lin.add_argument("--quiet", action="store_true", help="no log")
    lin.set_defaults(func=_linear)

    f = sub.add_parser(
        "fit", help="fit eq (33) to cached sweeps: a preset, or every rate sweep in a store"
    )
    f.add_argument("--preset", choices=sorted(PRESETS), default=None)
    f.add_argument(
        "--store", default=None, help="cache folder (default: $DYNTORSION_DATA, else data/scenes)"
    )
    f.set_defaults(func=_fit)
    return p


def _terminate(signum, frame) -> None:
    raise SystemExit(128 + signum)


def main(argv: Sequence[str] | None = None) -> int:
    """Run a subcommand; a package error prints one line and a non-zero status
    (``--debug``: the traceback instead)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in argv
    args = parser().parse_args([a for a in argv if a != "--debug"])
    main_thread = threading.current_thread() is threading.main_thread()
    old = signal.signal(signal.SIGTERM, _terminate) if main_thread else None
    try:
        return args.func(args)
    except KeyboardInterrupt:
        if debug:
            raise
        print("dyntorsion: interrupted; finished results are kept in the store", file=sys.stderr)
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


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
