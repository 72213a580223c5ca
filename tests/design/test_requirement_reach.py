"""The reach of a macro design space toward a safety requirement it cannot meet (issue 27, item 4: the best value
reached and the bounds that stop it, from the elastic mode and its multipliers).

References nobody here wrote the numbers of: :func:`gearopt.rating.rate_iso6336` called on the pair directly at the
reported macro values, an exhaustive grid scan of the same space, and finite differences of the least relaxation
against a moved bound (the multiplier is its first-order estimate). The train is the minimal pair with other names
(any train)."""

import dataclasses
import tomllib
import warnings
from pathlib import Path

import numpy as np
import pytest

import gearopt as go
from gearopt.data import system_from_data
from gearopt.design.recommendation import recommend
from gearopt.design.requirement_reach import DesignSpace, rating_reach, reach_table
from gearopt.design.requirements import TrainDesign
from gearopt.design.scene_spec import DesignVariable, Limit
from gearopt.errors import GearoptInputError
from gearopt.rating import RatingValidityWarning, StiffnessValidityWarning, rate_iso6336

MINIMAL = Path(go.__file__).parent / "data" / "minimal_train.toml"
MESH = "sun_gear-drum_gear"
SPEED = {MESH: 1500.0}
DYNAMIC = {"application_factor": 1.0, "K_v": 1.0}


@pytest.fixture(scope="module")
def system():
    text = MINIMAL.read_text().replace("pinion-wheel", MESH).replace("pinion", "sun_gear").replace("wheel",
                                                                                                   "drum_gear")
    return system_from_data(tomllib.loads(text), source="renamed.toml")


def _space(helix_max=8.0, shift=(0.0, 0.5)):
    return DesignSpace((DesignVariable("root_profile_shift", "train", lower=shift[0], upper=shift[1]),
                        DesignVariable("helix_angle_deg", "train", lower=0.0, upper=helix_max)),
                       (Limit("geometry_limits", MESH, options=dict(min_contact_ratio=1.1)),))


def _S_H(system, shift, helix, torque):
    train = dataclasses.replace(system.train("spur"), root_profile_shift=shift, helix_angle_deg=helix)
    grades = tuple(g.accuracy_grade_iso1328 for g in system.gears.values())
    with warnings.catch_warnings():         # the grid visits shifts outside the stiffness formula's validity
        warnings.simplefilter("ignore", RatingValidityWarning)
        warnings.simplefilter("ignore", StiffnessValidityWarning)
        s = rate_iso6336(train.pairs[MESH], torque, SPEED[MESH], accuracy_grade=grades, **DYNAMIC).safety_factors
    return [float(x) for x in s["S_H"]]


def _min_S_H(system, shift, helix, torque):
    return min(_S_H(system, shift, helix, torque))


def test_a_reachable_requirement_is_met_at_a_design_the_rating_confirms(system):
    reach = rating_reach(system, system.train("spur"), _space(), {MESH: 150.0}, SPEED, {"S_H": 1.0},
                         rating_options=DYNAMIC)["S_H"]
    assert reach.meets and reach.best_value >= 1.0 * (1 - 1e-6)
    v = reach.values
    assert reach.best_value == pytest.approx(_min_S_H(system, v["root_profile_shift"], v["helix_angle_deg"], 150.0),
                                             rel=1e-9)
    assert "meets it" in reach.text()


