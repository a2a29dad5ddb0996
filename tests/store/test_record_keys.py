"""Every committed record of a scene's kind has the key its parameters give today: a scene
rebuilt from a record's ``params`` (:meth:`Scene.from_params`) has the same params and
therefore the same key, so no record is orphaned by a change of how scenes are built.
(The page records beside them are keyed by a page's settings, not by a scene.)"""

from __future__ import annotations

import json
from collections import Counter

from dyntorsion.beyond.predictions import Prediction
from dyntorsion.buckling import onset_rules
from dyntorsion.buckling.scene import Scene
from dyntorsion.buckling.seed import Perturbation
from dyntorsion.model.rod import Rod
from dyntorsion.store import location
from dyntorsion.store.results import key
from dyntorsion.studies import linear_predictions, sweep, traces

#: the record kinds keyed by a scene's params
SCENE_KINDS = {sweep.KIND, linear_predictions.KIND, onset_rules.KIND, traces.KIND}


def _scene_params(kind: str, p: dict) -> dict:
    """The params of ``kind`` rebuilt from a record's ``p`` through a fresh Scene."""
    if kind == linear_predictions.KIND:
        seed = dict(p["perturbation"], direction=tuple(p["perturbation"]["direction"]))
        linear = {k: v for k, v in p["linear"].items() if k != "quadrature"}
        scene = Scene(
            a=p["a"], kappa0=p["kappa0"], rod=Rod.from_params(p["rod"]),
            seed=Perturbation(**seed), t_end=1.0,
        )  # fmt: skip
        return Prediction(scene, **linear).params()
    extra = {k: p[k] for k in ("linear", "samples") if k in p}
    scene = {k: v for k, v in p.items() if k not in extra}
    return Scene.from_params(scene).params() | extra


def test_every_committed_record_keeps_its_key():
    root = location.DATA
    paths = sorted(root.glob("*.json"))
    assert len(paths) > 100, f"no records found in {root}"
    seen: Counter[str] = Counter()
    for path in paths:
        rec = json.loads(path.read_text())
        if rec["kind"] not in SCENE_KINDS:
            continue
        again = _scene_params(rec["kind"], rec["params"])
        assert json.loads(json.dumps(again)) == rec["params"], path.name
        assert key(rec["kind"], again) == rec["key"] == path.stem.rsplit("-", 1)[1], path.name
        seen[rec["kind"]] += 1
    assert set(seen) == SCENE_KINDS
