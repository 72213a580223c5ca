"""Sizing of one shaft-hub joint for a target slip margin: Ipopt NLPs (through :class:`~gearopt.design.Problem`)
over the press-fit interference (and optionally fit length and hub outer diameter) or the taper-fit nut torque.

Press fit (:func:`size_press_fit`; model :func:`gearopt.joints.press_fit.press_fit`, Lame/DIN 7190 elastic):

* variable ``interference_um``: the *nominal* diametral interference, the middle of a tolerance band of width
  ``tolerance_band_um`` (default the H7/x6 band IT7 + IT6 at the fit diameter, or the data's present fit band);
  optionally ``length_mm`` and ``hub_outer_diameter_mm`` within bounds;
* weakest case, for the capacity: interference ``nominal - band/2`` minus the DIN 7190 smoothing loss (data Rz,
  ``smoothing_rule``) minus the centrifugal loss at each demand's speed; the friction force ``mu p pi d l`` must hold
  ``target_margin`` times the demand. ``slip="combined"`` (default) imposes the friction-force resultant
  ``F_cap >= S sqrt((2000 T/d)^2 + F_a^2)`` (it implies both single margins >= S); ``slip="separate"`` imposes
  ``T_cap >= S |T|`` and ``F_cap >= S |F_a|`` (torque slip and axial walk-off margins) each on its own;
* strongest case, for the stresses: interference ``nominal + band/2`` minus the smoothing loss, at rest and at each
  demand's speed (the centrifugal hoop stress adds there while the pressure drops); the hub and shaft von Mises
  stresses at the fit must stay below ``yield / min_*_yield_safety``;
* objective ``"min_interference"`` (default: the lightest fit that meets the margin) or ``"max_margin"`` (the largest
  common margin the stress limits allow, a free margin variable >= ``target_margin``).

The nominal interference is kept above ``band/2 + smoothing + largest centrifugal loss`` (a variable bound), so the
weakest effective interference stays positive and the model's ``max(delta, 0)`` never switches inside the NLP.

Taper fit (:func:`size_taper_fit`; model :func:`gearopt.joints.taper_fit.taper_fit`, thesis Eqs. 3.48-3.49): variable
nut tightening torque; weakest case at the *largest* nut factor of the range (lowest preload W = T_n/(k d)),
strongest at the smallest. Capacity ``"thesis"`` (thesis Eq. 3.48, W = N sin(theta)) or ``"engagement_friction"``
(locked-in normal force reduced by the engagement friction, see :mod:`gearopt.joints.taper_fit`). Slip:
``combined`` = ``S (|T|/T_cap + |F_a|/W) <= 1`` (rigid cone-clutch model, axial load taken as pulling off the
taper), or ``separate`` torque and axial margins. Hub von Mises safety at the strongest preload; thread stress
``W_max / A_s <= max_proof_fraction x proof strength`` when the proof strength is given.

Every result is re-evaluated with the numeric joint models (:func:`press_fit_sizing_margins`,
:func:`taper_fit_sizing_margins`), and for press fits the ISO 286 hole-basis fits (H6/x5, H7/x6, H8/x7 with shafts
m..u, :func:`gearopt.joints.iso286.fit_interference_um`) whose whole band lies between the required minimum and the
allowed maximum interference are listed (:func:`suggest_fit`).

Units: mm, um (diametral interference), N, N m, MPa, rpm.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np
import pandas as pd
from scipy.optimize import brentq

from .. import numerics as nm
from ..data import values as data_values
from ..errors import GearoptInputError
from ..validation import check_range
from ..joints.iso286 import fit_interference_um, tolerance_grade_um
from ..joints.press_fit import SMOOTHING_FACTORS, centrifugal_interference_loss_um, press_fit
from ..joints.taper_fit import THEORIES, taper_fit
from ..nlp.problem import Problem
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
    def from_data(cls, data: dict, joint: str) -> "PressFitSpec":
        """The spec of ``[joints.<joint>]`` (a ``press_fit``) with its ``[materials.*]``."""
        j, shaft, hub = _joint_entry(data, joint, "press_fit")
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
    def from_data(cls, data: dict, joint: str, *, proof_strength_MPa: float | None = None) -> "TaperFitSpec":
        """The spec of ``[joints.<joint>]`` (a ``taper_nut``). The data hold no bolt property class, so the proof
        strength is an argument (e.g. 830 MPa for class 10.9, ISO 898-1, as the data's nut-torque notes use)."""
        j, _, hub = _joint_entry(data, joint, "taper_nut")
        return cls(large_diameter_mm=j["taper_large_diameter_mm"], small_diameter_mm=j["taper_small_diameter_mm"],
                   half_angle_deg=j["taper_half_angle_deg"], friction=j["friction_coefficient"],
                   thread_diameter_mm=j["nut_thread_diameter_mm"], nut_factor_min=j["nut_factor_min"],
                   nut_factor_max=j["nut_factor_max"], hub_outer_diameter_mm=j["hub_outer_diameter_mm"],
                   hub_yield_MPa=hub["yield_strength_MPa"],
                   thread_stress_area_mm2=j.get("nut_thread_stress_area_mm2"),
                   proof_strength_MPa=proof_strength_MPa, nut_torque_Nm=j.get("nut_torque_Nm"), name=joint)


def _joint_entry(data: dict, joint: str, kind: str) -> tuple[dict, dict, dict]:
    d = data_values(data)
    joints = d.get("joints", {})
    if joint not in joints:
        raise GearoptInputError(f"joint={joint!r} is not in [joints] ({sorted(joints)})")
    j = joints[joint]
    if j["joint_type"] != kind:
        raise GearoptInputError(f"[joints.{joint}] joint_type={j['joint_type']!r}; this needs {kind!r}")
    mats = d.get("materials", {})
    for key in ("shaft_material", "hub_material"):
        if j[key] not in mats:
            raise GearoptInputError(f"[joints.{joint}] {key}={j[key]!r} is not in [materials] ({sorted(mats)})")
    return j, mats[j["shaft_material"]], mats[j["hub_material"]]


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
        "weakest_effective_interference_um": weak["effective_interference_um"],
        "weakest_pressure_MPa": weak["pressure_MPa"],
        "torque_capacity_Nm": weak["torque_capacity_Nm"],
        "axial_capacity_N": weak["axial_capacity_N"],
        "required_friction_force_N": required,
        "torque_margin": _ratio(weak["torque_capacity_Nm"], T),
        "axial_margin": _ratio(weak["axial_capacity_N"], Fa),
        "combined_margin": _ratio(weak["axial_capacity_N"], required),
        "hub_von_mises_rest_MPa": rest["hub_von_mises_MPa"],
        "hub_von_mises_speed_MPa": fast["hub_von_mises_MPa"],
        "shaft_von_mises_rest_MPa": rest["shaft_von_mises_MPa"],
        "shaft_von_mises_speed_MPa": fast["shaft_von_mises_MPa"],
        "hub_yield_safety": nm.fmin(rest["hub_yield_safety"], fast["hub_yield_safety"]),
        "shaft_yield_safety": nm.fmin(rest["shaft_yield_safety"], fast["shaft_yield_safety"]),
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
    t_cap = weak["torque_capacity_Nm"] if capacity == "thesis" else weak["torque_capacity_engagement_friction_Nm"]
    W = weak["bolt_preload_N"]
    T, Fa = float(demand.torque_Nm), float(demand.axial_force_N)
    util = abs(T) / t_cap + abs(Fa) / W
    out = {"preload_N": W, "preload_max_N": strong["bolt_preload_N"], "torque_capacity_Nm": t_cap,
           "axial_capacity_N": W, "torque_margin": _ratio(t_cap, T), "axial_margin": _ratio(W, Fa),
           "slip_utilisation": util, "combined_margin": 1.0 / util,
           "hub_von_mises_MPa": strong["hub_von_mises_MPa"], "hub_yield_safety": strong["hub_yield_safety"]}
    if spec.proof_strength_MPa is not None:
        stress = strong["bolt_preload_N"] / spec.thread_stress_area_mm2
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


# ----------------------------------------------------------------------------------------------------------------
# press fit
# ----------------------------------------------------------------------------------------------------------------

def size_press_fit(spec: PressFitSpec, demands: JointDemand | Sequence[JointDemand], *, target_margin: float = 1.5,
                   slip: str = "combined", min_hub_yield_safety: float = 1.2, min_shaft_yield_safety: float = 1.2,
                   tolerance_band_um: float | None = None, smoothing: bool = True,
                   smoothing_rule: str = "din7190_2001", free: Sequence[str] = ("interference_um",),
                   bounds: dict | None = None, objective: str = "min_interference", verbose: bool = False,
                   **ipopt: Any) -> JointSizing:
    """Size a press fit for ``target_margin`` at every demand (module docstring: weakest/strongest cases).

    Args:
        spec: the joint (:meth:`PressFitSpec.from_data` for a data entry).
        demands: one or several :class:`JointDemand` (all are imposed).
        target_margin: required slip margin S (>= 1).
        slip: ``"combined"`` (friction-force resultant) or ``"separate"`` (torque and axial margins).
        min_hub_yield_safety, min_shaft_yield_safety: von Mises yield safeties at the largest interference.
        tolerance_band_um: interference band width [um]; default the spec's present band, else IT7 + IT6.
        smoothing: apply the DIN 7190 smoothing loss of the spec's roughness (``smoothing_rule``).
        free: variables: ``"interference_um"`` always, plus optionally ``"length_mm"``,
            ``"hub_outer_diameter_mm"``.
        bounds: {variable: (low, high)}; defaults: interference up to 400 um (its lower bound is always at least
            half the band + smoothing + centrifugal loss), length 0.5-1.5 x the spec's, hub outer diameter
            max(1.2 d, 0.8 x the spec's) to 1.5 x the spec's.
        objective: ``"min_interference"`` or ``"max_margin"``.
        ipopt: Ipopt options for :meth:`Problem.solve`.

    Raises:
        GearoptInputError: bad arguments. InfeasibleProblemError (a SolveError): no design meets the margin within
            the stress limits and bounds; the error names the violated constraints.
    """
    demands = _as_demands(demands)
    check_range("target_margin", target_margin, 1.0, 100.0)
    check_range("min_hub_yield_safety", min_hub_yield_safety, 0.5, 10.0)
    check_range("min_shaft_yield_safety", min_shaft_yield_safety, 0.5, 10.0)
    if slip not in SLIP_CRITERIA:
        raise GearoptInputError(f"slip={slip!r} must be one of {SLIP_CRITERIA}")
    if objective not in PRESS_FIT_OBJECTIVES:
        raise GearoptInputError(f"objective={objective!r} must be one of {PRESS_FIT_OBJECTIVES}")
    free = tuple(free)
    allowed = ("interference_um", "length_mm", "hub_outer_diameter_mm")
    if "interference_um" not in free or set(free) - set(allowed):
        raise GearoptInputError(f"free={free!r} must contain 'interference_um' and only names of {allowed}")
    band = spec.present_band_um if tolerance_band_um is None else float(tolerance_band_um)
    if band is None:
        band = default_tolerance_band_um(spec.shaft_diameter_mm)
    check_range("tolerance_band_um", band, 0.0, 500.0, unit="um")
    loss = smoothing_loss_of(spec, smoothing, smoothing_rule)
    d = float(spec.shaft_diameter_mm)
    bnd = {"interference_um": (None, 400.0), "length_mm": (0.5 * spec.length_mm, 1.5 * spec.length_mm),
           "hub_outer_diameter_mm": (max(1.2 * d, spec.hub_outer_diameter_mm * 0.8), 1.5 * spec.hub_outer_diameter_mm)}
    for key, val in (bounds or {}).items():
        if key not in allowed:
            raise GearoptInputError(f"bounds key {key!r} must be one of {allowed}")
        lo, hi = val
        if lo is not None and hi is not None and hi <= lo:
            raise GearoptInputError(f"bounds[{key!r}]=({lo}, {hi}): upper must exceed lower")
        bnd[key] = (lo, hi)
    if bnd["hub_outer_diameter_mm"][0] is not None and bnd["hub_outer_diameter_mm"][0] <= d:
        raise GearoptInputError(f"bounds['hub_outer_diameter_mm'] lower={bnd['hub_outer_diameter_mm'][0]:g} mm must "
                                f"exceed the shaft diameter {d:g} mm")
    # keep the weakest effective interference positive over the whole box (largest centrifugal loss at the largest
    # hub diameter): the model's max(delta, 0) then never switches inside the NLP
    do_max = bnd["hub_outer_diameter_mm"][1] if "hub_outer_diameter_mm" in free else spec.hub_outer_diameter_mm
    cf = max(float(centrifugal_interference_loss_um(x.speed_rpm, d, spec.shaft_bore_mm, do_max, spec.shaft_E_MPa,
                                                    spec.shaft_nu, spec.hub_E_MPa, spec.hub_nu,
                                                    spec.shaft_density_kg_m3, spec.hub_density_kg_m3))
             for x in demands)
    floor = 0.5 * band + loss + max(cf, 0.0) + _INTERFERENCE_FLOOR_UM
    lo_i = floor if bnd["interference_um"][0] is None else max(floor, bnd["interference_um"][0])
    hi_i = bnd["interference_um"][1]
    if hi_i is not None and hi_i <= lo_i:
        raise GearoptInputError(f"interference upper bound {hi_i:g} um must exceed {lo_i:g} um (half band + "
                                f"smoothing + centrifugal loss)")

    p = Problem(name=f"press-fit sizing {spec.name}")
    x0_len = spec.length_mm
    length = (p.variable("length_mm", init=x0_len, lower=bnd["length_mm"][0], upper=bnd["length_mm"][1],
                         scale=x0_len, unit="mm") if "length_mm" in free else None)
    x0_do = spec.hub_outer_diameter_mm
    hub_do = (p.variable("hub_outer_diameter_mm", init=x0_do, lower=bnd["hub_outer_diameter_mm"][0],
                         upper=bnd["hub_outer_diameter_mm"][1], scale=x0_do, unit="mm")
              if "hub_outer_diameter_mm" in free else None)
    init = max(lo_i + 10.0, spec.interference_um or 0.0)
    if hi_i is not None:
        init = min(init, 0.5 * (lo_i + hi_i))
    delta = p.variable("interference_um", init=init, lower=lo_i, upper=hi_i, scale=max(init, 10.0), unit="um")
    margin = None
    if objective == "max_margin":
        margin = p.variable("margin", init=target_margin, lower=target_margin, upper=100.0, scale=target_margin)
    S = target_margin if margin is None else margin
    for x in demands:
        e = press_fit_sizing_margins(spec, delta, x, length_mm=length, hub_outer_diameter_mm=hub_do,
                                     tolerance_band_um=band, smoothing=smoothing, smoothing_rule=smoothing_rule)
        T, Fa = abs(float(x.torque_Nm)), abs(float(x.axial_force_N))
        tag = x.name
        if slip == "combined":
            req = e["required_friction_force_N"]
            p.subject_to(f"{tag}:slip_reserve_N", e["axial_capacity_N"] - S * req, lower=0.0, scale=req, unit="N")
        else:
            if T > 0.0:
                p.subject_to(f"{tag}:torque_reserve_Nm", e["torque_capacity_Nm"] - S * T, lower=0.0, scale=T,
                             unit="N m")
            if Fa > 0.0:
                p.subject_to(f"{tag}:axial_reserve_N", e["axial_capacity_N"] - S * Fa, lower=0.0, scale=Fa,
                             unit="N")
        hub_lim = spec.hub_yield_MPa / min_hub_yield_safety
        shaft_lim = spec.shaft_yield_MPa / min_shaft_yield_safety
        for case in ("rest", "speed"):
            if case == "speed" and x.speed_rpm == 0.0:
                continue
            p.subject_to(f"{tag}:hub_von_mises_{case}_MPa", e[f"hub_von_mises_{case}_MPa"], upper=hub_lim,
                         scale=hub_lim, unit="MPa")
            p.subject_to(f"{tag}:shaft_von_mises_{case}_MPa", e[f"shaft_von_mises_{case}_MPa"], upper=shaft_lim,
                         scale=shaft_lim, unit="MPa")
    if margin is None:
        p.minimize(delta, scale=max(init, 10.0))
    else:
        p.maximize(margin, scale=target_margin)
    res = p.solve(verbose=verbose, **ipopt)

    vals = {"interference_um": float(res.values["interference_um"]),
            "length_mm": float(res.values.get("length_mm", spec.length_mm)),
            "hub_outer_diameter_mm": float(res.values.get("hub_outer_diameter_mm", spec.hub_outer_diameter_mm)),
            "tolerance_band_um": band, "smoothing_loss_um": loss}
    if margin is not None:
        vals["margin"] = float(res.values["margin"])
    vals["interference_min_um"] = vals["interference_um"] - 0.5 * band
    vals["interference_max_um"] = vals["interference_um"] + 0.5 * band
    opts = dict(length_mm=vals["length_mm"], hub_outer_diameter_mm=vals["hub_outer_diameter_mm"],
                smoothing=smoothing, smoothing_rule=smoothing_rule)
    required_min = _required_min_interference_um(spec, demands, target_margin, slip, opts)
    allowed_max = _allowed_max_interference_um(spec, demands, min_hub_yield_safety, min_shaft_yield_safety, opts)
    vals["required_min_interference_um"] = required_min
    vals["allowed_max_interference_um"] = allowed_max
    margins = press_fit_margin_table(spec, vals["interference_um"], demands, tolerance_band_um=band, **opts)
    best, fits = suggest_fit(spec.shaft_diameter_mm, required_min, allowed_max)
    return JointSizing(joint=spec.name, joint_type="press_fit", values=vals, margins=margins, solve=res,
                       target_margin=float(target_margin), fit=best, fits=fits)


def press_fit_margin_table(spec: PressFitSpec, interference_um: float, demands, *, tolerance_band_um: float = 0.0,
                           **options) -> pd.DataFrame:
    """Numeric margins (:func:`press_fit_sizing_margins`) of a nominal interference at every demand, one row each."""
    rows = []
    for x in _as_demands(demands):
        e = press_fit_sizing_margins(spec, float(interference_um), x, tolerance_band_um=tolerance_band_um, **options)
        rows.append({"demand": x.name, "torque_Nm": float(x.torque_Nm), "axial_force_N": float(x.axial_force_N),
                     "speed_rpm": float(x.speed_rpm), **{k: float(v) for k, v in e.items()}})
    return pd.DataFrame(rows).set_index("demand")


def _required_min_interference_um(spec, demands, S, slip, opts) -> float:
    """Smallest minimum interference of the band [um] meeting margin S at every demand (band 0, numeric).

    The weakest capacity is linear in the interference above the losses, so one evaluation per demand scales."""
    need = 0.0
    for x in demands:
        e = press_fit_sizing_margins(spec, 1e3, x, tolerance_band_um=0.0, **opts)
        effective = float(e["weakest_effective_interference_um"])   # 1000 um less smoothing and centrifugal loss
        ratios = [e["combined_margin"]] if slip == "combined" else [e["torque_margin"], e["axial_margin"]]
        worst = min(float(r) for r in ratios)              # margin given by `effective` um of effective interference
        need = max(need, (1e3 - effective) + effective * S / worst)
    return need


def _allowed_max_interference_um(spec, demands, s_hub, s_shaft, opts) -> float:
    """Largest maximum interference of the band [um] keeping both yield safeties (numeric root of the safeties)."""
    def slack(delta):
        worst = math.inf
        for x in demands:
            with np.errstate(divide="ignore"):             # a lost fit has zero stress: safety inf
                e = press_fit_sizing_margins(spec, delta, x, tolerance_band_um=0.0, **opts)
            worst = min(worst, float(e["hub_yield_safety"]) / s_hub - 1.0, float(e["shaft_yield_safety"]) / s_shaft
                        - 1.0)
        return worst
    lo, hi = 1e-3, 50.0
    if slack(lo) <= 0.0:
        return 0.0
    while slack(hi) > 0.0:
        hi *= 2.0
        if hi > 1e5:
            return math.inf
    return float(brentq(slack, lo, hi, xtol=1e-9, rtol=1e-12))


def suggest_fit(diameter_mm: float, required_min_interference_um: float, allowed_max_interference_um: float,
                grades: Sequence[tuple[int, int]] = FIT_GRADES) -> tuple[dict | None, pd.DataFrame]:
    """ISO 286 hole-basis fits whose interference band lies in ``[required_min, allowed_max]`` [um].

    Candidates: H<h>/<letter><s> for the (hole, shaft) grades in ``grades`` and the tabulated shaft letters
    (m..u; a letter undefined at the diameter is skipped). Returns (best, table): best = the feasible fit with the
    smallest maximum interference (lowest assembly stress; ties: the coarser tolerance, cheaper), or None; the
    table lists every candidate with ``min_um``, ``max_um``, ``feasible``.
    """
    rows = []
    for hole, shaft in grades:
        for letter in SHAFT_LETTERS:
            fit = f"H{hole}/{letter}{shaft}"
            try:
                f = fit_interference_um(diameter_mm, fit)
            except GearoptInputError:
                continue
            ok = f["min_um"] >= required_min_interference_um and f["max_um"] <= allowed_max_interference_um
            rows.append({"fit": fit, "min_um": f["min_um"], "max_um": f["max_um"], "mean_um": f["mean_um"],
                         "band_um": f["max_um"] - f["min_um"], "feasible": bool(ok)})
    table = pd.DataFrame(rows)
    if table.empty:
        return None, table
    feasible = table[table["feasible"]].sort_values(["max_um", "band_um"], ascending=[True, False])
    if feasible.empty:
        return None, table
    return fit_interference_um(diameter_mm, str(feasible.iloc[0]["fit"])), table


# ----------------------------------------------------------------------------------------------------------------
# taper fit
# ----------------------------------------------------------------------------------------------------------------

def size_taper_fit(spec: TaperFitSpec, demands: JointDemand | Sequence[JointDemand], *, target_margin: float = 1.5,
                   slip: str = "combined", capacity: str = "thesis", min_hub_yield_safety: float = 1.2,
                   max_proof_fraction: float = 0.9, nut_torque_bounds_Nm: tuple[float, float] = (1.0, 2000.0),
                   verbose: bool = False, **ipopt: Any) -> JointSizing:
    """Minimum nut tightening torque of a taper joint for ``target_margin`` at every demand (module docstring).

    Constraints: slip (``combined``: ``S (|T|/T_cap + |F_a|/W) <= 1``; ``separate``: ``T_cap >= S|T|``,
    ``W >= S|F_a|``) at the largest nut factor; hub von Mises <= yield / ``min_hub_yield_safety`` and, with a proof
    strength, thread stress <= ``max_proof_fraction`` x proof strength at the smallest nut factor.
    """
    demands = _as_demands(demands)
    check_range("target_margin", target_margin, 1.0, 100.0)
    check_range("min_hub_yield_safety", min_hub_yield_safety, 0.5, 10.0)
    check_range("max_proof_fraction", max_proof_fraction, 0.0, 1.0, low_inclusive=False)
    if slip not in SLIP_CRITERIA:
        raise GearoptInputError(f"slip={slip!r} must be one of {SLIP_CRITERIA}")
    if capacity not in TAPER_CAPACITIES:
        raise GearoptInputError(f"capacity={capacity!r} must be one of {TAPER_CAPACITIES}")
    lo, hi = (float(v) for v in nut_torque_bounds_Nm)
    if not (0.0 < lo < hi):
        raise GearoptInputError(f"nut_torque_bounds_Nm=({lo:g}, {hi:g}) must satisfy 0 < low < high")
    p = Problem(name=f"taper-fit sizing {spec.name}")
    init = min(max(spec.nut_torque_Nm or 100.0, lo), hi)
    tn = p.variable("nut_torque_Nm", init=init, lower=lo, upper=hi, scale=init, unit="N m")
    first = None
    for x in demands:
        e = taper_fit_sizing_margins(spec, tn, x, capacity=capacity)
        first = first or e
        T, Fa = abs(float(x.torque_Nm)), abs(float(x.axial_force_N))
        if slip == "combined":
            p.subject_to(f"{x.name}:slip_utilisation", target_margin * e["slip_utilisation"], upper=1.0)
        else:
            if T > 0.0:
                p.subject_to(f"{x.name}:torque_reserve_Nm", e["torque_capacity_Nm"] - target_margin * T, lower=0.0,
                             scale=T, unit="N m")
            if Fa > 0.0:
                p.subject_to(f"{x.name}:axial_reserve_N", e["axial_capacity_N"] - target_margin * Fa, lower=0.0,
                             scale=Fa, unit="N")
    hub_lim = spec.hub_yield_MPa / min_hub_yield_safety
    p.subject_to("hub_von_mises_MPa", first["hub_von_mises_MPa"], upper=hub_lim, scale=hub_lim, unit="MPa")
    if spec.proof_strength_MPa is not None:
        lim = max_proof_fraction * spec.proof_strength_MPa
        p.subject_to("thread_stress_MPa", first["thread_stress_MPa"], upper=lim, scale=lim, unit="MPa")
    p.minimize(tn, scale=init)
    res = p.solve(verbose=verbose, **ipopt)
    t_opt = float(res.values["nut_torque_Nm"])
    margins = taper_margin_table(spec, t_opt, demands, capacity=capacity)
    vals = {"nut_torque_Nm": t_opt, "preload_min_N": float(margins["preload_N"].iloc[0]),
            "preload_max_N": float(margins["preload_max_N"].iloc[0]), "nut_factor_max": spec.nut_factor_max,
            "nut_factor_min": spec.nut_factor_min, "capacity": capacity}
    return JointSizing(joint=spec.name, joint_type="taper_nut", values=vals, margins=margins, solve=res,
                       target_margin=float(target_margin))


def taper_margin_table(spec: TaperFitSpec, nut_torque_Nm: float, demands, *, capacity: str = "thesis") -> pd.DataFrame:
    """Numeric margins (:func:`taper_fit_sizing_margins`) of a nut torque at every demand, one row each."""
    rows = []
    for x in _as_demands(demands):
        e = taper_fit_sizing_margins(spec, float(nut_torque_Nm), x, capacity=capacity)
        rows.append({"demand": x.name, "torque_Nm": float(x.torque_Nm), "axial_force_N": float(x.axial_force_N),
                     "speed_rpm": float(x.speed_rpm), **{k: float(v) for k, v in e.items()}})
    return pd.DataFrame(rows).set_index("demand")


# ----------------------------------------------------------------------------------------------------------------
# data entry point
# ----------------------------------------------------------------------------------------------------------------

def size_joint(data: dict, joint: str, demands, *, proof_strength_MPa: float | None = None,
               **options: Any) -> JointSizing:
    """Size ``[joints.<joint>]`` of the data: :func:`size_press_fit` or :func:`size_taper_fit` by its type
    (``proof_strength_MPa`` for taper nuts; ``options`` go to the sizing function)."""
    d = data_values(data)
    if joint not in d.get("joints", {}):
        raise GearoptInputError(f"joint={joint!r} is not in [joints] ({sorted(d.get('joints', {}))})")
    kind = d["joints"][joint]["joint_type"]
    if kind == "press_fit":
        return size_press_fit(PressFitSpec.from_data(data, joint), demands, **options)
    if kind == "taper_nut":
        return size_taper_fit(TaperFitSpec.from_data(data, joint, proof_strength_MPa=proof_strength_MPa), demands,
                              **options)
    raise GearoptInputError(f"[joints.{joint}] joint_type={kind!r} must be 'press_fit' or 'taper_nut'")


__all__ = ["JointDemand", "PressFitSpec", "TaperFitSpec", "JointSizing", "press_fit_sizing_margins",
           "taper_fit_sizing_margins", "size_press_fit", "size_taper_fit", "size_joint", "suggest_fit",
           "press_fit_margin_table", "taper_margin_table", "default_tolerance_band_um", "smoothing_loss_of",
           "SLIP_CRITERIA", "TAPER_CAPACITIES", "FIT_GRADES"]
