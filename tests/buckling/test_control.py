"""Step-size control (genalpha.control) and the three failure messages of the buckling scene."""

from dataclasses import replace

import numpy as np
import pytest

from dyntorsion import Rod
from dyntorsion import buckling as buckling
from dyntorsion import genalpha as ga
from dyntorsion.buckling.postbuckling import GridTooCoarseError, PostBucklingError
from dyntorsion.buckling.scene import Scene, simulate_scene
from dyntorsion.model.ends import Ends, IllPosedEndsError
from dyntorsion.verification import Manufactured, observed_orders

CONTROL = ga.Scheme(control=ga.StepControl())


def slope(h, err):
    return float(np.polyfit(np.log(h), np.log(err), 1)[0])


# ------------------------------------------------------------------ the option
def test_step_control_names_the_bad_parameter():
    with pytest.raises(ValueError, match="max_halvings"):
        ga.StepControl(max_halvings=0)
    with pytest.raises(ValueError, match="grow_after"):
        ga.StepControl(grow_after=0)
    with pytest.raises(ValueError, match="halvings"):
        ga.StepControl(max_halvings=3, refine=((0.0, 1.0, 4),))
    with pytest.raises(ValueError, match="t_start < t_end"):
        ga.StepControl(refine=((1.0, 0.5, 1),))
    with pytest.raises(TypeError, match="control"):
        ga.Scheme(control="adaptive")


def test_control_enters_the_cache_key_and_fixed_keys_do_not_change():
    fixed = Scene(a=1.6)
    assert "control" not in fixed.params()["scheme"]  # keys of fixed-step records unchanged
    ctl = ga.StepControl(max_halvings=6, refine=((1.0, 2.0, 2),))
    adaptive = Scene(a=1.6, scheme=ga.Scheme(control=ctl))
    p = adaptive.params()
    assert p["scheme"]["control"] == {"max_halvings": 6, "grow_after": 4, "refine": [[1.0, 2.0, 2]]}
    assert Scene.from_params(p).params() == p
    assert Scene.from_params(p).scheme == adaptive.scheme
    assert Scene.from_params(fixed.params()).params() == fixed.params()


# ------------------------------------------------------------------ accuracy
DIFFERENTIAL = ["u1", "u2", "u3", "w1", "w2", "w3", "k1", "k2", "k3"]


@pytest.mark.parametrize("lam_t", [-1.0, -0.5])
def test_variable_steps_keep_the_fixed_step_order(lam_t):
    """Manufactured 12-field solution; steps of dt, dt/2 and dt/8 in two refine windows.
    Time error (distance to a fixed-step run 16 x finer than the finest dt, same cells)
    falls at the fixed-step order.  For lam_t = -0.5 every field does (the rate history
    of eq 11 is carried across each change of step); at lam_t = -1 the differential
    fields do, while the internal forces n -- the multipliers of the constraints, on
    which the undamped trapezoidal rule leaves a (-1)^i error at each change of step --
    do not (see StepControl)."""
    m = Manufactured.random(amplitude=0.1, frequency=8.0)
    ys = m.model.scales()[0]
    T = 0.25 * m.model.rod.L / ys[0]
    fields = [m.model.system().index(f) for f in DIFFERENTIAL] if lam_t == -1.0 else slice(None)
    refine = ((0.2 * T, 0.45 * T, 1), (0.6 * T, 0.7 * T, 3))
    controlled = ga.Scheme(-1.0, lam_t, control=ga.StepControl(refine=refine))
    fixed = ga.Scheme(-1.0, lam_t)
    ref = m.solve(32, T / 4096, T, fixed).y
    dts = T / np.array([32, 64, 128, 256])
    err_var, err_fix = [], []
    for dt in dts:
        run = m.solve(32, dt, T, controlled)
        assert run.substeps.max() == 8 and run.substeps.min() == 1 and not run.rejections
        err_var.append(np.max(np.abs(run.y - ref)[:, fields] / ys[fields]))
        err_fix.append(np.max(np.abs(m.solve(32, dt, T, fixed).y - ref)[:, fields] / ys[fields]))
    assert slope(dts, err_var) >= 1.8
    assert slope(dts, err_var) == pytest.approx(slope(dts, err_fix), abs=0.15)


