"""The speed targets of issues 16 and 34, each beside its floor and beside a baseline commit.

    python benchmarks/bench_targets.py [--baseline COMMIT] [--quick] [--make-data]

Every measurement runs twice in this one invocation: with the code of this checkout
and with the code of ``--baseline`` (default 1f90f1e, "today's engine" of issue 34;
434e8a7 is the engine before the Newton stopping test of session 9, 6fcb9be the engine
before any speed work), checked out into a temporary git worktree and run in a subprocess, so both
see the same machine load.  Medians of repeated runs; nothing is asserted.  On the
shared 2-core machine the same code measured 0.7x-1.5x of itself between runs, so the
Newton counts per step of the Fig 8 scene are printed too (they do not depend on load).

* Fig 8 scene (a = 1.6, kappa0 = 0, stated seed) at N = 50, dt = 0.02 s run to
  t = 18 s, just past its first |u3(L)| peak, so that the onset can be detected
  (t_c within 0.5 % of the converged value on this grid; floor 50 ms);
* the same with each Newton stopping test (``Newton(stopping=...)``; the baseline has
  only the correction test and shows its default there);
* the same scene at N = 50, dt = 0.05 s, Newton tol 1e-6, ended after the first peak of
  |u3(L)| (``stop_after_first_peak``): the fastest setting found with t_c within 0.5 %
  of the converged value (printed);
* the same scene read in continuous time (``Onset.t_c_continuous``, the window rule on
  the cubic interpolant of the samples) at N = 50, dt = 0.15 s, tol 1e-6: the same
  accuracy in a third of the steps, as its t_c does not jump between grids;
  and the same with ``Newton(theta_reuse=0.5)`` (factors kept while the iteration
  contracts by 0.5: fewer factorisations, more corrections);
* the 16-rate Fig 10 sweep at the standard grid (N = 100, dt = 0.005 s), one core,
  nothing cached (floor 2 s), run to self-contact and ended after the first peak
  (``Scene(until="first-peak")``, the same onsets);
  and the same with ``long_steps=LongSteps()`` added to the preset's scheme (steps of
  8 dt while the rod is straight; the largest change of t_c against the run at dt is
  printed), and at dt = 0.02 s throughout (a quarter of the steps, the largest change
  of t_c printed): even then the sweep takes well over 2 s at the standard step;
* the same sweep in paced steps (``P.preset("fig10-paced")``, :mod:`dyntorsion.studies.pacing`:
  384 steps to each scene's estimated onset, Newton tol 1e-6, until the first peak;
  the estimates are timed with it), with its largest change of t_c against the
  standard grid (floor 2 s; ``benchmarks/bench_paced.py`` compares both with the
  converged onset); and in 96 paced steps read in continuous time, with its largest
  error against the N = 800 references of the first hold-out set (within 0.5 %);
* the fast onset estimate (``beyond.predictions.estimate``), median per Fig 10
  scene in ms (floor 10 ms);
* the linear prediction of the Fig 10 scene a = 1.6, with the torsional waves and on
  the uniform ramp (floor: no slower than the simulated scene);
* cost per node and step at N = 50 ... 1600 (floor: flat in N);
* issue 34, item 2: the Fig 8 scene's Newton corrections per step by phase of the run
  (straight, growing, onset, whip), residuals per step and factorisations at Newton tol
  1e-10 (the default), 1e-8 and 1e-6 and with full Newton, with the change of t_c each
  tolerance causes; and the same-grid time per step (target: half the baseline's).
  ``tests/genalpha/test_newton_counts.py`` pins the straight phase's counts; why it takes 4.7
  corrections and not 1 or 2 is in its docstring and in ``benchmarks/profile_fig08.py``;
* the engine's overhead: the wall time of the Fig 8 onset within 0.5 % and of the paced
  sweep's runs over the time spent inside the compiled march (floor 1.3: set-up, explicit
  operators and bookkeeping at most 30 % on top of the compiled work);
* with ``--make-data`` (``make bench`` passes it): ``make data`` with every record current,
  one run, two processes (floor 90 s; only this checkout: it times the records, not an
  engine).
"""

from __future__ import annotations

import argparse
import subprocess
import time
from pathlib import Path

from worktree import ROOT, checkout, run_code, run_json


