"""How likely is a walk-off: Monte Carlo over fit, friction, smoothing, damper state and overspeed exposure, on the
creep map of the friction-joint envelope (:func:`gearopt.dynamics.walk_off_envelope.joint_envelope`).

Per sample: a diametral interference (normal about the ISO 286 fit's mean, the tolerance band = +-3 sigma,
truncated to it [E]), a friction coefficient (uniform over :data:`JOINT_FRICTION_DATA`'s range), a DIN 7190
smoothing loss (factor uniform 0.4..0.8 x (Rz_shaft + Rz_hub): the 2017 and 2001 rules), a damper state
(categorical, :data:`DAMPER_STATE_PROBABILITIES` [E]) and hours in each speed band of the envelope within the
warranty period (log-normal, :data:`EXPOSURE_HOURS` [E]). The fit's capacity at each band's speed is
:func:`~gearopt.dynamics.walk_off_envelope.fit_capacity_N` (linear in the effective interference and in mu), the
creep per cycle is interpolated in log capacity on the envelope's capacity grid at that speed and damper state
(clamped at the grid's ends), and the distance walked is the sum over the bands of ``max(creep, 0) x cycles``:
conservative, as creep towards the shoulder at one speed is not credited against creep off the nose at another.
A sample walks off when the distance reaches ``distance_mm``.

The evaluation is vectorised (no model runs): the model runs are the envelope's, which take a ``map``-like
executor. No input here is fitted to a field rate: :mod:`gearopt.studies.calibration` calibrates the estimated
inputs of the same model against observed failure counts (the timing-train case,
:mod:`gearopt.cases.timing_train.failure`, against the source study's field record).
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from ..data import System, joint_record, system_of
from ..errors import GearoptInputError
from ..validation import check_range

#: Probability of each damper state over the warranty period [E].
DAMPER_STATE_PROBABILITIES = {"nominal": 0.94, "degraded": 0.05, "seized": 0.01}
DAMPER_STATE_PROBABILITIES_SOURCE = ("[E] no public failure statistics of viscous crankshaft dampers within 24 "
                                     "months were found; 5 % degraded and 1 % seized are placeholders to be "
                                     "replaced by field data -- the results are also given per damper state")

#: Hours in each speed band within the warranty period: log-normal (median [h], sigma of ln) [E].
EXPOSURE_HOURS = {"rated": (300.0, 1.0), "high_idle": (30.0, 1.0), "overspeed_test": (1.0, 1.5),
                  "motoring_overspeed": (0.1, 1.5)}
EXPOSURE_HOURS_SOURCE = ("[E] a heavy-truck engine runs ~3000-4000 h in 24 months, mostly below rated speed; "
                         "medians: 300 h at rated, 30 h at high idle, 1 h at the 3000 rpm overspeed (downhill "
                         "motoring beyond the governor), 0.1 h at 3300 rpm; log-normal spread sigma 1.0-1.5 (a "
                         "factor 3-4.5 per sigma) between drivers and duty cycles. No public measurement found.")

WALK_OFF_DISTANCE_MM = 3.0
WALK_OFF_DISTANCE_SOURCE = ("[E] axial travel at which the cam gear leaves a useful part of its 25 mm seat and "
                            "reaches the gear cover (the thesis' Fig. 1.1 shows the gear out of place; no figure "
                            "given)")
WARRANTY_MONTHS = 24.0
#: Creep per cycle below this [um] is integration noise of a joint that never slipped (set to zero).
CREEP_NOISE_UM = 1e-6


def _creep_interpolator(envelope: pd.DataFrame, joint: str):
    """{(speed, damper state): (log capacities, creep um/cycle)} from the envelope rows of ``joint``."""
    rows = envelope[envelope["joint"] == joint]
    if rows.empty:
        raise GearoptInputError(f"joint={joint!r} is not in the envelope ({sorted(envelope['joint'].unique())})")
    table = {}
    for (speed, state), g in rows.groupby(["speed_rpm", "damper_state"]):
        g = g.sort_values("capacity_N")
        creep = g["axial_creep_um_per_cycle"].to_numpy()
        table[(float(speed), str(state))] = (np.log(g["capacity_N"].to_numpy()),
                                             np.where(np.abs(creep) < CREEP_NOISE_UM, 0.0, creep))
    return table


def sample_inputs(system: System, joint: str, samples: int, seed: int = 0, *, speeds_rpm: dict | None = None,
                  damper_probabilities: dict | None = None, exposure_hours: dict | None = None,
                  interference_shift_um: float = 0.0) -> pd.DataFrame:
    """The Monte Carlo inputs (module docstring) as a DataFrame: ``interference_um``, ``friction_coefficient``,
    ``smoothing_loss_um``, ``damper_state`` and ``hours_<band>`` per sample. ``interference_shift_um`` moves the
    whole fit (a stronger fit class). ``system``: the :class:`~gearopt.data.System` of the data file (its
    ``system.joints[joint]`` fit range and roughness, ``[engine]`` speeds)."""
    from ..dynamics.walk_off_envelope import JOINT_FRICTION_DATA, envelope_speeds_rpm
    check_range("samples", samples, 1, None)
    system = system_of(system, "sample_inputs")
    j = joint_record(system, joint, "sample_inputs").entries
    rng = np.random.default_rng(seed)
    lo, hi = float(j["diametral_interference_min_um"]), float(j["diametral_interference_max_um"])
    mean, sigma = 0.5 * (lo + hi), (hi - lo) / 6.0
    delta = np.clip(rng.normal(mean, sigma, samples), lo, hi) + interference_shift_um
    f = JOINT_FRICTION_DATA
    mu = rng.uniform(f["friction_coefficient_min"], f["friction_coefficient_max"], samples)
    rz = float(j["shaft_roughness_Rz_um"]) + float(j["hub_roughness_Rz_um"])
    smoothing = rng.uniform(0.4, 0.8, samples) * rz
    probs = dict(DAMPER_STATE_PROBABILITIES if damper_probabilities is None else damper_probabilities)
    for k, v in probs.items():
        check_range(f"damper probability of {k!r}", v, 0.0, 1.0)
    if abs(sum(probs.values()) - 1.0) > 1e-9:
        raise GearoptInputError(f"damper state probabilities {probs} must sum to 1 (sum {sum(probs.values()):.6g})")
    states = rng.choice(list(probs), size=samples, p=list(probs.values()))
    out = pd.DataFrame({"interference_um": delta, "friction_coefficient": mu, "smoothing_loss_um": smoothing,
                        "damper_state": states})
    bands = envelope_speeds_rpm(system) if speeds_rpm is None else speeds_rpm
    exposure = dict(EXPOSURE_HOURS if exposure_hours is None else exposure_hours)
    for band in bands:
        if band not in exposure:
            raise GearoptInputError(f"exposure_hours has no band {band!r} (bands: {list(bands)})")
        median, s = exposure[band]
        check_range(f"median hours of {band!r}", median, 0.0, None, unit="h")
        check_range(f"sigma of {band!r}", s, 0.0, None)
        out[f"hours_{band}"] = median * np.exp(s * rng.standard_normal(samples))
    return out


def capacity_line(system: System, joint: str, speed_rpm: float) -> tuple[float, float, float]:
    """``(slope [N/um at mu0], centrifugal loss [um], mu0)`` of ``joint``'s fit capacity at ``speed_rpm``: linear in
    mu and in the effective interference above the centrifugal loss (the elastic Lame solution of
    :func:`~gearopt.dynamics.walk_off_envelope.fit_capacity_N`, fitted through two of its evaluations; tested
    against it). ``system``: as :func:`sample_inputs`."""
    from ..dynamics.walk_off_envelope import fit_capacity_N
    mu0 = 0.5
    c_hi = fit_capacity_N(system, joint, interference_um=200.0, friction_coefficient=mu0, speed_rpm=speed_rpm)
    c_lo = fit_capacity_N(system, joint, interference_um=100.0, friction_coefficient=mu0, speed_rpm=speed_rpm)
    slope = (c_hi - c_lo) / 100.0
    return slope, 200.0 - c_hi / slope, mu0


def sampled_capacity_N(system: System, joint: str, speed_rpm: float, interference_um, smoothing_loss_um,
                       friction_coefficient) -> np.ndarray:
    """Vectorised fit capacity [N] of the Monte Carlo samples (:func:`capacity_line`). ``system``: as
    :func:`sample_inputs`."""
    system = system_of(system, "sampled_capacity_N")
    slope, loss, mu0 = capacity_line(system, joint, speed_rpm)
    eff = np.maximum(np.asarray(interference_um, dtype=float) - np.asarray(smoothing_loss_um, dtype=float) - loss,
                     0.0)
    return np.maximum(slope * eff * np.asarray(friction_coefficient, dtype=float) / mu0, 1e-3)


def walk_off_probability(envelope: pd.DataFrame, system: System, joint: str, *, samples: int = 20000,
                         seed: int = 0, distance_mm: float = WALK_OFF_DISTANCE_MM,
                         damper_probabilities: dict | None = None, exposure_hours: dict | None = None,
                         interference_shift_um: float = 0.0, field_rate: float | None = None,
                         field_rate_source: str = "") -> dict:
    """Probability that ``joint``'s gear walks ``distance_mm`` off its seat within the warranty period (module
    docstring), from an envelope of one train.

    Returns a dict: ``walk_off_probability``, ``probability_by_damper_state`` (conditional on each state),
    ``median_distance_mm`` and ``p99_distance_mm`` of the walked distance, ``drivers`` (Spearman rank correlation
    of each input with the walked distance, largest magnitude first; NaN when nothing walks), ``samples``,
    ``seed``, ``field_rate`` and the ``assumptions`` (distance, period, exposure, damper probabilities, sources).
    ``system``: as :func:`sample_inputs`.
    """
    from ..dynamics.joint_friction import walked_distance_mm
    from ..dynamics.walk_off_envelope import envelope_speeds_rpm
    check_range("distance_mm", distance_mm, 0.0, None, low_inclusive=False, unit="mm")
    system = system_of(system, "walk_off_probability")
    speeds = set(envelope["speed_rpm"].astype(float))
    all_bands = envelope_speeds_rpm(system)
    bands = {b: v for b, v in all_bands.items() if v[0] in speeds}
    if not bands:
        raise GearoptInputError(f"the envelope's speeds {sorted(speeds)} contain no speed band of {all_bands}")
    inputs = sample_inputs(system, joint, samples, seed, speeds_rpm=bands, damper_probabilities=damper_probabilities,
                           exposure_hours=exposure_hours, interference_shift_um=interference_shift_um)
    table = _creep_interpolator(envelope, joint)
    distance = np.zeros(samples)
    for band, (speed, _) in bands.items():
        cap = sampled_capacity_N(system, joint, speed, inputs["interference_um"].to_numpy(),
                                 inputs["smoothing_loss_um"].to_numpy(), inputs["friction_coefficient"].to_numpy())
        creep = np.zeros(samples)
        for state in inputs["damper_state"].unique():
            key = (float(speed), str(state))
            if key not in table:
                raise GearoptInputError(f"the envelope has no run at {speed:g} rpm with damper {state!r}")
            log_c, c = table[key]
            sel = (inputs["damper_state"] == state).to_numpy()
            creep[sel] = np.interp(np.log(cap[sel]), log_c, c)
        distance += walked_distance_mm(np.maximum(creep, 0.0), speed, inputs[f"hours_{band}"].to_numpy())
    walked = distance >= distance_mm
    by_state = {s: float(walked[(inputs["damper_state"] == s).to_numpy()].mean())
                for s in sorted(inputs["damper_state"].unique())}
    drivers = {}
    ranks = pd.Series(distance).rank()
    for col in inputs.columns:
        if col == "damper_state":
            x = inputs[col].map({"nominal": 0, "degraded": 1, "seized": 2}).astype(float)
        else:
            x = inputs[col]
        rx = x.rank()
        drivers[col] = float(np.corrcoef(rx, ranks)[0, 1]) if ranks.std() > 0 and rx.std() > 0 else float("nan")
    drivers = dict(sorted(drivers.items(), key=lambda kv: -abs(kv[1]) if math.isfinite(kv[1]) else 0.0))
    return {"walk_off_probability": float(walked.mean()), "probability_by_damper_state": by_state,
            "median_distance_mm": float(np.median(distance)), "p99_distance_mm": float(np.quantile(distance, 0.99)),
            "drivers": drivers, "samples": int(samples), "seed": int(seed), "field_rate": field_rate,
            "assumptions": {"distance_mm": float(distance_mm), "distance_source": WALK_OFF_DISTANCE_SOURCE,
                            "period_months": WARRANTY_MONTHS,
                            "speed_bands_rpm": {b: v for b, (v, _) in bands.items()},
                            "exposure_hours_median_sigma": dict(EXPOSURE_HOURS if exposure_hours is None
                                                                else exposure_hours),
                            "exposure_source": EXPOSURE_HOURS_SOURCE,
                            "damper_state_probabilities": dict(DAMPER_STATE_PROBABILITIES
                                                               if damper_probabilities is None
                                                               else damper_probabilities),
                            "damper_source": DAMPER_STATE_PROBABILITIES_SOURCE,
                            "interference_shift_um": float(interference_shift_um),
                            "field_rate_source": field_rate_source}}




def creep_summary(rows: pd.DataFrame, distance_mm: float) -> dict:
    """Largest axial creep per cycle [um] of envelope rows (noise floor :data:`CREEP_NOISE_UM`), its speed, and the
    minutes it takes to walk ``distance_mm`` at that creep and speed (inf when it does not creep)."""
    creep = rows["axial_creep_um_per_cycle"].where(rows["axial_creep_um_per_cycle"].abs() >= CREEP_NOISE_UM, 0.0)
    if creep.empty:
        return {"max_axial_creep_um_per_cycle": 0.0, "at_speed_rpm": float("nan"), "minutes_to_walk_distance": "inf"}
    i = creep.idxmax()
    c, speed = float(creep[i]), float(rows.loc[i, "speed_rpm"])
    minutes = distance_mm * 1e3 / c / (speed / 2.0) if c > 0.0 else "inf"  # speed/2 cycles per minute (4-stroke)
    return {"max_axial_creep_um_per_cycle": c, "at_speed_rpm": speed, "minutes_to_walk_distance": minutes}


#: Helical alternatives of the cure, on the same footing as the spur train [E]: thrust scale (tan of a lower
#: helix angle over the present one, dynamics of the present train kept: an approximation) and a shift of the
#: cam fit's interference range.
__all__ = ["DAMPER_STATE_PROBABILITIES", "EXPOSURE_HOURS", "WALK_OFF_DISTANCE_MM", "WARRANTY_MONTHS",
           "sample_inputs", "capacity_line", "sampled_capacity_N", "walk_off_probability", "creep_summary"]
