"""The exact search on a co-design (issue 28: a global phase where the space is small enough; more starts never
worse): a scene with free macro variables (the train's root profile shift) beside relief amounts is screened on the
exact model, designs the geometry refuses rank last, the closed-form geometry limits count in the exact violation,
and each start is a whole local solve (refined, polished) of which the best exact one is returned.

Any train: the packaged minimal pair with its gears renamed (sun_gear/drum_gear). The independent references are
:func:`gearopt.ltca` at its default resolution and the pair's own geometry (``GearPair.constraints``,
``geometry()``) at the train rebuilt from the design's values."""

import dataclasses

import numpy as np
import pytest

from gearopt.contact.ltca import ltca
from gearopt.data import load_default_data, train_from_data
from gearopt.design.scene import DesignVariable, Limit, LoadCase, Objective, Scene
from gearopt.design.scene_search import exact_evaluation, exact_geometry_violations, search_scope

MESH = "sun_gear-drum_gear"
GEOMETRY = {"min_contact_ratio": 1.2, "min_backlash_mm": None}
MIN_LCR = 1.2
pytestmark = pytest.mark.filterwarnings("ignore::UserWarning")


@pytest.fixture(scope="module")
def train(renamed_minimal_path):
    return train_from_data(load_default_data(renamed_minimal_path))


def codesign_scene(train, variables=("tip_relief_1_um", "tip_relief_2_um"), **ltca_options) -> Scene:
    return Scene("co-design", train=train, load_cases=[LoadCase("T150", 150.0)],
                 variables=[DesignVariable("root_profile_shift", "train", lower=-0.3, upper=0.9)]
                 + [DesignVariable(v, MESH) for v in variables],
                 objectives=[Objective("ppte_um", MESH)],
                 limits=[Limit("geometry_limits", MESH, options=GEOMETRY),
                         Limit("loaded_contact_ratio", MESH, lower=MIN_LCR)],
                 ltca_options={"positions": 24, "macro_starts": 2, **ltca_options})


@pytest.fixture(scope="module")
def solved(train):
    built = codesign_scene(train).build()
    return built, built.solve(starts=2), codesign_scene(train).build().solve(starts=1)


def test_a_codesign_is_in_scope_and_takes_macro_starts_by_default(train):
    """``macro_starts`` screened starts where a macro variable beside the root shift is free (here the face width);
    one where the root shift alone is (it moves the contact ratios smoothly), or no macro variable, or a warm
    start."""
    built = codesign_scene(train).build()
    assert search_scope(built) is None and built.default_starts() == 1
    reliefs = [v for v in codesign_scene(train).variables if v.target == MESH]
    wide = dataclasses.replace(codesign_scene(train), variables=[
        *reliefs, DesignVariable("face_width_mm", MESH, lower=15.0, upper=25.0)]).build()
    assert search_scope(wide) is None and wide.default_starts() == 2
    micro = Scene("micro", train=train, load_cases=[LoadCase("T150", 150.0)],
                  variables=[DesignVariable("tip_relief_1_um", MESH)], objectives=[Objective("ppte_um", MESH)])
    assert micro.build().default_starts() == 1
    warm = codesign_scene(train).build(initial={"train.root_profile_shift": 0.25})
    assert warm.default_starts() == 1 and not warm.screened()


def test_geometry_limits_count_exactly_and_refused_designs_rank_last(train):
    built = codesign_scene(train, ("tip_relief_1_um", "tip_relief_1_start_roll_deg")).build()
    start = built.initial_values()
    # a root shift whose mate is pushed past its shift limits: the violation is the pair's own negative margins
    x = -0.3
    margins = dataclasses.replace(train, root_profile_shift=x).pairs[MESH].constraints(**GEOMETRY)
    expected = sum(max(-float(v), 0.0) for v in margins.values())
    assert expected > 0.0
    got = exact_geometry_violations(built, {**start, "train.root_profile_shift": x})
    assert got[f"geometry_limits {MESH}"] == pytest.approx(expected, rel=1e-12)
    # a free relief start past the tip margin of the pair at that shift (the NLP's constraint, exactly)
    pair = dataclasses.replace(train, root_profile_shift=0.2).pairs[MESH]
    high = float(pair.geometry()["eap_roll_deg"][0]) - built.options.model.start_margin_deg
    beyond = {**start, "train.root_profile_shift": 0.2, f"{MESH}.tip_relief_1_start_roll_deg": high + 0.5}
    assert exact_geometry_violations(built, beyond)[f"tip_relief_start_1_in_profile {MESH}"] == \
        pytest.approx(0.5, rel=1e-9)
    # a shift the exact LTCA refuses (transverse contact ratio below 1 at x = 2): no objective, infeasible
    assert dataclasses.replace(train, root_profile_shift=2.0).pairs[MESH].geometry()["transverse_contact_ratio"] < 1
    assert exact_evaluation(built, {**start, "train.root_profile_shift": 2.0}) == (np.inf, np.inf)


