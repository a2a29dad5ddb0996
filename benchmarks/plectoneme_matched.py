"""Run times at matched accuracy: PyElastica's plectoneme scene in both codes (issue 33,
item 5), written to ``data/bench/plectoneme_matched.json``.

The scene is that of ``pyelastica_plectoneme.py`` (PyElastica's example) and of
``plectoneme_dyntorsion.py`` (the same scene in dyntorsion: Kirchhoff rod, its contact
law, a point seed for the example's kick), each code's scene as those scripts state it
(imported from them: one place for each), followed from rest to ``T_STAR`` = 20 s: the
loop has formed (at about 10-12 s) and the plectoneme grows; PyElastica's rod passes
through itself only at 46.4 s.

Accuracy is judged by each code against its own limit, on the writhe at ``T_STAR`` (turns;
each code's own closure, the same on every rung) and the axial position of the sliding end
(mm): the two codes solve different models (shearable and extensible against Kirchhoff; two
contact laws; the kick against the seed), so their common error has no converged value to
be judged against, while each code's discretisation error does.  The limit is Richardson's
on the code's three finest rungs with the order they show
(:func:`dyntorsion.verification.richardson`, h = 1/n); a rung's error is its distance from
it.  Measured 2026-11-26 against the finest rung instead, PyElastica's errors fell as 1/n,
so its finest rung is itself about as far from the limit as the rung below it is from the
finest: judged against the finest, PyElastica looked twice as accurate as it is.  The
comparisons (``analysis`` in the record, ``--print``): for each PyElastica rung, the
cheapest dyntorsion rung at least as accurate, and the ratio of their wall times (an upper
bound on dyntorsion's time where its coarsest rung is already more accurate); for each
writhe tolerance ``TOLS``, the cheapest rung of each code within it.  Rungs that stop before
t* (under-resolved) are kept in the record and left out of the comparisons.

Ladders: dyntorsion N = ``DYN_CELLS`` at dt = 0.02 s (its scene's step; substeps near
contact as its ``Contact`` says); PyElastica ``PE_ELEMENTS`` elements at the example's step
rule dt = 0.0025 L / n (its explicit limit scales with the element; the kick of 1e-4 m/s
to the middle node, of mass 1/n kg, at each of the n / 0.0025 steps a second is a
momentum rate of 0.04 N whatever n: the same imperfection on every rung).
Each run is preceded by a short run of the same code on the same grid (``WARM`` = 0.2 s)
so that compilation is not timed; what only the contact phase compiles falls in the first
run of each code, its finest rung, which is the reference and never the matched rung.  All runs in one process, one after the other, on one core
(``OPENBLAS_NUM_THREADS=1``): the times are comparable with each other, not with a run on
another machine or under another load; the record says which runs were made in the same
invocation (``invocation``).  Written atomically after every run; a rerun resumes when the
parameters, this script and the code fingerprint are unchanged.

Run: ``python benchmarks/plectoneme_matched.py`` (needs PyElastica: ``pip install -e
'.[bench]'``; one core: the record keeps each run's wall time), ``--print`` to print the recorded table.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from importlib.metadata import version

import pyelastica_plectoneme as pe  # this script's folder, first on sys.path
from dyntorsion.studies.contact import plectoneme_dyntorsion as dyn
from dyntorsion.studies.contact.plectoneme_scene import DYN_DT, T_STAR
from dyntorsion.studies.contact.records import DATA, provenance, run_missing, write
from dyntorsion.verification import richardson

WARM = 0.2
DYN_CELLS = (30, 40, 50, 75, 100, 150, 200)
PE_ELEMENTS = (50, 75, 100, 150)
#: writhe tolerances [turns] at which the cheapest rung of each code is compared
TOLS = (0.1, 0.05, 0.02)
OUT = DATA / "bench" / "plectoneme_matched.json"
ROOTS = ("dyntorsion.beyond.contact.run:run_contact_scene",)
#: which invocation of this script made a run (set in main, inherited by the workers)
INVOCATION = "PLECTONEME_MATCHED_INVOCATION"


def params() -> dict:
    return {"t_star": T_STAR, "warm_up": WARM, "dyntorsion_cells": list(DYN_CELLS),
            "dyntorsion_dt": DYN_DT, "pyelastica_elements": list(PE_ELEMENTS),
            "tols": list(TOLS), "pyelastica_scene": pe.params(T_STAR),
            "dyntorsion_scene": dyn.contact_scene(DYN_CELLS[-1], DYN_DT).params()}  # fmt: skip


def dyntorsion_run(n: int) -> dict:
    from dyntorsion.beyond.contact.run import run_contact_scene

    run_contact_scene(dyn.contact_scene(n, DYN_DT), WARM)
    tick = time.perf_counter()
    run = run_contact_scene(dyn.contact_scene(n, DYN_DT), T_STAR)
    wall = time.perf_counter() - tick
    res, h = run.result(), run.history
    return {"n": n, "wall": wall, "invocation": os.environ.get(INVOCATION), "stopped": res["stopped"],
            "t_last": float(res["t_last"]), "writhe": float(res["writhe_turns"]),
            "end_mm": 1e3 * float(h["r"][-1][-1, 2])}  # fmt: skip


def pyelastica_run(n: int) -> dict:
    pe.N_ELEM, pe.DT = n, 0.0025 * pe.LENGTH / n  # the example's rule on this rung
    pe.run(WARM)
    tick = time.perf_counter()
    out = pe.run(T_STAR)
    wall = time.perf_counter() - tick
    return {"n": n, "wall": wall, "invocation": os.environ.get(INVOCATION), "stopped": "t_end",
            "t_last": float(out["t"][-1]), "writhe": float(out["writhe_turns"][-1]),
            "end_mm": 1e3 * float(out["end_axial_position"][-1]), "steps": out["steps"]}  # fmt: skip


def analysis(record: dict) -> dict:
    """Each code's limit of the writhe and of the sliding end's position at t* (Richardson
    on its three finest rungs, :func:`dyntorsion.verification.richardson`, h = 1/n), each
    rung's error against it, and the comparisons at matched accuracy: for each PyElastica
    rung, the cheapest dyntorsion rung at least as accurate; for each tolerance, the
    cheapest rung of each code within it (None: not on its ladder)."""
    out: dict = {"codes": {}, "pairs": [], "tols": []}
    for code in ("dyntorsion", "pyelastica"):
        rows = sorted((r for r in record[code] if r["stopped"] == "t_end"), key=lambda r: r["n"])
        h = [1.0 / r["n"] for r in rows]
        lim = {q: richardson(h, [r[q] for r in rows]) for q in ("writhe", "end_mm")}
        out["codes"][code] = {
            "limit": {q: (None if v is None else {"value": v[0], "order": v[1]})
                      for q, v in lim.items()},
            "rungs": [{"n": r["n"], "wall": r["wall"], "writhe": r["writhe"], "end_mm": r["end_mm"],
                       **{f"{q}_error": (None if lim[q] is None else abs(r[q] - lim[q][0]))
                          for q in ("writhe", "end_mm")}} for r in rows],
        }  # fmt: skip
    dyn, pe = (out["codes"][c]["rungs"] for c in ("dyntorsion", "pyelastica"))
    if all(r["writhe_error"] is not None for r in dyn + pe):
        for p in pe:
            ok = [d for d in dyn if d["writhe_error"] <= p["writhe_error"]]
            d = min(ok, key=lambda d: d["wall"]) if ok else None
            out["pairs"].append({"pyelastica": p, "dyntorsion": d,
                                 "ratio": None if d is None else p["wall"] / d["wall"]})  # fmt: skip
        for tol in TOLS:
            best = {}
            for code, rungs in (("dyntorsion", dyn), ("pyelastica", pe)):
                ok = [r for r in rungs if r["writhe_error"] <= tol]
                best[code] = min(ok, key=lambda r: r["wall"]) if ok else None
            out["tols"].append({"tol": tol, **best})
    return out


def table(record: dict) -> list[str]:
    a = record["analysis"]
    lines = [f"Plectoneme scene to {T_STAR:g} s; errors against each code's own limit:"]
    for code, c in a["codes"].items():
        lim = c["limit"]["writhe"]
        lines.append(f"  {code}: writhe limit "
                     + ("none (no order observed)" if lim is None
                        else f"{lim['value']:.4f} turns (observed order {lim['order']:.2f})"))  # fmt: skip
        for r in c["rungs"]:
            err = "-" if r["writhe_error"] is None else f"{r['writhe_error']:.4f}"
            lines.append(f"    n = {r['n']:3d}: {r['wall']:8.1f} s, writhe {r['writhe']:.4f} "
                         f"(error {err}), end {r['end_mm']:.2f} mm")  # fmt: skip
    for pair in a["pairs"]:
        p, d = pair["pyelastica"], pair["dyntorsion"]
        lines.append(f"  as accurate as PyElastica n = {p['n']} ({p['writhe_error']:.3f} turns, "
                     f"{p['wall']:.1f} s): "
                     + ("no dyntorsion rung" if d is None else
                        f"dyntorsion N = {d['n']} ({d['writhe_error']:.3f}, {d['wall']:.1f} s), "
                        f"ratio {pair['ratio']:.0f}"))  # fmt: skip
    for t in a["tols"]:
        parts = [f"{c} " + ("not on its ladder" if t[c] is None else f"n = {t[c]['n']} in "
                 f"{t[c]['wall']:.1f} s") for c in ("dyntorsion", "pyelastica")]  # fmt: skip
        lines.append(f"  writhe within {t['tol']:g} turns: " + ", ".join(parts))
    return lines


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--print", action="store_true", help="print the recorded table only")
    if ap.parse_args(argv).print:
        print("\n".join(table(json.loads(OUT.read_text()))))
        return 0
    os.environ[INVOCATION] = f"{os.getpid()}-{time.time():.0f}"
    # the scenes' code, not the record helpers' (they run and write, computing no number)
    imports = (dyn.__name__, dyn.SCENE, pe.__file__)
    code = provenance(__file__, ROOTS, imports) | {"pyelastica": version("pyelastica")}
    record = {"params": params(), "code": code, "dyntorsion": [], "pyelastica": []}
    record = run_missing(
        OUT, record,
        {"dyntorsion": [(n,) for n in DYN_CELLS], "pyelastica": [(n,) for n in PE_ELEMENTS]},
        {"dyntorsion": dyntorsion_run, "pyelastica": pyelastica_run},
        {"dyntorsion": lambda r: (r["n"],), "pyelastica": lambda r: (r["n"],)},
        lambda part, args, row: f"{part} n = {row['n']}: {row['wall']:.1f} s, writhe "
        f"{row['writhe']:.4f}, end {row['end_mm']:.2f} mm",
        processes=1, indent=1,
    )  # fmt: skip
    record["analysis"] = analysis(record)
    write(OUT, record, indent=1)
    print("\n".join(table(record)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