def test_constant_steps_with_control_are_bitwise_fixed_steps():
    """Nothing rejected, nothing refined: the controlled run is the fixed-step run."""
    m = Manufactured.random(amplitude=1.0)
    T = 0.25 * m.model.rod.L / m.model.scales()[0][0]
    fixed = m.solve(16, T / 40, T)
    ctl = m.solve(16, T / 40, T, CONTROL)
    assert not ctl.rejections and np.all(ctl.substeps == 1)
    assert np.array_equal(fixed.y, ctl.y) and np.array_equal(fixed.y_t, ctl.y_t)
    assert ctl.meta["control"] == {"accepted": 40, "rejected": 0, "smallest_dt": T / 40}


# ------------------------------------------------------------------ rejection and retry
def _whip(scheme, **run):
    sc = Scene(a=16.0, kappa0=10.0, n_cells=50, dt=0.01, scheme=scheme)
    return buckling.simulate(replace(sc, t_end=sc.duration()), progress=False, **run)


def test_rejected_steps_are_retried_with_smaller_steps():
    """The fixed-step run fails in the whip after buckling; the controlled run retries,
    gets further, records every rejection with its reason, and only then fails -- at
    dt_min, saying so (this grid is too coarse for the loops that form)."""
    with pytest.raises(PostBucklingError) as fixed:
        _whip(ga.Scheme(), check_every=1)
    assert fixed.value.dt is None and "Scheme(control=StepControl())" in str(fixed.value)
    with pytest.raises(PostBucklingError) as ctl:
        _whip(CONTROL)
    e = ctl.value
    assert e.t > fixed.value.t and e.dt == pytest.approx(0.01 / 2**10)
    assert "dt_min" in str(e) and f"dt={e.dt:.4g}" in str(e) and "post-buckling whip" in str(e)
    run = e.run
    assert len(run.rejections) >= 10 and run.substeps.max() > 1
    reasons = {r[2] for r in run.rejections}
    assert reasons <= {ga.newton.REASONS[s] for s in ga.Status if s in ga.newton.REASONS}
    n = fixed.value.run.t.size
    assert np.array_equal(run.traces["u3_end"][:n], fixed.value.run.traces["u3_end"])


def test_post_buckling_scene_runs_to_self_contact():
    """With control (contact checked every step) the fastest Fig 10 rate on the standard
    grid ends at self-contact, where the fixed-step run with its default checks fails."""
    sc = Scene(a=16.0, kappa0=10.0, n_cells=100, dt=0.005)
    fixed = simulate_scene(sc)
    assert fixed.stopped.startswith("failed") and "post-buckling whip" in fixed.stopped
    ctl = simulate_scene(Scene(a=16.0, kappa0=10.0, n_cells=100, dt=0.005, scheme=CONTROL))
    assert ctl.stopped.startswith("self-contact")
    assert buckling.detect_onset(ctl).t_c == buckling.detect_onset(fixed).t_c


# ------------------------------------------------------------------ three messages
def test_three_causes_three_messages():
    with pytest.raises(IllPosedEndsError, match="u3 prescribed at both ends"):
        Ends("both", ("k3", "u3", "w1", "w2", "u1", "u2"), ("u3", "w1", "w2", "w3", "u1", "u2"))
    rod = Rod()
    with pytest.warns(buckling.GridWarning), pytest.raises(GridTooCoarseError) as coarse:
        buckling.simulate(
            Scene(rod=rod, a=1000.0, n_cells=50, dt=20.0, t_end=200.0, kappa0=0.0), progress=False
        )
    assert "first 10 steps" in str(coarse.value) and "far too large" in str(coarse.value)
    assert coarse.value.step <= 10
    with pytest.raises(PostBucklingError, match="post-buckling whip") as whip:
        _whip(CONTROL)
    assert not isinstance(whip.value, GridTooCoarseError)


