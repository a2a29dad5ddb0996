"""Command-line options that describe a scene (rod, section, load, history, ends,
seed, grid, scheme) and their translation into a :class:`~dyntorsion.buckling.scene.Scene`."""

from __future__ import annotations

import argparse
from dataclasses import replace

import numpy as np

from ..buckling.loading import (
    AXIAL_LOADS,
    DISTRIBUTED_LOADS,
    ENDS,
    HISTORIES,
    AxialLoad,
    Polynomial,
    RampHold,
    Tabulated,
)
from ..buckling.scene import UNTIL, Scene
from ..buckling.seed import SEED_FORMS, STATED, Perturbation
from ..buckling.slender import check_slender
from ..buckling.turning import TurnHold
from ..model.rod import TABLE1, Rod
from ..studies import fidelity
from ..studies.fidelity import LEVELS
from ..studies.pacing import STEPS, TOL, paced
from ..studies.presets import PRESET_CONTROL
from .plugins import build


def parse_numbers(text: str, n: int | None, what: str) -> list[float]:
    """Comma-separated numbers of the option ``what`` (exactly ``n`` of them unless None)."""
    try:
        vals = [float(v) for v in text.split(",")]
    except ValueError:
        raise ValueError(f"{what}={text!r} must be comma-separated numbers") from None
    if n is not None and len(vals) != n:
        raise ValueError(f"{what}={text!r} must hold {n} numbers (got {len(vals)})")
    return vals


def level_type(name: str) -> str:
    """``--fidelity``: a level of :data:`dyntorsion.studies.fidelity.LEVELS` (the old names refused)."""
    try:
        return fidelity.check_level(name)
    except ValueError as err:
        raise argparse.ArgumentTypeError(str(err)) from None


def registered(registry: dict, option: str):
    """An argparse type: a name of ``registry`` (read when the option is parsed, after
    ``--plugin`` has added a user's own)."""

    def check(name: str) -> str:
        if name not in registry:
            raise argparse.ArgumentTypeError(
                f"{option} {name!r}; registered: {', '.join(sorted(registry))} "
                "(--plugin FILE adds a user's own)"
            )
        return name

    return check


def add_scene_options(p: argparse.ArgumentParser, kappa0: float) -> None:
    """The rod, section, load, history, ends, seed, grid and scheme options of a scene
    (``kappa0`` is the subcommand's default pretwist)."""
    p.add_argument(
        "--plugin",
        action="append",
        default=[],
        metavar="FILE_OR_MODULE",
        help="import a Python file or module first (repeatable): its histories, loads, seed "
        "forms and end sets join the registered ones",
    )
    g = p.add_argument_group("rod (default: Table 1)")
    g.add_argument(
        "--rho", type=float, default=TABLE1["rho"], help="density [kg/m^3] (%(default)s)"
    )
    g.add_argument(
        "--E", type=float, default=TABLE1["E"], help="Young's modulus [Pa] (%(default)s)"
    )
    g.add_argument("--nu", type=float, default=TABLE1["nu"], help="Poisson's ratio (%(default)s)")
    g.add_argument("--L", type=float, default=TABLE1["L"], help="length [m] (%(default)s)")
    sec = g.add_mutually_exclusive_group()
    sec.add_argument(
        "--D", type=float, default=None, help=f"diameter of a circle [m] ({TABLE1['D']:g})"
    )
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
        "(sum C_k t^k), 'table:FILE' (two columns t, kappa; t from 0); rotation control with "
        "--ends clamped-turned: 'turn-hold:TURNS,T_TURN[,TAU]' (s = 0 turned by TURNS in "
        "T_TURN s, then held; --kappa0 the pretwist); any registered kind as "
        "'KIND:name=value,...' (its constructor's keywords; --a and --kappa0 fill a and kappa0; "
        "';' separates the numbers of a sequence)",
    )
    g.add_argument("--tension", type=float, default=0.0, help="axial end load [N], > 0 tension")
    g.add_argument("--tension-rate", type=float, default=0.0, help="its rate [N/s]")
    g.add_argument(
        "--load",
        action="append",
        default=[],
        metavar="KIND:name=value,...",
        help="an axial end load (instead of --tension) or a distributed load of a registered "
        "kind, built from its constructor's keywords (repeatable)",
    )
    g.add_argument(
        "--ends",
        type=registered(ENDS, "--ends"),
        default="clamped",
        help=f"end conditions: {', '.join(sorted(ENDS))} or a plugin's (clamped: eq 30)",
    )
    g = p.add_argument_group("seed and grid")
    g.add_argument(
        "--seed",
        type=float,
        default=STATED,
        help="perturbation magnitude (N/m uniform, N for --seed-form point)",
    )
    g.add_argument(
        "--seed-form",
        type=registered(SEED_FORMS, "--seed-form"),
        default="uniform",
        help=f"{', '.join(sorted(SEED_FORMS))} or a plugin's",
    )
    g.add_argument("--seed-location", type=float, default=0.5, help="point seed position [m]")
    g.add_argument(
        "--fidelity",
        type=level_type,
        default=None,
        help=f"grid preset ({', '.join(LEVELS)}; dyntorsion.studies.fidelity), its time step scaled to the rod; "
        "instead of --n-cells/--dt/--lam-*",
    )
    for option, kind, default, what in GRID_OPTIONS:
        g.add_argument(option, type=kind, default=None, help=f"{what} ({default})")
    g.add_argument(
        "--control",
        action="store_true",
        help="step-size control: retry a failed step with smaller ones and follow the rod to "
        "self-contact (genalpha.StepControl; the presets always use it)",
    )
    g.add_argument(
        "--paced",
        type=int,
        nargs="?",
        const=STEPS,
        default=None,
        metavar="STEPS",
        help=f"time step = the fast-estimated onset time / STEPS (default {STEPS}), Newton tol "
        f"{TOL:g} (dyntorsion.studies.pacing; overrides the time step of --dt and --fidelity); ramps "
        "at clamped ends without axial load",
    )
    g.add_argument(
        "--until",
        choices=UNTIL,
        default="contact",
        help="contact: follow the whip to self-contact (default); first-peak: end once "
        "|u3(L)| has passed its first peak (the same onset, without the whip)",
    )
    g.add_argument(
        "--t-end",
        type=float,
        default=None,
        help="end time [s] (default for the ramp at clamped ends: 3x the paper's delay, eqs 33-34)",
    )


