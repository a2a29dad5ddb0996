"""Round-off past self-contact: runs of the committed contact records repeated with other
arithmetic, each in its own process -> data/contact/roundoff.json.

Variants of each run (:data:`VARIANTS`):

* ``pinned``: OpenBLAS's Haswell kernels and NumPy's AVX2 loops, what ``make`` asks for
  and what the committed records were computed with (:mod:`dyntorsion.store.environment`):
  it must repeat the committed record's numbers bit for bit;
* ``native``: the kernels and loops this machine picks itself (on a processor with AVX-512:
  OpenBLAS's SkylakeX kernels and NumPy's AVX-512 loops; not run where that is the same
  as ``pinned``);
* ``seed``: pinned, with the seed's force multiplied by 1 + 1e-10 (a perturbation of the
  size of round-off in the onset, the same on any machine).

The spread of each number over the variants is how many of its digits the arithmetic
decides.  ``make roundoff`` (one process a run, two at once).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from ...store.environment import cpu_has_avx512, numpy_avx512_groups
from .records import DATA, provenance, result_json, write

OUT = DATA / "contact" / "roundoff.json"
ROOTS = ("dyntorsion.beyond.contact.run:run_contact_scene",)
SEED_FACTOR = 1.0 + 1e-10

#: the runs repeated: (name, the record it comes from, how to find it there)
RUNS = (
    ("a16-first-contact-N400", "first_contact.json: runs N = 400, max_step 2.5e-4"),
    ("a16-past-N400", "first_contact.json: past N = 400, lambda -0.8, to 3.3 s, time route"),
    ("a16-past-N800", "first_contact.json: past N = 800, lambda -0.8, to 3.3 s, time route"),
    ("pyelastica-scene-N100-20s", "plectoneme_matched.json: dyntorsion N = 100 to 20 s"),
    ("fig07-continued-N800", "fig07_continued.json: N = 800, lambda -0.8, to 17.6 s"),
)
#: the numbers compared
QUANTITIES = ("first_contact_t", "first_self_contact_t", "max_penetration_over_D",
              "energy_residual", "max_link_gap_turns", "link_turns", "twist_turns",
              "writhe_turns", "max_contact_sites", "steps", "t_last")  # fmt: skip


def variants() -> dict[str, dict[str, str]]:
    """The environment variables of each variant (module docstring)."""
    pinned = {"OPENBLAS_CORETYPE": "Haswell", "NPY_DISABLE_CPU_FEATURES": numpy_avx512_groups()}
    out = {"pinned": pinned}
    if cpu_has_avx512():
        out["native"] = {"OPENBLAS_CORETYPE": "", "NPY_DISABLE_CPU_FEATURES": ""}
    out["seed"] = pinned | {"ROUNDOFF_SEED_FACTOR": repr(SEED_FACTOR)}
    return out


def one(name: str) -> dict:
    """Run ``name`` in this process (its arithmetic set by the environment)."""
    factor = float(os.environ.get("ROUNDOFF_SEED_FACTOR", "1"))
    if factor != 1.0:
        from ...buckling.seed import Perturbation

        force = Perturbation.force
        Perturbation.force = lambda self, *a, **k: factor * force(self, *a, **k)
    from ...beyond.contact.run import run_contact_scene
    from ...store.environment import numerical_environment

    if name == "a16-first-contact-N400":
        from . import contact_convergence as cc

        res = cc.grid_run(400, 2.5e-4)
    elif name in ("a16-past-N400", "a16-past-N800"):
        from . import contact_convergence as cc

        res = cc.past_run(400 if name.endswith("400") else 800, -0.8, 3.3, "time")["result"]
    elif name == "pyelastica-scene-N100-20s":
        from . import plectoneme_dyntorsion as dyn
        from . import plectoneme_scene as pm

        res = run_contact_scene(dyn.contact_scene(100, pm.DYN_DT), pm.T_STAR).result()
    elif name == "fig07-continued-N800":
        from . import fig07_continued as f7

        res = run_contact_scene(f7.contact_scene(800, -0.8, 17.6)).result()
    else:
        raise ValueError(f"run name={name!r}; allowed: {[r[0] for r in RUNS]}")

    res = json.loads(result_json(res))
    return {"environment": numerical_environment(),
            **{q: res.get(q) for q in QUANTITIES}, "stopped": res.get("stopped")}  # fmt: skip


def _child(name: str, variant: str, env: dict[str, str]) -> dict:
    full = dict(os.environ)
    for k, v in env.items():
        if v:
            full[k] = v
        else:
            full.pop(k, None)
    full["OPENBLAS_NUM_THREADS"] = "1"
    done = subprocess.run([sys.executable, "-m", __spec__.name, "--one", name], env=full,
                          capture_output=True, text=True)  # fmt: skip
    if done.returncode != 0:
        raise RuntimeError(f"{name} ({variant}) failed:\n{done.stderr[-2000:]}")
    return {"run": name, "variant": variant, **json.loads(done.stdout.splitlines()[-1])}


def spread(rows: list[dict]) -> dict:
    """For each run and number, the largest distance of a variant from ``pinned``."""
    out: dict[str, dict] = {}
    for name, _ in RUNS:
        by = {r["variant"]: r for r in rows if r["run"] == name}
        if "pinned" not in by:
            continue
        base = by["pinned"]
        out[name] = {}
        for q in QUANTITIES:
            far = [abs(r[q] - base[q]) for v, r in by.items()
                   if v != "pinned" and r[q] is not None and base[q] is not None]  # fmt: skip
            out[name][q] = max(far) if far else None
    return out


def committed(name: str, data: Path = DATA) -> dict:
    """The numbers of run ``name`` in the committed record it comes from (:data:`RUNS`):
    those of :data:`QUANTITIES` the record keeps."""

    def find(rel, part, key, want):
        rows = json.loads((data / rel).read_text()).get(part, [])
        for row in rows:
            if key(row) == want:
                return row
        raise LookupError(
            f"run {name!r}: {rel} holds no {part} entry {want!r} (a record not "
            f"written yet, or half written): compute that record first"
        )

    if name.startswith("a16-"):
        rel = "contact/first_contact.json"
        if name == "a16-first-contact-N400":
            res = find(rel, "runs", lambda r: (r["n_cells"], r["max_step"]), (400, 2.5e-4))
        else:
            n = 400 if name.endswith("400") else 800
            res = find(rel, "past", lambda p: (p["n_cells"], p["lam_t"], p["t_end"], p["route"]),
                       (n, -0.8, 3.3, "time"))["result"]  # fmt: skip
    elif name == "pyelastica-scene-N100-20s":
        row = find("bench/plectoneme_matched.json", "dyntorsion", lambda r: r["n"], 100)
        res = {"writhe_turns": row["writhe"], "t_last": row["t_last"], "stopped": row["stopped"]}
    elif name == "fig07-continued-N800":
        res = find("contact/fig07_continued.json", "runs", lambda r: r["n_cells"], 800)["result"]
    else:
        raise ValueError(f"run name={name!r}; allowed: {[r[0] for r in RUNS]}")
    return {q: res[q] for q in (*QUANTITIES, "stopped") if q in res}


def reproduced(rows: list[dict], data: Path = DATA) -> dict[str, list[str]]:
    """For each run, the numbers of its ``pinned`` variant that differ from the committed
    record's (an empty list: the record repeated bit for bit)."""
    out = {}
    for row in rows:
        if row["variant"] == "pinned":
            then = committed(row["run"], data)
            out[row["run"]] = [q for q, v in then.items() if row[q] != v]
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--jobs", type=int, default=2, help="runs at once (processes)")
    ap.add_argument("--one", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.one:
        print(json.dumps(one(args.one)))
        return 0
    var = variants()
    imports = tuple(f"{__package__}.{m}" for m in ("contact_convergence", "plectoneme_dyntorsion",
                                                   "plectoneme_scene", "fig07_continued"))  # fmt: skip
    record = {"params": {"runs": [list(r) for r in RUNS], "variants": var,
                         "seed_factor": SEED_FACTOR, "quantities": list(QUANTITIES)},
              "code": provenance(__spec__.name, ROOTS, imports), "runs": []}  # fmt: skip
    jobs = [(name, v) for name, _ in RUNS for v in var]
    jobs.sort(key=lambda j: ("fig07" not in j[0], "N800" not in j[0]))  # the longest first
    with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        futures = [pool.submit(_child, name, v, var[v]) for name, v in jobs]
        for fut in futures:
            row = fut.result()
            record["runs"].append(row)
            record["runs"].sort(key=lambda r: jobs.index((r["run"], r["variant"])))
            record["spread"] = spread(record["runs"])
            record["pinned_differs_from_committed"] = reproduced(record["runs"])
            write(OUT, record, indent=1)
            print(f"{row['run']} ({row['variant']}): first self-contact "
                  f"{row['first_self_contact_t']}, penetration {row['max_penetration_over_D']}, "
                  f"energy residual {row['energy_residual']}, writhe {row['writhe_turns']}",
                  flush=True)  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
