"""Crank torques of an inline engine: gas and reciprocating-inertia torque per cylinder, firing order and phasing.

Per cylinder (docs/default-data.md sec. 2.4; docs/source-study.md sec. 2 replaces the thesis' garbled Eqs. 3.20/3.21), with the
exact slider-crank ``s'``, ``s''`` of :mod:`gearopt.engine.kinematics` and the cylinder's crank angle ``theta`` from
its TDC:

* gas torque ``T_g = (p - p_cc) A s'(theta)``  (= ``F r sin(theta + beta)/cos(beta)``, the classical form);
* reciprocating-mass torque ``T_i = -m s'^2 theta'' - m s' s'' theta'^2`` (Lagrange, kinetic energy
  ``m (s' theta')^2/2``), at constant speed ``-m s' s'' omega^2``.

Sign convention: a positive torque drives the crankshaft in its direction of rotation (gas torque positive on the
power stroke). Rotating masses (crank pin, big end) belong to the throw inertias of the torsional model, not here.

Phase convention of :class:`EngineExcitation`: the engine crank angle is **0 at cylinder 1's firing TDC**; the
cylinder in position ``j`` (0-based) of the firing order fires at ``j * firing_interval`` deg (1-5-3-6-2-4 with
120 deg: cylinder 1 at 0, 5 at 120, 3 at 240, 6 at 360, 2 at 480, 4 at 600 deg). The engine cycle is 720 deg
(4 pi rad); crank angles may be any real number (an integrator's accumulated angle).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from .. import numerics as nm
from ..data import System, require_section
from ..errors import GearoptInputError
from .fourier import harmonic_basis
from .kinematics import (
    check_crank_geometry,
    check_values,
    slider_crank,
    slider_crank_from_sincos,
)
from .pressure import (
    CYCLE_DEG,
    DEFAULT_HARMONICS,
    FIRING_TDC_DEG,
    CylinderPressure,
    indicated_work_J,
    peak_pressure_bar,
)

_RPM_TO_RAD_S = 2.0 * math.pi / 60.0
_BAR_TO_MPA = 0.1


def _torques_from_kinematics(k, speed_rad_s, accel_rad_s2, net_pressure_bar, area_mm2, mass_kg):
    ds_m = k["ds_dtheta_mm"] * 1e-3
    d2s_m = k["d2s_dtheta2_mm"] * 1e-3
    gas = net_pressure_bar * _BAR_TO_MPA * area_mm2 * ds_m                       # N/mm^2 * mm^2 * m = N m
    inertia = -mass_kg * ds_m * (d2s_m * speed_rad_s * speed_rad_s + ds_m * accel_rad_s2)
    return gas, inertia


def crank_torque(crank_angle_deg, speed_rpm, bore_mm, stroke_mm, rod_length_mm, reciprocating_mass_kg,
                 cylinder_pressure_bar, crank_acceleration_rad_s2=0.0, crankcase_pressure_bar=0.0):
    """Gas and reciprocating-inertia torque [N m] of one cylinder on its crank throw.

    Args:
        crank_angle_deg: crank angle from this cylinder's TDC [deg] (360 periodic kinematics).
        speed_rpm: crank speed [rpm], >= 0.
        bore_mm, stroke_mm: cylinder bore and stroke [mm] (> 0); crank radius = stroke / 2.
        rod_length_mm: connecting-rod centre distance [mm], > stroke / 2.
        reciprocating_mass_kg: piston, pin, rings and the rod's reciprocating share [kg], >= 0.
        cylinder_pressure_bar: cylinder pressure at this angle [bar]; the force on the piston is
            ``(cylinder_pressure_bar - crankcase_pressure_bar) * A`` (default crankcase 0: pass the pressure
            difference, or absolute pressure with ``crankcase_pressure_bar=1``).
        crank_acceleration_rad_s2: crank angular acceleration [rad/s^2] (general form; 0 at constant speed).

    Returns:
        ``(gas_torque_Nm, inertia_torque_Nm)``, same type as the inputs (dual-typed, smooth in angle and speed).

    Source: exact slider-crank dynamics (docs/default-data.md sec. 2.4; Heywood ch. 2; Den Hartog, *Mechanical
    Vibrations*, sec. 5.5), not the thesis' Eqs. 3.20/3.21 (garbled, docs/source-study.md sec. 2).
    """
    check_values("speed_rpm", speed_rpm, 0.0, unit="rpm")
    check_values("bore_mm", bore_mm, 0.0, low_inclusive=False, unit="mm")
    check_values("stroke_mm", stroke_mm, 0.0, low_inclusive=False, unit="mm")
    check_values("reciprocating_mass_kg", reciprocating_mass_kg, 0.0, unit="kg")
    check_values("cylinder_pressure_bar", cylinder_pressure_bar, unit="bar")
    check_values("crank_acceleration_rad_s2", crank_acceleration_rad_s2, unit="rad/s^2")
    check_values("crank_angle_deg", crank_angle_deg, -1e6, 1e6, unit="deg")  # beyond, float angles lose degrees
    check_values("crankcase_pressure_bar", crankcase_pressure_bar, 0.0, 50.0, unit="bar")
    check_values("cylinder_pressure_bar", cylinder_pressure_bar, -50.0, 1e4, unit="bar")
    k = slider_crank(crank_angle_deg * (math.pi / 180.0), 0.5 * stroke_mm, rod_length_mm)
    area = 0.25 * math.pi * bore_mm * bore_mm
    return _torques_from_kinematics(k, speed_rpm * _RPM_TO_RAD_S, crank_acceleration_rad_s2,
                                    cylinder_pressure_bar - crankcase_pressure_bar, area, reciprocating_mass_kg)


@dataclass(frozen=True)
class EngineExcitation:
    """Crank torques of all cylinders of an inline 4-stroke engine at one speed-load point.

    Fields: ``bore_mm``, ``stroke_mm``, ``rod_length_mm``, ``reciprocating_mass_kg`` (per cylinder),
    ``pressure`` (:class:`CylinderPressure`, abs bar, firing TDC at 360 deg of its trace), ``firing_order``
    (cylinder numbers 1..n), ``firing_interval_deg`` (n * interval = 720), ``crankcase_pressure_bar`` (abs,
    default 1.0 [E] atmospheric), ``speed_rpm``/``load`` (operating point the pressure was scaled for; the
    inertia torque uses the instantaneous speed passed to the methods). Phase convention: module docstring.
    """

    bore_mm: float
    stroke_mm: float
    rod_length_mm: float
    reciprocating_mass_kg: float
    pressure: CylinderPressure
    firing_order: tuple = (1, 5, 3, 6, 2, 4)
    firing_interval_deg: float = 120.0
    crankcase_pressure_bar: float = 1.0
    speed_rpm: float | None = None
    load: float = 1.0
    _cylinder_pressures: tuple = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        check_values("bore_mm", self.bore_mm, 0.0, low_inclusive=False, unit="mm")
        check_values("stroke_mm", self.stroke_mm, 0.0, low_inclusive=False, unit="mm")
        check_crank_geometry(0.5 * self.stroke_mm, self.rod_length_mm)
        check_values("reciprocating_mass_kg", self.reciprocating_mass_kg, 0.0, unit="kg")
        check_values("crankcase_pressure_bar", self.crankcase_pressure_bar, 0.0, unit="bar")
        order = tuple(int(c) for c in self.firing_order)
        n = len(order)
        if n < 1 or sorted(order) != list(range(1, n + 1)):
            raise GearoptInputError(f"firing_order={self.firing_order!r} must be a permutation of 1..{n}")
        if abs(n * self.firing_interval_deg - CYCLE_DEG) > 1e-9:
            raise GearoptInputError(f"firing_interval_deg={self.firing_interval_deg:g} deg x {n} cylinders must "
                                    f"equal the {CYCLE_DEG:g} deg cycle (even firing)")
        object.__setattr__(self, "firing_order", order)
        # cylinder c's trace angle = engine angle - TDC_c + 360: pre-rotated series share one harmonic basis
        object.__setattr__(self, "_cylinder_pressures", tuple(
            self.pressure.shifted(FIRING_TDC_DEG - self.firing_tdc_deg(c)) for c in range(1, n + 1)))

    # ------------------------------------------------------------------------------------------------------------
    @classmethod
    def from_data(cls, system: System, speed_rpm: float | None = None, load: float = 1.0,
                  pressure: str = "table", harmonics: int = DEFAULT_HARMONICS, scale_to_map: bool = True,
                  crankcase_pressure_bar: float = 1.0) -> EngineExcitation:
        """The engine of ``system`` (its ``[engine]`` table; ``system`` the :class:`~gearopt.data.System` of the
        data file, required: a file without ``[engine]`` raises :class:`~gearopt.errors.MissingSectionError`) at
        ``speed_rpm`` (default the engine's rated speed) and ``load`` (0..1).

        ``pressure="table"``: the Mendes 2008 measured trace; ``"wiebe"``: the double-Wiebe model of
        ``engine.combustion``. With ``scale_to_map`` the trace is scaled to :func:`peak_pressure_bar` of the
        speed and load; otherwise the raw trace (152 bar measured, 180 bar Wiebe) is used at every speed.
        """
        e = require_section(system, "engine", "EngineExcitation.from_data")
        speed = e["rated_speed_rpm"] if speed_rpm is None else speed_rpm
        check_values("speed_rpm", speed, 0.0, low_inclusive=False, unit="rpm")
        check_values("load", load, 0.0, 1.0)
        speed = float(speed)
        if pressure == "table":
            p = CylinderPressure.from_data(system, harmonics=harmonics)
        elif pressure == "wiebe":
            p = CylinderPressure.from_double_wiebe(harmonics=harmonics, system=system)
        else:
            raise GearoptInputError(f"pressure={pressure!r} must be 'table' or 'wiebe'")
        if scale_to_map:
            p = p.scaled_to_peak(float(peak_pressure_bar(speed, load, system)))
        return cls(bore_mm=float(e["bore_mm"]), stroke_mm=float(e["stroke_mm"]),
                   rod_length_mm=float(e["connecting_rod_length_mm"]),
                   reciprocating_mass_kg=float(e["reciprocating_mass_kg"]), pressure=p,
                   firing_order=tuple(e["firing_order"]), firing_interval_deg=float(e["firing_interval_deg"]),
                   crankcase_pressure_bar=crankcase_pressure_bar, speed_rpm=speed, load=float(load))

    # ------------------------------------------------------------------------------------------------------------
    @property
    def cylinders(self) -> int:
        return len(self.firing_order)

    @property
    def piston_area_mm2(self) -> float:
        return 0.25 * math.pi * self.bore_mm ** 2

    @property
    def crank_radius_mm(self) -> float:
        return 0.5 * self.stroke_mm

    def firing_tdc_deg(self, cylinder: int) -> float:
        """Engine crank angle [deg, 0..720) of the firing TDC of ``cylinder`` (1-based number)."""
        if cylinder not in self.firing_order:
            raise GearoptInputError(f"cylinder={cylinder!r} must be one of 1..{len(self.firing_order)}")
        return self.firing_order.index(cylinder) * self.firing_interval_deg

    def cylinder_pressure_bar(self, cylinder: int, crank_angle_rad):
        """Absolute pressure [bar] in ``cylinder`` at the engine crank angle [rad] (dual-typed)."""
        cs, ss = harmonic_basis(0.5 * crank_angle_rad, self.pressure.harmonics)
        return self._cylinder_pressures[cylinder - 1].pressure_from_basis(cs, ss)

    def cylinder_pressures_bar(self, crank_angle_rad) -> list:
        """Absolute pressures [bar] of all cylinders (index i for cylinder i + 1) at one engine crank angle [rad]:
        one shared harmonic basis, so six pressures cost little more than one (dual-typed)."""
        cs, ss = harmonic_basis(0.5 * crank_angle_rad, self.pressure.harmonics)
        return [p.pressure_from_basis(cs, ss) for p in self._cylinder_pressures]

    # ------------------------------------------------------------------------------------------------------------
    def cylinder_torque_parts_Nm(self, crank_angle_rad, speed_rad_s, crank_accel_rad_s2=0.0, *,
                                 pressure_angle_rad=None, pressure_scale=1.0):
        """``(gas_torques, inertia_torques)``: two lists [N m], index i for cylinder i + 1.

        ``crank_angle_rad`` [rad, engine angle, 0 = cylinder 1 firing TDC], ``speed_rad_s`` [rad/s] and
        ``crank_accel_rad_s2`` [rad/s^2] are each either one value for a rigid crankshaft or a sequence with one
        value per cylinder (the angle, speed and acceleration of each throw in a torsional model). Dual-typed.

        ``pressure_angle_rad`` (optional, one engine angle [rad]): evaluate the cylinder pressures there instead of
        at the throw angles, e.g. along the nominal constant-speed motion (one shared basis for all cylinders);
        ``pressure_scale`` multiplies the absolute pressure (``(f p - p_cc) A s'``), e.g. a symbolic integrator
        parameter that sets the peak pressure per speed.
        """
        n = self.cylinders
        angles = _per_cylinder(crank_angle_rad, n, "crank_angle_rad")
        speeds = _per_cylinder(speed_rad_s, n, "speed_rad_s")
        accels = _per_cylinder(crank_accel_rad_s2, n, "crank_accel_rad_s2")
        for v in speeds:
            check_values("speed_rad_s", v, 0.0, unit="rad/s")
        check_values("pressure_scale", pressure_scale, 0.0)
        shared = not isinstance(crank_angle_rad, (list, tuple))
        r, lrod, area, m = self.crank_radius_mm, self.rod_length_mm, self.piston_area_mm2, self.reciprocating_mass_kg
        if pressure_angle_rad is not None:
            pressures = self.cylinder_pressures_bar(pressure_angle_rad)
        elif shared:
            pressures = self.cylinder_pressures_bar(crank_angle_rad)
        else:
            pressures = [self.cylinder_pressure_bar(i + 1, angles[i]) for i in range(n)]
        if shared:
            s0, c0 = nm.sin(crank_angle_rad), nm.cos(crank_angle_rad)
        gas, inertia = [], []
        for i in range(n):
            tdc = math.radians(self.firing_tdc_deg(i + 1))
            if shared:   # sin/cos of (theta - tdc) by rotation of one sin/cos pair
                st = s0 * math.cos(tdc) - c0 * math.sin(tdc)
                ct = c0 * math.cos(tdc) + s0 * math.sin(tdc)
            else:
                st, ct = nm.sin(angles[i] - tdc), nm.cos(angles[i] - tdc)
            k = slider_crank_from_sincos(st, ct, r, lrod)
            g, t = _torques_from_kinematics(k, speeds[i], accels[i],
                                            pressure_scale * pressures[i] - self.crankcase_pressure_bar, area, m)
            gas.append(g)
            inertia.append(t)
        return gas, inertia

    def cylinder_torque_Nm(self, cylinder: int, crank_angle_rad, speed_rad_s, crank_accel_rad_s2=0.0, *,
                           pressure_angle_rad=None, pressure_scale=1.0):
        """Gas + inertia torque [N m] of one ``cylinder`` (1-based) on its throw: ``crank_angle_rad`` is the
        throw's engine angle [rad] (0 = cylinder 1 firing TDC), ``speed_rad_s``/``crank_accel_rad_s2`` the throw's
        speed and acceleration; ``pressure_angle_rad``/``pressure_scale`` as in :meth:`cylinder_torque_parts_Nm`.
        Dual-typed."""
        tdc = math.radians(self.firing_tdc_deg(cylinder))
        check_values("speed_rad_s", speed_rad_s, 0.0, unit="rad/s")
        check_values("pressure_scale", pressure_scale, 0.0)
        p = self.cylinder_pressure_bar(cylinder, crank_angle_rad if pressure_angle_rad is None else pressure_angle_rad)
        k = slider_crank(crank_angle_rad - tdc, self.crank_radius_mm, self.rod_length_mm)
        g, t = _torques_from_kinematics(k, speed_rad_s, crank_accel_rad_s2, pressure_scale * p - self.crankcase_pressure_bar,
                                        self.piston_area_mm2, self.reciprocating_mass_kg)
        return g + t

    def cylinder_torques_Nm(self, crank_angle_rad, speed_rad_s, crank_accel_rad_s2=0.0, **pressure) -> list:
        """Gas + inertia torque [N m] of each cylinder (list, index i for cylinder i + 1); arguments as
        :meth:`cylinder_torque_parts_Nm`. Dual-typed, C-infinity in angle and speed."""
        gas, inertia = self.cylinder_torque_parts_Nm(crank_angle_rad, speed_rad_s, crank_accel_rad_s2, **pressure)
        return [g + t for g, t in zip(gas, inertia)]

    def total_torque_Nm(self, crank_angle_rad, speed_rad_s, crank_accel_rad_s2=0.0, **pressure):
        """Sum of all cylinders' torques [N m] (rigid-crank resultant); arguments as above."""
        for name, value, unit in (("crank_angle_rad", crank_angle_rad, "rad"), ("speed_rad_s", speed_rad_s, "rad/s"),
                                  ("crank_accel_rad_s2", crank_accel_rad_s2, "rad/s^2")):
            for v in (value if isinstance(value, (list, tuple)) else (value,)):  # one value or one per cylinder
                check_values(name, v, unit=unit)
        return nm.sum1(self.cylinder_torques_Nm(crank_angle_rad, speed_rad_s, crank_accel_rad_s2, **pressure))

    def reciprocating_inertia_kgm2(self, cylinder: int, crank_angle_rad):
        """``m s'^2`` [kg m^2] of ``cylinder`` at the engine crank angle [rad]: the angle-dependent inertia a
        torsional model may add to the throw instead of passing the crank acceleration (dual-typed)."""
        tdc = math.radians(self.firing_tdc_deg(cylinder))
        ds_m = slider_crank(crank_angle_rad - tdc, self.crank_radius_mm, self.rod_length_mm)["ds_dtheta_mm"] * 1e-3
        return self.reciprocating_mass_kg * ds_m * ds_m

    # ------------------------------------------------------------------------------------------------------------
    def indicated_work_per_cylinder_J(self) -> float:
        """Closed integral of ``p dV`` over the cycle [J] (numeric)."""
        return indicated_work_J(self.pressure, self.bore_mm, self.stroke_mm, self.rod_length_mm)

    def mean_torque_Nm(self) -> float:
        """Mean indicated crank torque [N m] of the engine = n W / (4 pi) (numeric)."""
        return self.cylinders * self.indicated_work_per_cylinder_J() / (4.0 * math.pi)

    def indicated_power_kW(self, speed_rpm: float | None = None) -> float:
        """Indicated power [kW] at ``speed_rpm`` (default the operating point's speed)."""
        n = self.speed_rpm if speed_rpm is None else speed_rpm
        if n is None:
            raise GearoptInputError("speed_rpm is needed: this excitation has no operating-point speed")
        return self.mean_torque_Nm() * float(n) * _RPM_TO_RAD_S * 1e-3


def _per_cylinder(value, n, name):
    if isinstance(value, (list, tuple)):
        if len(value) != n:
            raise GearoptInputError(f"{name} has {len(value)} entries: give one value or one per cylinder ({n})")
        return list(value)
    return [value] * n


__all__ = ["EngineExcitation", "crank_torque"]
