"""The consistency map's fits and claims (dyntorsion.studies.claims) on data with known answers."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from hypothesis import given
from hypothesis import strategies as st

from dyntorsion import Rod
from dyntorsion.buckling.statics import critical_twist
from dyntorsion.published import value
from dyntorsion.studies import claims as C
from dyntorsion.studies.consistency import LADDER

KC = critical_twist(Rod.paper())


def paper_kappa3(a, b=None, sigma=None, rho=1500.0):
    rod = Rod(rho=rho)
    b = value("b") if b is None else b
    sigma = value("sigma") if sigma is None else sigma
    return KC + b / rod.L * (np.asarray(a) * rod.L / rod.c) ** sigma


def test_rate_ranges_are_every_contiguous_run_of_four_or_more():
    ranges = C.rate_ranges(LADDER)
    n = len(LADDER)
    assert len(ranges) == sum(n - k + 1 for k in range(C.MIN_RATES, n + 1))
    assert (LADDER[0], LADDER[-1]) in ranges
    assert all(LADDER.index(hi) - LADDER.index(lo) >= C.MIN_RATES - 1 for lo, hi in ranges)


def test_the_papers_law_reproduces_its_own_predictions():
    """Eq (33) with b = 160.60, sigma = 0.5680 gives the paper's 20.11 s and 25.45 s: the
    fit of exact law data recovers b and sigma and those times to the stated digits."""
    a = np.array(LADDER)
    rng = np.random.default_rng(1)
    k = paper_kappa3(a) + 1e-4 * rng.standard_normal(a.size)
    cell = C.fit_cell(a, k)
    assert cell["b"] == pytest.approx(value("b"), rel=1e-4)
    assert cell["sigma"] == pytest.approx(value("sigma"), abs=1e-5)
    assert cell["law_fig8"] == pytest.approx(value("law_fig8"), abs=0.005)
    assert cell["law_fig9"] == pytest.approx(value("law_fig9"), abs=0.005)
    assert cell["m3"] < 1.0
    assert cell["kappa_cri_free"] == pytest.approx(KC, rel=1e-3)


def test_another_law_puts_the_papers_pair_outside_the_ellipse():
    a = np.array(LADDER[:8])
    rng = np.random.default_rng(2)
    k = paper_kappa3(a, b=110.0, sigma=0.45) + 0.01 * rng.standard_normal(a.size)
    cell = C.fit_cell(a, k)
    assert cell["b"] == pytest.approx(110.0, rel=0.02)
    assert cell["m3"] > 1.0


def _ladder_table(seeds, kappa3_of, rules=("window 10-50 %",)):
    rows = []
    for seed in seeds:
        for rule in rules:
            for a in LADDER:
                rows.append(
                    {
                        "seed": seed,
                        "form": "uniform",
                        "rule": rule,
                        "a": a,
                        "rho": 1500.0,
                        "kappa0": 10.0,
                        "status": "buckled",
                        "kappa3": kappa3_of(a, seed),
                        "t_c": (kappa3_of(a, seed) - 10) / a,
                    }
                )
    return pd.DataFrame(rows)


def test_at_seed_interpolates_in_log_seed_and_refuses_gaps():
    def k(a, seed):
        return 12.0 + a - 0.1 * math.log10(seed)

    t = _ladder_table([1e-12, 1e-10, 1e-8], k)
    mid = C.at_seed(t, 1e-9).set_index("a").kappa3
    assert np.allclose(mid.to_numpy(), [k(a, 1e-9) for a in mid.index])
    assert C.at_seed(t, 1e-14).kappa3.isna().all()
    t.loc[(t.seed == 1e-8) & (t.a == 1.0), "status"] = "forced"
    gap = C.at_seed(t, 1e-9).set_index("a").kappa3
    assert math.isnan(gap[1.0]) and gap.drop(1.0).notna().all()


def test_seed_for_fig8_inverts_the_direct_onsets():
    seeds = [1e-20, 1e-18, 1e-16, 1e-14]
    direct = pd.DataFrame(
        [
            {
                "seed": s,
                "form": "uniform",
                "rule": "threshold",
                "rho": rho,
                "a": 1.6,
                "kappa0": 0.0,
                "status": "buckled",
                "t_c": 10.0 - 0.7 * math.log10(s),
            }
            for s in seeds
            for rho in (1500.0, 5000.0)
        ]
    )
    found = C.seed_for_fig8(direct).iloc[0]
    assert math.log10(found.seed) == pytest.approx((10.0 - value("fig8_tc")) / 0.7, abs=1e-12)
    assert math.isnan(C.seed_for_fig8(direct, target=100.0).iloc[0].seed)


def test_all_four_claims_hold_for_a_world_that_obeys_the_paper():
    """A synthetic world whose every onset obeys eq (34) and whose Fig 8 run is 20.86 s:
    the cell over the whole ladder holds all four claims; a wrong Fig 8 breaks claim 1."""
    noise = dict(
        zip(LADDER, 1e-4 * np.random.default_rng(3).standard_normal(len(LADDER)), strict=True)
    )
    table = _ladder_table([1e-12], lambda a, s: paper_kappa3(a) + noise[a])
    cells = C.fits(table)
    direct = pd.DataFrame(
        [
            {
                "seed": 1e-12,
                "form": "uniform",
                "rule": "window 10-50 %",
                "rho": rho,
                "a": 1.6,
                "kappa0": 0.0,
                "status": "buckled",
                "t_c": t,
            }
            for rho, t in ((1500.0, value("fig8_tc")), (5000.0, value("law_fig9")))
        ]
    )
    judged = C.misfits(cells, direct, grid_error=0.01)
    whole = judged[(judged.a_lo == LADDER[0]) & (judged.a_hi == LADDER[-1])].iloc[0]
    assert whole.holds, whole[["m1", "m2", "m3", "m4"]].to_dict()
    direct.loc[direct.rho == 1500.0, "t_c"] += 0.1
    assert not C.misfits(cells, direct, grid_error=0.01).holds.any()


def test_local_exponent_of_a_power_law():
    table = _ladder_table([1e-8], lambda a, s: KC + 3.0 * a**0.6)
    ex = C.local_exponents(table)
    assert len(ex) == len(LADDER) - 1
    assert np.allclose(ex.exponent, 0.6)


@given(
    x=st.floats(-20.0, -6.0),
    t=st.lists(st.floats(5.0, 50.0), min_size=3, max_size=8, unique=True),
)
def test_at_seed_interpolates_between_its_neighbours(x, t):
    """Any seed inside the tabulated ones: the value lies between the two tabulated
    neighbours' (linear in log10 seed); outside them it is NaN, never extrapolated."""
    seeds = 10.0 ** np.linspace(-20.0, -6.0, len(t))
    table = pd.DataFrame(
        {"form": "uniform", "rule": "threshold", "a": 1.0, "rho": 1500.0, "kappa0": 10.0}
        | {"seed": seeds, "t_c": t, "status": "buckled"}
    )
    v = float(C.at_seed(table, 10.0**x, "t_c").t_c.iloc[0])
    xs = np.log10(seeds)
    i = min(int(np.searchsorted(xs, x, side="right")), len(xs) - 1)
    lo, hi = sorted((t[max(i - 1, 0)], t[i]))
    assert lo - 1e-9 <= v <= hi + 1e-9
    assert math.isnan(float(C.at_seed(table, 1e-22, "t_c").t_c.iloc[0]))
    assert math.isnan(float(C.at_seed(table, 1e-4, "t_c").t_c.iloc[0]))
