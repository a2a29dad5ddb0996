"""Prebuckling torsional waves (section 5).

While the rod is straight only kappa = k3 and omega = w3 are nonzero and eq (6)
reduces to the reduced moment balance and the reduced compatibility equation ::

    rho J omega_t = G J kappa_s,      kappa_t = omega_s,                (eq 22)

i.e. the wave equation kappa_tt = c^2 kappa_ss with c = sqrt(G / rho).  This
module holds

* the 2-field model :class:`Torsion` for the generalised-alpha engine ("model
  only what a scene requires");
* the three initial-boundary-value problems of the section -- linear loading
  (eq 23, solution eq 25), instantaneous release (eq 26, solution eq 27) and
  smooth release (eq 28, solution eq 29) -- as :class:`LinearLoading`,
  :class:`InstantRelease`, :class:`SmoothRelease`;
* their exact series in NumPy (vectorised) and in mpmath, summed as a
  :class:`Series` says (``Series(precise=True)``: mpmath), with a term count or a
  tolerance on a rigorous truncation bound; in mpmath without a term count, the
  whole series at any parameters (:mod:`.reference`:
  chi-function tails, eq 29's Duhamel integrals by one shared rule and an
  expansion by parts);
* their closed-form d'Alembert solutions (travelling fronts with reflections),
  in NumPy or mpmath (``digits=``), an independent check of the series;
* the smooth transition functions f of Fig 5 (:class:`ExpQuartic`, the default,
  and the fully flat :class:`FlatBlend`);
* :func:`solve`, which runs a problem on the engine.

Eigenvalues of all three problems: sqrt(lambda_n) = (2n - 1) pi / (2L).
"""

from .checks import (
    DEFAULT_DIGITS,
    DEFAULT_TOL,
    DEFAULT_TOL_DUHAMEL,
    DEFAULT_TOL_PRECISE,
    FIELDS,
    MAX_DUHAMEL_WORK,
    MAX_IMAGES,
    MAX_TERMS,
    MAX_TERMS_DUHAMEL,
    MP_BUDGET_S,
    MP_TERM_S,
    Series,
    sqrt_lambda,
)
from .dalembert import instant_release_dalembert, linear_loading_dalembert, smooth_release_dalembert
from .problems import InstantRelease, LinearLoading, Problem, SmoothRelease, WaveSolution, solve
from .series import (
    instant_release_bound,
    instant_release_exact,
    linear_loading_bound,
    linear_loading_exact,
    smooth_release_bound,
    smooth_release_exact,
)
from .torsion import Torsion
from .transitions import (
    DEFAULT_TRANSITION,
    CustomTransition,
    ExpQuartic,
    FlatBlend,
    Transition,
    smoothing,
)

__all__ = [
    "CustomTransition",
    "DEFAULT_DIGITS",
    "DEFAULT_TOL",
    "DEFAULT_TOL_DUHAMEL",
    "DEFAULT_TOL_PRECISE",
    "DEFAULT_TRANSITION",
    "ExpQuartic",
    "FIELDS",
    "FlatBlend",
    "InstantRelease",
    "LinearLoading",
    "MAX_DUHAMEL_WORK",
    "MAX_IMAGES",
    "MAX_TERMS",
    "MAX_TERMS_DUHAMEL",
    "MP_BUDGET_S",
    "MP_TERM_S",
    "Problem",
    "Series",
    "SmoothRelease",
    "Torsion",
    "Transition",
    "WaveSolution",
    "instant_release_bound",
    "instant_release_dalembert",
    "instant_release_exact",
    "linear_loading_bound",
    "linear_loading_dalembert",
    "linear_loading_exact",
    "smooth_release_bound",
    "smooth_release_dalembert",
    "smooth_release_exact",
    "smoothing",
    "solve",
    "sqrt_lambda",
]
