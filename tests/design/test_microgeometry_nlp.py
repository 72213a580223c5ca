"""PPTE-minimising microgeometry NLP (issue 3 item 6): the optimum beats the unmodified pair and the thesis'
minimum tip relief on the exact LTCA, respects its limits, agrees with the NLP's own objective, is not beaten by a
local grid around it, and reproduces Harris' analytic optimum for constant stiffness."""

import numpy as np
import pytest

import gearopt as go
from gearopt.contact.ltca import ltca
from gearopt.contact.microgeometry import Microgeometry
from gearopt.design.microgeometry_nlp import min_tip_relief_design, optimise_microgeometry
from gearopt.errors import GearoptInputError, SolveError


@pytest.fixture(scope="module")
def crank_cam():
    return go.load_default_train("spur").pairs["crank-cam"]


@pytest.fixture(scope="module")
def design(crank_cam):
    return optimise_microgeometry(crank_cam, 300.0)


def test_optimum_beats_unmodified_and_minimum_tip_relief(design):
    t = design.table.set_index("design")
    assert t.loc["optimised", "ppte_um"] < 0.25 * t.loc["unmodified", "ppte_um"]
    assert t.loc["optimised", "ppte_um"] < t.loc["min_tip_relief", "ppte_um"]


def test_refinement_verifies_the_optimum_against_the_exact_ltca(crank_cam, design):
    """Semi-infinite refinement (default): the returned design is verified -- the smooth model's PPTE at its positions
    agrees with the exact LTCA at 1280 positions within the refinement's tolerance (2 %, or 0.01 um) -- and the
    refinement re-solved on more positions than the first solve's 40."""
    ref = design.refinement
    assert ref.attrs["verified"] and ref["positions"].max() > 40
    smooth = design.scene.quantities.set_index("quantity").loc["ppte_um", "value"]
    assert abs(smooth - design.ppte_um) <= max(0.02 * design.ppte_um, 0.01)


def test_limits_hold_on_the_exact_ltca(design):
    t = design.table.set_index("design")
    assert t.loc["optimised", "max_contact_stress_MPa"] <= t.loc["unmodified", "max_contact_stress_MPa"] * 1.002
    assert t.loc["optimised", "loaded_contact_ratio"] >= 1.2
    for k, v in design.values.items():
        assert v >= 0.0, k


def test_nlp_objective_equals_exact_ppte_of_the_optimum(crank_cam, design):
    # the blended relief is part of the design, so at a uniform 40-position grid only the contact smoothing
    # (0.05 um softplus, which lowers a gap by at most w ln 2 per flank) and the sampling separate the smooth model
    # from the exact one; the converged check (1280 positions) sees the TE between the samples too
    from gearopt.contact.ltca_smooth import LTCAModel
    sampled = ltca(crank_cam, 300.0, microgeometry=design.microgeometry, positions=40).ppte_um
    smooth = float(LTCAModel(crank_cam, positions=40).evaluate(design.microgeometry, 300.0).ppte_um)
    assert smooth == pytest.approx(sampled, abs=2 * 0.05 * np.log(2) + 1e-3)
    assert sampled <= design.ppte_um < sampled + 0.5


def test_no_better_point_on_a_local_grid(crank_cam, design):
    # a brute-force check around the optimum over the two amounts (starts and crown held)
    base = design.microgeometry
    best = design.ppte_um
    for d1 in (-0.5, 0.5):
        for d2 in (-0.5, 0.5):
            m = Microgeometry(tip_relief_um=(base.tip_relief_um[0] + d1, base.tip_relief_um[1] + d2),
                              tip_relief_start_roll_deg=base.tip_relief_start_roll_deg,
                              profile_crown_um=base.profile_crown_um, relief_smoothing_deg=base.relief_smoothing_deg)
            assert ltca(crank_cam, 300.0, microgeometry=m).ppte_um >= best - 0.02


def test_constant_stiffness_recovers_harris_relief_depth():
    # Harris (1958): with constant stiffness the TE is made constant by a linear relief over the double-contact
    # zone of depth w/c' (sum over both gears); the NLP should find (near) zero PPTE
    pair = go.GearPair.from_profile_shifts(teeth=(30, 60), profile_shifts=(0.0, 0.0), module_mm=3.0,
                                           face_width_mm=20.0)
    d = optimise_microgeometry(pair, 200.0, stiffness=14.0, groups=("tip_relief",), positions=60)
    assert d.ppte_um < 0.1 * d.exact["unmodified"][200.0].ppte_um


def test_robust_design_over_load_cases(crank_cam):
    d = optimise_microgeometry(crank_cam, [200.0, 300.0, 400.0], refine=False)   # one solve each: the comparison
    t = d.table[d.table.design == "optimised"]                                  # is of the objectives, not the
    worst = t.ppte_um.max()                                                     # refinement (tested above)
    single = optimise_microgeometry(crank_cam, 300.0, refine=False)
    worst_single = max(ltca(crank_cam, x, microgeometry=single.microgeometry).ppte_um for x in (200.0, 300.0, 400.0))
    assert worst < worst_single


