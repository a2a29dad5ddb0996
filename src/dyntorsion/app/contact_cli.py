"""``dyntorsion buckle --contact``: a buckling scene followed past self-contact (issue 33,
:mod:`dyntorsion.beyond.contact`), and ``--json`` for every buckle run: one JSON object."""

from __future__ import annotations

import argparse
import json
import math
from typing import Any

import numpy as np

from ..beyond.contact.run import Contact, ContactScene, run_contact_scene
from ..buckling.scene import Scene

__all__ = ["add_contact_options", "buckle_contact", "print_json"]


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
    g.add_argument("--viscous", type=float, default=0.0,
                   help="linear viscous damping of the velocity per length [N s/m^2] (default 0)")  # fmt: skip
    b.add_argument("--json", action="store_true", help="print the result as one JSON object")


def _clean(value: Any) -> Any:
    """JSON-ready: numpy scalars as numbers, NaN and inf as null."""
    if isinstance(value, dict):
        return {str(k): _clean(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_clean(v) for v in value]
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def print_json(row: dict[str, Any]) -> None:
    print(json.dumps(_clean(row), sort_keys=True))


def buckle_contact(args: argparse.Namespace, scene: Scene) -> int:
    """Run ``scene`` past contact; print the result (JSON with ``--json``); exit status 1
    when the run did not reach its end (a passage or a Newton failure)."""
    if args.t_end is None:
        raise ValueError("--contact needs --t-end T [s]: how long to follow the rod past contact")
    contact = Contact(
        stiffness=args.contact_stiffness, damping=args.contact_damping, viscous=args.viscous
    )
    result = run_contact_scene(ContactScene(scene, contact)).result()
    if args.json:
        print_json(result)
    else:
        for key in ("scene", "stopped", "dt_run", "first_contact_t", "max_penetration_over_D",
                    "contact_sites", "link_turns", "twist_turns", "writhe_turns",
                    "max_link_gap_turns", "energy_residual"):  # fmt: skip
            print(f"{key:<24} {result[key]}")
    return 0 if result["stopped"] == "t_end" else 1
