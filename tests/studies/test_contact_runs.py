"""Runs past contact as records of the store (dyntorsion.studies.contact_runs, kind
"contact-run"): computed once, read back identical, keyed by the whole contact scene."""

from __future__ import annotations

import json
import math

import pytest

from dyntorsion import Rod
from dyntorsion.app.cli import main
from dyntorsion.beyond.contact.run import Contact, ContactScene
from dyntorsion.buckling.scene import Scene
from dyntorsion.buckling.seed import Perturbation
from dyntorsion.buckling.turning import TurnHold
from dyntorsion.genalpha.scheme import Scheme
from dyntorsion.store.results import Store
from dyntorsion.studies.contact_runs import KIND, contact_run

ROD = Rod(E=1e6, nu=-0.25, D=0.05, L=1.0, rho=1.0 / (math.pi * 0.025**2))


def scene(turns: float = 3.0) -> ContactScene:
    """PyElastica's plectoneme rod turned fast enough to touch itself within 6 s."""
    sc = Scene(history=TurnHold(turns, 4.0, tau=0.1), ends="clamped-turned", rod=ROD, n_cells=30,
               dt=0.01, t_end=6.0, scheme=Scheme(lam_t=-0.8), seed=Perturbation(1e-3, form="point"))  # fmt: skip
    return ContactScene(sc, Contact(stiffness=1e7, viscous=2.0, viscous_moment=2.0, max_step=0.01))


def test_a_run_past_contact_is_computed_once_and_read_back(tmp_path):
    first, cached = contact_run(scene(), tmp_path)
    assert not cached and first["summary"]["first_self_contact_t"] is not None
    again, cached = contact_run(scene(), tmp_path)
    assert cached and again == first
    assert len(first["history"]["t"]) == len(first["history"]["end_moment"]) > 10
    assert len(first["final_centreline"]) == 31
    (path,) = tmp_path.glob(f"{KIND}-*.json")
    assert Store(tmp_path).read(path)["params"] == json.loads(json.dumps(scene().params()))


def test_another_contact_or_scene_is_not_served_the_record(tmp_path, monkeypatch):
    contact_run(scene(), tmp_path)
    import dyntorsion.studies.contact_runs as C

    calls = []
    real = C.run_contact_scene
    monkeypatch.setattr(C, "run_contact_scene", lambda cs: calls.append(cs) or real(cs))
    other = ContactScene(scene().scene, Contact(stiffness=2e7, viscous=2.0, viscous_moment=2.0,
                                                max_step=0.01))  # fmt: skip
    contact_run(other, tmp_path)
    contact_run(scene(2.5), tmp_path)
    assert len(calls) == 2 and len(list(tmp_path.glob(f"{KIND}-*.json"))) == 3


def test_the_cli_reads_a_stored_contact_run(tmp_path, capsys):
    args = ["buckle", "--ends", "clamped-turned", "--history", "turn-hold:3,4", "--kappa0", "0",
            "--E", "1e6", "--nu", "-0.25", "--D", "0.05", "--rho", str(1.0 / (math.pi * 0.025**2)),
            "--seed", "1e-3", "--seed-form", "point", "--n-cells", "30", "--dt", "0.01",
            "--lam-t", "-0.8", "--contact", "--t-end", "6", "--contact-stiffness", "1e7",
            "--contact-max-step", "0.01", "--viscous", "2", "--viscous-moment", "2",
            "--store", str(tmp_path), "--json"]  # fmt: skip
    main(args)
    one = json.loads(capsys.readouterr().out)
    main(args)
    two = json.loads(capsys.readouterr().out)
    assert not one.pop("cached") and two.pop("cached") and one == two
    assert one["plectoneme_turns"] is not None


def test_the_cli_passes_the_contact_options_and_names_a_bad_one(monkeypatch, capsys):
    """--contact-min-arc and the other --contact-* options reach the Contact; a value out of
    range is refused with the parameter's name and range, before any run."""
    import dyntorsion.app.contact_cli as cli

    seen = {}

    class Done:
        def result(self):
            return {"stopped": "t_end", "max_penetration_over_D": 0.0,
                    "max_link_gap_turns": 0.0, "energy_residual_scheme": 0.0}  # fmt: skip

    def fake(cs):
        seen["contact"] = cs.contact
        return Done()

    monkeypatch.setattr(cli, "run_contact_scene", fake)
    base = ["buckle", "--a", "16", "--kappa0", "10", "--contact", "--t-end", "3.3",
            "--fidelity", "quick", "--json"]  # fmt: skip
    assert main(base + ["--contact-min-arc", "1.5", "--contact-stiffness", "2e7",
                        "--contact-max-cell-bend", "2"]) == 0  # fmt: skip
    c = seen["contact"]
    assert (c.min_arc, c.stiffness, c.max_cell_bend) == (1.5, 2e7, 2.0)
    capsys.readouterr()
    seen.clear()
    assert main(base + ["--contact-min-arc", "0.5"]) != 0
    assert "min_arc=0.5 must be >= 1" in capsys.readouterr().err and not seen


def test_only_contact_scenes_are_cached():
    with pytest.raises(TypeError, match="ContactScene"):
        contact_run(scene().scene)
