"""Inputs, margin expressions and results of shaft-hub joint sizing (:mod:`gearopt.design.joint_sizing`): the
joint specs and demands read from the data, the dual-typed weakest/strongest-case margins of a press fit and a taper
fit, and the :class:`JointSizing` result. Units: mm, um (diametral interference), N, N m, MPa, rpm."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import pandas as pd

from .. import numerics as nm
from ..data import System, joint_record, material_record, system_of
from ..errors import GearoptInputError
from ..validation import check_range
from ..joints.iso286 import tolerance_grade_um
from ..joints.press_fit import SMOOTHING_FACTORS, press_fit
from ..joints.taper_fit import THEORIES, taper_fit
from ..nlp.result import ProblemResult

SLIP_CRITERIA = ("combined", "separate")
PRESS_FIT_OBJECTIVES = ("min_interference", "max_margin")
TAPER_CAPACITIES = ("thesis", "engagement_friction")
#: Hole-basis fit families searched by :func:`suggest_fit`: (hole grade, shaft grade).
FIT_GRADES = ((7, 6), (6, 5), (8, 7))
#: Shaft letters of the interference fits tabulated in :mod:`gearopt.joints.iso286`.
SHAFT_LETTERS = ("m", "n", "p", "r", "s", "t", "u")
_INTERFERENCE_FLOOR_UM = 0.05   # weakest effective interference kept above this (variable bound) [um]


# ----------------------------------------------------------------------------------------------------------------
# inputs
# ----------------------------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class JointDemand:
    """One load case at a joint: torque through the joint [N m] (sign irrelevant), axial force on the gear [N]
    (sign irrelevant: the worst direction is assumed), shaft speed [rpm] (centrifugal loss of press fits)."""

    torque_Nm: float
    axial_force_N: float = 0.0
    speed_rpm: float = 0.0
    name: str = "demand"

    def __post_init__(self):
        for key in ("torque_Nm", "axial_force_N"):
            v = getattr(self, key)
            if not math.isfinite(float(v)):
                raise GearoptInputError(f"{key}={v!r} of demand {self.name!r} must be finite")
        check_range("speed_rpm", self.speed_rpm, 0.0, 1e5, unit="rpm")
        if float(self.torque_Nm) == 0.0 and float(self.axial_force_N) == 0.0:
            raise GearoptInputError(f"demand {self.name!r} has torque_Nm=0 and axial_force_N=0: nothing to size for "
                                    f"(limit: at least one nonzero load)")


@dataclass(frozen=True)
class PressFitSpec:
    """Geometry, materials and present fit of one press-fit joint (units in the names; ``roughness_Rz_um`` =
    (Rz shaft, Rz hub) for the DIN 7190 smoothing loss; ``fit`` and ``interference_*_um`` describe the present
    design, if any)."""

    shaft_diameter_mm: float
    shaft_bore_mm: float
    hub_outer_diameter_mm: float
    length_mm: float
    friction: float
    shaft_E_MPa: float
    shaft_nu: float
    hub_E_MPa: float
    hub_nu: float
    shaft_yield_MPa: float
    hub_yield_MPa: float
    shaft_density_kg_m3: float = 7850.0
    hub_density_kg_m3: float = 7850.0
    roughness_Rz_um: tuple | None = None
    fit: str | None = None
    interference_um: float | None = None
    interference_min_um: float | None = None
    interference_max_um: float | None = None
    name: str = "press fit"

    def __post_init__(self):
        check_range("shaft_diameter_mm", self.shaft_diameter_mm, 0.0, None, low_inclusive=False, unit="mm")
        check_range("shaft_bore_mm", self.shaft_bore_mm, 0.0, self.shaft_diameter_mm, high_inclusive=False,
                    unit="mm")
        check_range("hub_outer_diameter_mm", self.hub_outer_diameter_mm, self.shaft_diameter_mm, None,
                    low_inclusive=False, unit="mm")
        check_range("length_mm", self.length_mm, 0.0, None, low_inclusive=False, unit="mm")
        check_range("friction", self.friction, 0.0, 1.0, low_inclusive=False, high_inclusive=False)
        for key in ("shaft_yield_MPa", "hub_yield_MPa", "shaft_E_MPa", "hub_E_MPa"):
            check_range(key, getattr(self, key), 0.0, None, low_inclusive=False, unit="MPa")

    @property
    def present_band_um(self) -> float | None:
        """Width of the present fit's interference band [um], if the data give it."""
        if self.interference_min_um is None or self.interference_max_um is None:
            return None
        return float(self.interference_max_um) - float(self.interference_min_um)

    @classmethod
    def from_data(cls, system: System, joint: str) -> "PressFitSpec":
        """The spec of the joint ``joint`` of ``system`` (``system.joints[joint]``, a ``press_fit``) with its
        ``system.materials``. ``system``: the :class:`~gearopt.data.System` of the data file."""
        j, shaft, hub = _joint_entry(system_of(system, "PressFitSpec.from_data"), joint, "press_fit")
        return cls(shaft_diameter_mm=j["shaft_diameter_mm"], shaft_bore_mm=j["shaft_bore_diameter_mm"],
                   hub_outer_diameter_mm=j["hub_outer_diameter_mm"], length_mm=j["fit_length_mm"],
                   friction=j["friction_coefficient"], shaft_E_MPa=shaft["E_MPa"], shaft_nu=shaft["poisson_ratio"],
                   hub_E_MPa=hub["E_MPa"], hub_nu=hub["poisson_ratio"], shaft_yield_MPa=shaft["yield_strength_MPa"],
                   hub_yield_MPa=hub["yield_strength_MPa"], shaft_density_kg_m3=shaft["density_kg_m3"],
                   hub_density_kg_m3=hub["density_kg_m3"],
                   roughness_Rz_um=(j["shaft_roughness_Rz_um"], j["hub_roughness_Rz_um"]), fit=j.get("fit"),
                   interference_um=j.get("diametral_interference_um"),
                   interference_min_um=j.get("diametral_interference_min_um"),
                   interference_max_um=j.get("diametral_interference_max_um"), name=joint)