# ------------------------------------------------------------------ after the onset
def test_localisation_width():
    from dyntorsion.buckling.postbuckling import localisation_width

    s = np.linspace(0.0, 2.0, 201)
    assert localisation_width(s, np.ones_like(s)) == pytest.approx(0.5, abs=0.01)
    narrow = np.exp(-(((s - 0.7) / 0.01) ** 2))
    wide = np.exp(-(((s - 0.7) / 0.1) ** 2))
    assert localisation_width(s, narrow) < 0.2 * localisation_width(s, wide)
    # half the mass of a Gaussian lies within +-0.477 sigma*sqrt(2): width 0.954 * 0.1 / L
    assert localisation_width(s, wide) == pytest.approx(0.0954 / 2.0, abs=0.01)
    with pytest.raises(ValueError, match="share"):
        localisation_width(s, wide, share=1.0)


def test_contact_measures_of_a_run_to_contact():
    from dyntorsion.buckling.postbuckling import contact_measures

    run = simulate_scene(Scene(a=16.0, kappa0=10.0, n_cells=100, dt=0.005, scheme=CONTROL))
    m = contact_measures(run)
    assert m.t_contact == run.run.t_final and m.time_to_contact == m.t_contact - m.t_c > 0
    assert m.twist == pytest.approx(10.0 + 16.0 * m.t_contact)
    assert m.max_curvature > 2 * np.pi / run.rod.L  # looped, far from the straight rod
    assert 0 < m.width < 0.5
    fixed = simulate_scene(Scene(a=16.0, kappa0=10.0, n_cells=100, dt=0.005))
    with pytest.raises(ValueError, match="self-contact"):
        contact_measures(fixed)


@pytest.mark.parametrize("quadrature", ["trapezoidal", "midpoint"])
def test_energy_balance_closes_at_second_order_before_the_onset(quadrature):
    """E - E0 - W (work of the end twist and the seed) along the prebuckling run: a small
    fraction of the work done, falling as dt^2 with both load quadratures."""
    from dyntorsion.buckling.postbuckling import energy_balance

    defects = []
    for dt in (0.01, 0.005, 0.0025):
        run = buckling.simulate(
            Scene(
                a=16.0,
                kappa0=10.0,
                n_cells=50,
                dt=dt,
                t_end=1.0,
                scheme=ga.Scheme(quadrature=quadrature),
            ),
            snapshots=np.arange(0.0, 1.0 + dt / 2, dt),
            progress=False,
        )
        eb = energy_balance(run)
        assert eb.W[-1] > 0 and eb.t.size == run.t.size
        assert np.max(np.abs(eb.defect)) < 1e-4 * eb.W[-1]
        defects.append(np.max(np.abs(eb.defect)))
    assert observed_orders([0.01, 0.005, 0.0025], defects) == pytest.approx([2.0, 2.0], abs=0.1)


def test_run_scene_records_what_the_controller_did():
    from dyntorsion.buckling.scene import run_scene

    coarse = dict(a=16.0, kappa0=10.0, n_cells=50, dt=0.01)
    fixed = run_scene(Scene(**coarse))
    ctl = run_scene(Scene(**coarse, scheme=CONTROL))
    assert "control" not in fixed  # fixed-step records keep their fields
    c = ctl["control"]
    assert c["rejected"] >= 10 and c["accepted"] > ctl["steps"]
    assert c["smallest_dt"] < 0.01 / 8 and "dt_min" in ctl["stopped"]
    assert ctl["t_c"] == fixed["t_c"]  # the onset comes before the first rejection


def test_cli_control_follows_the_rod_to_self_contact(capsys):
    """`dyntorsion buckle --control` runs past the whip that stops the fixed-step run."""
    from dyntorsion.app.cli import main

    args = ["buckle", "--a", "16", "--kappa0", "10", "--n-cells", "100", "--dt", "0.005"]
    main(args)
    fixed = capsys.readouterr().out
    assert main([*args, "--control"]) == 0
    controlled = capsys.readouterr().out
    stop = {text: line for text in (fixed, controlled) for line in text.splitlines()
            if line.startswith("stopped")}  # fmt: skip
    assert "failed" in stop[fixed] and "self-contact" in stop[controlled]
    t_c = [line for line in controlled.splitlines() if line.startswith("t_c")]
    assert t_c and t_c[0] in fixed  # the same onset
