"""One value per fact: the numbers several pages show, computed and rounded once."""

import math

import pytest

from dyntorsion.app import facts as F
from dyntorsion.app import glance
from dyntorsion.studies.presets import cached


def test_percent_two_significant_figures_signed():
    assert glance.percent(-0.0038863) == "−0.39 %"
    assert glance.percent(2.886e-5) == "+0.0029 %"  # T: not "0 %"
    assert glance.percent(-0.3) == "−30 %"
    assert glance.percent(0.0) == "0 %"
    with pytest.raises(ValueError, match="rel=nan"):
        glance.percent(math.nan)


def test_ended_reads_the_time_from_the_record():
    assert F.ended("self-contact at t = 22.09 s (segments 38 and 95)") == (
        "self-contact at t = 22.09 s"
    )
    assert F.ended("failed: no convergence", 3.14159) == "Newton failure at t = 3.14 s"
    assert F.ended("t_end", 40.0) == "end of the run, t = 40.00 s"
    with pytest.raises(ValueError, match="names no time; give t_last"):
        F.ended("t_end")
    assert F.fixed(-0.001) == "0.00"


def test_facts_are_the_records_and_the_glance_tables_values():
    f = F.facts()
    rows = cached("fig08-09-tiny-seed").set_index("rho")
    assert f["fig8_tiny_tc"] == f"{rows.loc[1500.0, 't_c']:.2f}"
    assert f["fig9_tiny_tc"] == f"{rows.loc[5000.0, 't_c']:.2f}"
    assert f["fig8_tiny_ended"].startswith("self-contact at t = ")
    # the at-a-glance table shows the same t_c, relative difference, b and sigma
    t = glance.compact()
    tiny = t[t["seed [N/m]"] == "10⁻¹⁷"].set_index("quantity")
    assert tiny.loc["Fig 8: $t_c$", "ours"] == f["fig8_tiny_tc"]
    assert tiny.loc["Fig 8: $t_c$", "difference"] == f["fig8_tiny_rel"]
    assert tiny.loc["$b$, eq (34)", "ours"] == f["fig10_tiny_b"]
    assert tiny.loc["$\\sigma$, eq (34)", "ours"] == f["fig10_tiny_sigma"]
    assert tiny.loc["Fig 10: $\\kappa_3(a\\to 0)$", "ours"] == f["fig10_tiny_kcfree"]
    static = t[t["seed [N/m]"] == "–"].set_index("quantity")
    assert static.loc["$T=4L/c$", "difference"] == f["T1_rel"] == "+0.0029 %"