def test_the_train_of_a_design_is_built_once_and_is_the_train_rebuilt_from_its_values(train):
    """An exact evaluation asks for the train at one design from its geometry limits and its exact LTCA: the scene
    keeps its recent trains by the variables' values (one propagation through the meshes per design, not one per
    question), and a kept train is the one ``dataclasses.replace`` builds from those values."""
    from gearopt.design.scene_models import TRAIN_CACHE_SIZE

    built = codesign_scene(train).build()
    start = built.initial_values()
    first = built.train_at({**start, "train.root_profile_shift": 0.25})
    assert built.train_at({**start, "train.root_profile_shift": 0.25}) is first
    assert built.numeric_pair(MESH, {**start, "train.root_profile_shift": 0.25}) is first.pairs[MESH]
    reference = dataclasses.replace(train, root_profile_shift=0.25)
    assert first.profile_shifts == reference.profile_shifts
    assert first.pairs[MESH].geometry()["tip_diameter_mm"] == reference.pairs[MESH].geometry()["tip_diameter_mm"]
    other = built.train_at({**start, "train.root_profile_shift": 0.3})
    assert other is not first and other.root_profile_shift == 0.3
    for x in np.linspace(0.0, 0.5, TRAIN_CACHE_SIZE):           # the oldest trains leave the bounded store
        built.train_at({**start, "train.root_profile_shift": float(x)})
    assert built.train_at({**start, "train.root_profile_shift": 0.25}) is not first


def test_each_start_is_refined_and_the_best_exact_design_returned(train, solved):
    built, result, one = solved
    table = result.starts
    assert len(table) == 2 and (table["origin"] == "exact screen").all()
    assert table["chosen"].sum() == 1
    assert table.loc[table["chosen"], "refined_exact_objective"].iloc[0] == table["refined_exact_objective"].min()
    # the starts nest: the two-start answer is never worse on the exact model than the one-start answer
    assert result.exact_check["ppte_um"].max() <= one.exact_check["ppte_um"].max() * (1 + 1e-9)
    # no screened design that meets every exact limit is better than the answer
    feasible = result.screen[result.screen["exact_violation"] <= 1e-3]
    assert result.refinement.attrs["verified_objective"] <= feasible["exact_objective"].min() * (1 + 1e-9)


def test_the_codesign_meets_its_limits_on_an_independent_evaluation(train, solved):
    _, result, _ = solved
    values = result.values
    pair = dataclasses.replace(train, root_profile_shift=values["train.root_profile_shift"]).pairs[MESH]
    assert min(float(v) for v in pair.constraints(**GEOMETRY).values()) >= -1e-6
    run = ltca(pair, 150.0, microgeometry=result.microgeometry[MESH])
    assert run.loaded_contact_ratio >= MIN_LCR * (1 - 0.01)
    assert run.ppte_um == pytest.approx(result.exact_check["ppte_um"].max(), rel=0.02)


def test_limit_move_check_on_the_renamed_pair(train, solved):
    """Any train: :func:`gearopt.studies.limit_move_check` on the renamed pair's co-design names its limit by the
    user's mesh name, and an inactive limit (zero multiplier) moved by +-0.5 % leaves the exact optimum where it is
    within the check's 0.01 um; an active one moves it by its sensitivity times the move within the same."""
    from gearopt.studies import limit_move_check

    _, result, _ = solved
    check = limit_move_check(result, every_limit=True)
    row = check.set_index("limit").loc[f"loaded_contact_ratio[{MESH}] (lower)"]
    assert row["bound"] == MIN_LCR
    if not row["active"]:
        assert abs(row["sensitivity"]) < 1e-6         # Ipopt's multiplier of an inactive bound
    for tag, sign in (("minus", -1.0), ("plus", 1.0)):
        predicted = row["sensitivity"] * sign * 0.005 * MIN_LCR
        assert abs(row[f"exact_objective_{tag}"] - row["exact_objective"] - predicted) <= max(0.1 * abs(predicted),
                                                                                             0.01)
    assert row["check"] == "agrees"


def test_first_order_macro_derivatives_reach_the_same_lbfgs_optimum(train):
    """``ltca_options["macro_derivative_order"] = 1`` (one Newton step carries the macro-symbolic LTCA's exact first
    derivatives) on the renamed pair's co-design solved with L-BFGS, as the timing-train co-design is: the same
    iterations and the same exact optimum as the default order 2 (L-BFGS asks for no second derivative)."""
    runs = []
    for order in (2, 1):
        built = codesign_scene(train, max_refinements=0, macro_derivative_order=order).build()
        assert built.models[f"ltca_macro:{MESH}"].derivative_steps == order
        runs.append(built.solve(starts=1, hessian_approximation="limited-memory"))
    two, one = runs
    assert one.solve.iterations == two.solve.iterations
    for name, value in two.values.items():
        assert one.values[name] == pytest.approx(value, rel=1e-6, abs=1e-8)
    assert one.exact_check["ppte_um"].max() == pytest.approx(two.exact_check["ppte_um"].max(), rel=1e-6)
