"""The number of plectoneme turns of a centreline: how many times the
two strands of a plectoneme wind round each other.

A plectoneme is the rod folded back on itself at its tip, its two strands in contact
and wound round their common axis; the strands are symmetric about the fold, so node i of
one strand lies against node j = k - i of the other, k = i + j fixed (twice the fold).
The touching pairs (|r_j - r_i| < ``touch`` D, the arc between them longer than
``min_arc`` D) vote for k: the fold is the k with most touching pairs within +- D / 2 of
arc.  Along the strand, from the first to the last touching pair of that fold, the vector
d = r_j - r_i between the strands turns round the plectoneme's local axis a = t_i - t_j
(the strands' tangents t, antiparallel, so their difference points along the axis); the
plectoneme turns are the angle d turns through, in the plane normal to a, unwrapped
along the strand, over 2 pi.  For two helices of radius D / 2 about a straight axis wound
n times round each other this gives n (tests).

It reads a centreline alone, so PyElastica's final shape and dyntorsion's are counted by
one rule.  The tip loop and the tails are not counted: only where the strands touch.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["Plectoneme", "plectoneme_turns"]


class Plectoneme(NamedTuple):
    """turns: signed winding of the strands [turns] (0 when no run of contact pairs);
    pairs: the number of node pairs in the run; strand: (i_first, i_last, j_first, j_last)
    the nodes of the run (-1 when none)."""

    turns: float
    pairs: int
    strand: tuple[int, int, int, int]


def plectoneme_turns(
    r: np.ndarray, diameter: float, min_arc: float = 3.0, touch: float = 1.1
) -> Plectoneme:
    """The plectoneme turns of the centreline ``r`` (N+1, 3), nodes equally spaced
    (module docstring).  ``min_arc``: pairs closer along the rod than that many diameters
    never count; ``touch``: the largest centre distance of a touching pair, in diameters."""
    r = np.asarray(r, dtype=float)
    if r.ndim != 2 or r.shape[1] != 3 or r.shape[0] < 3:
        raise ValueError(f"r of shape {r.shape}: need (N+1, 3) with N >= 2")
    if not diameter > 0 or not min_arc >= 0 or not touch > 0:
        raise ValueError(
            f"diameter={diameter!r}, min_arc={min_arc!r}, touch={touch!r} must be > 0, >= 0, > 0"
        )
    ds = np.linalg.norm(np.diff(r, axis=0), axis=1).mean()
    gap = max(1, int(np.ceil(min_arc * diameter / ds)))
    n1 = r.shape[0]
    dist = np.linalg.norm(r[:, None, :] - r[None, :, :], axis=2)
    i_all, j_all = np.nonzero(np.triu(dist < touch * diameter, k=gap))
    if i_all.size == 0:
        return Plectoneme(0.0, 0, (-1, -1, -1, -1))
    votes = np.bincount(i_all + j_all, minlength=2 * n1)
    w = max(1, int(round(0.5 * diameter / ds)))
    k = int(np.argmax(np.convolve(votes, np.ones(2 * w + 1), mode="same")))
    i = np.arange(n1)
    j = k - i
    ok = (j > i + gap) & (j < n1)
    touching = np.zeros(n1, bool)
    touching[ok] = dist[i[ok], j[ok]] < touch * diameter
    if touching.sum() < 2:
        return Plectoneme(0.0, int(touching.sum()), (-1, -1, -1, -1))
    first, last = np.flatnonzero(touching)[[0, -1]]
    i = np.arange(first, last + 1)
    j = k - i
    t = np.gradient(r, axis=0)
    axis = t[i] - t[j]
    axis /= np.linalg.norm(axis, axis=1)[:, None]
    d = r[j] - r[i]
    d -= np.sum(d * axis, axis=1)[:, None] * axis
    d /= np.linalg.norm(d, axis=1)[:, None]
    a_mid = axis[1:] + axis[:-1]
    a_mid /= np.linalg.norm(a_mid, axis=1)[:, None]
    sin = np.sum(np.cross(d[:-1], d[1:]) * a_mid, axis=1)
    cos = np.sum(d[:-1] * d[1:], axis=1)
    turns = float(np.sum(np.arctan2(sin, cos)) / (2.0 * np.pi))
    return Plectoneme(turns, int(i.size), (int(i[0]), int(i[-1]), int(j[0]), int(j[-1])))
