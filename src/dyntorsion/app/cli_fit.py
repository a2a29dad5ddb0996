"""``dyntorsion fit`` and the fits that ``dyntorsion sweep`` prints: eq (33) fitted to each
family of scenes (the same everything but the loading rate), with each family's own rod,
axial load and static critical twist."""

from __future__ import annotations

import argparse
import re
import sys

from ..buckling.delay_law import fit_power_law
from ..buckling.scene import Scene
from ..published import value
from ..store.location import default_store
from ..store.results import Store
from ..studies.presets import cached, preset
from ..studies.sweep import KIND, run_sweep

__all__ = ["fit", "fit_rows", "print_fit"]


def print_fit(rows: list[dict]) -> None:
    """Fit eq (33) to each family of scenes (same everything but the rate), with each
    family's own rod, axial load and static critical twist."""
    families: dict[str, list[dict]] = {}
    for r in rows:
        if r["a"] is not None and r["kappa3"] is not None:
            families.setdefault(r["family"], []).append(r)
    if not families:
        print('fit: no scene with a loading rate and a "buckled" onset to fit')
    sweeps = []
    for grp in families.values():
        pairs = {(round(r["a"], 9), r["scene"].dt) for r in grp}
        if len(pairs) == len({a for a, _ in pairs}):
            sweeps.append(grp)  # each rate at one step (fixed, or following the rate: paced)
        else:  # some rate at several steps: one sweep per step
            by_dt: dict[float, list[dict]] = {}
            for r in grp:
                by_dt.setdefault(r["scene"].dt, []).append(r)
            sweeps.extend(by_dt.values())
    for grp in sweeps:
        seen, pts = set(), []  # one record a rate (records differing only in t_end)
        for r in grp:
            if round(r["a"], 9) not in seen:
                seen.add(round(r["a"], 9))
                pts.append(r)
        head = pts[0]
        name = head["label"]
        steps = sorted({r["scene"].dt for r in pts})
        if len(steps) > 1:
            name = re.sub(r"dt=\S+", f"dt={steps[0]:g}-{steps[-1]:g}", name)
        if len(pts) == 1:
            continue  # a single scene, not a rate sweep
        if len(pts) < 4:
            print(
                f"fit {name}: {len(pts)} rate(s) with an onset; eq (33) needs at least 4 "
                "(3 parameters with kappa_cri free, plus one) -- add rates to this sweep"
            )
            continue
        a = [r["a"] for r in pts]
        k = [r["kappa3"] for r in pts]
        rod = head["rod"]
        try:
            kc = head["scene"].kappa_cri()
            modes = (kc, None)
        except ValueError as err:
            print(f"fit {name}: kappa_cri fixed skipped ({err})")
            modes = (None,)
        for mode in modes:
            try:
                f = fit_power_law(a, k, rod, kappa_cri=mode, n_boot=500)
            except ValueError as err:
                print(f"fit {name}: not fitted ({err})")
                continue
            tag = "kappa_cri fixed" if mode is not None else "kappa_cri free "
            print(
                f"fit {name} {tag}: b = {f.b:.2f} +- {f.b_err:.2f}, "
                f"sigma = {f.sigma:.4f} +- {f.sigma_err:.4f}, "
                f"kappa_cri = {f.kappa_cri:.4f} +- {f.kappa_cri_err:.4f} "
                f"(paper, Table 1 rod: b = {value('b'):.2f}, sigma = {value('sigma'):.4f})"
            )


def fit_rows(table, scenes: list[Scene]) -> list[dict]:
    rows = []
    for (_, r), sc in zip(table.iterrows(), scenes, strict=True):
        label = sc.label().split(" ", 1)[1] if sc.history is None else sc.label()  # drop a=
        rows.append(
            {
                "a": sc.twist.rate,
                "kappa3": r["kappa3"] if r["status"] == "buckled" else None,
                "family": r["family"],
                "rod": sc.rod,
                "scene": sc,
                "label": f"[{label}]",
            }
        )
    return rows


def fit(args: argparse.Namespace) -> int:
    """``dyntorsion fit``: eq (33) fitted to a cached preset, or to every rate sweep in a store."""
    if args.preset:
        scenes = preset(args.preset)
        table = cached(args.preset, args.store)
    else:
        store = Store(args.store or default_store())
        skipped: list = []
        scenes = []
        for rec in store.records(KIND, skipped=skipped):
            try:
                scenes.append(Scene.from_params(rec["params"]))
            except (ValueError, TypeError, KeyError) as err:
                skipped.append(err)
        if skipped:
            print(
                f"fit: {len(skipped)} record(s) of {store.root} skipped (damaged, or a scene "
                f"this package cannot rebuild, e.g. a custom history): {skipped[0]}",
                file=sys.stderr,
            )
        if not scenes:
            raise ValueError(f"--store {store.root}: no usable {KIND} records to fit")
        table = run_sweep(scenes, args.store, compute=False, on_stale="error", progress=False)
    print_fit(fit_rows(table, scenes))
    return 0
