"""The LTCA options of a scene as typed records (:mod:`gearopt.design.scene_options`): the defaults are the former
flat dict, flat keys map onto the records and back, bad values and unknown keys raise naming them, and a build's
options layer the defaults, the data's ``[lubrication]``, the scene's ``ltca_options`` and the build's overrides."""

import dataclasses

import pytest

import gearopt as go
from gearopt.data import system_from_data
from gearopt.design import (ContactModelOptions, ContactTemperatureOptions, ExactCheckOptions, LTCAOptions,
                            RefinementOptions, SearchOptions)
from gearopt.design.scene import DEFAULT_LTCA_OPTIONS, BuiltScene, DesignVariable, Objective, Scene
from gearopt.design.scene_file import scene_from_data
from gearopt.design.scene_options import OPTION_GROUP
from gearopt.errors import GearoptInputError

MESH = "crank-cam"

FORMER_DEFAULTS = {
    "positions": 40, "smoothing_um": 0.05, "stiffness": "iso6336", "relief_smoothing_deg": 0.1,
    "bulk_temperature_C": 100.0, "friction_coefficient": 0.06, "check_positions": 1280, "start_margin_deg": 0.25,
    "helical_slices": 11, "engagement_width_mm": 0.0005, "root_rotation": "cw",
    "refine_tolerance": 0.02, "max_refinements": 6, "max_helical_slices": 41, "min_smoothing_um": 0.005,
    "refine_abs_tolerance_um": 0.01, "refine_stress_tolerance": 0.01,
    "refine_neighbours": 3, "approach": "nested"}
"""``DEFAULT_LTCA_OPTIONS`` as the dict it was before the records."""

SEARCH_DEFAULTS = {"screen_samples": 64, "screen_positions": 320, "screen_max_variables": 8,
                   "polish_evaluations_per_variable": 25, "macro_starts": 4, "stop_without_progress": False,
                   "stop_on_divergence": True,
                   "spring_limit_screen": 0.2, "count_width_um": 0.25, "macro_derivative_order": 2}
TOLERANCE_DEFAULTS = {"relief_tolerance_um": 2.0, "relief_start_tolerance_deg": 0.5, "relief_sharp_start": True,
                      "toleranced_ppte_width_um": 0.01, "toleranced_ppte_screen": 0.05, "toleranced_ppte_lazy": False}
"""The options added since (issue 28: the exact screen, polish and a co-design's default starts,
:class:`SearchOptions`; issue 29: the refinement's stop without progress and on divergence, the per-spring limits by
exchange; issue 26:
the smooth loaded-contact count's width, :data:`gearopt.contact.ltca_smooth.DEFAULT_COUNT_WIDTH_UM`; issue 27: the
relief tolerances of ``ppte_um_toleranced``, the requirement's defaults)."""

DEFAULTS = {**FORMER_DEFAULTS, **SEARCH_DEFAULTS, **TOLERANCE_DEFAULTS}


def test_defaults_equal_the_former_dict():
    assert LTCAOptions().flat() == DEFAULTS
    assert dict(DEFAULT_LTCA_OPTIONS) == DEFAULTS
    for name, value in DEFAULTS.items():      # same types too (ints stay ints)
        assert type(DEFAULT_LTCA_OPTIONS[name]) is type(value), name
    with pytest.raises(TypeError):
        DEFAULT_LTCA_OPTIONS["positions"] = 24      # read-only


def test_flat_keys_map_onto_the_records_by_concern():
    o = LTCAOptions()
    assert isinstance(o.model, ContactModelOptions) and o.model.positions == 40 and o.model.approach == "nested"
    assert isinstance(o.temperature, ContactTemperatureOptions) and o.temperature.friction_coefficient == 0.06
    assert isinstance(o.check, ExactCheckOptions) and o.check.check_positions == 1280
    assert isinstance(o.refinement, RefinementOptions) and o.refinement.max_refinements == 6
    assert o.root_rotation == "cw" and o.limit_backoff == ()
    assert isinstance(o.search, SearchOptions) and o.search.screen_samples == 64
    assert set(OPTION_GROUP) == set(DEFAULTS)
    for name, group in OPTION_GROUP.items():
        assert hasattr(o if group is None else getattr(o, group), name)