def ladder_t_c(preset: str, n_cells: int, dt: float, reading: str = "t_c") -> float:
    """t_c (or ``reading``, e.g. ``"t_c_continuous"``) of one grid of a cached accuracy
    ladder (``make data``: ``accuracy-fig08``, the Fig 8 scene; ``accuracy-fast``,
    a = 16); nan while the records are stale (the numerical code changed since
    ``make data``)."""
    from dyntorsion.store.results import StaleResultError
    from dyntorsion.studies import presets as P

    try:
        t = P.cached(preset)
    except StaleResultError:
        return float("nan")
    row = t[(t["n_cells"] == n_cells) & ((t["dt"] - dt).abs() < 1e-12 * dt)]
    return float(row[reading].iloc[0])


def standard_error_pct(preset: str) -> float:
    """The standard grid's (N = 100, dt = 0.005 s) t_c error against the ladder's finest."""
    return 100 * abs(ladder_t_c(preset, 100, 0.005) / ladder_t_c(preset, 400, 0.00125) - 1)


#: the measuring code's Scene and simulate on this engine or on an older one (the baseline's
#: simulate took the scene's fields as keywords); ``b`` is ``dyntorsion.buckling``
SCENE_COMPAT = r"""
try:
    from dyntorsion.buckling import Scene
    simulate = b.simulate
except ImportError:  # engines before simulate(scene) took the scene's fields as keywords

    def Scene(**fields):
        return fields

    def simulate(scene, **options):
        return b.simulate(**scene, **options)
"""

