"""Stepping: how the steps of a chunk of levels are taken.  The compiled march
(:mod:`.march`) at the fixed step; with ``scheme.control`` step-size control
(:mod:`.control`) instead; with ``scheme.long_steps`` long steps first while the solution
is quiet (:mod:`.long`); with a state-dependent source its own steps (:mod:`.state_steps`).  Each returns the number of levels it completed and, if a step's
Newton solve failed, the :class:`~.newton.ConvergenceError` that says when and why."""

from __future__ import annotations

from typing import Any

import numpy as np

from .control import Adaptive
from .long import LongPhase
from .march import Halt, Recording, march
from .newton import REASONS, ConvergenceError, Status
from .plan import Plan, RunParts
from .state_steps import StateSteps

__all__ = ["Stepper"]


class Stepper:
    """The steppers of one run, sharing its factors and work arrays: ``parts`` is the
    run's :class:`~.plan.RunParts`; ``state`` a :class:`~.state.StateSource` of its sources,
    or None."""

    def __init__(self, parts: RunParts, state=None) -> None:
        self.system, self.levels, self.ctx = parts.system, parts.levels, parts.ctx
        scheme = parts.scheme
        self.coupled = None
        if state is not None:
            self.coupled = StateSteps(state, parts)
        self.adaptive = None
        if scheme.control is not None:
            self.adaptive = Adaptive(scheme.control, parts)
        self.long = None
        if scheme.long_steps is not None:
            self.long = LongPhase(scheme.long_steps, parts)

    def end(self, k0: int, k1: int, plan: Plan) -> tuple[int, bool]:
        """Where the chunk from level k0 ends (at most k1), and whether in long steps."""
        if self.long is not None and self.long.active:
            k_long = self.long.end(k0, k1, plan.landing(k0))
            if k_long is not None:
                return k_long, True
        return k1, False

    def long_chunk(self, k0, k1, plan, stats, rec_t, rec_vals) -> int:
        """Long steps from k0 to at most k1; the levels completed (recorded as reached)."""
        return self.long.chunk(k0, k1, self.levels, plan, stats, rec_t, rec_vals) - k0

    def chunk(
        self, k0: int, k1: int, rec: Recording, stats: np.ndarray, gate, test, watch, times
    ) -> tuple[int, ConvergenceError | None]:
        """Steps from level k0 to k1 at the fixed step (or under step control, or with a
        state-dependent source)."""
        if self.coupled is not None:
            return self.coupled.chunk(k0, k1)
        if self.adaptive is not None:
            return self.adaptive.chunk(k0, k1, rec, stats, gate, test, watch)
        completed, outcome = march(
            self.system.F, self.system.dF, test, self.ctx,
            self.levels.forcing(slice(k0, k1 + 1)), rec, Halt(gate, watch), stats,
        )  # fmt: skip
        failure = None
        if completed < k1 - k0 and outcome.status != Status.CONVERGED:
            failure = ConvergenceError(
                float(times[k0 + completed + 1]),
                k0 + completed + 1,
                outcome.corrections,
                outcome.residual,
                REASONS.get(Status(outcome.status), "unknown")
                + " (also after a retry from the other predictor with a fresh Jacobian)",
            )
        return completed, failure

    def substeps(self, done: int) -> np.ndarray:
        """The steps accepted on each interval of the fixed grid."""
        base = (
            np.ones(done, np.int64)
            if self.adaptive is None
            else self.adaptive.substeps[:done].copy()
        )
        return base if self.long is None else self.long.substeps(base)

    def summary(self, done: int) -> dict[str, Any]:
        """What step control and long steps did, for the run's ``meta``."""
        return {
            **({} if self.coupled is None else {"state": self.coupled.summary()}),
            **({} if self.adaptive is None else {"control": self.adaptive.summary(done)}),
            **({} if self.long is None else {"long_steps": self.long.summary()}),
        }

    @property
    def reason(self) -> str | None:
        """Why a state-dependent source ended the run (None: it did not)."""
        return None if self.coupled is None else self.coupled.reason

    @property
    def rejections(self) -> list:
        return [] if self.adaptive is None else list(self.adaptive.rejections)