def test_a_flat_mapping_round_trips():
    flat = {"positions": 24, "max_refinements": 0, "helical_slices": 7, "bulk_temperature_C": 90.0,
            "approach": "lifted", "stiffness": 15.0, "root_rotation": "ccw", "check_positions": 640}
    o = LTCAOptions.from_mapping(flat)
    assert o.model.positions == 24 and o.refinement.max_refinements == 0 and o.model.helical_slices == 7
    assert o.temperature.bulk_temperature_C == 90.0 and o.model.approach == "lifted" and o.root_rotation == "ccw"
    assert o.check.check_positions == 640 and o.model.stiffness == 15.0
    assert o.flat() == {**DEFAULTS, **flat}
    assert LTCAOptions.from_mapping(o.flat()) == o
    assert LTCAOptions.from_mapping({}) == LTCAOptions() == LTCAOptions.from_mapping(None)
    # integral floats are counts; numbers are stored as float
    assert LTCAOptions.from_mapping({"positions": 24.0}).model.positions == 24
    assert type(LTCAOptions.from_mapping({"smoothing_um": 1}).model.smoothing_um) is float


def test_replace_takes_flat_overrides_and_keeps_the_rest():
    o = LTCAOptions.from_mapping({"positions": 24})
    r = o.replace(smoothing_um=0.025, helical_slices=21)
    assert (r.model.positions, r.model.smoothing_um, r.model.helical_slices) == (24, 0.025, 21)
    assert o.model.smoothing_um == 0.05                       # frozen: the original is unchanged
    assert o.replace() is o
    b = o.replace(limit_backoff={"loaded_contact_ratio[crank-cam]@T300": 0.01})
    assert b.backoff("loaded_contact_ratio[crank-cam]@T300") == 0.01 and b.backoff("other") == 0.0
    assert "limit_backoff" not in b.flat()
    with pytest.raises(dataclasses.FrozenInstanceError):
        o.model.positions = 12


@pytest.mark.parametrize("key, value, words", [
    ("positions", 1, ["positions=1", ">= 2"]),
    ("positions", 2.5, ["positions=2.5", "integer"]),
    ("smoothing_um", 0.0, ["smoothing_um=0", "> 0"]),
    ("smoothing_um", "0.05", ["smoothing_um='0.05'", "not a number"]),
    ("stiffness", "hertz", ["stiffness='hertz'", "iso6336"]),
    ("stiffness", -3.0, ["stiffness=-3", "> 0"]),
    ("relief_smoothing_deg", 6.0, ["relief_smoothing_deg=6", "<= 5"]),
    ("helical_slices", 0, ["helical_slices=0", ">= 1"]),
    ("approach", "direct", ["approach='direct'", "nested", "lifted"]),
    ("macro_derivative_order", 3, ["macro_derivative_order=3", "<= 2"]),
    ("spring_limit_screen", 0.0, ["spring_limit_screen=0", "> 0"]),
    ("spring_limit_screen", 1.5, ["spring_limit_screen=1.5", "<= 1"]),
    ("bulk_temperature_C", 1500.0, ["bulk_temperature_C=1500", "1000"]),
    ("friction_coefficient", 1.0, ["friction_coefficient=1", "< 1"]),
    ("check_positions", 0, ["check_positions=0", ">= 2"]),
    ("root_rotation", "left", ["root_rotation='left'", "cw"]),
    ("refine_tolerance", -0.1, ["refine_tolerance=-0.1", "> 0"]),
    ("max_refinements", -1, ["max_refinements=-1", ">= 0"]),
    ("min_smoothing_um", float("nan"), ["min_smoothing_um", "NaN"]),
    ("screen_samples", 48, ["screen_samples=48", "power of two"]),
    ("screen_samples", -2, ["screen_samples=-2", ">= 0"]),
    ("screen_max_variables", 0, ["screen_max_variables=0", ">= 1"]),
    ("polish_evaluations_per_variable", 2.5, ["polish_evaluations_per_variable=2.5", "integer"]),
    ("macro_starts", 0, ["macro_starts=0", ">= 1"]),
    ("screen_positions", 8, ["screen_positions=8", ">= 16"]),
])
def test_bad_values_raise_naming_the_option_value_and_limit(key, value, words):
    with pytest.raises(GearoptInputError) as info:
        LTCAOptions.from_mapping({key: value})
    for w in words:
        assert w in str(info.value)
    with pytest.raises(GearoptInputError):           # the records check themselves, and replace checks too
        LTCAOptions().replace(**{key: value})


