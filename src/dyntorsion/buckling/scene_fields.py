"""The checks of a :class:`~dyntorsion.buckling.spec.Scene`'s fields that are not numbers:
which kind of object each holds, and the model switches in their canonical form."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from ..genalpha import Newton, Scheme
from ..model.rod import Rod
from .seed import Perturbation

__all__ = ["TYPED", "canonical_terms", "public"]


def public(kind: type) -> str:
    """The name a user imports ``kind`` by (``dyntorsion.Rod``, ...)."""
    return f"dyntorsion.{kind.__name__}" if kind is Rod else f"{kind.__module__}.{kind.__name__}"


#: the fields of a :class:`Scene` that hold one kind of object (None is not one of them)
TYPED = {"rod": Rod, "seed": Perturbation, "scheme": Scheme, "newton": Newton}


def canonical_terms(terms: Any) -> tuple[tuple[str, float], ...]:
    """Model switches as a sorted tuple of (name, weight); a name given twice is refused
    (it would be keyed as one weight and simulated with another)."""
    try:
        pairs = [(k, v) for k, v in (terms.items() if isinstance(terms, Mapping) else terms)]
    except (TypeError, ValueError):
        raise TypeError(f"terms={terms!r} must be a mapping or pairs (name, weight)") from None
    names = [str(k) for k, _ in pairs]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise ValueError(f"terms: switch(es) {twice} given more than once")
    out = []
    for k, v in pairs:
        try:
            w = float(v)
        except (TypeError, ValueError):
            raise ValueError(f"terms[{k!r}]={v!r} must be a number (a weight, 1 = on)") from None
        if not math.isfinite(w):
            raise ValueError(f"terms[{k!r}]={v!r} must be a finite weight")
        out.append((str(k), w))
    return tuple(sorted(out))
