"""Shared test set-up: floating-point errors raise, random seeds are fixed, and the
hypothesis profile is chosen by ``$DYNTORSION_HYPOTHESIS``: ``fast`` (default, `make
test`: few examples, derandomised) or ``long`` (`make test-all`: many, random)."""

from __future__ import annotations

import os

import numpy as np
import pytest
from hypothesis import HealthCheck, settings

settings.register_profile(
    "fast",
    max_examples=20,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much],
)
settings.register_profile(
    "long",
    max_examples=300,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much],
)
settings.load_profile(os.environ.get("DYNTORSION_HYPOTHESIS", "fast"))


@pytest.fixture(autouse=True)
def _strict_floating_point():
    old = np.seterr(all="raise", under="ignore")
    yield
    np.seterr(**old)


@pytest.fixture
def rng():
    return np.random.default_rng(20261121)
