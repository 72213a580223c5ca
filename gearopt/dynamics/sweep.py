"""Speed sweep of a timing model: peak and RMS mesh forces, gear and joint torques, axial forces and contact counts
per speed, with and without lash (the design-torque and joint-load inputs of the main job).

Each (speed, lash) point runs the model's cached simulator (one integrator per lash option, parameters per speed):
``run_in_cycles`` cycles from the static state (or until ``steady_state_tol``), then ``cycles`` recorded cycles over
which the statistics are taken. With lash the default train rattles at higher speeds and its response is not
periodic (the cycle-to-cycle change stays large, reported in ``cycle_change``): the statistics then describe the
recorded cycles, and more cycles give steadier values.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..errors import GearoptInputError, check_range


def simulation_statistics(sim, shafts=()) -> pd.DataFrame:
    """Per mesh (and per named shaft) statistics of a :class:`~gearopt.dynamics.simulate.Simulation`.

    Mesh rows: ``peak_drive_force_N``, ``peak_back_force_N``, ``mean_force_N``, ``rms_force_N``, ``min_force_N``,
    ``peak_axial_force_N``, ``peak_gear_2_torque_Nm``/``rms_gear_2_torque_Nm`` (force x r_b2: the torque the mesh
    puts on its driven gear, e.g. the cam gear for ``crank-cam``), ``drive_separations_per_cycle`` and
    ``back_impacts_per_cycle`` (integrated contact-indicator variation; sampled counts if no lash quadrature).
    Shaft rows (``shafts``): ``peak_torque_Nm``, ``min_torque_Nm``, ``mean_torque_Nm``, ``rms_torque_Nm``
    (e.g. ``"cam-cam_station_1"``: the torque through the cam gear's shaft-hub joint).
    """
    summary = sim.summary()
    n_cyc = max(1, sim.cycles)
    rows = []
    for mesh, s in summary.iterrows():
        r2 = sim.mesh_base_radii_mm[mesh][1] * 1e-3
        f = sim.mesh_force_N[mesh]
        sep = s.get("drive_separations_integrated", s["drive_separations_sampled"])
        imp = s.get("back_impacts_integrated", s["back_impacts_sampled"])
        rows.append({"element": mesh, "element_type": "mesh", "peak_drive_force_N": s["peak_drive_force_N"],
                     "peak_back_force_N": s["peak_back_force_N"], "mean_force_N": s["mean_force_N"],
                     "rms_force_N": s["rms_force_N"], "min_force_N": s["min_force_N"],
                     "peak_axial_force_N": s["peak_axial_force_N"],
                     "peak_gear_2_torque_Nm": float(np.max(np.abs(f))) * r2,
                     "rms_gear_2_torque_Nm": s["rms_force_N"] * r2,
                     "drive_separations_per_cycle": float(sep) / n_cyc, "back_impacts_per_cycle": float(imp) / n_cyc})
    for name in shafts:
        if name not in sim.shaft_torque_Nm.columns:
            raise GearoptInputError(f"shaft {name!r} is not in the simulation {list(sim.shaft_torque_Nm.columns)}")
        t = sim.shaft_torque_Nm[name]
        rows.append({"element": name, "element_type": "shaft", "peak_torque_Nm": float(t.max()),
                     "min_torque_Nm": float(t.min()), "mean_torque_Nm": float(t.mean()),
                     "rms_torque_Nm": float(np.sqrt((t ** 2).mean()))})
    return pd.DataFrame(rows)


def speed_sweep(model, speeds_rpm, backlash=(False, True), cycles: int = 2, run_in_cycles: int = 2,
                steady_state_tol: float | None = None, rtol: float = 1e-6, shafts=("cam-cam_station_1",),
                parameters: dict | None = None, **options) -> pd.DataFrame:
    """Sweep ``model`` (a :class:`~gearopt.dynamics.default_model.TimingModel`) over ``speeds_rpm`` [rpm] for each
    lash option in ``backlash``; returns one row per (speed, lash, element) with the columns of
    :func:`simulation_statistics` plus ``speed_rpm``, ``backlash``, ``cycle_change`` (last run-in/recorded cycle's
    change) and ``run_time_s``. ``options`` go to the simulator (``jit=True`` pays off for long sweeps)."""
    speeds = np.atleast_1d(np.asarray(speeds_rpm, dtype=float))
    check_range("cycles", cycles, 1, None)
    frames = []
    for lash in backlash:
        for speed in speeds:
            sim = model.simulate(float(speed), cycles, backlash=bool(lash), rtol=rtol, parameters=parameters,
                                 run_in_cycles=run_in_cycles, steady_state_tol=steady_state_tol, **options)
            stats = simulation_statistics(sim, shafts)
            stats.insert(0, "backlash", bool(lash))
            stats.insert(0, "speed_rpm", float(speed))
            stats["cycle_change"] = sim.cycle_change[-1] if sim.cycle_change else np.nan
            stats["run_time_s"] = sim.stats["run_time_s"]
            frames.append(stats)
    return pd.concat(frames, ignore_index=True)


__all__ = ["speed_sweep", "simulation_statistics"]