def rod_from(args: argparse.Namespace) -> Rod:
    """The rod of the options: Table 1's by default, or a section or explicit properties."""
    if args.properties:
        B1, B2, C, rhoA, r1, r2, r3, t = parse_numbers(args.properties, 8, "--properties")
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
        a, b = parse_numbers(args.ellipse, 2, "--ellipse")
        return Rod.elliptic(a=a, b=b, **mat)
    if args.rectangle:
        w, h = parse_numbers(args.rectangle, 2, "--rectangle")
        return Rod.rectangular(w=w, h=h, **mat)
    return Rod(D=TABLE1["D"] if args.D is None else args.D, **mat)


def _ramp(args, a, rest):
    if rest:
        raise ValueError(f"--history ramp:{rest}: the ramp takes --a and --kappa0")
    return {"a": a, "kappa0": args.kappa0}


def _ramp_hold(args, a, rest):
    vals = parse_numbers(rest.replace(":", ","), None, "--history ramp-hold:HOLD[:TAU]")
    if len(vals) not in (1, 2):
        raise ValueError("--history ramp-hold:HOLD[:TAU] takes one or two numbers")
    return {"history": RampHold(a, vals[0], args.kappa0, *vals[1:])}


def _poly(args, a, rest):
    return {"history": Polynomial(tuple(parse_numbers(rest, None, "--history poly")))}


def _turn_hold(args, a, rest):
    vals = parse_numbers(rest, None, "--history turn-hold:TURNS,T_TURN[,TAU]")
    if len(vals) not in (2, 3):
        raise ValueError("--history turn-hold:TURNS,T_TURN[,TAU] takes two or three numbers")
    return {"history": TurnHold(*vals, pretwist=args.kappa0)}


def _table(args, a, rest):
    try:
        t, k = np.loadtxt(rest, delimiter=None, unpack=True, ndmin=2)
    except (OSError, ValueError) as err:
        raise ValueError(
            f"--history table:{rest}: cannot read two columns t, kappa ({err})"
        ) from None
    return {"history": Tabulated(tuple(t), tuple(k))}


#: the short forms of ``--history``: (parser, whether it takes the rate --a)
SHORT_HISTORIES = {
    "ramp": (_ramp, True),
    "ramp-hold": (_ramp_hold, True),
    "poly": (_poly, False),
    "turn-hold": (_turn_hold, False),
    "table": (_table, False),
}


