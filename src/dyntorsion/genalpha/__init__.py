"""The generalised-alpha method in space and time (section 3).

The engine integrates any first-order system on a uniform grid s_j = j ds,
j = 0..N, and time levels t_i = t_0 + i dt, ::

    M y_t + K y_s + F(y) + q(s, t) = 0,                                   (eq 7)

with nb_left boundary rows ``P_L y(0, t) = g_L(t)`` and nb_right rows
``P_R y(L, t) = g_R(t)``, nb_left + nb_right = number of fields.  It knows
nothing about rods: a model supplies M, K, F, dF/dy (compiled) and its scales.

Discretisation.  Substituting eq (11) into eq (10) with the parameters of
eq (13) (for which beta + gamma = 1, hence zeta = 0 in eq 12) gives, for the
cell between nodes j-1 and j, ::

    M [(1-a_s) abar_j + a_s abar_{j-1}]
      + K [(1-b_t)(y_j^i - y_{j-1}^i) + b_t (y_j^{i-1} - y_{j-1}^{i-1})] / ds
      + <F>_j = 0,

    abar = (1-a_t) y_t^i + a_t y_t^{i-1}
         = (1-a_t)/(g_t dt) (y^i - y^{i-1}) + [a_t - (1-a_t)(1-g_t)/g_t] y_t^{i-1},

where ``<F>_j`` is the load vector averaged over the four corners of the cell
with weights (1-b_t, b_t) x (1-b_s, b_s) -- the generalised trapezoidal rule of
eq (9), the paper's choice -- or F at the equally weighted state -- the
generalised midpoint rule.  The source q is always corner-averaged.  Note that
the spatial derivative needs no history (zeta = 0): only y_t^{i-1} is carried,
and at lambda_t = -1 its coefficient vanishes as well.

Each step is a nonlinear system for y^i at all nodes, solved by a damped Newton
method in the spirit of NLEQ1 (scaled corrections, natural monotonicity test,
damping, Jacobian reuse), on the almost-block-diagonal Jacobian (``_abd``).

Where each part lives:

* :mod:`.scheme` -- the parameters of eq (13) and the step's coefficients;
* :mod:`.system` -- the model (M, K, F, dF, scales) and the boundary rows of eq (7);
* :mod:`.discrete` -- the residual of eq (10)-(12), its Jacobian and LU factors;
* :mod:`.abd` -- the almost-block-diagonal LU of that Jacobian;
* :mod:`.newton` -- the damped Newton solve of one step;
* :mod:`.march` -- the compiled time march and the rate update of eq (11);
* :mod:`.stepping` -- how a chunk of levels is stepped (fixed, controlled or long);
* :mod:`.control` -- step-size control: rejected steps retried with half the step;
* :mod:`.long` -- long steps while the solution is quiet;
* :mod:`.state`, :mod:`.state_steps`, :mod:`.low_rank` -- sources that depend on the
  state (contact): their Jacobian in the band and in rank-one terms, and their steps;
* :mod:`.watch`, :mod:`.stopping` -- stop tests, compiled or in Python;
* :mod:`.parts` -- the parts of a run: problem, grid, sources, output, stops;
* :mod:`.guard` -- checks before a run: its time grid, memory and duration;
* :mod:`.integrate` -- the driver (validation, sources, initial rate, chunks between
  checks), with :mod:`.plan` (its bookkeeping), :mod:`.recording` and :mod:`.run`
  (the :class:`Run` it returns);
* :mod:`.initial` -- consistent initial rates and states.
"""

from ..model.system import Boundary, System
from .discrete import Constants, Work
from .initial import algebraic_residual, consistent_initial_state, consistent_rates
from .integrate import integrate, newton_iteration_kernel
from .newton import ConvergenceError, Newton, Outcome, Status
from .parts import Grid, Output, Problem, Sources, Stops
from .run import Run
from .scheme import (
    QUADRATURES,
    Coefficients,
    LongSteps,
    Scheme,
    SchemeWarning,
    StepControl,
    parameters,
)

__all__ = [
    "parameters",
    "Scheme",
    "SchemeWarning",
    "StepControl",
    "LongSteps",
    "System",
    "Boundary",
    "Newton",
    "ConvergenceError",
    "Run",
    "integrate",
    "Problem",
    "Grid",
    "Sources",
    "Output",
    "Stops",
    "consistent_rates",
    "algebraic_residual",
    "consistent_initial_state",
    "newton_iteration_kernel",
    "Status",
    "Outcome",
    "Coefficients",
    "Constants",
    "Work",
    "QUADRATURES",
]