@dataclass(frozen=True)
class TaperFitSpec:
    """Geometry, nut and materials of one nut-clamped taper joint (units in the names). ``nut_factor_min``/``_max``:
    the tightening scatter (the weakest case uses the max); ``thread_stress_area_mm2`` and ``proof_strength_MPa``
    enable the bolt proof-load limit; ``nut_torque_Nm`` is the present design."""

    large_diameter_mm: float
    small_diameter_mm: float
    half_angle_deg: float
    friction: float
    thread_diameter_mm: float
    nut_factor_min: float
    nut_factor_max: float
    hub_outer_diameter_mm: float
    hub_yield_MPa: float
    thread_stress_area_mm2: float | None = None
    proof_strength_MPa: float | None = None
    nut_torque_Nm: float | None = None
    theory: str = "uniform_pressure"
    name: str = "taper fit"

    def __post_init__(self):
        check_range("nut_factor_min", self.nut_factor_min, 0.0, 1.0, low_inclusive=False)
        check_range("nut_factor_max", self.nut_factor_max, self.nut_factor_min, 1.0)
        check_range("hub_yield_MPa", self.hub_yield_MPa, 0.0, None, low_inclusive=False, unit="MPa")
        check_range("hub_outer_diameter_mm", self.hub_outer_diameter_mm, self.large_diameter_mm, None,
                    low_inclusive=False, unit="mm")
        if self.theory not in THEORIES:
            raise GearoptInputError(f"theory={self.theory!r} must be one of {THEORIES}")
        if self.proof_strength_MPa is not None:
            check_range("proof_strength_MPa", self.proof_strength_MPa, 0.0, None, low_inclusive=False, unit="MPa")
            if self.thread_stress_area_mm2 is None:
                raise GearoptInputError("proof_strength_MPa needs thread_stress_area_mm2")

    @classmethod
    def from_data(cls, system: System, joint: str, *, proof_strength_MPa: float | None = None) -> "TaperFitSpec":
        """The spec of the joint ``joint`` of ``system`` (``system.joints[joint]``, a ``taper_nut``; ``system`` as
        :meth:`PressFitSpec.from_data`). The data hold no bolt property class, so the proof strength is an argument
        (e.g. 830 MPa for class 10.9, ISO 898-1, as the data's nut-torque notes use)."""
        j, _, hub = _joint_entry(system_of(system, "TaperFitSpec.from_data"), joint, "taper_nut")
        return cls(large_diameter_mm=j["taper_large_diameter_mm"], small_diameter_mm=j["taper_small_diameter_mm"],
                   half_angle_deg=j["taper_half_angle_deg"], friction=j["friction_coefficient"],
                   thread_diameter_mm=j["nut_thread_diameter_mm"], nut_factor_min=j["nut_factor_min"],
                   nut_factor_max=j["nut_factor_max"], hub_outer_diameter_mm=j["hub_outer_diameter_mm"],
                   hub_yield_MPa=hub["yield_strength_MPa"],
                   thread_stress_area_mm2=j.get("nut_thread_stress_area_mm2"),
                   proof_strength_MPa=proof_strength_MPa, nut_torque_Nm=j.get("nut_torque_Nm"), name=joint)


