"""Speed sweep of a timing model: peak and RMS mesh forces, gear and joint torques, axial forces, contact counts and
the walk-off margins of shaft-hub joints per speed, with and without lash (the design-torque and joint-load inputs
of the main job).

Each (speed, lash) point runs the model's cached simulator (one integrator per lash option, parameters per speed):
``run_in_cycles`` cycles from the static state (or until ``steady_state_tol``), then ``cycles`` recorded cycles over
which the statistics are taken. With lash the default train rattles at higher speeds and its response is not
periodic (the cycle-to-cycle change stays large, reported in ``cycle_change``): the statistics then describe the
recorded cycles, and more cycles give steadier values.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pandas as pd

from ..data import System, system_of
from ..errors import GearoptInputError
from ..geometry.forces import mesh_torque_Nm
from ..validation import check_range


def simulation_statistics(sim, shafts=()) -> pd.DataFrame:
    """Per mesh (and per named shaft) statistics of a :class:`~gearopt.dynamics.simulate.Simulation`.

    Mesh rows: ``peak_drive_force_N``, ``peak_back_force_N``, ``mean_force_N``, ``rms_force_N``, ``min_force_N``,
    ``peak_axial_force_N``, ``peak_gear_2_torque_Nm``/``rms_gear_2_torque_Nm`` (force x r_b2: the torque the mesh
    puts on its driven gear), ``drive_separations_per_cycle`` and
    ``back_impacts_per_cycle`` (integrated contact-indicator variation; sampled counts if no lash quadrature).
    Shaft rows (``shafts``): ``peak_torque_Nm``, ``min_torque_Nm``, ``mean_torque_Nm``, ``rms_torque_Nm``
    (e.g. ``"cam-cam_station_1"``: the torque through the cam gear's shaft-hub joint).
    """
    summary = sim.summary()
    n_cyc = max(1, sim.cycles)
    rows = []
    for mesh, s in summary.iterrows():
        r2_mm = sim.mesh_base_radii_mm[mesh][1]
        f = sim.mesh_force_N[mesh]
        sep = s.get("drive_separations_integrated", s["drive_separations_sampled"])
        imp = s.get("back_impacts_integrated", s["back_impacts_sampled"])
        rows.append({"element": mesh, "element_type": "mesh", "peak_drive_force_N": s["peak_drive_force_N"],
                     "peak_back_force_N": s["peak_back_force_N"], "mean_force_N": s["mean_force_N"],
                     "rms_force_N": s["rms_force_N"], "min_force_N": s["min_force_N"],
                     "peak_axial_force_N": s["peak_axial_force_N"],
                     "peak_gear_2_torque_Nm": mesh_torque_Nm(float(np.max(np.abs(f))), r2_mm),
                     "rms_gear_2_torque_Nm": mesh_torque_Nm(s["rms_force_N"], r2_mm),
                     "drive_separations_per_cycle": float(sep) / n_cyc, "back_impacts_per_cycle": float(imp) / n_cyc})
    for name in shafts:
        if name not in sim.shaft_torque_Nm.columns:
            raise GearoptInputError(f"shaft {name!r} is not in the simulation {list(sim.shaft_torque_Nm.columns)}")
        t = sim.shaft_torque_Nm[name]
        rows.append({"element": name, "element_type": "shaft", "peak_torque_Nm": float(t.max()),
                     "min_torque_Nm": float(t.min()), "mean_torque_Nm": float(t.mean()),
                     "rms_torque_Nm": float(np.sqrt((t ** 2).mean()))})
    return pd.DataFrame(rows)


def _gear_inertia_kgm2(system: System, gear: str) -> tuple[float, str]:
    """Own inertia [kg m^2] of a gear lumped into a larger network node and its source: ``gears.<gear>.inertia_kgm2``
    of the :class:`~gearopt.data.System` if the file gives it, else the file's solid-disc estimate
    ``solid_disc_inertia_kgm2``; raises if neither exists."""
    system = system_of(system, "the gear inertia of a walk-off history")
    spec = system.gears[gear].entries if gear in system.gears else {}
    for key in ("inertia_kgm2", "solid_disc_inertia_kgm2"):
        if key in spec:
            return float(spec[key]), f"gears.{gear}.{key}"
    raise GearoptInputError(f"gear {gear!r}: no inertia_kgm2 or solid_disc_inertia_kgm2 in the data; pass "
                            f"gear_inertia_kgm2")


def _model_gear_inertia_kgm2(model, gear: str) -> tuple[float, str]:
    """Own inertia of ``gear`` [kg m^2] and its source: what the model provides (``model.gear_inertia_kgm2``, e.g.
    :class:`~gearopt.dynamics.train_model.TrainModel`), else the model's system's (:func:`_gear_inertia_kgm2` of
    ``model.system``)."""
    if hasattr(model, "gear_inertia_kgm2"):
        return model.gear_inertia_kgm2(gear)
    return _gear_inertia_kgm2(model.system, gear)


def walk_off_history(model, sim, joint: str = "cam", interference: str = "nominal",
                     root_rotation: str = "cw", gear_inertia_kgm2: float | None = None) -> dict:
    """Axial force, joint torque and slip margins of one shaft-hub joint over a simulation (gearopt.joints).

    The per-mesh torques on each mesh's first gear (force x r_b1, + when it drives) go to
    :func:`gearopt.joints.walk_off` (hands, rotation senses and the thrust direction, +z = off the shaft nose),
    which sums the axial forces of all meshes of the joint's gear. The joint torque [N m] (+ when the gear drives
    its shaft, as :mod:`gearopt.joints.walk_off`) is

    * for a gear that is its own network node with a shaft element to its load (the accessory gears of an engine's
      timing train): that shaft's torque (it includes the gear's own inertia torque);
    * for a gear lumped into a larger node (a crank gear in a node of the crankshaft chain, ``model.gear_nodes``) or
      a gear on its own node without a shaft: the gear's rotational equilibrium, ``sum of its mesh torques (F r_b
      of each of its meshes, signed) - J_g alpha``, with ``alpha`` the node's angular acceleration from the equations of motion
      (:func:`~gearopt.dynamics.simulate.node_accelerations`) and ``J_g`` the gear's own inertia
      (``gear_inertia_kgm2``; default ``gears.<gear>.inertia_kgm2`` of the data, else its
      ``solid_disc_inertia_kgm2`` estimate -- 0.00373 kg m^2 for the default crank gear). Approximation: the gear
      is taken as a rigid body moving with the node (the nose between gear seat and node is rigid), so the seat
      carries the rest of the node's torques; ``gear_inertia_kgm2=0`` gives the plain mesh-torque sum;
    * for a gear that is its own node without a shaft element but with an external torque on it (the driving or a
      load gear of :class:`~gearopt.dynamics.train_model.TrainModel`, whose drive or load acts through the joint):
      the same rotational equilibrium with the gear's own inertia (``model.gear_inertia_kgm2(gear)``).

    The capacity is :func:`gearopt.joints.joint_capacity` of ``[joints.<joint>]`` at the simulation speed
    (centrifugal loss) and ``interference`` case, and :func:`gearopt.joints.margin_history` gives the margins.

    Returns a dict: ``axial_force_N``, ``joint_torque_Nm``, ``torque_margin`` and ``axial_margin`` (arrays over the
    simulation), ``capacity`` (dict),
    ``joint_torque_method`` (``"shaft"`` or ``"mesh_sum"``), ``gear_inertia_kgm2`` (mesh_sum only), and the
    margin summary (``min_torque_margin``, ``min_axial_margin``, ``min_combined_margin``, ``max_slip_utilisation``,
    ...). A gear that is its own node without a shaft element (the lube-pump idler on its stub) raises
    ``GearoptInputError``: its joint carries only the hub's inertia torque, which the model does not resolve.
    """
    from ..joints import joint_capacity, margin_history, walk_off
    from .simulate import node_accelerations

    system = system_of(model.system, "walk_off_history")
    joints = system.joints
    if joint not in joints:
        raise GearoptInputError(f"joint={joint!r} is not in [joints] ({sorted(joints)})")
    gear = joints[joint].gear
    node = getattr(model, "gear_nodes", {}).get(gear, gear)
    torques = {mesh: mesh_torque_Nm(sim.mesh_force_N[mesh].to_numpy(), sim.mesh_base_radii_mm[mesh][0])
               for mesh in sim.mesh_force_N.columns}
    extra = {}
    shafts = [s.name for s in model.network.shafts.values() if s.node_a == gear] if node == gear else []
    loaded = any(t.node == node for t in model.network.torques.values())
    if node == gear and not shafts and not loaded:
        raise GearoptInputError(f"joint {joint!r}: gear {gear!r} has no shaft element in the network (its joint "
                                f"torque is not a network output)")
    if shafts:
        res = walk_off(model.train, torques, root_rotation=root_rotation)
        torque = sim.shaft_torque_Nm[shafts[0]].to_numpy()
        extra["joint_torque_method"] = "shaft"
    else:
        if gear_inertia_kgm2 is None:
            j_g, source = _model_gear_inertia_kgm2(model, gear)
        else:
            check_range("gear_inertia_kgm2", gear_inertia_kgm2, 0.0, None, unit="kg m^2")
            j_g, source = float(gear_inertia_kgm2), "argument"
        if node not in model.network.inertias:
            raise GearoptInputError(f"joint {joint!r}: gear node {node!r} is not in the network")
        if j_g > model.network.inertias[node].inertia_kgm2:
            raise GearoptInputError(f"joint {joint!r}: gear inertia {j_g} kg m^2 exceeds its node {node!r}'s "
                                    f"{model.network.inertias[node].inertia_kgm2} kg m^2")
        if j_g == 0.0 or node in model.network.boundary_nodes:
            alpha = np.zeros(len(sim.time_s))
        else:
            sign = 1.0 if model.network.speed_ratios()[node] >= 0 else -1.0
            alpha = sign * node_accelerations(model.network, sim)[node].to_numpy()  # in the gear's own sense
        res = walk_off(model.train, torques, root_rotation=root_rotation, inertia_torques_Nm={gear: j_g * alpha})
        torque = np.asarray(res.joint_torque_Nm[gear], dtype=float) * np.ones(len(sim.time_s))
        extra.update(joint_torque_method="mesh_sum", gear_inertia_kgm2=j_g, gear_inertia_source=source)
    axial = np.asarray(res.axial_force_N[gear], dtype=float) * np.ones(len(sim.time_s))
    cap = joint_capacity(system, joint, interference=interference, speed_rpm=sim.speed_rpm)
    hist = margin_history(cap.type, torque, axial, cap.torque_capacity_Nm, cap.axial_capacity_N)
    summary = {k: v for k, v in hist.items() if k.startswith(("min_", "max_", "argmin_"))}
    margins = {k: np.atleast_1d(hist[k]) * np.ones(len(sim.time_s)) for k in ("torque_margin", "axial_margin")}
    return {"axial_force_N": axial, "joint_torque_Nm": torque, "capacity": cap, **extra, **summary, **margins}


def cycle_spread(history, cycles: int) -> dict:
    """Spread over the recorded engine cycles of a margin history (samples evenly spread over ``cycles`` cycles):
    the worst (smallest) value of each cycle, summarised as ``worst``, ``median`` and ``best`` of those per-cycle
    minima. A periodic response gives three equal numbers; a rattling backlash response does not, and the spread
    says how far one recorded cycle is from another."""
    arr = np.atleast_1d(np.asarray(history, dtype=float))
    n = max(1, int(cycles))
    if arr.size < n:
        n = 1
    per_cycle = arr[: arr.size - arr.size % n].reshape(n, -1).min(axis=1)
    return {"worst": float(per_cycle.min()), "median": float(np.median(per_cycle)), "best": float(per_cycle.max())}


def speed_sweep(model, speeds_rpm, backlash=(False, True), cycles: int = 2, run_in_cycles: int = 2,
                steady_state_tol: float | None = None, rtol: float = 1e-6, shafts=None,
                joints=None, parameters: dict | None = None, executor: Any = "serial", *,
                workers: int | None = None, progress: bool | None = None, **options) -> pd.DataFrame:
    """Sweep ``model`` (a torsional model: :func:`~gearopt.dynamics.train_model` or the timing case's model) over ``speeds_rpm`` [rpm] for each
    lash option in ``backlash``; returns one row per (speed, lash, element) with the columns of
    :func:`simulation_statistics` plus ``speed_rpm``, ``backlash``, ``cycle_change`` (last run-in/recorded cycle's
    change) and ``run_time_s``; with ``joints`` (``[joints.*]`` names) also one ``element_type == "joint"`` row per
    joint from :func:`walk_off_history`: ``peak_axial_force_N`` (largest |F_a| on the gear), ``max_off_nose_force_N``
    (largest pull off the shaft nose, +z), ``peak_torque_Nm`` (largest |joint torque|), ``min_torque_margin``,
    ``min_axial_margin``, ``min_combined_margin``, ``max_slip_utilisation`` -- the walk-off margin over speed --
    and the margins' spread over the recorded ``cycles`` (:func:`cycle_spread`: ``torque_margin_cycle_worst``,
    ``..._median``, ``..._best``, the same for ``axial_margin``).
    ``shafts``/``joints`` default to the model's ``sweep_shafts``/``sweep_joints`` (the timing model, which has
    none: ``("cam-cam_station_1",)`` and ``("cam",)``).
    ``options`` go to the simulator (JIT kernels come from the on-disk compile cache, :mod:`gearopt.compile_cache`).
    A (speed, lash) run already computed this session with the same settings is re-used
    (:func:`gearopt.dynamics.simulate.simulate`, ``reuse``).

    ``executor``: who runs the (speed, lash) points -- ``"serial"`` (default), ``"processes"``, ``"dask"``, a
    ``dask.distributed.Client`` or a :class:`gearopt.executor.Executor` (``workers``, ``progress`` as there); each
    point is one task, the rows come back in (lash, speed) order whoever ran them, so the table is the same
    (``run_time_s`` aside). A worker process gets its own copy of the model (serialised with cloudpickle) and
    builds its integrator there (compiled kernels from the on-disk cache); the session re-use then holds per
    process."""
    from ..executor import using_executor

    shafts = getattr(model, "sweep_shafts", ("cam-cam_station_1",)) if shafts is None else shafts
    joints = getattr(model, "sweep_joints", ("cam",)) if joints is None else joints
    speeds = np.atleast_1d(np.asarray(speeds_rpm, dtype=float))
    check_range("cycles", cycles, 1, None)
    settings = dict(cycles=cycles, run_in_cycles=run_in_cycles, steady_state_tol=steady_state_tol, rtol=rtol,
                    shafts=tuple(shafts), joints=tuple(joints), parameters=parameters, options=dict(options))
    tasks = [(model, float(speed), bool(lash), settings) for lash in backlash for speed in speeds]
    with using_executor(executor, workers=workers, progress=progress) as ex:
        frames = ex.map(sweep_point, tasks, desc="speed sweep")
    return pd.concat(frames, ignore_index=True)


def sweep_point(task: tuple) -> pd.DataFrame:
    """Executor task of :func:`speed_sweep`: the rows of one (speed, lash) point."""
    model, speed, lash, st = task
    sim = model.simulate(speed, st["cycles"], backlash=lash, rtol=st["rtol"], parameters=st["parameters"],
                         run_in_cycles=st["run_in_cycles"], steady_state_tol=st["steady_state_tol"], **st["options"])
    stats = simulation_statistics(sim, st["shafts"])
    rows = []
    for joint in st["joints"]:
        w = walk_off_history(model, sim, joint)
        spread = {f"{key}_cycle_{stat}": v for key in ("torque_margin", "axial_margin")
                  for stat, v in cycle_spread(w[key], sim.cycles).items()}
        rows.append({"element": f"joint:{joint}", "element_type": "joint", "cycles": int(sim.cycles), **spread,
                     "peak_axial_force_N": float(np.max(np.abs(w["axial_force_N"]))),
                     "max_off_nose_force_N": float(np.max(w["axial_force_N"])),
                     "peak_torque_Nm": float(np.max(np.abs(w["joint_torque_Nm"]))),
                     **{k: w[k] for k in ("min_torque_margin", "min_axial_margin", "min_combined_margin",
                                          "max_slip_utilisation")}})
    if rows:
        stats = pd.concat([stats, pd.DataFrame(rows)], ignore_index=True)
    stats.insert(0, "backlash", bool(lash))
    stats.insert(0, "speed_rpm", float(speed))
    stats["cycle_change"] = sim.cycle_change[-1] if sim.cycle_change else np.nan
    stats["run_time_s"] = sim.stats["run_time_s"]
    return stats


__all__ = ["speed_sweep", "sweep_point", "cycle_spread", "simulation_statistics", "walk_off_history"]
