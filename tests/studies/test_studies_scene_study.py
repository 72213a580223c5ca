"""scene_study: a sensitivity report that cannot be made (the optimum is not a regular local optimum) is said in the
study, and the front and the Monte Carlo still come (issue 13: a failed part is recorded, the study goes on)."""

import importlib

import pytest

from gearopt.errors import GearoptInputError

from studies_scenes import MESH, relief_scene


scene_study_module = importlib.import_module("gearopt.studies.scene_study")  # the module, not the function


@pytest.mark.filterwarnings("ignore")
def test_a_failed_sensitivity_report_is_recorded_and_the_study_goes_on(monkeypatch):
    def not_regular(result, **_):
        raise GearoptInputError("the parametric re-solve moved crank-cam.tip_relief_1_um and the objective")

    monkeypatch.setattr(scene_study_module, "sensitivity_report", not_regular)
    study = scene_study_module.scene_study(relief_scene(), "loaded_contact_ratio", MESH, points=3, samples=16,
                                           starts=1)
    assert study.sensitivity is None and "moved crank-cam.tip_relief_1_um" in study.sensitivity_error
    head = study.headline()
    assert head["sensitivities"] == [] and head["sensitivity_note"].startswith("not available: ")
    assert head["objective"]["value"] == pytest.approx(float(study.optimum.solve.objective))
    assert len(study.monte_carlo.table) == 16 and head["front"]["points"] >= 3
    assert "Sensitivities of the optimum: not available -- the parametric re-solve" in study.markdown()


@pytest.mark.filterwarnings("ignore")
def test_the_front_is_verified_and_says_where_the_requirement_cuts_it():
    """Issue 27: a trade-off front is verified by the exact LTCA by default (a column says which points were), and
    the points beyond the scene's own limit on the traded quantity are flagged, not the front."""
    scene = relief_scene()
    study = scene_study_module.scene_study(scene, "loaded_contact_ratio", MESH, points=3, samples=8, starts=1)
    t = study.front.table
    assert {"verified", "exact_objective", "meets_limit"} <= set(t.columns)
    limit = next(lim.lower for lim in scene.limits if lim.quantity == "loaded_contact_ratio")
    assert study.front.limit == limit
    q = t[study.front.quantity_column]
    assert list(t["meets_limit"]) == list(q >= limit * (1 - 1e-9))
    head = study.headline()["front"]
    assert head["verified"] == int(t.loc[t["status"] == "ok", "verified"].sum())
    assert head["beyond_requirement"] == int((~t["meets_limit"] & (t["status"] == "ok")).sum())
    text = study.markdown()
    assert "verified by the exact LTCA" in text and "local first-order estimates" in text
