"""The Cosserat rod of section 2 with linear viscous damping per unit length (for
comparisons with damped references): the balances of eq (7) gain

    linear momentum   ... + gamma_u u = 0,      angular momentum   ... + gamma_w w = 0

(a force -gamma_u u [N/m] and a moment -gamma_w w [N m/m] per length, body frame), inside
the implicit step with its Jacobian (a lagged damping force is unstable in the scheme
already at gamma_u dt / rho A ~ 0.16: measured on the a = 16 scene, N = 50, dt = 3.7e-4 s,
gamma_u = 0.5 N s/m^2 failed at t = 0.73 s, 0.05 ran).  The kernels add the two terms to
those of :mod:`dyntorsion.model.cosserat`, which is left as it is (a scene without damping
runs the very same model).
"""

from __future__ import annotations

import numpy as np

from ..._numba import jacobian_kernel, load_kernel
from ...model.cosserat import FIELDS, Cosserat, load_jacobian, load_vector
from ...model.system import System

__all__ = ["damped_system"]

#: where the two damping coefficients sit in the parameter vector (after Cosserat's)
_GU, _GW = 15, 16


@load_kernel
def damped_load_vector(y, p, out):
    """F(y) of eq (7) (:func:`~dyntorsion.model.cosserat.load_vector`, which reads p[:15])
    plus gamma_u u in the linear and gamma_w w in the angular momentum rows."""
    load_vector(y, p, out)
    for i in range(3):
        out[i] += p[_GU] * y[i]
        out[3 + i] += p[_GW] * y[3 + i]


@jacobian_kernel
def damped_load_jacobian(y, p, out):
    """dF/dy of :func:`damped_load_vector`."""
    load_jacobian(y, p, out)
    for i in range(3):
        out[i, i] += p[_GU]
        out[3 + i, 3 + i] += p[_GW]


def damped_system(model: Cosserat, gamma_u: float, gamma_w: float) -> System:
    """The engine's system of ``model`` with the damping (module docstring)."""
    params = np.concatenate([model.params, [float(gamma_u), float(gamma_w)]])
    return System.from_model(
        model, names=FIELDS, F=damped_load_vector, dF=damped_load_jacobian, params=params
    )
