"""The failure reproduction of the timing-train case: the walk-off envelope of the helical baseline and the spur
redesign (:func:`gearopt.dynamics.walk_off_envelope.joint_envelope` on the packaged engine's timing model) and the
walk-off probability of their joints (:func:`gearopt.studies.failure.walk_off_probability`), with the helical
alternatives the source study weighed and its field record as the sanity check."""

from __future__ import annotations

from ...data import System, system_of
from ...studies.failure import (DAMPER_STATE_PROBABILITIES, DAMPER_STATE_PROBABILITIES_SOURCE, EXPOSURE_HOURS,
                                EXPOSURE_HOURS_SOURCE, WALK_OFF_DISTANCE_MM, WALK_OFF_DISTANCE_SOURCE,
                                WARRANTY_MONTHS, creep_summary, walk_off_probability)
from ...geometry.forces import axial_force_N
from ...validation import check_range

#: Field rate of the source study: 213 walk-offs in 247 853 engines in 24 months (thesis sec. 1).
FIELD_RATE = 213.0 / 247853.0
FIELD_RATE_SOURCE = "thesis sec. 1: 213 of 247 853 engines in 24 months of mature reliability data (RPH 0.085)"

HELICAL_ALTERNATIVES = {
    "helical_helix_3deg": {"thrust_scale": float(axial_force_N(1.0, 3.0) / axial_force_N(1.0, 6.0)),
                           "interference_shift_um": 0.0,
                           "description": "helix angle 3 deg instead of 6 deg (thrust x tan 3/tan 6; dynamics of "
                                          "the 6 deg train kept)"},
    "helical_stronger_fit": {"thrust_scale": 1.0, "interference_shift_um": 25.0,
                             "description": "cam fit interference range shifted +25 um (a stronger fit class) [E]"},
}


