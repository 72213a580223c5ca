"""The shaft-hub joints of a :class:`~gearopt.data.System` (its ``[joints.*]`` and ``[materials.*]`` records):
capacities from :func:`~gearopt.joints.press_fit.press_fit` / :func:`~gearopt.joints.taper_fit.taper_fit`. (The
timing train's quasi-static accessory load case lives in its case package,
:func:`gearopt.cases.timing_train.accessory_load_torques_Nm`.)

Press fits use the nominal (mean) ISO 286 interference by default and, like the thesis (plain Shigley formula), no
smoothing loss; ``smoothing=True`` applies DIN 7190 to the data's Rz values. Taper joints use the data's nut torque
and nut factor (thesis Table 3.11 range) and the thesis' uniform-pressure form (Eq. 3.48).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from .. import numerics as nm
from ..data import System, joint_record, material_record, system_of
from ..errors import GearoptInputError
from ._record import ResultRecord
from .press_fit import press_fit
from .taper_fit import taper_fit

JOINT_TYPES = ("press_fit", "taper_nut")
_INTERFERENCE_KEYS = {"nominal": "diametral_interference_um", "min": "diametral_interference_min_um",
                      "max": "diametral_interference_max_um"}
_NUT_FACTOR_KEYS = {"nominal": "nut_factor", "min": "nut_factor_min", "max": "nut_factor_max"}


@dataclass(frozen=True, eq=False, kw_only=True)
class JointCapacity(ResultRecord):
    """Capacity of one ``[joints.<joint>]`` entry (:func:`joint_capacity`). Numeric values are floats; with symbolic
    ``overrides`` the capacities are CasADi expressions. Fields only one joint type has are ``None`` for the other.
    ``as_row()`` (= ``to_dict()``) gives the set fields as one table row, in the order of the fields."""

    joint: str
    """Name of the ``[joints.*]`` entry."""
    gear: str
    """Gear the joint holds."""
    type: str
    """``"press_fit"`` or ``"taper_nut"``."""
    fit: str
    """ISO 286 fit of a press fit (e.g. ``"H7/s6"``), the taper designation of a taper joint."""
    fit_diameter_mm: Any
    """Fit diameter [mm]: the shaft diameter of a press fit, the mean cone diameter of a taper."""
    interference_um: Any = None
    """Press fits: effective diametral interference at ``speed_rpm`` [um]."""
    pressure_MPa: Any
    """Fit pressure [MPa] (press fit: Lame; taper: cone contact pressure)."""
    torque_capacity_Nm: Any
    """Torque the joint holds without slip [N m] (taper: thesis form, Eq. 3.48)."""
    axial_capacity_N: Any
    """Axial force the joint holds [N] (press fit: friction force; taper: the nut preload)."""
    bolt_preload_N: Any = None
    """Taper joints: nut preload [N]."""
    torque_capacity_engagement_friction_Nm: Any = None
    """Taper joints: torque capacity with the engagement friction [N m]."""
    hub_hoop_stress_MPa: Any
    """Hoop stress at the hub bore [MPa]."""
    hub_von_mises_MPa: Any
    """Von Mises stress at the hub bore [MPa]."""
    hub_yield_safety: Any
    """Hub yield strength / hub von Mises stress [-]."""

    def as_row(self) -> dict[str, Any]:
        """One table row: the set fields (``None`` ones left out), in field order (e.g. for ``pd.DataFrame``)."""
        return self.to_dict()


def joint_capacity(system: System, joint: str, *, interference: str = "nominal", nut_factor: str = "nominal",
                   smoothing: bool = False, theory: str = "uniform_pressure", speed_rpm: float = 0.0,
                   overrides: dict | None = None) -> JointCapacity:
    """Capacity of the joint ``joint`` of ``system`` (``system.joints[joint]`` with its hub and shaft
    ``system.materials``) as a :class:`JointCapacity` record.

    ``system``: the :class:`~gearopt.data.System` of the data file (``gearopt.load_system(path)``; a raw dict raises
    :class:`~gearopt.errors.GearoptInputError` naming the conversion). A joint or material the file
    lacks raises :class:`~gearopt.errors.DataFileError` naming the file and the key path (``joints.<name>``,
    ``materials.<name>``).

    ``interference``: ``"nominal"``/``"min"``/``"max"`` of the ISO 286 fit (press fits); ``nut_factor``:
    ``"nominal"``/``"min"``/``"max"`` (taper joints; the *max* factor gives the *lowest* preload); ``smoothing``:
    apply DIN 7190 (0.8 sum Rz) to press fits; ``theory`` of the taper; ``speed_rpm`` for the centrifugal loss.
    Fields: ``joint``, ``gear``, ``type``, ``fit``, ``pressure_MPa``, ``torque_capacity_Nm``, ``axial_capacity_N``,
    ``hub_hoop_stress_MPa``, ``hub_von_mises_MPa``, ``hub_yield_safety``, ``fit_diameter_mm`` and for tapers
    ``bolt_preload_N`` and ``torque_capacity_engagement_friction_Nm``, for press fits ``interference_um``.

    ``overrides`` replaces entries of ``[joints.<joint>]`` by value, numeric or CasADi-symbolic (a design variable of an
    NLP: e.g. ``{"diametral_interference_um": x}`` with ``interference="nominal"``, ``fit_length_mm``,
    ``nut_torque_Nm``); symbolic entries give symbolic capacities.
    """
    system = system_of(system, "joint_capacity")
    j = dict(joint_record(system, joint, "joint_capacity").entries)
    unknown = set(overrides or {}) - set(j)
    if unknown:
        raise GearoptInputError(f"overrides={sorted(unknown)} are not entries of [joints.{joint}] ({sorted(j)})")
    j.update(overrides or {})
    hub = material_record(system, j["hub_material"], "joint_capacity", f"joints.{joint}.hub_material")
    shaft = material_record(system, j["shaft_material"], "joint_capacity", f"joints.{joint}.shaft_material")
    row: dict[str, Any] = {"joint": joint, "gear": j["gear"], "type": j["joint_type"]}
    if j["joint_type"] == "press_fit":
        if interference not in _INTERFERENCE_KEYS:
            raise GearoptInputError(f"interference={interference!r} must be one of {sorted(_INTERFERENCE_KEYS)}")
        kw = {}
        if smoothing:
            kw["roughness_Rz_um"] = (j["shaft_roughness_Rz_um"], j["hub_roughness_Rz_um"])
        r = press_fit(j["shaft_diameter_mm"], j["shaft_bore_diameter_mm"], j["hub_outer_diameter_mm"],
                      j["fit_length_mm"], j[_INTERFERENCE_KEYS[interference]], shaft["E_MPa"], shaft["poisson_ratio"],
                      hub["E_MPa"], hub["poisson_ratio"], j["friction_coefficient"], speed_rpm=speed_rpm,
                      shaft_density_kg_m3=shaft["density_kg_m3"], hub_density_kg_m3=hub["density_kg_m3"],
                      hub_yield_MPa=hub["yield_strength_MPa"], shaft_yield_MPa=shaft["yield_strength_MPa"], **kw)
        row.update(fit=j["fit"], fit_diameter_mm=j["shaft_diameter_mm"], interference_um=r.effective_interference_um,
                   pressure_MPa=r.pressure_MPa, torque_capacity_Nm=r.torque_capacity_Nm,
                   axial_capacity_N=r.axial_capacity_N, hub_hoop_stress_MPa=r.hub_hoop_stress_MPa,
                   hub_von_mises_MPa=r.hub_von_mises_MPa, hub_yield_safety=r.hub_yield_safety)
    elif j["joint_type"] == "taper_nut":
        if nut_factor not in _NUT_FACTOR_KEYS:
            raise GearoptInputError(f"nut_factor={nut_factor!r} must be one of {sorted(_NUT_FACTOR_KEYS)}")
        r = taper_fit(j["taper_large_diameter_mm"], j["taper_small_diameter_mm"], j["taper_half_angle_deg"],
                      j["friction_coefficient"], nut_torque_Nm=j["nut_torque_Nm"],
                      nut_factor=j[_NUT_FACTOR_KEYS[nut_factor]], thread_diameter_mm=j["nut_thread_diameter_mm"],
                      theory=theory, hub_outer_diameter_mm=j["hub_outer_diameter_mm"],
                      hub_yield_MPa=hub["yield_strength_MPa"])
        row.update(fit=j.get("taper", "taper"), fit_diameter_mm=0.5 * (j["taper_large_diameter_mm"]
                                                                     + j["taper_small_diameter_mm"]),
                   pressure_MPa=r.contact_pressure_MPa, torque_capacity_Nm=r.torque_capacity_Nm,
                   axial_capacity_N=r.axial_capacity_N, bolt_preload_N=r.bolt_preload_N,
                   torque_capacity_engagement_friction_Nm=r.torque_capacity_engagement_friction_Nm,
                   hub_hoop_stress_MPa=r.hub_hoop_stress_MPa, hub_von_mises_MPa=r.hub_von_mises_MPa,
                   hub_yield_safety=r.hub_yield_safety)
    else:
        raise GearoptInputError(f"[joints.{joint}] joint_type={j['joint_type']!r} must be one of {JOINT_TYPES}")
    return JointCapacity(**{k: (float(v) if nm.is_numeric(v) and not isinstance(v, (str, bool)) else v)
                            for k, v in row.items()})


def joint_capacities(system: System, **options) -> dict[str, JointCapacity]:
    """:func:`joint_capacity` of every joint of ``system`` (``system.joints``), keyed by joint name."""
    system = system_of(system, "joint_capacities")
    return {name: joint_capacity(system, name, **options) for name in system.joints}


__all__ = ["joint_capacity", "joint_capacities", "JointCapacity", "JOINT_TYPES"]