def _joint_entry(system: System, joint: str, kind: str) -> tuple:
    """(entries of ``system.joints[joint]``, its shaft material, its hub material): a joint of another ``kind`` raises
    naming it; a joint or material the file lacks raises naming the file and key path."""
    system = system_of(system, f"the {kind} spec")
    j = joint_record(system, joint, f"the {kind} spec").entries
    if j["joint_type"] != kind:
        raise GearoptInputError(f"[joints.{joint}] joint_type={j['joint_type']!r}; this needs {kind!r}")
    shaft, hub = (material_record(system, j[key], f"the {kind} spec", f"joints.{joint}.{key}")
                  for key in ("shaft_material", "hub_material"))
    return j, shaft, hub


def default_tolerance_band_um(shaft_diameter_mm: float) -> float:
    """Interference band of an H7/x6 hole-basis fit [um]: IT7 + IT6 at the diameter (ISO 286-1)."""
    return tolerance_grade_um(shaft_diameter_mm, 7) + tolerance_grade_um(shaft_diameter_mm, 6)


def _as_demands(demands) -> tuple[JointDemand, ...]:
    if isinstance(demands, JointDemand):
        demands = (demands,)
    out = tuple(demands)
    if not out or not all(isinstance(x, JointDemand) for x in out):
        raise GearoptInputError("demands must be a JointDemand or a non-empty sequence of JointDemand")
    names = [x.name for x in out]
    if len(set(names)) != len(names):
        raise GearoptInputError(f"demand names {names} must be unique")
    return out


def _ratio(capacity, demand):
    """capacity/|demand|; inf for a numeric zero demand (no finite margin exists)."""
    if nm.is_symbolic(capacity, demand):
        return capacity / nm.fabs(demand)
    dem = abs(nm.to_float(demand))
    return nm.to_float(capacity) / dem if dem > 0.0 else math.inf


# ----------------------------------------------------------------------------------------------------------------
# margin expressions (dual-typed)
# ----------------------------------------------------------------------------------------------------------------

def smoothing_loss_of(spec: PressFitSpec, smoothing: bool, smoothing_rule: str = "din7190_2001") -> float:
    """DIN 7190 diametral smoothing loss [um] of the spec's roughness (0 if ``smoothing`` is off or no Rz given)."""
    if smoothing_rule not in SMOOTHING_FACTORS:
        raise GearoptInputError(f"smoothing_rule={smoothing_rule!r} must be one of {sorted(SMOOTHING_FACTORS)}")
    if not smoothing or spec.roughness_Rz_um is None:
        return 0.0
    return SMOOTHING_FACTORS[smoothing_rule] * (spec.roughness_Rz_um[0] + spec.roughness_Rz_um[1])