def test_unknown_keys_raise_naming_the_nearest_option():
    with pytest.raises(GearoptInputError, match=r"unknown option 'postions' \(did you mean 'positions'\?\)"):
        LTCAOptions.from_mapping({"postions": 24})
    with pytest.raises(GearoptInputError, match="'max_refinement'.*'max_refinements'.*'zzz'"):
        LTCAOptions.from_mapping({"max_refinement": 0, "zzz": 1})
    with pytest.raises(GearoptInputError, match="limit_backoff"):   # the refinement's, not a user option
        LTCAOptions.from_mapping({"limit_backoff": {}})
    with pytest.raises(GearoptInputError, match="did you mean 'smoothing_um'"):
        LTCAOptions().replace(smoothing=0.1)


def test_scene_ltca_options_are_checked_when_built():
    train = go.load_default_train("spur")
    scene = Scene("bad", train=train, variables=[DesignVariable("profile_shift_1", MESH)],
                  objectives=[Objective("min_tip_thickness_mm", MESH, sense="max")],
                  ltca_options={"max_refinments": 0})
    with pytest.raises(GearoptInputError, match="did you mean 'max_refinements'"):
        scene.build()
    with pytest.raises(GearoptInputError, match="positions=1"):
        dataclasses.replace(scene, ltca_options={"positions": 1}).build()


def test_build_options_layer_defaults_lubrication_scene_and_overrides():
    data = go.load_system().data                            # a deep copy of the validated file
    data["lubrication"]["oil_temperature_C"] = 90.0
    data["lubrication"]["mean_friction_coefficient"] = 0.05
    scene = Scene("layers", train=go.load_default_train("spur"), data=system_from_data(data),
                  variables=[DesignVariable("profile_shift_1", MESH)],
                  objectives=[Objective("min_tip_thickness_mm", MESH, sense="max")])
    built = scene.build()
    assert isinstance(built.options, LTCAOptions)
    assert built.options.temperature == ContactTemperatureOptions(90.0, 0.05)      # the data's lubrication
    user = dataclasses.replace(scene, ltca_options={"friction_coefficient": 0.04, "positions": 24}).build()
    assert user.options.temperature == ContactTemperatureOptions(90.0, 0.04)       # the user's over the data's
    again = BuiltScene(user.scene, options={"smoothing_um": 0.025})                 # a build's override on top
    assert (again.options.model.smoothing_um, again.options.model.positions) == (0.025, 24)
    assert again.options.temperature.friction_coefficient == 0.04
    assert again.parametric_twin(approach="lifted").options.model.smoothing_um == 0.025
    with pytest.raises(GearoptInputError, match="did you mean 'smoothing_um'"):
        BuiltScene(user.scene, options={"smoothing": 0.025})


def test_scene_file_ltca_options_errors_name_the_scene():
    spec = {"train": "spur", "ltca_options": {"positons": 24},
            "objectives": [{"quantity": "min_tip_thickness_mm", "target": MESH, "sense": "max"}],
            "variables": [{"name": "profile_shift_1", "target": MESH}]}
    data = {"scenes": {"s": spec}}
    with pytest.raises(GearoptInputError, match=r"\[scenes\.s\] ltca_options: unknown option 'positons' "
                                                r"\(did you mean 'positions'\?\)"):
        scene_from_data(data, "s", train_data=go.load_system())
    spec["ltca_options"] = {"positions": 24, "max_refinements": 0}
    scene = scene_from_data(data, "s", train_data=go.load_system())
    assert scene.ltca_options == {"positions": 24, "max_refinements": 0}
