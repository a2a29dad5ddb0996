"""``dyntorsion buckle --contact``: a buckling scene followed past self-contact
(:mod:`dyntorsion.beyond.contact`; with ``--store`` read from or written to the store as a
``contact-run`` record, :mod:`dyntorsion.studies.contact_runs`), its result with the
checks, each reading beside its bound (:mod:`dyntorsion.beyond.contact.checks`),
and ``--json`` for every buckle run: one JSON object."""

from __future__ import annotations

import argparse

from ..beyond.contact.checks import verdict
from ..beyond.contact.run import Contact, ContactScene, run_contact_scene
from ..buckling.scene import Scene
from ..store.results import UnsavedResultError
from ..studies.contact_runs import contact_run
from .cli_rtol import result_json

__all__ = ["add_contact_options", "buckle_contact"]


def add_contact_options(b: argparse.ArgumentParser) -> None:
    """The options of ``buckle`` that run past contact and print JSON."""
    g = b.add_argument_group("past self-contact (dyntorsion.beyond.contact)")
    g.add_argument(
        "--contact",
        action="store_true",
        help="run through self-contact to --t-end with a penalty contact law (the run "
        "otherwise stops at the first self-contact)",
    )
    d = Contact()
    g.add_argument("--contact-stiffness", type=float, default=d.stiffness,
                   help=f"penalty stiffness per length k [N/m^2] (default {d.stiffness:g})")  # fmt: skip
    g.add_argument("--contact-damping", type=float, default=d.damping,
                   help=f"damping ratio of the contact (default {d.damping:g})")  # fmt: skip
    g.add_argument("--contact-min-arc", type=float, default=d.min_arc,
                   help="parts of the rod closer than this along it never touch, in diameters "
                   f"(default {d.min_arc:g}; PyElastica's RodSelfContact skips about 1.5)")  # fmt: skip
    g.add_argument("--contact-max-step", type=float, default=d.max_step,
                   help="implicit contact: the longest step near contact [s] (default "
                   f"{d.max_step:g}; the scene's step elsewhere)")  # fmt: skip
    g.add_argument("--contact-max-cell-bend", type=float, default=d.max_cell_bend,
                   help="stop as under-resolved once a cell holds more bending than this "
                   f"[rad] (default {d.max_cell_bend:g})")  # fmt: skip
    g.add_argument("--contact-lagged", action="store_true",
                   help="the contact lagged one step (the first cut; step cut to "
                   "omega_c dt <= 0.5) instead of inside the implicit step")  # fmt: skip
    g.add_argument("--viscous", type=float, default=0.0,
                   help="linear viscous damping of the velocity per length [N s/m^2] (default 0)")  # fmt: skip
    g.add_argument("--viscous-moment", type=float, default=0.0,
                   help="linear viscous damping of the spin per length [N s] (default 0)")  # fmt: skip
    b.add_argument("--json", action="store_true", help="print the result as one JSON object")


def buckle_contact(args: argparse.Namespace, scene: Scene) -> int:
    """Run ``scene`` past contact; print the result (JSON with ``--json``); exit status 1
    when the run did not reach its end (a passage or a Newton failure)."""
    if args.t_end is None:
        raise ValueError("--contact needs --t-end T [s]: how long to follow the rod past contact")
    if args.rtol is not None:
        raise ValueError("--contact runs the scene's own grid; --rtol chooses grids: give one")
    if args.until != "contact":
        raise ValueError(
            f"--contact follows the rod through self-contact to --t-end; --until {args.until} "
            "ends the run before it: give one"
        )
    contact = Contact(
        stiffness=args.contact_stiffness, damping=args.contact_damping, viscous=args.viscous,
        min_arc=args.contact_min_arc,
        viscous_moment=args.viscous_moment,
        implicit=not args.contact_lagged, max_step=args.contact_max_step,
        max_cell_bend=args.contact_max_cell_bend,
    )  # fmt: skip
    cs = ContactScene(scene, contact)
    unsaved = None
    if getattr(args, "store", None):
        try:
            record, cached = contact_run(cs, args.store, on_stale=args.on_stale)
        except UnsavedResultError as err:  # printed below, then the error
            record, cached, unsaved = err.result, False, err
        result = {**record["summary"], "cached": cached}
    else:
        result = run_contact_scene(cs).result()
    result["checks"] = verdict(result)
    _print(args, result)
    if unsaved is not None:
        raise unsaved
    return 0 if result["stopped"] == "t_end" else 1


def _print(args: argparse.Namespace, result: dict) -> None:
    if args.json:
        print(result_json(result))
    else:
        for key in ("scene", "stopped", "dt_run", "first_contact_t", "max_penetration_over_D",
                    "contact_sites", "plectoneme_turns", "link_turns", "twist_turns", "writhe_turns",
                    "max_link_gap_turns", "max_cell_bend", "energy_residual",
                    "energy_residual_scheme"):  # fmt: skip
            print(f"{key:<24} {result[key]}")
        for c in result["checks"]["checks"]:
            r = c["reading"]
            reading = f"{r:.4g}" if isinstance(r, float) else str(r).split(":")[0]
            print(f"check: {c['name']:<22} {reading:<24} bound {c['bound']!s:<6} "
                  f"{'met' if c['met'] else 'NOT met'}")  # fmt: skip