MEASURE = (
    r"""
import json, statistics, sys, time
sys.path.insert(0, sys.argv[1])
quick = sys.argv[2] == "1"
from dyntorsion import buckling as b
from dyntorsion.buckling import scene as S
from dyntorsion.studies import presets as P
from dyntorsion.beyond.linear_stability import LateralModel
"""
    + SCENE_COMPAT
    + r"""try:  # the integration's settings in one part (older engines took them as keywords)
    from dyntorsion.beyond.linear_stability import PassageSteps
    SHORT_PASSAGE = {"steps": PassageSteps(t_end=0.1)}
except ImportError:
    SHORT_PASSAGE = {"t_end": 0.1}

def median(f, n):
    out = []
    for _ in range(n):
        t = time.perf_counter(); f(); out.append(time.perf_counter() - t)
    return statistics.median(out)

simulate(Scene(a=1.6, n_cells=10, dt=0.05, t_end=0.2, kappa0=0.0))
res = {}
fig8 = lambda: b.detect_onset(simulate(Scene(a=1.6, n_cells=50, dt=0.02, t_end=18.0, kappa0=0.0)))
res["fig8_onset_s"] = median(fig8, 3)
res["fig8_t_c"] = fig8().t_c
from dyntorsion.genalpha import Newton
for stop in ("correction", "contraction"):
    try:
        nw = Newton(stopping=stop)
    except TypeError:
        nw = Newton()
    run = lambda: b.detect_onset(simulate(Scene(a=1.6, n_cells=50, dt=0.02, t_end=18.0, newton=nw, kappa0=0.0)))
    res[f"fig8_{stop}_s"] = median(run, 3)
    onset = run()
    res[f"fig8_{stop}_t_c"] = onset.t_c
    sim = simulate(Scene(a=1.6, n_cells=50, dt=0.02, t_end=18.0, newton=nw, kappa0=0.0)).run
    res[f"fig8_{stop}_per_step"] = [
        float(sim.iterations.sum() / sim.steps),
        float(sim.residual_evaluations.sum() / sim.steps),
        int(sim.factorisations.sum()),
    ]
# issue 34, item 2: Newton corrections per step by phase, residuals per step and
# factorisations of the same-grid run, and its time per step; the same for looser tolerances
PHASES = [(0.0, 5.0), (5.0, 10.0), (10.0, 13.0), (13.0, 15.0), (15.0, 18.01)]
def by_phase(newton):
    import numpy as np
    sim = simulate(Scene(a=1.6, n_cells=50, dt=0.02, t_end=18.0, newton=newton, kappa0=0.0))
    r = sim.run
    t = 0.02 * np.arange(1, r.steps + 1)
    its = np.asarray(r.iterations)[: r.steps]
    return {
        "phases": [float(its[(t >= a - 1e-9) & (t < c - 1e-9)].mean()) for a, c in PHASES],
        "per_step": float(its.mean()),
        "residuals": float(np.asarray(r.residual_evaluations)[: r.steps].mean()),
        "lu": int(np.sum(r.factorisations)),
        "t_c": b.detect_onset(sim).t_c,
    }
res["newton_ladder"] = {f"{tol:g}": by_phase(Newton(tol=tol)) for tol in (1e-10, 1e-8, 1e-6)}
res["newton_ladder"]["full"] = by_phase(Newton(reuse=False))
same = lambda: simulate(Scene(a=1.6, n_cells=50, dt=0.02, t_end=18.0, kappa0=0.0), stop_at_contact=False)
res["fig8_us_per_step"] = 1e6 * median(same, 7) / 900
# the fastest Fig 8 run to its onset within 0.5 % of the converged t_c (N = 400,
# dt = 0.00125 s, the accuracy-fig08 ladder): N = 50, dt = 0.05 s, Newton tol 1e-6, ended after the
# first peak of |u3(L)| (the baseline has no such ending and runs to t = 18 s)
def fast8():
    kw = dict(a=1.6, kappa0=0.0, n_cells=50, dt=0.05, t_end=18.0, newton=Newton(tol=1e-6))
    try:
        return b.detect_onset(simulate(Scene(until="first-peak", **kw)))
    except TypeError:
        return b.detect_onset(simulate(Scene(**kw)))
try:
    res["fig8_fast_s"] = median(fast8, 5)
    res["fig8_fast_t_c"] = fast8().t_c
except Exception:
    res["fig8_fast_s"] = res["fig8_fast_t_c"] = float("nan")
# the same scene read in continuous time (the window's ends and the line from the cubic
# interpolant, dyntorsion.buckling.onset.continuous_window_fit), whose t_c does not jump
# as samples enter the window: within 0.5 % at three times the step (a scan of
# N = 25, 50 x dt = 0.05..0.2 s x tol 1e-10..1e-4 on 2026-11-27, docs/benchmarks.md)
def fast8c():
    kw = dict(a=1.6, kappa0=0.0, n_cells=50, dt=0.15, t_end=18.0, newton=Newton(tol=1e-6))
    return b.detect_onset(simulate(Scene(until="first-peak", **kw))).t_c_continuous
try:
    res["fig8_fast_cont_s"] = median(fast8c, 5)
    res["fig8_fast_cont_t_c"] = fast8c()
except (TypeError, AttributeError):  # the baseline has no continuous reading
    res["fig8_fast_cont_s"] = res["fig8_fast_cont_t_c"] = float("nan")
# the same keeping the factors while the iteration contracts by 0.5 (not 0.25): fewer
# factorisations for more corrections (a scan on the quiet machine, 2026-11-27: 56 -> 36
# factorisations, 491 -> 597 corrections, 28 -> 21 ms; t_c +0.269 -> +0.262 %)
def fast8c_half():
    kw = dict(a=1.6, kappa0=0.0, n_cells=50, dt=0.15, t_end=18.0, newton=Newton(tol=1e-6, theta_reuse=0.5))
    return b.detect_onset(simulate(Scene(until="first-peak", **kw))).t_c_continuous
try:
    res["fig8_fast_half_s"] = median(fast8c_half, 5)
    res["fig8_fast_half_t_c"] = fast8c_half()
except (TypeError, AttributeError):
    res["fig8_fast_half_s"] = res["fig8_fast_half_t_c"] = float("nan")
scenes = P.preset("fig10")
if quick:
    scenes = scenes[::4]
res["fig10_scenes"] = len(scenes)
res["fig10_sweep_s"] = median(lambda: [S.run_scene(sc) for sc in scenes], 1)
from dataclasses import replace
try:
    short = [replace(sc, until="first-peak") for sc in scenes]
    res["fig10_peak_s"] = median(lambda: [S.run_scene(sc) for sc in short], 1)
except TypeError:
    res["fig10_peak_s"] = res["fig10_sweep_s"]
try:  # the baseline has no Scene(until=...)
    peak_ref = [S.run_scene(sc) for sc in short]
    coarse = [replace(sc, dt=0.02) for sc in short]
    out2 = []
    res["fig10_coarse_s"] = median(lambda: out2.extend([S.run_scene(sc) for sc in coarse]), 1)
    res["fig10_coarse_err_pct"] = max(
        100 * abs(o["t_c"] / r["t_c"] - 1) for o, r in zip(out2[-len(coarse):], peak_ref))
except NameError:
    peak_ref = None
    res["fig10_coarse_s"] = res["fig10_coarse_err_pct"] = float("nan")
try:
    from dyntorsion.genalpha import LongSteps
    longs = [
        replace(sc, until="first-peak", scheme=replace(sc.scheme, long_steps=LongSteps()))
        for sc in scenes
    ]
    out = []
    res["fig10_long_s"] = median(lambda: out.extend([S.run_scene(sc) for sc in longs]), 1)
    ref = peak_ref if peak_ref is not None else [S.run_scene(sc) for sc in short]
    res["fig10_long_err_pct"] = max(
        100 * abs(o["t_c"] / r["t_c"] - 1) for o, r in zip(out[-len(longs):], ref))
except ImportError:
    res["fig10_long_s"] = res["fig10_peak_s"]
    res["fig10_long_err_pct"] = 0.0
if "fig10-paced" in P.PRESETS:  # paced steps (dyntorsion.studies.pacing)
    P.preset("fig10-paced")  # the linear models of the estimate are built once a process

    def paced_sweep():
        todo = P.preset("fig10-paced")  # the estimates are part of the cost
        return [S.run_scene(sc) for sc in (todo[::4] if quick else todo)]

    out3 = []
    res["fig10_paced_s"] = median(lambda: out3.extend(paced_sweep()), 3)
    res["fig10_paced_err_pct"] = max(
        100 * abs(o["t_c"] / r["t_c"] - 1) for o, r in zip(out3[-len(scenes):], peak_ref))
    res["fig10_paced_steps"] = sum(o["steps"] for o in out3[-len(scenes):])
    try:  # read in continuous time, 96 paced steps suffice (scan of 2026-11-27)
        from dyntorsion.studies.sweep import run_sweep
        from dyntorsion.studies.pacing import paced

        refs = run_sweep(P.reference_scenes(("tolerance-holdout",))[:16], compute=False,
                         on_stale="error", progress=False).t_c_continuous.to_numpy()
        refs = refs[::4] if quick else refs

        def paced96():
            todo = [paced(replace(sc, until="first-peak"), steps=96) for sc in scenes]
            return [S.run_scene(sc)["t_c_continuous"] for sc in todo]

        out5 = []
        res["fig10_paced96_s"] = median(lambda: out5.append(paced96()), 3)
        res["fig10_paced96_err_pct"] = max(100 * abs(c / r - 1) for c, r in zip(out5[-1], refs))
    except Exception:  # the baseline has no continuous reading (or the records are stale)
        res["fig10_paced96_s"] = res["fig10_paced96_err_pct"] = float("nan")
else:  # the baseline has none: its first-peak sweep
    res["fig10_paced96_s"] = res["fig10_paced96_err_pct"] = float("nan")
    res["fig10_paced_s"] = res["fig10_peak_s"]
    res["fig10_paced_err_pct"] = 0.0
    res["fig10_paced_steps"] = float("nan")
# the engine's overhead over its compiled work: the wall time of a run over the time spent
# inside the compiled march (set-up, explicit operators, bookkeeping and the onset reading
# are the rest), for the Fig 8 onset within 0.5 % and the paced sweep's runs
try:
    import dyntorsion.genalpha.control as _ctl
    import dyntorsion.genalpha.stepping as _st

    _spent, _real = [0.0], _st.march

    def _timed(*args):
        t = time.perf_counter()
        out = _real(*args)
        _spent[0] += time.perf_counter() - t
        return out

    def overhead(f, n):
        ratios = []
        for _ in range(n):
            _spent[0] = 0.0
            t = time.perf_counter()
            f()
            ratios.append((time.perf_counter() - t) / _spent[0])
        return statistics.median(ratios)

    _st.march = _ctl.march = _timed
    try:
        res["fig8_fast_overhead"] = overhead(fast8, 7)
        built = P.preset("fig10-paced")
        built = built[::4] if quick else built
        res["fig10_paced_overhead"] = overhead(lambda: [S.run_scene(sc) for sc in built], 3)
    finally:
        _st.march = _ctl.march = _real
except Exception:  # an engine without these parts, or without paced presets
    res["fig8_fast_overhead"] = res["fig10_paced_overhead"] = float("nan")
try:
    from dyntorsion.beyond.predictions import estimate
except ImportError:
    estimate = None
if estimate is not None:
    estimate(scenes[0])
    res["estimate_ms"] = 1e3 * statistics.median(
        [median(lambda sc=sc: estimate(sc), 3) for sc in scenes])
else:
    res["estimate_ms"] = float("nan")
model = LateralModel()
model.passage(1.6, 10.0, 1e-8, waves=False, **SHORT_PASSAGE)
res["linear_waves_s"] = median(lambda: model.passage(1.6, 10.0, 1e-8, waves=True), 1 if quick else 3)
res["linear_ramp_s"] = median(lambda: model.passage(1.6, 10.0, 1e-8, waves=False), 3)
res["sim_fig10_a1.6_s"] = median(
    lambda: simulate(Scene(a=1.6, kappa0=10.0, n_cells=100, dt=0.005, t_end=10.0)), 1 if quick else 3)
per = {}
for n in (50, 200, 800, 1600):
    run = simulate(Scene(a=1.6, n_cells=n, dt=0.005, t_end=0.1, kappa0=0.0))
    per[n] = 1e6 * run.run.wall_time / run.run.steps / (n + 1)
res["us_per_node_step"] = per
print(json.dumps(res))
"""
)


