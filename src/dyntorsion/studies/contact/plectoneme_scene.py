"""The plectoneme scene of PyElastica's example (``RodSelfContact/PlectonemesCase``): the
numbers both codes run, in SI units, kept in one place.

The rod: length ``LENGTH`` [m], radius ``RADIUS`` [m], mass ``MASS`` [kg], Young's modulus
``E`` [Pa] and shear modulus ``SHEAR`` = E / 1.5 [Pa] (Poisson's ratio -0.25), on
``N_ELEM`` elements in PyElastica.  The loading: one end turned by ``TURNS`` turns in
``T_TWIST`` [s] at a constant rate, then held for ``T_HOLD`` [s].  The matched comparison
(``benchmarks/plectoneme_matched.py``, :mod:`.contact_roundoff`) follows both codes from
rest to ``T_STAR`` [s], dyntorsion with the time step ``DYN_DT`` [s].
"""

from __future__ import annotations

__all__ = ["TURNS", "T_TWIST", "T_HOLD", "LENGTH", "RADIUS", "MASS", "E", "SHEAR", "N_ELEM",
           "T_STAR", "DYN_DT"]  # fmt: skip

TURNS = 10
T_TWIST = 5.0 * TURNS
T_HOLD = 50.0
LENGTH, RADIUS, MASS, E = 1.0, 0.025, 1.0, 1e6
SHEAR = E / 1.5
N_ELEM = 150
T_STAR = 20.0
DYN_DT = 0.02
