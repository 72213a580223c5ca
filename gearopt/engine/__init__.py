"""Engine excitation: slider-crank kinematics, cylinder pressure (measured table or double Wiebe, as smooth periodic
functions), gas and reciprocating-inertia crank torques per cylinder with firing order, and accessory load-torque maps.

Every function of angle or speed is dual-typed (floats, numpy arrays, CasADi SX/MX) and smooth in the angle, so the
torsional dynamics can call it inside a CasADi integrator's right-hand side.

Conventions: crank angle 0 = cylinder 1 firing TDC (engine excitation); pressure traces over 0..720 deg with the
firing TDC at 360 deg; positive crank torque drives the crankshaft; accessory torques are loads (positive resists).
"""

from .accessories import (AccessoryTorque, air_compressor_torque_Nm, camshaft_torque_Nm, fuel_pump_torque_Nm,
                          ideal_compressor_cycle, lube_pump_torque_Nm)
from .excitation import EngineExcitation, crank_torque
from .fourier import FourierSeries, harmonic_basis
from .kinematics import reciprocating_inertia_kgm2, slider_crank, slider_crank_from_sincos
from .pressure import (CYCLE_DEG, FIRING_TDC_DEG, CylinderPressure, double_wiebe_cycle, imep_bar, indicated_work_J,
                       motored_peak_pressure_bar, peak_pressure_bar)

__all__ = [
    "AccessoryTorque", "air_compressor_torque_Nm", "camshaft_torque_Nm", "fuel_pump_torque_Nm", "lube_pump_torque_Nm",
    "ideal_compressor_cycle", "EngineExcitation", "crank_torque", "FourierSeries", "harmonic_basis",
    "reciprocating_inertia_kgm2", "slider_crank", "slider_crank_from_sincos", "CYCLE_DEG", "FIRING_TDC_DEG",
    "CylinderPressure", "double_wiebe_cycle", "imep_bar", "indicated_work_J", "motored_peak_pressure_bar",
    "peak_pressure_bar",
]