def press_fit_sizing_margins(spec: PressFitSpec, interference_um, demand: JointDemand, *, length_mm=None,
                             hub_outer_diameter_mm=None, tolerance_band_um=0.0, smoothing: bool = True,
                             smoothing_rule: str = "din7190_2001") -> dict:
    """Margins of a press fit of nominal interference ``interference_um`` [um] at one demand (dual-typed).

    Weakest case (capacity): ``nominal - band/2`` less the smoothing loss and the centrifugal loss at
    ``demand.speed_rpm``; strongest case (stresses): ``nominal + band/2`` less the smoothing loss, at rest and at the
    demand's speed, the lower safety reported. ``length_mm``/``hub_outer_diameter_mm`` override the spec's (may be
    symbols). Returns ``weakest_effective_interference_um``, ``torque_capacity_Nm``, ``axial_capacity_N``,
    ``required_friction_force_N`` (``sqrt((2000 T/d)^2 + F_a^2)``), ``torque_margin`` (T_cap/|T|),
    ``axial_margin`` (F_cap/|F_a|), ``combined_margin`` (F_cap / required friction force; inf for a numeric zero
    demand), and ``hub_von_mises_MPa``/``shaft_von_mises_MPa`` per case (``_rest``, ``_speed``) with
    ``hub_yield_safety``/``shaft_yield_safety`` (the smaller of the two cases).
    """
    d, di = spec.shaft_diameter_mm, spec.shaft_bore_mm
    length = spec.length_mm if length_mm is None else length_mm
    do = spec.hub_outer_diameter_mm if hub_outer_diameter_mm is None else hub_outer_diameter_mm
    loss = smoothing_loss_of(spec, smoothing, smoothing_rule)
    check_range("tolerance_band_um", tolerance_band_um, 0.0, None, unit="um")
    common = dict(shaft_E_MPa=spec.shaft_E_MPa, shaft_nu=spec.shaft_nu, hub_E_MPa=spec.hub_E_MPa, hub_nu=spec.hub_nu,
                  friction=spec.friction, smoothing_loss_um=loss, shaft_density_kg_m3=spec.shaft_density_kg_m3,
                  hub_density_kg_m3=spec.hub_density_kg_m3, shaft_yield_MPa=spec.shaft_yield_MPa,
                  hub_yield_MPa=spec.hub_yield_MPa)
    half = 0.5 * tolerance_band_um
    weak = press_fit(d, di, do, length, interference_um - half, speed_rpm=demand.speed_rpm, **common)
    rest = press_fit(d, di, do, length, interference_um + half, speed_rpm=0.0, **common)
    fast = press_fit(d, di, do, length, interference_um + half, speed_rpm=demand.speed_rpm, **common)
    T, Fa = float(demand.torque_Nm), float(demand.axial_force_N)
    required = math.hypot(2000.0 * T / float(d), Fa)
    return {
        "weakest_effective_interference_um": weak.effective_interference_um,
        "weakest_pressure_MPa": weak.pressure_MPa,
        "torque_capacity_Nm": weak.torque_capacity_Nm,
        "axial_capacity_N": weak.axial_capacity_N,
        "required_friction_force_N": required,
        "torque_margin": _ratio(weak.torque_capacity_Nm, T),
        "axial_margin": _ratio(weak.axial_capacity_N, Fa),
        "combined_margin": _ratio(weak.axial_capacity_N, required),
        "hub_von_mises_rest_MPa": rest.hub_von_mises_MPa,
        "hub_von_mises_speed_MPa": fast.hub_von_mises_MPa,
        "shaft_von_mises_rest_MPa": rest.shaft_von_mises_MPa,
        "shaft_von_mises_speed_MPa": fast.shaft_von_mises_MPa,
        "hub_yield_safety": nm.fmin(rest.hub_yield_safety, fast.hub_yield_safety),
        "shaft_yield_safety": nm.fmin(rest.shaft_yield_safety, fast.shaft_yield_safety),
    }


