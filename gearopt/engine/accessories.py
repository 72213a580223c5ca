"""Accessory load torques over each accessory's own shaft angle: valve train (camshaft), common-rail fuel pump,
single-cylinder air compressor, lube pump. **All estimates [E]**: no public measurements exist (docs/default-data.md sec. 2.6); shapes come from first-principles models, then mean and peak are set to the data's [E] numbers
(``engine.camshaft``, ``engine.fuel_pump``, ``engine.air_compressor``, ``engine.lube_pump``).

Sign convention: the torque is the **load** the accessory puts on its drive shaft, positive resisting the rotation
(the drive must supply it); in a torsional model the external torque on the accessory's inertia is its negative.
Angles are the accessory shaft's own rotation [rad] in its direction of rotation, any real value (2 pi periodic).

Every map is an :class:`AccessoryTorque`: a truncated Fourier series over one shaft revolution (C-infinity,
dual-typed: floats, numpy, CasADi SX/MX; see :mod:`gearopt.engine.fourier`) with its fit error against the
underlying model recorded. For repeated evaluation build the map once (``AccessoryTorque.camshaft(system)``) and call
it; the module-level functions rebuild it from the data on every call.

Phase conventions [E]: cam angle 0 when the crank is at cylinder 1's firing TDC (cam = crank / 2); fuel-pump angle 0
at plunger 1's peak torque; compressor angle 0 at its piston's TDC; lube-pump angle arbitrary.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..data import System, require_section
from ..errors import GearoptInputError
from .fourier import FourierSeries
from .kinematics import check_values, slider_crank

TWO_PI = 2.0 * math.pi

# Model constants without a data entry: all [E], chosen here (the lead may move them into default_train.toml).
VALVE_EVENT_HALF_WIDTH_CAM_DEG = 60.0      # cam lobe event +-60 cam deg (240 crank deg duration)
VALVE_SPRING_PRELOAD_FRACTION = 0.4        # spring preload / load at max lift
EXHAUST_LOBE_CENTRE_CRANK_DEG = 250.0      # after firing TDC (exhaust max lift about 110 deg before gas-exchange TDC)
INTAKE_LOBE_CENTRE_CRANK_DEG = 470.0       # after firing TDC (intake max lift about 110 deg after gas-exchange TDC)
COMPRESSOR_ROD_TO_CRANK_RATIO = 4.0        # connecting rod / crank radius of the air compressor
COMPRESSOR_CLEARANCE_RATIO = 0.05          # clearance volume / swept volume
COMPRESSOR_POLYTROPIC_EXPONENT = 1.3
COMPRESSOR_SUCTION_PRESSURE_BAR = 1.0      # abs (naturally aspirated compressor); crankcase also 1 bar abs
LUBE_PUMP_ROTOR_TEETH = 7                  # gerotor inner rotor: ripple order
LUBE_PUMP_RIPPLE_FRACTION = 0.05           # "low ripple": +-5 % of the mean


@dataclass(frozen=True)
class AccessoryTorque:
    """Load torque [N m] of one accessory over its shaft angle [rad] (Fourier series, period 2 pi).

    Fields: ``name``, ``series``, ``source`` (model and data), ``fit_max_error_Nm`` (series against the model it was
    fitted to), ``mean_Nm``, ``max_Nm``, ``min_Nm`` (of the series).
    """

    name: str
    series: FourierSeries
    source: str
    fit_max_error_Nm: float
    mean_Nm: float
    max_Nm: float
    min_Nm: float

    def torque_Nm(self, angle_rad):
        """Load torque [N m] at the shaft angle [rad] (dual-typed, any real angle)."""
        return self.series(angle_rad)

    __call__ = torque_Nm

    # ------------------------------------------------------------------------------------------------------------
    @classmethod
    def from_model(cls, name, fun, harmonics, source, mean_Nm=None, max_Nm=None, samples=4096):
        """Fit ``fun`` (vectorised, angle [rad] -> N m) with ``harmonics``; if ``mean_Nm``/``max_Nm`` are given,
        the map becomes ``alpha * fit + beta`` with that mean and maximum (alpha > 0); the recorded fit error is of
        the scaled series against the equally scaled model."""
        series = FourierSeries.fit_function(fun, TWO_PI, harmonics, samples)
        x = np.arange(samples) * (TWO_PI / samples)
        ref = np.asarray(fun(x), dtype=float)
        alpha, beta = 1.0, 0.0
        if mean_Nm is not None and max_Nm is not None:
            _, _, smax, _ = series.extrema()
            if not smax > series.mean:
                raise GearoptInputError(f"{name}: a constant model cannot be scaled to a peak")
            alpha = (max_Nm - mean_Nm) / (smax - series.mean)
            beta = mean_Nm - alpha * series.mean
            series = series.scaled(alpha, beta)
            ref = alpha * ref + beta
        err = float(np.max(np.abs(np.asarray(series(x)) - ref)))
        smin, _, smax, _ = series.extrema()
        return cls(name=name, series=series, source=source, fit_max_error_Nm=err, mean_Nm=series.mean,
                   max_Nm=smax, min_Nm=smin)

    # ------------------------------------------------------------------------------------------------------------
    @classmethod
    def camshaft(cls, system: System, harmonics: int = 48) -> AccessoryTorque:
        """Valve-train load torque on the camshaft over the cam angle [rad] (6 cylinders, 12 lobes).

        Model [E]: each lobe lifts its tappet ``h = H ((1 + cos(pi psi / beta)) / 2)^2`` (C2 profile) over
        ``|psi| < beta`` (cam half-width ``beta`` = 60 deg), H set by the maximum lift slope of 12 mm/rad
        (docs/default-data.md sec. 2.6; H = 6.2 mm);
        spring force ``F = F_max (f0 + (1 - f0) h / H)`` with ``F_max`` = ``tappet_load_at_max_lift_N`` and
        preload fraction f0 = 0.4; lobe torque ``F dh/dpsi`` (resisting on the opening flank, driving on the
        closing flank). Exhaust and intake lobes of cylinder c are centred 250 and 470 crank deg after its firing
        TDC (firing order and interval from ``engine``). The sum repeats every 60 cam deg (cam orders 6, 12, 18 ...,
        as ``valve_train_excitation_orders_cam``); its oscillating part is scaled so the peak is
        ``valve_train_torque_mean_Nm + valve_train_torque_amplitude_Nm`` and the mean set to
        ``valve_train_torque_mean_Nm`` (friction).
        """
        e = _engine(system, "AccessoryTorque.camshaft")
        cam = e["camshaft"]
        order = list(e["firing_order"])
        interval = float(e["firing_interval_deg"])
        f_max = float(cam["tappet_load_at_max_lift_N"])
        slope_m = 12.0e-3                                   # m/rad, docs/default-data.md sec. 2.6 (lift slope <= 12 mm/rad)
        beta = math.radians(VALVE_EVENT_HALF_WIDTH_CAM_DEG)
        lift = slope_m * beta / (math.pi * 0.75 * math.sin(math.pi / 3.0))   # max of c sin u is at u = pi/3
        centres = []
        for c in range(1, len(order) + 1):
            tdc = order.index(c) * interval
            centres += [math.radians(0.5 * (tdc + EXHAUST_LOBE_CENTRE_CRANK_DEG)),
                        math.radians(0.5 * (tdc + INTAKE_LOBE_CENTRE_CRANK_DEG))]

        def fun(x):
            total = np.zeros_like(np.asarray(x, dtype=float))
            for c0 in centres:
                psi = np.mod(x - c0 + math.pi, TWO_PI) - math.pi
                inside = np.abs(psi) < beta
                c = np.where(inside, 0.5 * (1.0 + np.cos(math.pi * psi / beta)), 0.0)
                h = lift * c * c
                dh = -lift * math.pi / beta * c * np.sin(math.pi * psi / beta)
                force = f_max * (VALVE_SPRING_PRELOAD_FRACTION + (1.0 - VALVE_SPRING_PRELOAD_FRACTION) * h / lift)
                total += force * dh
            return total    # opening flank (psi < 0, dh/dpsi > 0) resists: load positive there

        mean = float(cam["valve_train_torque_mean_Nm"])
        return cls.from_model("camshaft", fun, harmonics,
                              "[E] lobe model (spring force x lift slope, 12 lobes), scaled to engine.camshaft "
                              "mean and amplitude", mean_Nm=mean,
                              max_Nm=mean + float(cam["valve_train_torque_amplitude_Nm"]))

    @classmethod
    def fuel_pump(cls, system: System, harmonics: int = 48) -> AccessoryTorque:
        """Common-rail pump load torque over the pump angle [rad] (``engine.fuel_pump``: plungers, mean, peak).

        Model [E]: each of the n plungers delivers once per revolution, its torque pulse a periodic von Mises bump
        ``exp(kappa (cos(x - 2 pi j / n) - 1))`` (smooth, non-negative); ``kappa`` solves
        peak/mean = ``torque_peak_Nm / torque_mean_Nm`` (90/35) in closed form terms (mean of one bump
        ``exp(-kappa) I0(kappa)``), then the sum is scaled to ``torque_mean_Nm``.
        """
        from scipy.optimize import brentq
        from scipy.special import i0e

        fp = _engine(system, "AccessoryTorque.fuel_pump")["fuel_pump"]
        n = int(fp["plungers"])
        mean, peak = float(fp["torque_mean_Nm"]), float(fp["torque_peak_Nm"])
        check_values("fuel_pump.plungers", n, 1)
        check_values("fuel_pump.torque_mean_Nm", mean, 0.0, low_inclusive=False, unit="N m")
        check_values("fuel_pump.torque_peak_Nm", peak, mean, float(n) * mean, low_inclusive=False,
                     high_inclusive=False, unit="N m")
        shifts = [TWO_PI * j / n for j in range(n)]

        def bumps(x, kappa):
            return sum(np.exp(kappa * (np.cos(x - s) - 1.0)) for s in shifts)

        def ratio_gap(kappa):
            x = np.linspace(-math.pi / n, math.pi / n, 2001)
            return float(np.max(bumps(x, kappa))) / (n * float(i0e(kappa))) - peak / mean

        kappa = brentq(ratio_gap, 1e-6, 500.0, xtol=1e-12)
        scale = mean / (n * float(i0e(kappa)))
        return cls.from_model("fuel_pump", lambda x: scale * bumps(x, kappa), harmonics,
                              f"[E] {n} plunger pulses (von Mises, kappa {kappa:.4g}) scaled to engine.fuel_pump "
                              "mean and peak")

    @classmethod
    def air_compressor(cls, system: System, loaded: bool = True, harmonics: int = 48) -> AccessoryTorque:
        """Single-cylinder air-compressor load torque over its crank angle [rad] (0 = piston TDC).

        Loaded [E]: ideal pV cycle (``engine.air_compressor`` bore, stroke, discharge pressure; suction 1 bar abs,
        clearance 5 %, polytropic n 1.3, rod/crank 4): re-expansion from TDC until suction pressure, suction to BDC,
        compression until discharge pressure, delivery to TDC; load torque ``(p - 1 bar) A s'`` opposed to the piston
        motion, exact slider-crank ``s'``. The ideal cycle gives mean 10.0, max 94 N m; valve losses and friction are
        folded into ``alpha T + beta`` with the data's ``torque_mean_loaded_Nm`` and ``torque_peak_Nm`` (alpha 1.22,
        beta 4.8 N m); the minimum then follows (about -27 N m; the data's -50 N m is a rougher estimate). The
        48-harmonic series is within 2.3 N m of the (kinked, valve-event) ideal shape.
        Unloaded [E]: the compressor's reciprocating-inertia shape ``-(s'/r)(s''/r)`` (zero mean) scaled to
        +-``torque_amplitude_unloaded_Nm``.
        """
        ac = _engine(system, "AccessoryTorque.air_compressor")["air_compressor"]
        r = 0.5 * float(ac["stroke_mm"])
        rod = COMPRESSOR_ROD_TO_CRANK_RATIO * r
        if not loaded:
            amp = float(ac["torque_amplitude_unloaded_Nm"])
            x = np.linspace(0.0, TWO_PI, 20001)
            k = slider_crank(x, r, rod)
            norm = float(np.max(np.abs(k["ds_dtheta_mm"] * k["d2s_dtheta2_mm"])))

            def unloaded(t):
                kk = slider_crank(t, r, rod)
                return -amp * kk["ds_dtheta_mm"] * kk["d2s_dtheta2_mm"] / norm
            return cls.from_model("air_compressor_unloaded", unloaded, harmonics,
                                  "[E] reciprocating-inertia shape scaled to engine.air_compressor unloaded amplitude")
        ideal = ideal_compressor_cycle(system)["torque_Nm"]
        return cls.from_model("air_compressor", ideal, harmonics,
                              "[E] ideal pV cycle, scaled to engine.air_compressor loaded mean and peak",
                              mean_Nm=float(ac["torque_mean_loaded_Nm"]), max_Nm=float(ac["torque_peak_Nm"]))

    @classmethod
    def lube_pump(cls, system: System) -> AccessoryTorque:
        """Gerotor lube-pump load torque over the pump angle [rad]: ``engine.lube_pump.torque_mean_Nm`` with a
        +-5 % ripple at the 7-tooth inner-rotor order [E] ("low ripple", docs/default-data.md sec. 2.6)."""
        mean = float(_engine(system, "AccessoryTorque.lube_pump")["lube_pump"]["torque_mean_Nm"])
        z = LUBE_PUMP_ROTOR_TEETH
        return cls.from_model("lube_pump", lambda x: mean * (1.0 + LUBE_PUMP_RIPPLE_FRACTION * np.sin(z * x)), z,
                              "[E] mean from engine.lube_pump, 5 % ripple at the rotor-tooth order")


def ideal_compressor_cycle(system: System) -> dict:
    """Ideal pV cycle of the single-cylinder air compressor (numeric; the shape behind
    :meth:`AccessoryTorque.air_compressor`).

    Re-expansion of the clearance gas from TDC (polytropic, exponent n) until the suction pressure, suction at
    ``p_s`` to BDC, polytropic compression until the discharge pressure, delivery at ``p_d`` to TDC; instantaneous
    valves, no losses. Load torque ``-(p - p_cc) A s'(theta)`` with crankcase ``p_cc = p_s`` and the exact
    slider-crank ``s'`` (rod/crank 4 [E]). Returns dict: ``torque_Nm`` (vectorised function of the crank angle
    [rad], 0 = TDC), ``swept_volume_mm3``, ``clearance_volume_mm3``, ``suction_pressure_bar``,
    ``discharge_pressure_bar``, ``polytropic_exponent``, ``crank_radius_mm``, ``rod_length_mm``, ``area_mm2``.
    """
    ac = _engine(system, "ideal_compressor_cycle")["air_compressor"]
    bore, stroke = float(ac["bore_mm"]), float(ac["stroke_mm"])
    r = 0.5 * stroke
    rod = COMPRESSOR_ROD_TO_CRANK_RATIO * r
    area = 0.25 * math.pi * bore * bore
    v_d = area * stroke
    v_c = COMPRESSOR_CLEARANCE_RATIO * v_d
    p_s, p_d = COMPRESSOR_SUCTION_PRESSURE_BAR, float(ac["discharge_pressure_bar_abs"])
    n = COMPRESSOR_POLYTROPIC_EXPONENT
    check_values("air_compressor.discharge_pressure_bar_abs", p_d, p_s, low_inclusive=False, unit="bar")

    def torque_Nm(t):
        t = np.mod(np.asarray(t, dtype=float), TWO_PI)
        k = slider_crank(t, r, rod)
        v = v_c + area * k["piston_displacement_mm"]
        down = t <= math.pi
        p = np.where(down, np.maximum(p_d * (v_c / v) ** n, p_s), np.minimum(p_s * ((v_c + v_d) / v) ** n, p_d))
        return -(p - p_s) * 0.1 * area * k["ds_dtheta_mm"] * 1e-3

    return {"torque_Nm": torque_Nm, "swept_volume_mm3": v_d, "clearance_volume_mm3": v_c, "suction_pressure_bar": p_s,
            "discharge_pressure_bar": p_d, "polytropic_exponent": n, "crank_radius_mm": r, "rod_length_mm": rod,
            "area_mm2": area}


def _engine(system: System, needed_by: str):
    """The ``[engine]`` table of the :class:`~gearopt.data.System` ``system``: no System (None, a raw dict), or a
    file without ``[engine]``, raise naming the argument or the file and section (never the packaged data)."""
    return require_section(system, "engine", needed_by)


# --------------------------------------------------------------------------------------------------------------------
# convenience functions (rebuild the map from the data on every call)
# --------------------------------------------------------------------------------------------------------------------

def camshaft_torque_Nm(cam_angle_rad, system: System):
    """Valve-train load torque [N m] at the cam angle [rad] (see :meth:`AccessoryTorque.camshaft`). Dual-typed."""
    _engine(system, "camshaft_torque_Nm")
    return AccessoryTorque.camshaft(system)(cam_angle_rad)


def fuel_pump_torque_Nm(pump_angle_rad, system: System):
    """Common-rail pump load torque [N m] at the pump angle [rad] (:meth:`AccessoryTorque.fuel_pump`)."""
    _engine(system, "fuel_pump_torque_Nm")
    return AccessoryTorque.fuel_pump(system)(pump_angle_rad)


def air_compressor_torque_Nm(angle_rad, system: System, loaded: bool = True):
    """Air-compressor load torque [N m] at its crank angle [rad] (:meth:`AccessoryTorque.air_compressor`)."""
    _engine(system, "air_compressor_torque_Nm")
    return AccessoryTorque.air_compressor(system, loaded=loaded)(angle_rad)


def lube_pump_torque_Nm(angle_rad, system: System):
    """Lube-pump load torque [N m] at the pump angle [rad] (:meth:`AccessoryTorque.lube_pump`)."""
    _engine(system, "lube_pump_torque_Nm")
    return AccessoryTorque.lube_pump(system)(angle_rad)


__all__ = [
    "AccessoryTorque",
    "air_compressor_torque_Nm",
    "camshaft_torque_Nm",
    "fuel_pump_torque_Nm",
    "ideal_compressor_cycle",
    "lube_pump_torque_Nm",
]
