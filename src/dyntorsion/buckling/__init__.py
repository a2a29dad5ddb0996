"""Section 6: torsional buckling.

* :mod:`.scene` -- a :class:`~.scene.Scene` is everything one buckling run depends on (rod,
  ends, end-twist history, axial load, seed, grid, scheme); :func:`~.scene.run_scene` runs it;
* :mod:`.loading` -- end-twist histories (the ramp of eq 30 and others) and axial loads;
* :mod:`.turning` -- rotation control: the end turned by a prescribed angle (:class:`~.turning.TurnHold`);
* :mod:`.seed` -- the perturbative force that seeds buckling;
* :mod:`.simulation` -- the 12-field rod under eq (30), integrated by the engine of section 3;
* :mod:`.stops` -- compiled stop tests: self-contact, crossing, the first peak;
* :mod:`.run` -- a run's traces and snapshots, and its shapes (section 4);
* :mod:`.onset`, :mod:`.onset_rules` -- the onset of buckling read from u3(L, t);
* :mod:`.postbuckling` -- after the onset: energy, curvature, localisation;
* :mod:`.statics` -- the static critical twist, eqs (31)-(32);
* :mod:`.delay_law` -- the delay law, eqs (33)-(34), fitted to a rate sweep.
"""

from .chebyshev import critical_twist_numerical
from .delay_law import PowerLawFit, fit_power_law
from .onset import STATUSES, Onset, check_window, classify_onset, detect_onset
from .run import BucklingRun
from .scene import run_scene
from .seed import Perturbation
from .simulation import GridWarning, check_grid, simulate
from .spec import Scene
from .statics import M_CRI_MP, critical_moment, critical_twist, m_cri

__all__ = [
    "M_CRI_MP",
    "m_cri",
    "critical_moment",
    "critical_twist",
    "critical_twist_numerical",
    "Perturbation",
    "BucklingRun",
    "Scene",
    "run_scene",
    "simulate",
    "GridWarning",
    "check_grid",
    "Onset",
    "detect_onset",
    "check_window",
    "classify_onset",
    "STATUSES",
    "PowerLawFit",
    "fit_power_law",
]
