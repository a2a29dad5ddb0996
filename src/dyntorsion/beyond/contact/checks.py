"""The checks of a run past contact, each with its bound, in one place.

A run past contact (:func:`~.run.run_contact_scene`, ``dyntorsion buckle --contact``) is
within the issue's bounds when

* it reached its end time (no passage of the rod through itself, no failed Newton solve,
  not stopped as under-resolved);
* its deepest overlap stayed within 1 % of the diameter;
* link = twist + writhe held to 0.01 turns at every check (Călugăreanu-White-Fuller);
* its energy budget closes to 1 % of the work done, the scheme's numerical dissipation on
  its own line (``energy_residual_scheme``, :mod:`.budget`).

:func:`checks` reads each from a run's result and says what it read, against what bound,
and whether the bound is met; :func:`verdict` is the same as one JSON-ready dict (what
``dyntorsion buckle --contact --json`` prints under ``checks``).  The pages and tests read
the bounds from :data:`BOUNDS`, so each has one value everywhere.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass
from typing import Any

__all__ = ["BOUNDS", "Check", "checks", "verdict"]

#: the issue's bounds: the deepest overlap over D, |Lk - Tw - Wr| [turns], and what the
#: scheme's energy lines leave over the work done
BOUNDS: dict[str, float] = {"overlap": 0.01, "link": 0.01, "energy": 0.01}
#: the fields of a run's result the checks read
_READ = ("stopped", "max_penetration_over_D", "max_link_gap_turns", "energy_residual_scheme")


@dataclass(frozen=True)
class Check:
    """One check of a run: its ``name``, what it reads (``quantity``, the result's field),
    the ``reading`` (None where the run has none), the ``bound`` it is held to and whether
    it is ``met``."""

    name: str
    quantity: str
    reading: float | str | None
    bound: float | str
    met: bool


def _at_most(value: Any, bound: float) -> bool:
    return value is not None and math.isfinite(float(value)) and abs(float(value)) <= bound


def checks(result: Mapping[str, Any]) -> tuple[Check, ...]:
    """The checks of the module docstring on ``result`` (a run's result dict:
    :meth:`~.run.ContactRun.result`, or a record's copy of it)."""
    missing = [k for k in _READ if k not in result]
    if missing:
        raise KeyError(f"result has no {', '.join(missing)}: not the result of a run past contact")
    stopped = str(result["stopped"])
    overlap = result["max_penetration_over_D"]
    gap = result["max_link_gap_turns"]
    energy = result["energy_residual_scheme"]
    return (
        Check("reached its end", "stopped", stopped, "t_end", stopped == "t_end"),
        Check("overlap", "max_penetration_over_D", overlap, BOUNDS["overlap"],
              _at_most(overlap, BOUNDS["overlap"])),
        Check("link = twist + writhe", "max_link_gap_turns", gap, BOUNDS["link"],
              _at_most(gap, BOUNDS["link"])),
        Check("energy budget", "energy_residual_scheme", energy,
              BOUNDS["energy"], _at_most(energy, BOUNDS["energy"])),
    )  # fmt: skip


def verdict(result: Mapping[str, Any]) -> dict[str, Any]:
    """:func:`checks` as one JSON-ready dict: ``met`` (every check met), ``unmet`` (the
    names of those that are not) and ``checks`` (each with its reading and bound)."""
    cs = checks(result)
    return {
        "met": all(c.met for c in cs),
        "unmet": [c.name for c in cs if not c.met],
        "checks": [asdict(c) for c in cs],
    }
