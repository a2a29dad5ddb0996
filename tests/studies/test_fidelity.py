"""Fidelity presets: valid, ordered, and as accurate as the Accuracy and cost page says."""

from dataclasses import replace

import numpy as np
import pytest

from dyntorsion import Rod
from dyntorsion import waves as w
from dyntorsion.app.cli import main
from dyntorsion.studies import fidelity
from dyntorsion.studies import presets as P
from dyntorsion.studies import sweep as S
from dyntorsion.studies.fidelity import Fidelity


def test_levels_refine_monotonically():
    for scene, levels in fidelity.PRESETS.items():
        assert tuple(levels) == fidelity.LEVELS, scene
        grids = [levels[name] for name in fidelity.LEVELS]
        assert all(
            g1.n_cells < g2.n_cells and g1.dt > g2.dt
            for g1, g2 in zip(grids[:-1], grids[1:], strict=True)
        ), scene


@pytest.mark.parametrize(
    "kw, name",
    [
        ({"n_cells": 1, "dt": 0.01}, "n_cells"),
        ({"n_cells": 10, "dt": 0.0}, "dt"),
        ({"n_cells": 10, "dt": 0.01, "lam_t": 0.5}, "lam_t"),
        ({"n_cells": 10, "dt": 0.01, "lam_s": -1.5}, "lam_s"),
    ],
)
def test_bad_fidelity(kw, name):
    with pytest.raises(ValueError, match=name):
        Fidelity(**kw)


def test_get_and_environment(monkeypatch):
    own = Fidelity(80, 0.004)
    assert fidelity.get("buckling", own) is own
    assert fidelity.get("buckling", "fine") == Fidelity(200, 0.0025)
    with pytest.raises(ValueError, match="renamed: use 'fine'"):
        fidelity.get("buckling", "paper")
    monkeypatch.setenv("DYNTORSION_FIDELITY", "quick")
    assert fidelity.get("waves") == fidelity.PRESETS["waves"]["quick"]
    monkeypatch.setenv("DYNTORSION_FIDELITY", "fast")
    with pytest.raises(ValueError, match="DYNTORSION_FIDELITY"):
        fidelity.level()
    with pytest.raises(ValueError, match="scene="):
        fidelity.get("fig99", "quick")
    with pytest.raises(ValueError, match="fidelity="):
        fidelity.get("waves", "best")


def test_standard_buckling_is_the_grid_of_the_cached_sweeps():
    """The presets' grid is the standard level's (and their scheme adds step control)."""
    std = fidelity.get("buckling", "standard")
    for sc in P.preset("fig10"):
        expected = S.Scene(a=sc.a, seed=sc.seed, **std.simulate_kwargs())
        expected = replace(expected, scheme=replace(expected.scheme, control=P.PRESET_CONTROL))
        assert sc.params() == expected.params()


def test_cli_fidelity_flag(capsys):
    assert main(["buckle", "--a", "10", "--kappa0", "10", "--fidelity", "quick"]) == 0
    assert "N=50 dt=0.01" in capsys.readouterr().out
    assert main(["buckle", "--a", "10", "--lam-t", "0.5"]) == 2
    assert "lam_t" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["buckle", "--a", "10", "--fidelity", "paper"])
    assert "renamed: use 'fine'" in capsys.readouterr().err
    assert main(["buckle", "--a", "10", "--lam-t", "0.5"]) == 2
    assert "lam_t" in capsys.readouterr().err


# ------------------------------------------------------------------ measured accuracy
LIMITS = {"quick": 0.01, "standard": 0.005, "fine": 0.001}


@pytest.mark.parametrize("ladder", ["accuracy-fig08", "accuracy-fast"])
def test_buckling_presets_meet_their_accuracy(ladder):
    """t_c of each preset against the finest grid of the committed ladder (N = 400,
    dt = 0.00125): quick within 1 %, standard within 0.5 %, fine within 0.1 %."""
    table = P.cached(ladder)
    ref = table[(table.n_cells == 400) & (table.dt == 0.00125)]["t_c"].iloc[0]
    for name, limit in LIMITS.items():
        f = fidelity.get("buckling", name)
        row = table[(table.n_cells == f.n_cells) & (table.dt == f.dt)]
        assert abs(row["t_c"].iloc[0] / ref - 1) < limit, name


def test_wave_presets_converge_to_the_exact_release():
    """Smooth release (Fig 6 scene): the max error falls with each level, at order
    about 2 per halving of both steps."""
    rod = Rod()
    problem = w.SmoothRelease(10.0, 50.0)
    errs = []
    for name in fidelity.LEVELS:
        f = fidelity.get("waves", name)
        sol = w.solve(problem, rod=rod, times=[0.01], **f.solve_kwargs())
        exact = problem.exact(sol.s, 0.01, c=rod.c, L=rod.L, series=w.Series(terms=200))
        errs.append(float(sol.errors(exact[None, :])["max"][0]))
    assert errs[0] > errs[1] > errs[2]
    ratio = fidelity.get("waves", "standard").n_cells / fidelity.get("waves", "quick").n_cells
    order = np.log(errs[1] / errs[2]) / np.log(
        fidelity.get("waves", "fine").n_cells / fidelity.get("waves", "standard").n_cells
    )
    assert ratio == 2 and 1.7 < order < 2.3
