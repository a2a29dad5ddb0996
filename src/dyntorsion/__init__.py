"""dyntorsion: dynamic torsional buckling of elastic rods.

A replication of *Dynamic torsional buckling: prebuckling waves and delayed
instability*: the body-frame Cosserat rod (section 2), the generalised-alpha
method in space and time (section 3), rod shapes (section 4), prebuckling
torsional waves (section 5) and delayed buckling (section 6).
"""

from __future__ import annotations

from ._version import __version__
from .model.rod import Rod

__all__ = ["Rod", "__version__"]