def measure(src: Path, quick: bool) -> dict:
    return run_json(MEASURE, src, "1" if quick else "0")


PER_STEP = (
    r"""
import statistics, sys, time
sys.path.insert(0, sys.argv[1])
from dyntorsion import buckling as b
"""
    + SCENE_COMPAT
    + r"""run = lambda: simulate(Scene(a=1.6, n_cells=50, dt=0.02, t_end=18.0, kappa0=0.0), stop_at_contact=False)
run()
out = []
for _ in range(5):
    t = time.perf_counter(); r = run(); out.append((time.perf_counter() - t) / r.run.steps)
print(1e6 * statistics.median(out))
"""
)


def per_step_alternating(srcs: dict[str, Path], rounds: int = 5) -> dict[str, float]:
    """The same-grid Fig 8 run's time per step (us) of each source tree, measured in
    ``rounds`` alternating subprocesses (a median of 5 runs each) so that both see the
    same swings of the machine's load; the smallest median of each."""
    best = dict.fromkeys(srcs, float("inf"))
    for _ in range(rounds):
        for key, src in srcs.items():
            best[key] = min(best[key], float(run_code(PER_STEP, src)))
    return best


def make_data_line() -> str:
    """One run of ``make data ON_STALE=error`` (2 processes), timed when it computed nothing:
    no stale record (it would stop) and no file of ``data/`` changed or added (git)."""

    def changed() -> str:
        return subprocess.run(
            ["git", "-C", str(ROOT), "status", "--porcelain", "data"],
            capture_output=True, text=True, check=True,
        ).stdout  # fmt: skip

    if changed():
        return "make data: not timed, data/ has uncommitted changes"
    t = time.perf_counter()
    done = subprocess.run(
        ["make", "-C", str(ROOT), "data", "ON_STALE=error", "JOBS=2"], capture_output=True
    )
    wall = time.perf_counter() - t
    if done.returncode != 0:
        return "make data: not timed, a record is stale (make data would recompute it)"
    if changed():
        return "make data: not timed, it computed missing records (run it again)"
    met = "yes" if wall <= 90.0 else "no"
    return f"{'issue 34: make data, every record current, 2 processes':52s} {90.0:8.3f} {wall:9.3f}  (one run)  {met}"