def history_from(args: argparse.Namespace, a: float | None) -> dict:
    """Scene keywords for the end twist: a and kappa0 (the ramp) or a history; a short
    form of :data:`SHORT_HISTORIES`, or ``KIND:name=value,...`` of any registered kind."""
    kind, _, rest = args.history.partition(":")
    if kind in SHORT_HISTORIES and "=" not in rest:
        parse, rated = SHORT_HISTORIES[kind]
        if rated and a is None:
            raise ValueError(f"--history {kind} needs the loading rate --a")
        if not rated and a is not None:
            raise ValueError(
                f"--history {kind}: --a and --rates set the rate of a ramp, and this history "
                "fixes its own end twist; drop --a/--rates, or use --history ramp or ramp-hold"
            )
        return parse(args, a, rest)
    defaults = {"kappa0": args.kappa0, **({} if a is None else {"a": a})}
    hist = build(HISTORIES, "history", args.history, "--history", defaults)
    if a is not None and getattr(hist, "a", None) != a:
        raise ValueError(
            f"--history {args.history}: --a and --rates set the rate a, which {kind} does not "
            "take; drop --a/--rates"
        )
    return Scene.twist_keywords(hist)


def loads_from(args: argparse.Namespace) -> dict:
    """Scene keywords for ``--tension``/``--tension-rate`` and every ``--load``: the
    axial end load and the distributed loads, each a registered kind."""
    axial, spread = [], []
    for text in args.load:
        kind = text.partition(":")[0]
        if kind in AXIAL_LOADS and kind in DISTRIBUTED_LOADS:
            raise ValueError(
                f"--load {text!r}: kind {kind!r} is both an axial and a distributed load"
            )
        if kind in AXIAL_LOADS:
            axial.append(build(AXIAL_LOADS, "axial load", text, "--load"))
        else:
            registry = {**AXIAL_LOADS, **DISTRIBUTED_LOADS}
            spread.append(build(registry, "load", text, "--load"))
    if len(axial) > 1 or (axial and (args.tension or args.tension_rate)):
        raise ValueError(
            "--load: one axial end load at most, and not with --tension/--tension-rate"
        )
    tension = axial[0] if axial else AxialLoad(args.tension, args.tension_rate)
    return {"tension": tension, "loads": tuple(spread)}


#: the grid's options: option, type, default, what it sets (``--fidelity`` sets all four)
GRID_OPTIONS = (
    ("--n-cells", int, 100, "cells along the rod"),
    ("--dt", float, 0.005, "time step [s]"),
    ("--lam-s", float, -1.0, "lambda_inf in space, [-1, 0]"),
    ("--lam-t", float, -1.0, "lambda_inf in time, [-1, 0]"),
)


def grid_options(args: argparse.Namespace) -> dict:
    """``n_cells``, ``dt``, ``lam_s`` and ``lam_t`` as given, else their defaults; with
    ``--fidelity`` none may be given (it sets them all: one would be ignored)."""
    given = [o for o, *_ in GRID_OPTIONS if getattr(args, o[2:].replace("-", "_")) is not None]
    if getattr(args, "fidelity", None) and given:
        raise ValueError(
            f"--fidelity {args.fidelity} sets the grid and the scheme; {', '.join(given)} "
            "would be ignored: give one or the other"
        )
    return {
        o[2:].replace("-", "_"): (
            v if (v := getattr(args, o[2:].replace("-", "_"))) is not None else d
        )
        for o, _, d, _ in GRID_OPTIONS
    }


def scene_from(args: argparse.Namespace, a: float | None) -> Scene:
    """The :class:`~dyntorsion.buckling.scene.Scene` the options describe, at the loading rate ``a``
    (the grid of ``--fidelity`` scaled to the rod; ``--control`` adds step-size control;
    ``--paced`` sets the step by :func:`~dyntorsion.studies.pacing.paced`); a rod too thick
    for the thin-rod model is refused (:func:`~dyntorsion.buckling.slender.check_slender`)."""
    rod = rod_from(args)
    check_slender(rod)  # a rod too thick for the thin-rod model: refused before any grid
    seed = Perturbation(magnitude=args.seed, form=args.seed_form, location=args.seed_location)
    options = grid_options(args)  # refuses --fidelity with any of them
    grid = fidelity.get("buckling", args.fidelity or fidelity.Fidelity(**options), rod=rod)
    kwargs = grid.simulate_kwargs()
    if args.control:
        kwargs["scheme"] = replace(kwargs["scheme"], control=PRESET_CONTROL)
    scene = Scene(
        rod=rod,
        seed=seed,
        t_end=args.t_end,
        **loads_from(args),
        ends=args.ends,
        until=args.until,
        **history_from(args, a),
        **kwargs,
    )
    return scene if args.paced is None else paced(scene, steps=args.paced)


def parse_rates(text: str) -> list[float]:
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
    rates = parse_numbers(text, None, "--rates") if text.strip(", ") else []
    if not rates:
        raise ValueError(f"--rates {text!r} holds no rate (e.g. 0.1,0.4,1.6 or geom:0.05:16:12)")
    return rates
