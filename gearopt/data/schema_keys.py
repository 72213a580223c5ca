"""The table of keys of gearopt's data files: the constants of the layout, the explicit per-key rules (:data:`RULES`:
meaning, unit, range, choices) and the unit convention of key suffixes (:data:`UNIT_SUFFIXES`), with the look-ups
that the validation and the documentation share (:func:`rule_for`, :func:`unit_of`, :func:`default_range`).

The keys themselves come from the packaged reference file (:func:`gearopt.data.schema_tree.schema`).
"""

from __future__ import annotations

from dataclasses import dataclass

SCHEMA_VERSION = 1
REQUIRED_SECTIONS = ("schema_version", "rack", "trains", "gears", "meshes")
#: Tables whose keys are names chosen by the user; every entry follows the same item layout.
NAMED_TABLES = ("gears", "meshes", "materials", "joints", "trains")
TRAIN_KINDS = ("spur", "helical")
#: Keys every entry of these named tables must have (the gear-train builder reads them); the other keys of their
#: entries are optional. Entries of the other named tables need the keys every default entry has.
REQUIRED_ITEM_KEYS = {"gears": {"teeth", "face_width_mm"}, "meshes": {"gears", "centre_distance_mm"},
                      "trains": {"helix_angle_deg", "root_mesh", "root_gear"}}
MAX_MAGNITUDE = 1e15

SECTION_USES = {
    "trains": "every study (the train's helix angle and profile-shift root)",
    "design_loads": "rating at design load and the torque range of the microgeometry design",
    "design_limits": "the stress, temperature and contact-ratio limits of the design NLPs",
    "joints": "joint capacities, slip and walk-off margins",
    "materials": "joint capacities and blank masses",
    "lubrication": "flash and contact temperatures",
    "excitation": "the torsional dynamics of a train without an engine",
    "engine": "the torsional dynamics of an engine's train",
    "dynamics": "mesh damping of the torsional dynamics",
    "field_record": "the failure model's fleet evidence and duty assumptions (walk-off calibration)",
    "requirements": "the limits the verdict judges and the design NLPs carry (optional: defaults)",
}
"""What each optional section is for (the message of a missing one names it)."""

#: Unit of a key, from its name's suffix (longest suffix first).
UNIT_SUFFIXES = {
    "_N_per_mm_sqrt_s_K": "N/(mm s^0.5 K)", "_Nms_per_rad": "N m s/rad", "_Nm_per_rad": "N m/rad",
    "_N_per_m": "N/m", "_kg_m3": "kg/m^3", "_W_mK": "W/(m K)", "_J_kgK": "J/(kg K)", "_per_K": "1/K",
    "_bar_abs": "bar (absolute)", "_Rz_um": "um (Rz)", "_kgm2": "kg m^2", "_mm2": "mm^2", "_percent": "%",
    "_MPa": "MPa", "_HRC": "HRC", "_rpm": "rpm", "_deg": "deg", "_bar": "bar", "_kW": "kW", "_kJ": "kJ",
    "_Hz": "Hz", "_Nm": "N m", "_h": "h", "_mm": "mm", "_um": "um", "_kg": "kg", "_HV": "HV", "_C": "degC", "_N": "N",
    "_L": "L", "_K": "K",
}
#: Units whose quantities cannot be negative (lengths and micrometres only outside allowances and deviations).
NON_NEGATIVE_UNITS = {"h", "kg m^2", "kg", "kg/m^3", "Hz", "rpm", "mm^2", "L", "W/(m K)", "J/(kg K)", "N/m", "N m/rad",
                      "N m s/rad", "kW", "HRC", "HV", "bar", "bar (absolute)", "mm", "um", "um (Rz)", "MPa", "N",
                      "kJ", "N/(mm s^0.5 K)", "1/K"}
SIGNED_WORDS = ("allowance", "deviation", "change", "offset", "torque_min", "start_of_combustion")


@dataclass(frozen=True)
class Rule:
    """Explicit rule of one key (``*`` in a path matches any entry of a named table)."""

    meaning: str
    low: float | None = None
    high: float | None = None
    low_inclusive: bool = True
    high_inclusive: bool = True
    kind: str | None = None  # "int", "float", "str", "list[str]" ... (default: the default file's kind)
    choices: tuple | None = None
    length: int | None = None
    required: bool | None = None  # default: required if every default entry has the key


