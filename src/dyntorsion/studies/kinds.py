"""The record kinds the studies write, and where the computation of each starts (the roots
of its code fingerprint, :func:`dyntorsion.store.fingerprint.register_kind`)."""

from __future__ import annotations

from ..store.fingerprint import register_kind

__all__ = ["KINDS"]

#: the ends and loads a scene is keyed by are part of every scene's computation
_SCENE = (
    "dyntorsion.buckling.spec:Scene",
    "dyntorsion.buckling.loading",
    "dyntorsion.buckling.loads",
    "dyntorsion.buckling.seed",
    "dyntorsion.model.ends",
)
KINDS: dict[str, tuple[str, ...]] = {
    "buckling-onset": ("dyntorsion.buckling.scene:run_scene", *_SCENE),
    "linear-onset": (
        "dyntorsion.beyond.predictions:run_prediction",
        "dyntorsion.beyond.predictions:Prediction",
        *_SCENE,
    ),
    "onset-rules": ("dyntorsion.buckling.onset_rules:run_rules", *_SCENE),
    "onset-trace": ("dyntorsion.studies.traces:compare", *_SCENE),
    "wave-convergence": ("dyntorsion.studies.wave_convergence:convergence",),
    "after-onset": (
        "dyntorsion.studies.after_onset:study",
        "dyntorsion.studies.after_onset:params",
        *_SCENE,
    ),
    "accuracy-runs": (
        "dyntorsion.studies.accuracy_runs:study",
        "dyntorsion.studies.accuracy_runs:params",
        *_SCENE,
    ),
    "tolerance-tables": (
        "dyntorsion.studies.tolerance_tables:study",
        "dyntorsion.studies.tolerance_tables:params",
        *_SCENE,
    ),
    "consistency-tables": (
        "dyntorsion.studies.consistency_tables:study",
        "dyntorsion.studies.consistency_tables:params",
        *_SCENE,
    ),
    "preset-endings": (
        "dyntorsion.studies.preset_endings:study",
        "dyntorsion.studies.preset_endings:params",
        *_SCENE,
    ),
    "contact-run": (
        "dyntorsion.beyond.contact.run:run_contact_scene",
        "dyntorsion.beyond.contact.run:ContactScene",
        *_SCENE,
    ),
}
for _kind, _roots in KINDS.items():
    register_kind(_kind, _roots)
