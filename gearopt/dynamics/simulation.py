"""The result record of a torsional simulation (:meth:`gearopt.dynamics.simulate.Simulator.run`): time series as
DataFrames per output quantity, with the per-mesh summaries computed from them."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..errors import GearoptInputError

#: Quantities of the output DataFrames (one column per element).
QUANTITIES = ("mesh_force_N", "drive_force_N", "back_force_N", "transmission_error_um", "mesh_stiffness_N_per_m",
               "drive_contact", "back_contact", "axial_force_N", "shaft_torque_Nm", "external_torque_Nm",
               "boundary_torque_Nm")


@dataclass
class Simulation:
    """Result of :meth:`~gearopt.dynamics.simulate.Simulator.run`: time series as DataFrames (index ``time_s``, one
    column per element).

    ``mesh_force_N`` signed force along the line of action (drive flanks positive), ``drive_force_N`` /
    ``back_force_N`` flank forces, ``transmission_error_um`` dynamic transmission error delta along the line of
    action, ``mesh_stiffness_N_per_m`` k(psi), ``drive_contact``/``back_contact`` smooth contact indicators,
    ``axial_force_N`` F_bt tan(beta_b) (helical meshes), ``shaft_torque_Nm`` in each shaft's sense of rotation,
    ``external_torque_Nm`` in each node's own sense, ``boundary_torque_Nm`` reaction torques of the speed boundary,
    ``node_angle_mrad`` angle deviations, ``node_speed_rpm`` absolute speeds. ``time_s`` and ``crank_angle_deg``
    (reference-node angle) arrays; ``cycle_change`` per simulated cycle (run-in first); ``contact_variation``
    integrated contact-indicator variations per mesh; ``stats`` run time and integrator counters (``integration_time_s``
the cycle loop, of it ``integrator_time_s`` in the integrator calls and ``output_time_s`` in the output functions,
``function_evaluation_time_s`` the integrator's own right-hand-side, Jacobian and quadrature evaluations as CasADi
times them, all summed over ``cycles_integrated``; the same in process CPU time: ``integration_cpu_time_s``,
``integrator_cpu_time_s``, ``function_evaluation_cpu_time_s``; ``steps_per_cycle``); ``cycles``
    recorded cycles; ``mesh_base_radii_mm`` (r_b1, r_b2) per mesh; ``angle_offset_rad`` the reference-node angle
    [rad] at the start of the first recorded cycle (so ``crank_angle_deg`` + it is the integration's own angle);
    ``steady_state_method`` ``"run-in"`` or ``"shooting"`` and ``shooting`` (residual, iterations, ...; see
    :meth:`~gearopt.dynamics.simulate.Simulator.periodic_state`).
    """

    speed_rpm: float
    backlash: bool
    time_s: np.ndarray
    crank_angle_deg: np.ndarray
    frames: dict
    contact_variation: pd.DataFrame
    cycle_change: list
    run_in_cycles: int
    steady_state_tol: float | None
    final_state: np.ndarray
    stats: dict = field(default_factory=dict)
    parameters: dict = field(default_factory=dict)
    cycles: int = 1
    mesh_base_radii_mm: dict = field(default_factory=dict)
    angle_offset_rad: float = 0.0
    steady_state_method: str = "run-in"
    shooting: dict = field(default_factory=dict)

    def __getattr__(self, name):
        frames = self.__dict__.get("frames", {})
        if name in frames:
            return frames[name]
        raise AttributeError(name)

    def frame(self, quantity: str, index: str = "time_s") -> pd.DataFrame:
        """One output DataFrame (e.g. ``"mesh_force_N"``) indexed by ``"time_s"`` or ``"crank_angle_deg"``."""
        if quantity not in self.frames:
            raise GearoptInputError(f"quantity={quantity!r} is not an output; available: {sorted(self.frames)}")
        if index == "time_s":
            return self.frames[quantity]
        if index == "crank_angle_deg":
            return self.frames[quantity].set_axis(pd.Index(self.crank_angle_deg, name="crank_angle_deg"), axis=0)
        raise GearoptInputError(f"index={index!r} must be 'time_s' or 'crank_angle_deg'")

    @property
    def converged(self) -> bool:
        """True if a steady-state tolerance was given and the last cycle change is below it."""
        return self.steady_state_tol is not None and bool(self.cycle_change) and \
            self.cycle_change[-1] < self.steady_state_tol

    def contact_summary(self) -> pd.DataFrame:
        """Per mesh: contact changes counted on the output samples and from the integrated indicator variation.

        ``drive_separations_sampled`` (drive-contact indicator falling through 0.5), ``back_impacts_sampled``
        (back-contact indicator rising through 0.5), and the integrated equivalents ``drive_separations_integrated``
        = total variation of the drive indicator / 2 and ``back_impacts_integrated`` = that of the back indicator / 2
        (over the recorded cycles; fractional when a contact starts or ends mid-way). ``integrated - sampled`` well
        above 0.5 means the output grid is too coarse to show every contact change (the integration itself is not
        affected)."""
        rows = []
        for mesh in self.frames["mesh_force_N"].columns:
            d = self.frames["drive_contact"][mesh].to_numpy()
            b = self.frames["back_contact"][mesh].to_numpy()
            row = {"mesh": mesh,
                   "drive_separations_sampled": int(np.sum((d[:-1] >= 0.5) & (d[1:] < 0.5))),
                   "back_impacts_sampled": int(np.sum((b[:-1] < 0.5) & (b[1:] >= 0.5)))}
            if mesh in self.contact_variation.index:
                row["drive_separations_integrated"] = float(self.contact_variation.loc[mesh, "drive"] / 2.0)
                row["back_impacts_integrated"] = float(self.contact_variation.loc[mesh, "back"] / 2.0)
            rows.append(row)
        return pd.DataFrame(rows).set_index("mesh")

    def summary(self) -> pd.DataFrame:
        """Per mesh over the recorded cycles: peak drive/back flank force [N], mean, RMS and minimum of the signed
        force [N], peak |axial force| [N], peak-to-peak TE [um], and the contact counts of :meth:`contact_summary`."""
        f = self.frames
        out = pd.DataFrame({
            "peak_drive_force_N": f["drive_force_N"].max(),
            "peak_back_force_N": f["back_force_N"].max(),
            "mean_force_N": f["mesh_force_N"].mean(),
            "rms_force_N": np.sqrt((f["mesh_force_N"] ** 2).mean()),
            "min_force_N": f["mesh_force_N"].min(),
            "peak_axial_force_N": f["axial_force_N"].abs().max(),
            "te_peak_to_peak_um": f["transmission_error_um"].max() - f["transmission_error_um"].min(),
        })
        out.index.name = "mesh"
        return out.join(self.contact_summary())


__all__ = ["Simulation", "QUANTITIES"]