def taper_fit_sizing_margins(spec: TaperFitSpec, nut_torque_Nm, demand: JointDemand, *,
                             capacity: str = "thesis") -> dict:
    """Margins of a taper joint tightened with ``nut_torque_Nm`` [N m] at one demand (dual-typed).

    Weakest case at ``spec.nut_factor_max`` (lowest preload), strongest (hub stress, thread stress) at
    ``spec.nut_factor_min``. ``capacity``: ``"thesis"`` (Eq. 3.48) or ``"engagement_friction"``. Returns
    ``preload_N`` (weakest), ``preload_max_N``, ``torque_capacity_Nm``, ``axial_capacity_N`` (= weakest preload),
    ``torque_margin``, ``axial_margin``, ``slip_utilisation`` (``|T|/T_cap + |F_a|/W``), ``combined_margin``
    (its inverse), ``hub_von_mises_MPa``, ``hub_yield_safety`` and, with the proof strength, ``thread_stress_MPa``
    and ``proof_utilisation``.
    """
    if capacity not in TAPER_CAPACITIES:
        raise GearoptInputError(f"capacity={capacity!r} must be one of {TAPER_CAPACITIES}")
    args = (spec.large_diameter_mm, spec.small_diameter_mm, spec.half_angle_deg, spec.friction)
    kw = dict(nut_torque_Nm=nut_torque_Nm, thread_diameter_mm=spec.thread_diameter_mm, theory=spec.theory,
              hub_outer_diameter_mm=spec.hub_outer_diameter_mm, hub_yield_MPa=spec.hub_yield_MPa)
    weak = taper_fit(*args, nut_factor=spec.nut_factor_max, **kw)
    strong = taper_fit(*args, nut_factor=spec.nut_factor_min, **kw)
    t_cap = weak.torque_capacity_Nm if capacity == "thesis" else weak.torque_capacity_engagement_friction_Nm
    W = weak.bolt_preload_N
    T, Fa = float(demand.torque_Nm), float(demand.axial_force_N)
    util = abs(T) / t_cap + abs(Fa) / W
    out = {"preload_N": W, "preload_max_N": strong.bolt_preload_N, "torque_capacity_Nm": t_cap,
           "axial_capacity_N": W, "torque_margin": _ratio(t_cap, T), "axial_margin": _ratio(W, Fa),
           "slip_utilisation": util, "combined_margin": 1.0 / util,
           "hub_von_mises_MPa": strong.hub_von_mises_MPa, "hub_yield_safety": strong.hub_yield_safety}
    if spec.proof_strength_MPa is not None:
        stress = strong.bolt_preload_N / spec.thread_stress_area_mm2
        out["thread_stress_MPa"] = stress
        out["proof_utilisation"] = stress / spec.proof_strength_MPa
    return out


# ----------------------------------------------------------------------------------------------------------------
# results
# ----------------------------------------------------------------------------------------------------------------

@dataclass
class JointSizing:
    """Result of :func:`size_press_fit` / :func:`size_taper_fit`.

    ``values``: the optimum with units in the keys (press fit: ``interference_um`` nominal,
    ``interference_min_um``/``interference_max_um`` of the band, ``required_min_interference_um`` and
    ``allowed_max_interference_um`` (the admissible interval a fit's band must lie in), ``length_mm``,
    ``hub_outer_diameter_mm``, ``tolerance_band_um``; taper: ``nut_torque_Nm``, preloads). ``margins``: one row per
    demand, re-evaluated with the numeric joint models. ``fit``: the suggested ISO 286 fit (dict of
    :func:`fit_interference_um`) or None; ``fits``: every candidate with its feasibility. ``solve``: the Problem
    result (``solve.constraints`` is the constraint table with margins and multipliers).
    """

    joint: str
    joint_type: str
    values: dict
    margins: pd.DataFrame
    solve: ProblemResult
    target_margin: float
    fit: dict | None = None
    fits: pd.DataFrame | None = field(default=None, repr=False)

    @property
    def table(self) -> pd.DataFrame:
        """The constraint table of the solve (name, value, bounds, margin, multiplier, active)."""
        return self.solve.constraints

    @property
    def active_constraints(self) -> list[str]:
        """Names of the active constraints at the optimum."""
        c = self.solve.constraints
        return [str(n) for n in c.loc[c["active"], "name"]]