def targets(now: dict) -> list[tuple[str, str, float | None]]:
    """The targets measured by :data:`MEASURE`: (label, key of ``now``, floor or None),
    the 16-rate floors scaled to the rates measured."""
    rows = [
        ("Fig 8 scene to its onset, N=50, dt=0.02 s", "fig8_onset_s", 0.05),
        ("  with Newton(stopping='correction')", "fig8_correction_s", 0.05),
        ("  with Newton(stopping='contraction')", "fig8_contraction_s", 0.05),
        ("  N=50, dt=0.05 s, tol 1e-6, until first peak", "fig8_fast_s", 0.05),
        (f"Fig 10 sweep, {now['fig10_scenes']} rates, standard grid, 1 core", "fig10_sweep_s",
         2.0 * now["fig10_scenes"] / 16),
        ("  each scene until its first peak (same onsets)", "fig10_peak_s",
         2.0 * now["fig10_scenes"] / 16),
        ("  and LongSteps() before the onset", "fig10_long_s", 2.0 * now["fig10_scenes"] / 16),
        ("  until the first peak at dt=0.02 s (4x fewer steps)", "fig10_coarse_s",
         2.0 * now["fig10_scenes"] / 16),
        ("  paced (384 steps to the estimated onset, tol 1e-6)", "fig10_paced_s",
         2.0 * now["fig10_scenes"] / 16),
        ("fast onset estimate, median per Fig 10 scene [ms]", "estimate_ms", 10.0),
        ("linear prediction a=1.6 with waves", "linear_waves_s", now["sim_fig10_a1.6_s"]),
        ("linear prediction a=1.6, uniform ramp", "linear_ramp_s", now["sim_fig10_a1.6_s"]),
        ("(the simulated Fig 10 scene a=1.6 to 10 s)", "sim_fig10_a1.6_s", None),
        ("Fig 8 onset within 0.5 % (the fastest setting)", "fig8_fast_s", 0.010),
        ("the same read in continuous time, dt=0.15 s", "fig8_fast_cont_s", 0.010),
        ("  and Newton(theta_reuse=0.5)", "fig8_fast_half_s", 0.010),
        (f"{now['fig10_scenes']}-rate sweep, each onset within 0.5 % (paced)",
         "fig10_paced_s", 0.3 * now["fig10_scenes"] / 16),
        ("the same in continuous time, 96 paced steps", "fig10_paced96_s",
         0.3 * now["fig10_scenes"] / 16),
        ("engine overhead, Fig 8 onset within 0.5 %: wall / compiled march",
         "fig8_fast_overhead", 1.3),
        ("engine overhead, paced sweep's runs: wall / compiled march",
         "fig10_paced_overhead", 1.3),
    ]  # fmt: skip
    return rows


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--baseline", default="1f90f1e", help="commit of the engine to compare with")
    p.add_argument("--quick", action="store_true", help="a quarter of the Fig 10 rates")
    p.add_argument(
        "--make-data", action="store_true",
        help="time `make data` with every record current (stops at a stale one)",
    )  # fmt: skip
    args = p.parse_args()
    start = time.perf_counter()
    now = measure(ROOT / "src", args.quick)
    with checkout(args.baseline) as wt:
        base = measure(wt / "src", args.quick)
        alternating = per_step_alternating({"now": ROOT / "src", "baseline": wt / "src"})
    # the same-grid step in alternating rounds: back to back, the same code measured
    # 0.33 of itself under the load of another job (2026-11-25)
    now["fig8_step_us"], base["fig8_step_us"] = alternating["now"], alternating["baseline"]
    rows = targets(now) + [
        ("same-grid Fig 8 step [us], half the baseline's", "fig8_step_us",
         0.5 * alternating["baseline"]),
    ]  # fmt: skip
    print(f"baseline {args.baseline}; medians; {time.perf_counter() - start:.0f} s in all")
    print(f"{'target':52s} {'floor':>8s} {'now':>9s} {'baseline':>9s} {'ratio':>6s}  met")
    for label, key, floor in rows:
        fl = "" if floor is None else f"{floor:.3f}"
        met = "" if floor is None else ("yes" if now[key] <= floor else "no")
        print(
            f"{label:52s} {fl:>8s} {now[key]:9.3f} {base[key]:9.3f} "
            f"{base[key] / now[key]:6.1f}  {met}"
        )
    print(
        "Fig 10 sweep at dt = 0.02 s: largest |t_c change| against dt = 0.005 s: "
        f"{now['fig10_coarse_err_pct']:.3f} % (the standard grid's own error against "
        f"N = 400, dt = 0.00125 s: {standard_error_pct('accuracy-fig08'):.2f} % for the Fig 8 "
        f"scene, {standard_error_pct('accuracy-fast'):.2f} % at a = 16)"
    )
    converged = ladder_t_c("accuracy-fig08", 400, 0.00125)
    for key in ("fig8_t_c", "fig8_correction_t_c", "fig8_contraction_t_c", "fig8_fast_t_c"):
        print(f"{key}: now {now[key]:.6f} s, baseline {base[key]:.6f} s")
    print(
        f"fig8_fast_t_c against the converged {converged:.5f} s (N = 400, dt = 0.00125 s): "
        f"{100 * (now['fig8_fast_t_c'] / converged - 1):+.3f} %"
    )
    converged_c = ladder_t_c("accuracy-fig08", 400, 0.00125, "t_c_continuous")
    print(
        f"fig8_fast_cont_t_c {now['fig8_fast_cont_t_c']:.6f} s against the converged "
        f"{converged_c:.5f} s (read in continuous time, N = 400, dt = 0.00125 s): "
        f"{100 * (now['fig8_fast_cont_t_c'] / converged_c - 1):+.3f} %; with "
        f"theta_reuse=0.5 {100 * (now['fig8_fast_half_t_c'] / converged_c - 1):+.3f} %"
    )
    print(
        "Fig 10 sweep with LongSteps(): largest |t_c change| against the same scenes at dt "
        f"throughout: {now['fig10_long_err_pct']:.4f} %"
    )
    print(
        "Fig 10 sweep paced (dyntorsion.studies.pacing; the baseline runs its first-peak sweep): "
        f"largest |t_c change| against the standard grid {now['fig10_paced_err_pct']:.3f} %, "
        f"{now['fig10_paced_steps']} steps (benchmarks/bench_paced.py: both against the "
        "converged onset)"
    )
    print(
        "Fig 10 sweep paced at 96 steps, read in continuous time: largest |t_c error| against "
        f"the N = 800 references (tolerance-reference) {now['fig10_paced96_err_pct']:.3f} %"
    )
    print("Fig 8 scene: corrections / residuals per step, factorisations (load-independent)")
    for stop in ("correction", "contraction"):
        n, b = now[f"fig8_{stop}_per_step"], base[f"fig8_{stop}_per_step"]
        print(
            f"  {stop:12s} now {n[0]:.2f} / {n[1]:.2f}, {n[2]}; baseline {b[0]:.2f} / {b[1]:.2f}, {b[2]}"
        )
    print(
        "Fig 8 scene, N = 50, dt = 0.02 s to 18 s: Newton corrections per step by phase "
        "[0,5) [5,10) [10,13) [13,15) [15,18) s, residuals per step, factorisations, "
        "t_c change against tol 1e-10 (load-independent; issue 34, item 2)"
    )
    ref_tc = now["newton_ladder"]["1e-10"]["t_c"]
    for key in now["newton_ladder"]:
        for who, d in (("now", now), ("baseline", base)):
            row = d["newton_ladder"][key]
            phases = " ".join(f"{p:.2f}" for p in row["phases"])
            print(
                f"  tol {key:6s} {who:8s} {phases}  {row['per_step']:.2f} / "
                f"{row['residuals']:.2f}, {row['lu']:5d} LU, t_c {row['t_c'] / ref_tc - 1:+.1e}"
            )
    print(
        f"same-grid time per step (us): now {now['fig8_us_per_step']:.1f}, baseline "
        f"{base['fig8_us_per_step']:.1f}, ratio {now['fig8_us_per_step'] / base['fig8_us_per_step']:.2f} "
        "(target of issue 34: 0.5)"
    )
    a_now, a_base = alternating["now"], alternating["baseline"]
    print(
        f"  the same in 5 alternating rounds (smallest medians): now {a_now:.1f}, baseline "
        f"{a_base:.1f}, ratio {a_now / a_base:.2f}"
    )
    if args.make_data:
        print(make_data_line())
    else:
        print("make data <= 90 s on 2 cores: not measured (--make-data times it)")
    print("cost per node and step (us), N: now / baseline")
    for n in now["us_per_node_step"]:
        print(
            f"  N={n:>5s}: {now['us_per_node_step'][n]:6.2f} / {base['us_per_node_step'][n]:6.2f}"
        )


if __name__ == "__main__":
    main()