def test_infeasible_stress_limit_raises_a_typed_error(crank_cam):
    with pytest.raises(SolveError) as info:
        optimise_microgeometry(crank_cam, 300.0, max_contact_stress_MPa=300.0, max_iter=200)
    assert "contact_stress" in str(info.value)


def test_bad_input_is_named(crank_cam):
    with pytest.raises(GearoptInputError, match="groups"):
        optimise_microgeometry(crank_cam, 300.0, groups=("lead_crown",))
    with pytest.raises(GearoptInputError, match="torque_Nm"):
        optimise_microgeometry(crank_cam, 0.0)


def test_min_tip_relief_design_starts_at_single_contact_boundary(crank_cam):
    m = min_tip_relief_design(crank_cam, 300.0)
    g = crank_cam.geometry()
    for i in range(2):
        assert g["pitch_point_roll_deg"][i] < m.tip_relief_start_roll_deg[i] < g["eap_roll_deg"][i]
        assert m.tip_relief_um[i] > 0


def test_multistart_returns_the_best_start_and_tables_every_start(crank_cam):
    d = optimise_microgeometry(crank_cam, [150.0, 300.0, 450.0], starts=4, seed=1, max_refinements=1)
    assert len(d.starts) == 4 and d.starts.success.any()
    # every start is refined; the best on the exact model is returned: the lowest exact objective among the
    # starts that meet every exact limit, and its exact objective is the design's
    chosen = d.starts[d.starts.chosen]
    assert len(chosen) == 1 and chosen.objective_um.iloc[0] == pytest.approx(d.ppte_um, rel=1e-9)
    admissible = d.starts[d.starts.exact_violation == 0.0]
    assert chosen.objective_um.iloc[0] == admissible.objective_um.min()
    with pytest.raises(GearoptInputError, match="starts"):
        optimise_microgeometry(crank_cam, [150.0, 300.0, 450.0], starts=0)


def test_root_stress_and_temperature_limits_are_constraints_and_infeasibility_is_named(crank_cam):
    d = optimise_microgeometry(crank_cam, [300.0, 450.0], max_root_stress_MPa=300.0, max_flash_temperature_C=135.0,
                               speed_rpm=2500.0)
    names = " ".join(d.solve.constraints["base"])
    assert "max_root_stress_MPa" in names and "max_contact_temperature_C" in names
    for t in (300.0, 450.0):
        r = ltca(crank_cam, t, microgeometry=d.microgeometry, speed_rpm=2500.0)
        assert max(r.max_root_stress_MPa) <= 300.0 * 1.01 and r.max_flash_temperature_C <= 135.5
    # at 450 N m the unmodified root stress of gear 2 is ~284 MPa: a 260 MPa limit cannot be met
    with pytest.raises(SolveError) as info:
        optimise_microgeometry(crank_cam, [300.0, 450.0], max_root_stress_MPa=260.0, starts=1)
    assert "root_stress" in str(info.value)
    with pytest.raises(GearoptInputError, match="speed_rpm"):
        optimise_microgeometry(crank_cam, 300.0, max_flash_temperature_C=130.0)


def test_exact_limit_violations_name_each_broken_limit_with_its_relative_shortfall(crank_cam):
    """The exact check names what the exact LTCA breaks (the smooth loaded contact ratio counts a pair whose gap
    just closed as partly loaded, so an optimiser can sit on a limit the exact model breaks): each broken limit of
    the design's scene with its relative shortfall or excess summed over the load cases; met limits give 0."""
    from gearopt.design.scene_search import exact_limit_violations

    d = optimise_microgeometry(crank_cam, [150.0, 450.0], positions=20, check_positions=160, max_refinements=0)
    built, exact = d.scene.source, d.scene.exact_check
    assert set(exact_limit_violations(built, exact).values()) == {0.0}      # the design meets its limits
    spoiled = exact.copy()
    spoiled["loaded_contact_ratio"] = [1.1, 1.3]                              # 1.2 required at both
    spoiled["max_contact_stress_MPa"] = exact["max_contact_stress_MPa"] * 1.01
    got = exact_limit_violations(built, spoiled)
    mesh = "crank-cam"
    assert got[f"loaded_contact_ratio {mesh}"] == pytest.approx(0.1 / 1.2)
    limit = d.limits["contact_stress"]
    expected = sum(max(v - limit, 0.0) / limit for v in spoiled["max_contact_stress_MPa"])
    assert expected > 0 and got[f"max_contact_stress_MPa {mesh}"] == pytest.approx(expected)


def test_scene_options_pass_through_and_an_unknown_one_is_named(crank_cam):
    """``ltca_options`` reach the scene behind the design (here the exact polish's budget: at most 3 evaluations per
    variable, plus its start and end); an unknown option is refused by name."""
    d = optimise_microgeometry(crank_cam, [150.0, 450.0], groups=("tip_relief",), positions=20, check_positions=160,
                               ltca_options={"polish_evaluations_per_variable": 3})
    polish = d.refinement.attrs["polish"]
    assert polish is not None and polish["evaluations"].iloc[0] <= 3 * 4 + 2
    with pytest.raises(GearoptInputError, match="polish_evals"):
        optimise_microgeometry(crank_cam, 300.0, ltca_options={"polish_evals": 3})