RULES: dict[str, Rule] = {
    "schema_version": Rule("version of the key layout; this gearopt reads version 1", 1, 1, kind="int"),
    "title": Rule("free text naming the data set", required=False),
    "rack.module_mm": Rule("normal module m_n of the basic rack", 0.05, 100.0, low_inclusive=True),
    "rack.pressure_angle_deg": Rule("normal pressure angle alpha_n of the basic rack", 0.0, 45.0,
                                    low_inclusive=False, high_inclusive=False),
    "rack.addendum_coefficient": Rule("addendum h_aP* of the basic rack, per m_n", 0.0, 3.0, low_inclusive=False),
    "rack.dedendum_coefficient": Rule("dedendum h_fP* of the basic rack, per m_n", 0.0, 3.0, low_inclusive=False),
    "rack.root_radius_coefficient": Rule("root radius rho_fP* of the basic rack, per m_n", 0.0, 1.0),
    "trains.*.helix_angle_deg": Rule("reference helix angle beta of the train (0: spur)", 0.0, 45.0,
                                     high_inclusive=False),
    "trains.*.root_mesh": Rule("the mesh whose shifts are set first ('<driving>-<driven>', a key of meshes)"),
    "trains.*.root_gear": Rule("the gear of the root mesh whose profile shift or split is given"),
    "trains.*.root_profile_shift": Rule("profile shift coefficient x of the root gear", -3.0, 3.0, required=False),
    "trains.*.root_shift_split": Rule("ISO/TR 4467 split lambda of the root mesh's sum of shifts", -0.5, 1.5,
                                      required=False),
    "trains.*.root_hand": Rule("helix hand of the root gear ('right'/'left')", choices=("right", "left"),
                               required=False),
    "trains.*.shift_distribution_lambda": Rule("ISO/TR 4467 lambda used for the other meshes", -0.5, 1.5,
                                               required=False),
    "trains.*.thesis_profile_shifts": Rule("profile shifts of the source study by gear name (comparison only)",
                                           -3.0, 3.0, kind="map[float]", required=False),
    "gears.*.teeth": Rule("number of teeth z", 5, 10000, kind="int"),
    "gears.*.face_width_mm": Rule("face width b", 0.0, 10000.0, low_inclusive=False),
    "gears.*.tooth_thickness_upper_allowance_um": Rule("upper normal tooth-thickness allowance E_sns", -5000.0,
                                                       5000.0),
    "gears.*.tooth_thickness_lower_allowance_um": Rule("lower normal tooth-thickness allowance E_sni", -5000.0,
                                                       5000.0),
    "gears.*.tip_diameter_upper_allowance_mm": Rule("upper tip-diameter allowance", -50.0, 50.0),
    "gears.*.tip_diameter_lower_allowance_mm": Rule("lower tip-diameter allowance", -50.0, 50.0),
    "gears.*.accuracy_grade_iso1328": Rule("ISO 1328 accuracy grade", 1, 12, kind="int"),
    "gears.*.material": Rule("material name (a key of materials)"),
    "gears.*.role": Rule("what the gear drives (free text)"),
    "gears.*.speed_ratio_to_crank": Rule("speed of the gear / crank speed", 0.0, 100.0, low_inclusive=False),
    "gears.*.web_pocket_area_fraction": Rule("fraction of the web area removed by pockets", 0.0, 1.0,
                                             high_inclusive=False),
    "meshes.*.gears": Rule("the two gears of the mesh, driving first (keys of gears)", kind="list[str]", length=2),
    "meshes.*.centre_distance_mm": Rule("working centre distance a", 0.0, 1e5, low_inclusive=False),
    "meshes.*.centre_distance_upper_allowance_mm": Rule("upper centre-distance allowance", -50.0, 50.0),
    "meshes.*.centre_distance_lower_allowance_mm": Rule("lower centre-distance allowance", -50.0, 50.0),
    "meshes.*.design_torque_Nm": Rule("design torque on the driving gear of the mesh (rating at design load; the "
                                      "microgeometry design range is this times design_loads.torque_range_fractions)",
                                      0.0, 1e7, low_inclusive=False, required=False),
    "meshes.*.torque_range_Nm": Rule("load cases of the mesh's design range, design torque first (default: "
                                     "design_torque_Nm x design_loads.torque_range_fractions)", 0.0, 1e7,
                                     low_inclusive=False, kind="list[float]", required=False),
    "meshes.*.sum_profile_shift": Rule("sum of profile shifts x1 + x2 (check value)", -6.0, 6.0),
    "meshes.*.standard_centre_distance_change_percent": Rule("a / a_d - 1 (check value)", -50.0, 50.0),
    "meshes.*.speed_ratio_error_percent": Rule("speed-ratio error against the target (check value)", -100.0, 100.0),
    "joints.*.axial_retention": Rule("how the gear is held axially besides its fit: 'none' (fit and key only), "
                                     "'retained' (a retainer plate, a clamped hub) or 'unknown' (the walk-off "
                                     "calibration weighs both)", choices=("none", "retained", "unknown"),
                                     required=False),
    "joints.*.field_failures": Rule("failures of this joint (walk-offs) observed in the fleet of [field_record] within "
                                    "its period", 0, None, kind="int", required=False),
    "field_record.fleet_size": Rule("units (engines) in the fleet of the field record", 1, None, kind="int"),
    "field_record.period_months": Rule("period of the field record (the exposure hours are per period)", 0.0, 1200.0,
                                       low_inclusive=False),
    "field_record.walk_off_distance_mm": Rule("axial travel at which a walked gear has failed", 0.0, 1000.0,
                                              low_inclusive=False),
    "field_record.damper_degraded_probability": Rule("share of units with a degraded damper in the period", 0.0, 1.0),
    "field_record.damper_seized_probability": Rule("share of units with a seized damper in the period", 0.0, 1.0),
    "field_record.rated_hours_median_h": Rule("median hours per unit at the rated speed in the period",
                                           0.0, 1e6),
    "field_record.rated_hours_sigma": Rule("log-normal spread (sigma of ln hours) at the rated speed",
                                        0.0, 10.0),
    "field_record.high_idle_hours_median_h": Rule("median hours per unit at the high idle speed in the period",
                                           0.0, 1e6),
    "field_record.high_idle_hours_sigma": Rule("log-normal spread (sigma of ln hours) at the high idle speed",
                                        0.0, 10.0),
    "field_record.overspeed_test_hours_median_h": Rule("median hours per unit at the overspeed test speed in the period",
                                           0.0, 1e6),
    "field_record.overspeed_test_hours_sigma": Rule("log-normal spread (sigma of ln hours) at the overspeed test speed",
                                        0.0, 10.0),
    "field_record.motoring_overspeed_hours_median_h": Rule("median hours per unit at the motoring overspeed speed in the period",
                                           0.0, 1e6),
    "field_record.motoring_overspeed_hours_sigma": Rule("log-normal spread (sigma of ln hours) at the motoring overspeed speed",
                                        0.0, 10.0),
    "service.backlash_range_mm": Rule("service backlash range (min, max)", 0.0, 10.0, kind="list[float]", length=2),
    "materials.*.E_MPa": Rule("Young's modulus", 1e3, 1e6),
    "materials.*.poisson_ratio": Rule("Poisson's ratio", 0.0, 0.5, low_inclusive=False, high_inclusive=False),
    "materials.*.thermal_expansion_per_K": Rule("linear thermal expansion coefficient", 0.0, 1e-3),
    "materials.*.description": Rule("free text"),
    "materials.*.used_for": Rule("free text"),
    "joints.*.joint_type": Rule("'press_fit' or 'taper_nut'", choices=("press_fit", "taper_nut")),
    "joints.*.free": Rule("the joint's interference (press fit) or nut torque (taper) is a design variable: a "
                          "recommendation sizes it for the requirements", kind="bool", required=False),
    "joints.*.gear": Rule("the gear held by the joint (a key of gears)"),
    "joints.*.friction_coefficient": Rule("friction coefficient of the joint surfaces", 0.0, 1.0,
                                          low_inclusive=False, high_inclusive=False),
    "joints.*.torque_capacity_Nm": Rule("torque capacity computed by the source (a check value)", required=False),
    "joints.*.nut_factor": Rule("nut factor k of T = k F d", 0.0, 1.0, low_inclusive=False, required=False),
    "joints.*.taper_half_angle_deg": Rule("half angle of the taper", 0.0, 45.0, low_inclusive=False,
                                          high_inclusive=False, required=False),
    "engine.cylinders": Rule("number of cylinders", 1, 32, kind="int"),
    "engine.strokes_per_cycle": Rule("2 or 4", choices=(2, 4), kind="int"),
    "engine.valves_per_cylinder": Rule("valves per cylinder", 1, 8, kind="int"),
    "engine.bore_mm": Rule("cylinder bore", 1.0, 2000.0),
    "engine.stroke_mm": Rule("piston stroke", 1.0, 5000.0),
    "engine.connecting_rod_length_mm": Rule("connecting-rod centre distance", 1.0, 10000.0),
    "engine.compression_ratio": Rule("geometric compression ratio", 1.0, 50.0, low_inclusive=False),
    "engine.firing_order": Rule("cylinders in firing order (a permutation of 1..cylinders)", 1, 32,
                                kind="list[int]"),
    "engine.crank_rod_ratio": Rule("crank radius / rod length", 0.0, 1.0, low_inclusive=False,
                                   high_inclusive=False),
    "engine.camshaft.stations": Rule("cam stations (lumped inertias) along the camshaft", 1, 100, kind="int"),
    "engine.fuel_pump.plungers": Rule("pump plungers", 1, 16, kind="int"),
    "engine.combustion.model": Rule("combustion model", choices=("double_wiebe",)),
    "engine.combustion.premixed_fraction": Rule("premixed share of the heat release", 0.0, 1.0),
    "engine.combustion.ratio_of_specific_heats": Rule("gamma of the cylinder charge", 1.0, 2.0,
                                                      low_inclusive=False),
    "engine.crankshaft.shaft_loss_factor": Rule("material loss factor of the crankshaft", 0.0, 1.0),
    "engine.crankshaft.mode_1_damping_ratio": Rule("damping ratio of the first crankshaft mode", 0.0, 1.0),
    "dynamics.mesh_damping_ratio": Rule("damping ratio of the gear meshes", 0.0, 1.0, high_inclusive=False),
    "excitation.gear": Rule("the gear the driving torque acts on (a key of gears)"),
    "excitation.mean_torque_Nm": Rule("mean driving torque on that gear", -1e7, 1e7),
    "excitation.harmonic_orders": Rule("orders of the torque harmonics per revolution of the driving gear", 0.0,
                                       1000.0, low_inclusive=False, kind="list[float]", required=False),
    "excitation.harmonic_amplitudes_Nm": Rule("amplitudes of the torque harmonics", 0.0, 1e7, kind="list[float]",
                                              required=False),
    "excitation.harmonic_phases_deg": Rule("phases of the torque harmonics", -360.0, 360.0, kind="list[float]",
                                           required=False),
    "excitation.speed_rpm": Rule("default speed of the driving gear", 0.0, 1e6, low_inclusive=False,
                                 required=False),
    "lubrication.mean_friction_coefficient": Rule("mean tooth friction coefficient (Blok)", 0.0, 1.0,
                                                  high_inclusive=False),
    "lubrication.oil_temperature_C": Rule("oil (bulk) temperature", -50.0, 300.0),
    "design_loads.application_factor_K_A": Rule("ISO 6336-1 application factor (default 1)", 1.0, 10.0,
                                                required=False),
    "design_loads.torque_range_fractions": Rule("load cases of each mesh's design range as fractions of its design "
                                                "torque (default [1.0])", 0.0, 100.0, low_inclusive=False,
                                                kind="list[float]", required=False),
    "design_loads.overspeed_rpm": Rule("highest speed of the reference shaft the joints must hold (a train "
                                       "without an [engine]; an engine states its overspeed_test_speed_rpm)", 0.0,
                                       1e6, low_inclusive=False, required=False),
    "design_loads.speed_rpm": Rule("speed of the reference shaft at which the design loads act", 0.0, 1e6,
                                   low_inclusive=False, required=False),
    "design_limits.max_root_stress_MPa": Rule("largest admissible LTCA root stress", 0.0, 1e5, low_inclusive=False,
                                              required=False),
    "design_limits.max_contact_temperature_C": Rule("largest admissible contact temperature (bulk + flash)", -50.0,
                                                    1000.0, required=False),
    "design_limits.min_loaded_contact_ratio": Rule("smallest admissible loaded contact ratio", 0.0, 5.0,
                                                   required=False),
    "requirements.min_slip_margin": Rule("smallest joint slip margin (capacity / torque demand), static at the weakest "
                                         "fit and over speed at the dynamic peaks", 0.0, 100.0, required=False),
    "requirements.min_axial_margin": Rule("smallest walk-off margin (axial capacity / thrust), static and over speed",
                                          0.0, 100.0, required=False),
    "requirements.min_hub_yield_safety": Rule("smallest hub yield safety (nominal fit)", 0.0, 100.0, required=False),
    "requirements.min_S_H": Rule("smallest ISO 6336-2 pitting safety S_H (static and at the dynamic peak)", 0.0,
                                 100.0, required=False),
    "requirements.min_S_F": Rule("smallest ISO 6336-3 tooth-root safety S_F (static and at the dynamic peak)", 0.0,
                                 100.0, required=False),
    "requirements.min_S_B": Rule("smallest ISO/TS 6336-20 flash-temperature scuffing safety S_B", 0.0, 100.0,
                                 required=False),
    "requirements.max_contact_temperature_C": Rule("largest contact temperature (bulk + flash, exact LTCA)", -50.0,
                                                   1000.0, required=False),
    "requirements.min_loaded_contact_ratio": Rule("smallest loaded contact ratio (exact LTCA, every load case)", 0.0,
                                                  5.0, required=False),
    "requirements.min_contact_ratio": Rule("smallest worst-case transverse contact ratio (tolerances)", 0.0, 5.0,
                                           required=False),
    "requirements.ppte_form": Rule("the PPTE requirement: 'unmodified' (largest PPTE over the range <= the "
                                   "unmodified pair's) or 'value' (<= max_ppte_um)", choices=("unmodified", "value"),
                                   required=False),
    "requirements.max_ppte_um": Rule("largest PPTE over each mesh's design range (ppte_form = 'value')", 0.0, 1000.0,
                                     low_inclusive=False, required=False),
    "requirements.ppte_no_load_case_worse": Rule("also no load case of the range worse than the unmodified pair",
                                                 kind="bool", required=False),
    "requirements.ppte_relief_tolerance_um": Rule("half-width of the tip-relief amount tolerance the PPTE is judged "
                                                  "over (0: nominal only)", 0.0, 100.0, required=False),
    "requirements.ppte_relief_start_tolerance_deg": Rule("half-width of the relief-start tolerance [roll angle] the "
                                                         "PPTE is judged over", 0.0, 10.0, required=False),
    "requirements.ppte_sharp_start": Rule("judge the PPTE with a sharp relief start too (not only the designed blend)",
                                          kind="bool", required=False),
    "microgeometry.initial.tip_relief_shape": Rule("tip relief shape", choices=("linear", "parabolic", "arc")),
}


def rule_for(path: str) -> Rule | None:
    """The explicit rule of a concrete key path (entry names replaced by ``*``)."""
    return RULES.get(generic_path(path))


def generic_path(path: str) -> str:
    parts = path.split(".")
    if parts and parts[0] in NAMED_TABLES and len(parts) > 1:
        parts[1] = "*"
    return ".".join(parts)


def unit_of(key: str) -> str:
    """The unit of a key from its name's suffix ('' for dimensionless keys)."""
    for suffix, unit in UNIT_SUFFIXES.items():
        if key.endswith(suffix):
            return unit
    return ""


def default_range(path: str) -> tuple[float | None, float | None]:
    """Range of a number without an explicit rule: non-negative for units that cannot be negative (lengths outside
    allowances and deviations, masses, inertias, stiffnesses, speeds, pressures ...), otherwise any finite value."""
    key = path.rsplit(".", 1)[-1]
    unit = unit_of(key)
    if unit in NON_NEGATIVE_UNITS and not any(w in key for w in SIGNED_WORDS):
        return 0.0, None
    return None, None
