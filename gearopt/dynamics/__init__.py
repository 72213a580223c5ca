"""Torsional dynamics of gear trains: network builder, gear-mesh force with time-varying stiffness and backlash,
CasADi time integration with periodic steady state, linear analysis (modes, Campbell, forced response), speed
sweeps and sensitivities through the integrator. (The packaged engine's timing-system model is a case:
:mod:`gearopt.cases.timing_train`.)

Modules: :mod:`~gearopt.dynamics.mesh` (mesh force, stiffness shape, axial force), :mod:`~gearopt.dynamics.network`
(:class:`TorsionalNetwork`), :mod:`~gearopt.dynamics.simulate` (:class:`Simulator`, :class:`Simulation`),
:mod:`~gearopt.dynamics.modes` (linear analysis), :mod:`~gearopt.dynamics.train_model` (:func:`train_model`: any
train with a generic ``[excitation]``), :mod:`~gearopt.dynamics.sweep` (:func:`speed_sweep`),
:mod:`~gearopt.dynamics.sensitivity` (:func:`response_sensitivities`).
"""

from .mesh import (
    MeshStiffnessShape,
    axial_force_N,
    contact_line_length_ratio,
    mesh_force,
    restitution_coefficient,
)
from .modes import (
    campbell_diagram,
    damped_modes,
    forced_response,
    linear_matrices,
    mode_shapes,
    natural_frequencies_Hz,
)
from .network import TorsionalNetwork
from .sensitivity import response_sensitivities
from .simulate import INTEGRATORS, PeriodicStateError, Simulation, Simulator, node_accelerations, simulate
from .sweep import simulation_statistics, speed_sweep, walk_off_history
from .train_model import TrainModel, train_model

__all__ = [
    "TorsionalNetwork", "MeshStiffnessShape", "mesh_force", "axial_force_N", "contact_line_length_ratio",
    "restitution_coefficient", "Simulator", "Simulation", "simulate", "INTEGRATORS", "linear_matrices",
    "natural_frequencies_Hz", "mode_shapes", "damped_modes", "campbell_diagram", "forced_response",
    "speed_sweep", "simulation_statistics", "response_sensitivities",
    "node_accelerations", "walk_off_history", "PeriodicStateError", "train_model", "TrainModel",
]
