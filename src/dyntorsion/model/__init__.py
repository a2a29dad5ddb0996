"""Section 2 and Table 1: the rod and the body-frame Cosserat system.

* :mod:`.rod` -- the rod and its section (Table 1: E, nu, rho, r, L; G, A, I, J, B, C, c);
* :mod:`.system` -- what the engine needs of any first-order model, eq (7)
  ``M y_t + K y_s + F(y) + q = 0``, and the boundary rows at its ends;
* :mod:`.cosserat` -- the 12 fields of eq (6), their load vector F and its Jacobian;
* :mod:`.ends` -- which fields each end prescribes (eq 30 and other end sets).

Nothing here imports a later section.
"""

from .cosserat import FIELDS, IDX, TERMS, Cosserat, load_jacobian, load_vector
from .rod import Rod
from .system import Boundary, System

__all__ = [
    "FIELDS",
    "IDX",
    "TERMS",
    "Cosserat",
    "load_vector",
    "load_jacobian",
    "Rod",
    "System",
    "Boundary",
]
