"""The command line: ``dyntorsion buckle``, ``sweep``, ``linear``, ``fit``.

``python -m dyntorsion ...`` is the same program.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

import numpy as np

from . import __version__, fidelity
from .buckling import Perturbation, critical_twist, fit_power_law
from .fidelity import LEVELS
from .results import ON_STALE
from .rod import Rod
from .sweep import DATA, PRESETS, Scene, cached, run_scene, run_sweep


def _level(name: str) -> str:
    try:
        return fidelity.check_level(name)
    except ValueError as err:
        raise argparse.ArgumentTypeError(str(err)) from None


def _scene_options(p: argparse.ArgumentParser, kappa0: float) -> None:
    g = p.add_argument_group("scene")
    g.add_argument("--kappa0", type=float, default=kappa0, help="initial twist [1/m]")
    g.add_argument("--rho", type=float, default=1500.0, help="density [kg/m^3] (Table 1: 1500)")
    g.add_argument("--E", type=float, default=1.25e7, help="Young's modulus [Pa]")
    g.add_argument("--nu", type=float, default=0.25, help="Poisson's ratio")
    g.add_argument("--D", type=float, default=1e-3, help="diameter [m]")
    g.add_argument("--L", type=float, default=1.0, help="length [m]")
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
        help=f"grid preset ({', '.join(LEVELS)}; dyntorsion.fidelity); overrides --n-cells/--dt/--lam-*",
    )
    g.add_argument("--n-cells", type=int, default=100, help="cells along the rod")
    g.add_argument("--dt", type=float, default=0.005, help="time step [s]")
    g.add_argument("--lam-s", type=float, default=-1.0, help="lambda_inf in space, [-1, 0]")
    g.add_argument("--lam-t", type=float, default=-1.0, help="lambda_inf in time, [-1, 0]")
    g.add_argument(
        "--t-end",
        type=float,
        default=None,
        help="end time [s] (default: 3x the paper's delay, eqs 33-34)",
    )


def _scene(args: argparse.Namespace, a: float) -> Scene:
    rod = Rod(E=args.E, nu=args.nu, D=args.D, L=args.L, rho=args.rho)
    seed = Perturbation(magnitude=args.seed, form=args.seed_form, location=args.seed_location)
    grid = fidelity.get(
        "buckling",
        args.fidelity
        or fidelity.Fidelity(args.n_cells, args.dt, lam_s=args.lam_s, lam_t=args.lam_t),
    )
    return Scene(
        a=a, kappa0=args.kappa0, rod=rod, seed=seed, t_end=args.t_end, **grid.simulate_kwargs()
    )


def _rates(text: str) -> list[float]:
    """'0.1,0.4,1.6' or 'geom:0.05:16:12' (12 rates spaced logarithmically)."""
    if text.startswith("geom:"):
        lo, hi, n = text[5:].split(":")
        return [float(v) for v in np.geomspace(float(lo), float(hi), int(n))]
    return [float(v) for v in text.split(",") if v.strip()]


def _buckle(args: argparse.Namespace) -> int:
    scene = _scene(args, args.a)
    if args.store:
        table = run_sweep([scene], args.store, on_stale=args.on_stale, progress=False)
        row = table.iloc[0].to_dict()
    else:
        row = run_scene(scene)
    kc = critical_twist(scene.rod)
    print(f"scene      {scene.label()}")
    print(f"stopped    {row['stopped']}")
    if row["t_c"] is None or (isinstance(row["t_c"], float) and np.isnan(row["t_c"])):
        print("no onset detected before the run ended")
        return 1
    print(f"t_c        {row['t_c']:.4f} +- {row['uncertainty_t']:.4f} s")
    print(
        f"kappa3     {row['kappa3']:.4f} +- {row['uncertainty_kappa3']:.4f} 1/m "
        f"(static kappa_cri = {kc:.4f})"
    )
    return 0


def _sweep_scenes(args: argparse.Namespace) -> list[Scene]:
    if args.preset:
        if args.rates:
            raise SystemExit("give either --preset or --rates, not both")
        return [sc for name in args.preset for sc in PRESETS[name]()]
    if not args.rates:
        raise SystemExit("give --rates (e.g. 0.1,0.4,1.6 or geom:0.05:16:12) or --preset")
    return [_scene(args, a) for a in _rates(args.rates)]


def _print_fit(table) -> None:
    ok = table.dropna(subset=["kappa3"])
    for _, grp in ok.groupby("family", sort=False):
        grp = grp.loc[~grp["a"].round(9).duplicated()]
        if len(grp) < 4:
            continue
        rho, k0, seed, n, dt = grp.iloc[0][["rho", "kappa0", "seed", "n_cells", "dt"]]
        rod = Rod(rho=rho)
        for mode in ("static", None):
            f = fit_power_law(grp["a"], grp["kappa3"], rod, kappa_cri=mode, n_boot=500)
            tag = "kappa_cri fixed" if mode else "kappa_cri free "
            print(
                f"fit rho={rho:g} kappa0={k0:g} seed={seed:g} N={n} dt={dt:g} {tag}: "
                f"b = {f.b:.2f} +- {f.b_err:.2f}, sigma = {f.sigma:.4f} +- {f.sigma_err:.4f}, "
                f"kappa_cri = {f.kappa_cri:.4f} +- {f.kappa_cri_err:.4f} "
                "(paper: b = 160.60, sigma = 0.5680)"
            )


def _log(message: str) -> None:
    from tqdm.auto import tqdm

    tqdm.write(message, file=sys.stderr)


def _sweep(args: argparse.Namespace) -> int:
    scenes = _sweep_scenes(args)
    executor, client, cluster = None, None, None
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
        "rho",
        "seed",
        "n_cells",
        "dt",
        "t_c",
        "kappa3",
        "uncertainty_kappa3",
        "cached",
    ]
    with np.printoptions(precision=4):
        print(table[cols].to_string(index=False, float_format=lambda v: f"{v:.5g}"))
    _print_fit(table)
    return 0


def _linear(args: argparse.Namespace) -> int:
    from . import linear_stability as LS

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
    table = cached(args.preset, args.store)
    _print_fit(table)
    return 0


def _linear_presets() -> list[str]:
    from .linear_stability import PRESETS as LINEAR

    return list(LINEAR)


def parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="dyntorsion", description=__doc__.splitlines()[0])
    p.add_argument("--version", action="version", version=f"dyntorsion {__version__}")
    sub = p.add_subparsers(dest="command", required=True)

    b = sub.add_parser("buckle", help="one buckling scene: print t_c and kappa3")
    b.add_argument("--a", type=float, required=True, help="loading rate [rad/(m s)]")
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
    s.add_argument("--store", default=str(DATA), help="cache folder (default: data/scenes)")
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
        help="linear-stability predictions of the onset (dyntorsion.linear_stability; cached)",
    )
    lin.add_argument(
        "--preset",
        action="append",
        required=True,
        choices=sorted(_linear_presets()),
        help="a named set of predictions (repeatable)",
    )
    lin.add_argument("--store", default=str(DATA), help="cache folder (default: data/scenes)")
    lin.add_argument("--jobs", type=int, default=1, help="local worker processes")
    lin.add_argument("--on-stale", choices=ON_STALE, default="recompute")
    lin.add_argument("--quiet", action="store_true", help="no log")
    lin.set_defaults(func=_linear)

    f = sub.add_parser("fit", help="fit eq (33) to a cached preset sweep")
    f.add_argument("--preset", choices=sorted(PRESETS), default="fig10")
    f.add_argument("--store", default=str(DATA))
    f.set_defaults(func=_fit)
    return p


def main(argv: Sequence[str] | None = None) -> int:
    args = parser().parse_args(argv)
    try:
        return args.func(args)
    except ValueError as err:
        print(f"dyntorsion: error: {err}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
