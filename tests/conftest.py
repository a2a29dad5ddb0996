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


@pytest.fixture(scope="session")
def current_record():
    """``load(record, source)``: the committed record ``data/<record>`` written by the
    module ``source`` (``dyntorsion.studies.contact.<name>``) or by ``benchmarks/<source>``,
    asserted current (``why_stale`` says why not)."""
    import json
    from pathlib import Path

    from dyntorsion.store.fingerprint import why_stale

    root = Path(__file__).resolve().parents[1]

    def load(record: str, source: str) -> dict:
        rec = json.loads((root / "data" / record).read_text())
        where = source if source.startswith("dyntorsion.") else root / "benchmarks" / source
        stale = why_stale(rec["code"], where)
        assert stale is None, f"data/{record}: {stale}"
        return rec

    return load


@pytest.fixture
def rng():
    return np.random.default_rng(20261121)


@pytest.fixture(scope="session", autouse=True)
def _committed_data_untouched():
    """No test writes into the committed store data/scenes: a stale record must make a
    test fail, never be recomputed in place (tests use temporary stores to write)."""
    from pathlib import Path

    store = Path(__file__).resolve().parents[1] / "data" / "scenes"

    def state():
        # in-flight atomic writes (".*.tmp") come and go: only records count
        if not store.is_dir():
            return {}
        return {p.name: p.stat().st_mtime_ns for p in store.glob("*") if not p.name.startswith(".")}

    before = state()
    yield
    after = state()
    changed = sorted(n for n in after.keys() | before.keys() if after.get(n) != before.get(n))
    assert not changed, f"tests wrote into {store}: {changed[:5]}"