def test_an_unreachable_requirement_reports_the_best_of_the_space_and_the_bound_that_stops_it(system):
    torque = 250.0
    reach = rating_reach(system, system.train("spur"), _space(helix_max=4.0), {MESH: torque}, SPEED, {"S_H": 1.0},
                         rating_options=DYNAMIC)["S_H"]
    assert not reach.meets
    # an exhaustive scan of the same space (converged reference) finds nothing better than the reach, within 0.5 %
    grid = max(_min_S_H(system, x, b, torque) for x in np.linspace(0.0, 0.5, 11) for b in np.linspace(0.0, 4.0, 9))
    assert grid < 1.0
    assert reach.best_value == pytest.approx(grid, rel=5e-3)
    v = reach.values
    assert reach.best_value == pytest.approx(_min_S_H(system, v["root_profile_shift"], v["helix_angle_deg"], torque),
                                             rel=1e-9)
    # S_H rises with the helix angle here: its upper bound stops the reach, and the sentence says so
    assert _min_S_H(system, v["root_profile_shift"], 4.0, torque) > _min_S_H(system, v["root_profile_shift"], 2.0,
                                                                               torque)
    stop = [s for s in reach.stopped_by if s["name"] == "helix_angle_deg"]
    assert stop and stop[0]["side"] == "upper" and stop[0]["kind"] == "bound" and stop[0]["multiplier"] < 0
    assert "no design of the space" in reach.text() and "upper bound of helix_angle_deg" in reach.text()
    # the multiplier is the first-order change of the least summed shortfall when the bound moves: a finite
    # difference of two reaches 0.2 deg apart agrees within 10 %
    wider = rating_reach(system, system.train("spur"), _space(helix_max=4.2), {MESH: torque}, SPEED, {"S_H": 1.0},
                         rating_options=DYNAMIC)["S_H"]
    def summed_shortfall(r):         # sum over the rated gears of max(limit - S_H, 0), rated directly
        return sum(max(1.0 - x, 0.0) for x in _S_H(system, r.values["root_profile_shift"],
                                                     r.values["helix_angle_deg"], torque))
    slope = (summed_shortfall(wider) - summed_shortfall(reach)) / 0.2
    assert slope < 0 and slope == pytest.approx(stop[0]["multiplier"], rel=0.1)
    table = reach_table({"S_H": reach})
    assert list(table["requirement"]) == ["S_H"] and not table["meets"].iloc[0]


def test_recommend_adds_the_reach_to_a_failing_safety(system):
    strict = dataclasses.replace(system, requirements=dataclasses.replace(system.requirements, min_S_H=2.5))
    rec = recommend(strict, [TrainDesign(strict.train("spur"), name="as drawn")], size_joints=False,
                    design_space=_space())
    row = rec.check.row("S_H", "all rated meshes")
    assert row.verdict == "FAIL" and not row.fixed
    assert row.what_it_would_take.startswith("no design of the space (root_profile_shift 0..0.5, helix_angle_deg "
                                             "0..8)")
    assert "the torque must fall" in row.what_it_would_take          # the smallest change is still there
    found = row.detail["design_space_reach"]
    assert found["best_value"] >= row.value and not found["meets"]
    assert rec.as_json()["requirements"]       # JSON-ready


def test_bad_reach_calls_are_named(system):
    train = system.train("spur")
    with pytest.raises(GearoptInputError, match="S_X"):
        rating_reach(system, train, _space(), {MESH: 100.0}, SPEED, {"S_X": 1.0})
    with pytest.raises(GearoptInputError, match="speeds_rpm"):
        rating_reach(system, train, _space(), {MESH: 100.0}, {}, {"S_H": 1.0})
    with pytest.raises(GearoptInputError, match="both bounds"):
        DesignSpace((DesignVariable("root_profile_shift", "train", lower=0.0),))
    with pytest.raises(GearoptInputError, match="target 'train'"):
        DesignSpace((DesignVariable("profile_shift_1", MESH, lower=0.0, upper=0.5),))


def test_a_known_reach_of_the_same_signature_is_taken_not_solved_again(system, monkeypatch):
    """``recommend(known_reaches=...)``: a reach computed before for the same space, requirement, limit, torques,
    speeds and rating keywords (its signature, kept through JSON) is reused; another signature is solved."""
    import gearopt.design.recommendation as recommendation
    from gearopt.design.requirement_reach import RequirementReach

    strict = dataclasses.replace(system, requirements=dataclasses.replace(system.requirements, min_S_H=2.5))
    design = TrainDesign(strict.train("spur"), name="as drawn")
    first = recommend(strict, [design], size_joints=False, design_space=_space())
    row = first.check.row("S_H", "all rated meshes")
    known = RequirementReach.from_json(row.detail["design_space_reach"])
    assert known.signature["torques_Nm"] == row.detail["torques_Nm"]

    def no_solve(*args, **kwargs):
        raise AssertionError("rating_reach called although a known reach matches")
    monkeypatch.setattr(recommendation, "rating_reach", no_solve)
    again = recommend(strict, [design], size_joints=False, design_space=_space(), known_reaches=[known])
    assert again.check.row("S_H", "all rated meshes").what_it_would_take == row.what_it_would_take
    with pytest.raises(AssertionError, match="known reach"):        # another space: solved (here: refused)
        recommend(strict, [design], size_joints=False, design_space=_space(helix_max=4.0), known_reaches=[known])
