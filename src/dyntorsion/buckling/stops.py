"""The stop tests of the buckling scene (:func:`~dyntorsion.buckling.simulation.simulate`), compiled
(:class:`~dyntorsion.genalpha.watch.CompiledStop`): the march consults them itself at
every check level, so a run checked at every step does not return to Python at every
step.

* Self-contact: two non-neighbouring parts of the centreline (spatial route of
  section 4, :func:`~dyntorsion.shapes.shape`) closer than the rod's thickness, or,
  checked at every level, a pair of segments that passed through each other since the
  previous level (:func:`~dyntorsion.shapes.crossing`).  A centreline whose tangent
  turns by less than :data:`STRAIGHT` in all (``ds sum_j |kappa_perp|``) keeps points an
  arc length l apart at least l cos(pi/6) > l/2 apart: no contact, nothing computed.
* First peak: ``|u3(L, t)|``, having reached u_ref = L / T0, has fallen below
  :data:`~dyntorsion.buckling.onset.PEAK_FALL` of its running maximum.
"""

from __future__ import annotations

import numpy as np

from .. import shapes
from .._numba import jit
from ..genalpha.march import norm_sum
from ..genalpha.watch import STOP_SIGNATURE, CompiledStop
from ..model.rod import Rod
from .onset import PEAK_FALL, reference_level

__all__ = ["STRAIGHT", "scene_stop", "scene_test"]

#: total bending turn ``ds * sum_j |kappa_perp|`` below which no self-contact can be
STRAIGHT = np.pi / 3

# params
_DS, _DIAMETER, _MIN_ARC, _U_REF, _FALL, _CONTACT, _PEAK, _EVERY_LEVEL = range(8)
# index: the fields k1, k2 (k3 follows k2) and u3
_K1, _K2, _U = range(3)
# state: code (0 going on, then one of the three below), previous centreline kept,
# distance, segments i and j, running maximum of |u3(L)|
_CODE, _HAS_PREVIOUS, _DISTANCE, _I, _J, _MAX = range(6)
_TOUCH, _CROSSED, _PEAKED = 1.0, 2.0, 3.0


@jit(signature=STOP_SIGNATURE)
def scene_test(y, watch):
    """Whether the buckling scene stops at the level y (see the module docstring)."""
    p, st, work, ix = watch.params, watch.state, watch.work, watch.index
    n1 = y.shape[0]
    if p[_CONTACT] != 0.0:
        if norm_sum(y, ix[_K1 : _K2 + 1], p[_DS]) < STRAIGHT:
            st[_HAS_PREVIOUS] = 0.0
        else:
            R = work[: 9 * n1].reshape((n1, 3, 3))
            r = work[9 * n1 : 12 * n1].reshape((n1, 3))
            previous = work[12 * n1 : 15 * n1].reshape((n1, 3))
            frame0 = work[15 * n1 : 15 * n1 + 9].reshape((3, 3))
            k = ix[_K1]  # k1, k2, k3 side by side
            shapes.shape_kernel(y[:, k : k + 3], p[_DS], frame0, R, r)
            d, i, j = shapes.self_contact_kernel(r, p[_DIAMETER], p[_MIN_ARC])
            if i >= 0 and d < p[_DIAMETER]:
                st[_CODE], st[_DISTANCE], st[_I], st[_J] = _TOUCH, d, i, j
                return True
            ci, cj = -1, -1
            if st[_HAS_PREVIOUS] != 0.0:
                ci, cj = shapes.crossing_kernel(previous, r, p[_DIAMETER], p[_MIN_ARC])
            if p[_EVERY_LEVEL] != 0.0:
                previous[:] = r
                st[_HAS_PREVIOUS] = 1.0
            else:
                st[_HAS_PREVIOUS] = 0.0
            if ci >= 0:
                st[_CODE], st[_I], st[_J] = _CROSSED, ci, cj
                return True
    if p[_PEAK] != 0.0:
        u = abs(y[n1 - 1, ix[_U]])
        if u >= p[_U_REF] or st[_MAX] > 0.0:
            st[_MAX] = max(st[_MAX], u)
            if u < p[_FALL] * st[_MAX]:
                st[_CODE] = _PEAKED
                return True
    return False


def _reason(t: float, st: np.ndarray) -> str:
    code = st[_CODE]
    i, j = int(st[_I]), int(st[_J])
    if code == _TOUCH:
        return (
            f"self-contact at t = {t:.6g} s (segments {i} and {j}, distance {st[_DISTANCE]:.3g} m)"
        )
    if code == _CROSSED:
        return (
            f"self-contact at t = {t:.6g} s (segments {i} and {j} passed through each "
            "other since the previous level)"
        )
    return f"first peak of |u3(L)| passed at t = {t:.6g} s"


def scene_stop(
    system, rod: Rod, n_cells: int, *, contact: bool, first_peak: bool, every_level: bool
) -> CompiledStop:
    """The stop of one buckling run: at self-contact (``contact``; crossings too when
    the run is checked at ``every_level``) and/or after the first peak of ``|u3(L)|``."""
    n1 = n_cells + 1
    params = np.zeros(8)
    params[_DS], params[_DIAMETER] = rod.L / n_cells, rod.thickness
    params[_MIN_ARC] = 2.0 * rod.thickness  # shapes' default: never neighbouring segments
    params[_U_REF], params[_FALL] = reference_level(rod), PEAK_FALL
    params[_CONTACT], params[_PEAK] = float(contact), float(first_peak)
    params[_EVERY_LEVEL] = float(every_level)
    index = np.array([system.index("k1"), system.index("k2"), system.index("u3")], np.int64)
    if system.index("k3") != index[_K2] + 1:
        raise ValueError("the contact test reads k1, k2, k3 as consecutive fields")
    work = np.zeros(15 * n1 + 9)  # frames, centreline, previous centreline, left frame
    work[15 * n1 :] = np.eye(3).ravel()
    return CompiledStop(scene_test, params, np.zeros(6), work, _reason, index)