def failure_reproduction(system: System, *, quick: bool = False, joints=("cam", "crank"), samples: int = 20000,
                         seed: int = 0, distance_mm: float | None = None, executor="serial",
                         workers: int | None = None, alternatives: dict | None = None, calibrate: bool = True,
                         calibration_samples: int = 1000, prior_samples: int = 256) -> dict:
    """Envelope (:func:`~gearopt.dynamics.walk_off_envelope.joint_envelope`) and Monte Carlo
    (:func:`walk_off_probability`) of the helical and the spur train and the helical alternatives
    (:data:`HELICAL_ALTERNATIVES`). ``quick`` (smoke test, not a result): 3300 rpm, degraded damper only (probabilities conditional on it),
    three fit levels, one cycle from the static state (start-up transient included); else all speeds and damper states, recorded cycles after one run-in cycle.
    ``executor`` (``"serial"``, ``"processes"``, an :class:`~gearopt.studies.executor.Executor` ...; ``workers``)
    runs the envelope's (speed, damper state) points. ``system``: the :class:`~gearopt.data.System` of a data file
    of the timing train's layout (``gearopt.load_system()`` for the packaged one).

    The duty (hours per speed band, damper-state shares, walk-off distance) comes from the data's
    ``[field_record]`` when it has one (else the estimates of :mod:`gearopt.studies.failure`; ``distance_mm``
    overrides the distance). With ``calibrate`` and joints with ``field_failures``, the estimated inputs are
    calibrated against the field counts (:func:`gearopt.studies.calibration.calibrate_walk_off` on the helical
    train's envelope, which then also carries a copy of each joint with its shoulder on the other side;
    ``prior_samples`` prior samples (64 at most in ``quick``), ``calibration_samples`` engines per probability) and
    every train's headline ``walk_off_probability`` is the posterior predictive one (``walk_off_probability_interval_90``
    beside it; the uncalibrated Monte Carlo's as ``walk_off_probability_uncalibrated``).

    Returns ``{"envelopes": {train: DataFrame}, "probabilities": {train: {joint: dict}}, "summary": {train:
    {joint: {"max_slip_utilisation", "max_axial_creep_um_per_cycle", "walk_off_probability", ...}}},
    "assumptions": dict, "calibration": dict or None}``.
    """
    from ...dynamics.walk_off_envelope import (
        BELOW_TOLERANCE_FRACTIONS,
        DAMPER_STATES,
        DAMPER_STATES_SOURCE,
        JOINT_FRICTION_DATA,
        envelope_speeds_rpm,
        joint_envelope,
    )
    from ...studies.calibration import (FLIPPED_PREFIX, WalkOffModel, calibrate_walk_off, default_uncertain_inputs,
                                        field_record)
    system = system_of(system, "failure_reproduction")
    record = field_record(system) if "field_record" in system.sections else None
    if distance_mm is None:
        distance_mm = record.walk_off_distance_mm if record is not None else WALK_OFF_DISTANCE_MM
    check_range("distance_mm", distance_mm, 0.0, None, low_inclusive=False, unit="mm")
    evidence = [e for e in (record.evidence if record is not None else ()) if e.joint in joints]
    calibrate = bool(calibrate and evidence)
    base_damper = record.damper_probabilities if record is not None else DAMPER_STATE_PROBABILITIES
    exposure = record.exposure_hours if record is not None else EXPOSURE_HOURS
    bands = envelope_speeds_rpm(system)
    speeds = [bands["motoring_overspeed"][0]] if quick else [v for v, _ in bands.values()]
    states = ("degraded",) if quick else tuple(DAMPER_STATES)
    total = sum(base_damper[s] for s in states)
    damper_probabilities = {s: base_damper[s] / total for s in states}
    run = {"cycles": 1, "run_in_cycles": 0, "levels": 3} if quick else {"cycles": 2, "run_in_cycles": 1,
                                                                       "levels": 4}
    run["damper_states"] = states
    alternatives = HELICAL_ALTERNATIVES if alternatives is None else alternatives
    trains = {"helical": ("helical", "", 0.0), "spur": ("spur", "", 0.0)}
    helical_variants = {}
    for name, alt in alternatives.items():
        trains[name] = ("helical", f"{name}:" if float(alt["thrust_scale"]) != 1.0 else "",
                        float(alt["interference_shift_um"]))
        if float(alt["thrust_scale"]) != 1.0:
            helical_variants.update({f"{name}:{j}": (j, float(alt["thrust_scale"])) for j in joints})
    if calibrate:
        helical_variants.update({FLIPPED_PREFIX + j: (j, -1.0) for j in joints})
    from ...executor import using_executor
    from .model import default_timing_model
    models = {kind: default_timing_model(kind, system=system) for kind in ("helical", "spur")}
    def envelope(kind, executor_map):
        return joint_envelope(models[kind], joints, speeds_rpm=speeds, executor_map=executor_map,
                              variants=helical_variants if kind == "helical" else None, **run)

    for kind in models:  # build both simulators first (no runs), so that forked workers inherit both
        envelope(kind, lambda fn, items: [])
    with using_executor(executor, workers=workers) as ex:
        runs = {kind: envelope(kind, ex.map) for kind in models}
    envelopes, probabilities, summary = {}, {}, {}
    for name, (kind, prefix, shift) in trains.items():
        env = runs[kind]
        env = env[env["joint"].str.startswith(prefix)] if prefix else env[~env["joint"].str.contains(":")]
        env = env.assign(joint=env["joint"].str.slice(len(prefix)), train=name)
        envelopes[name] = env
        probabilities[name], summary[name] = {}, {}
        for joint in joints:
            rows_all = env[env["joint"] == joint]
            is_below = rows_all["fit_case"].str.endswith("x_weakest")
            rows, below = rows_all[~is_below], rows_all[is_below]
            pr = walk_off_probability(env, system, joint, samples=samples, seed=seed, distance_mm=distance_mm,
                                      interference_shift_um=shift if joint == "cam" else 0.0,
                                      damper_probabilities=damper_probabilities, exposure_hours=exposure,
                                      field_rate=FIELD_RATE,
                                      field_rate_source=FIELD_RATE_SOURCE)
            probabilities[name][joint] = pr
            nominal = rows[rows["fit_case"] == "nominal"]
            summary[name][joint] = {
                "max_slip_utilisation": float(rows["max_rigid_utilisation"].max()),
                "max_slip_utilisation_nominal_fit": float(nominal["max_rigid_utilisation"].max()),
                **creep_summary(rows, distance_mm),
                "max_axial_creep_um_per_cycle_nominal_fit": creep_summary(nominal, distance_mm)[
                    "max_axial_creep_um_per_cycle"],
                "max_off_nose_thrust_N": float(rows["max_off_nose_thrust_N"].max()),
                "max_key_force_N": float(rows["max_key_force_N"].max()),
                "capacity_N_weakest_fit": float(rows.loc[rows["fit_case"] == "weakest", "capacity_N"].min())
                if (rows["fit_case"] == "weakest").any() else float("nan"),
                "capacity_N_nominal_fit": float(nominal["capacity_N"].min()) if not nominal.empty else float("nan"),
                "below_tolerance": {f"{f:g}x_weakest_fit": {
                    "max_slip_utilisation": float(g["max_rigid_utilisation"].max()), **creep_summary(g, distance_mm)}
                    for f, (_, g) in zip(BELOW_TOLERANCE_FRACTIONS, below.groupby("level"))},
                "walk_off_probability": pr["walk_off_probability"],
                "probability_by_damper_state": pr["probability_by_damper_state"],
                "drivers": pr["drivers"]}
    calibration = None
    if calibrate:
        base = runs["helical"]
        model = WalkOffModel(base, system, joints, exposure_hours=exposure, samples=calibration_samples, seed=seed)
        cal = calibrate_walk_off(model, evidence, default_uncertain_inputs(joints, record), seed=seed,
                                 prior_samples=min(prior_samples, 64) if quick else prior_samples)
        spur_model = WalkOffModel(runs["spur"], system, joints, exposure_hours=exposure, samples=calibration_samples,
                                  seed=seed)
        for name, (kind, prefix, shift) in trains.items():
            for joint in joints:
                pred = cal.predict(joint, model=spur_model if kind == "spur" else model,
                                   label=f"{prefix}{joint}" if prefix else None,
                                   theta_offsets={"cam.interference_shift_um": shift} if joint == "cam" else None)
                row = summary[name][joint]
                row["walk_off_probability_uncalibrated"] = row["walk_off_probability"]
                row["walk_off_probability"] = pred["walk_off_probability"]
                row["walk_off_probability_interval_90"] = pred["interval_90"]
        calibration = cal.to_json()
        calibration["quick"] = bool(quick)
    assumptions = {
        "speeds_rpm": {b: {"speed_rpm": v, "source": src} for b, (v, src) in bands.items() if v in speeds},
        "damper_states": {s: {"multiplier_of_data": DAMPER_STATES[s], "damping_Nms_per_rad": None} for s in states},
        "damper_source": DAMPER_STATES_SOURCE,
        "fit_cases": "weakest = min ISO 286 interference, DIN 7190 smoothing 0.8 sum Rz, mu min; strongest = max "
                     "interference, 0.4 sum Rz, mu max",
        "joint_data": dict(JOINT_FRICTION_DATA),
        "distance_mm": float(distance_mm),
        "distance_source": (record.sources.get("walk_off_distance_mm", "") if record is not None
                            else WALK_OFF_DISTANCE_SOURCE),
        "period_months": record.period_months if record is not None else WARRANTY_MONTHS,
        "exposure_hours_median_sigma": dict(exposure),
        "exposure_source": (record.sources.get("rated_hours_median_h", "") if record is not None
                            else EXPOSURE_HOURS_SOURCE),
        "damper_state_probabilities": damper_probabilities,
        "damper_probability_source": (record.sources.get("damper_degraded_probability", "") if record is not None
                                      else DAMPER_STATE_PROBABILITIES_SOURCE), "field_rate": FIELD_RATE,
        "field_rate_source": FIELD_RATE_SOURCE, "alternatives": {k: v["description"] for k, v in alternatives.items()},
        "recorded_cycles": run["cycles"], "run_in_cycles": run["run_in_cycles"], "samples": int(samples),
        "coupling": "one-way: slip states driven by the torsional model, not fed back (bounded by the key)"}
    c0 = float(system.section("engine", "failure_reproduction")["crankshaft"]["damper_viscous_damping_Nms_per_rad"])
    for s in states:
        assumptions["damper_states"][s]["damping_Nms_per_rad"] = c0 * DAMPER_STATES[s]
    return {"envelopes": envelopes, "probabilities": probabilities, "summary": summary, "assumptions": assumptions,
            "calibration": calibration}


__all__ = ["FIELD_RATE", "HELICAL_ALTERNATIVES", "failure_reproduction"]
