"""Compare the buckling records of an older commit with the current store, scene by scene.

Old records (any earlier key layout) are mapped to today's :class:`~dyntorsion.buckling.scene.Scene`
and looked up by today's key; their results are compared entry by entry.  Prints one line
per preset-level summary and every scene whose numbers differ.

    python -m dyntorsion.studies.compare_records 6fcb9be [--store data/scenes]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from collections import Counter

from .. import genalpha as ga
from ..buckling import Perturbation
from ..model.rod import Rod
from ..store import location as L
from ..store import results as R
from . import sweep as S


def old_records(commit: str, kind: str = S.KIND) -> list[dict]:
    names = subprocess.run(
        ["git", "ls-tree", "--name-only", f"{commit}:data/scenes"],
        capture_output=True, text=True, check=True,
    ).stdout.split()  # fmt: skip
    out = []
    for name in names:
        if name.startswith(kind + "-"):
            text = subprocess.run(
                ["git", "show", f"{commit}:data/scenes/{name}"],
                capture_output=True,
                text=True,
                check=True,
            ).stdout
            out.append(json.loads(text))
    return out


def scene_of(p: dict) -> S.Scene:
    """Today's Scene for an old params dict (an earlier key layout) or a current one."""
    if "history" in p:
        return S.Scene.from_params(p)
    model = p.get("model", {})
    seed = dict(p["perturbation"])
    seed["direction"] = tuple(seed["direction"])
    return S.Scene(
        a=p["a"],
        kappa0=p["kappa0"],
        rod=Rod(**p["rod"]),
        seed=Perturbation(**seed),
        n_cells=p["n_cells"],
        dt=p["dt"],
        t_end=p["t_end"],
        scheme=ga.Scheme(**p["scheme"]),
        newton=ga.Newton(**p["newton"]),
        window=tuple(p["onset"]["window"]),
        variations=tuple(tuple(v) for v in p["onset"]["variations"]),
        terms=tuple(model.get("terms", {}).items()),
        rotary_inertia_scale=model.get("rotary_inertia_scale", 1.0),
    )


def compare(old: dict, new: dict) -> tuple[str, float, list[str]]:
    """'identical' or 'differs', the largest relative change of a shared number, and the
    entries that changed other than by a float (a status, a stop reason, a count)."""
    worst, other = 0.0, []
    for k, v in old.items():
        w = new.get(k)
        if isinstance(v, float) and isinstance(w, float):
            worst = max(worst, abs(w - v) / max(abs(v), 1e-300))
        elif k == "stopped" and isinstance(v, str):
            if v.split(" (")[0] != str(w).split(" (")[0]:
                other.append(f"stopped: {v!r} -> {w!r}")
        elif v != w:
            other.append(k)
    same = worst == 0.0 and not other
    return ("identical" if same else "differs"), worst, other


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("commit")
    ap.add_argument("--store", default=str(L.default_store()))
    args = ap.parse_args(argv)
    store = R.Store(args.store)
    tally: Counter = Counter()
    worst, t_c_worst, t_c_ratio = 0.0, (0.0, ""), (0.0, "")
    for rec in old_records(args.commit):
        sc = scene_of(rec["params"])
        path = store.path(S.KIND, sc.params())
        if not path.exists():
            tally["not recomputed"] += 1
            continue
        new = store.read(path)
        old_r, new_r = rec["result"], new["result"]
        verdict, rel, other = compare(old_r, new_r)
        tally[verdict] += 1
        if verdict != "identical":
            worst = max(worst, rel)
            also = f"; also changed: {', '.join(other)}" if other else ""
            print(f"{verdict} (largest relative change {rel:.2g}{also}): {sc.label()}")
        if isinstance(old_r.get("t_c"), float) and isinstance(new_r.get("t_c"), float):
            d = abs(new_r["t_c"] - old_r["t_c"])
            t_c_worst = max(t_c_worst, (d, sc.label()))
            if old_r.get("uncertainty_t"):
                t_c_ratio = max(t_c_ratio, (d / old_r["uncertainty_t"], sc.label()))
    print(", ".join(f"{n} {k}" for k, n in tally.items()), f"; largest relative change {worst:.2g}")
    print(f"largest |change of t_c| {t_c_worst[0]:.3g} s ({t_c_worst[1]})")
    print(f"largest |change of t_c| / onset uncertainty {t_c_ratio[0]:.3g} ({t_c_ratio[1]})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
