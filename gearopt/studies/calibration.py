"""Calibration of the walk-off failure model to fleet evidence: which of the estimated inputs are consistent with the
failures a fleet showed (and did not show).

The model is the Monte Carlo of :mod:`gearopt.studies.failure` on an envelope's creep maps
(:func:`gearopt.dynamics.walk_off_envelope.joint_envelope`): per engine a fit (interference within the ISO 286 band,
friction coefficient, DIN 7190 smoothing), a damper state and hours in each speed band; the gear walks off when the
creep of its fit at each band's speed, times the band's cycles, adds up to the walk-off distance. The population
inputs the source data only estimate ([E]) become uncertain inputs ``theta`` (:class:`UncertainInput`): per joint
an interference shift of the whole fit, the spread of the fits about it and how the gear is held (its mounting), and for the fleet the
friction coefficient's mean, the smoothing factor's mean, the damper states' probabilities, the hours at overspeed
and at running speeds and the walk-off distance.

Likelihood: the observed failure count of each joint with evidence (:class:`FieldEvidence`) is binomial in the fleet
size with the model's probability ``p_joint(theta)`` (:func:`scipy.stats.binom.logpmf`); joints are independent given
``theta`` (their inputs are drawn independently per engine, the population inputs are shared).

Posterior: importance sampling from the prior (uniform, or log-uniform for a ``"log"`` input, in a scrambled Sobol'
sequence, :class:`scipy.stats.qmc.Sobol`; each shoulder-side combination with equal prior weight), weighted by the
likelihood. Reported per input: the ``prior`` range, ``posterior`` (weighted median and 5/95 % quantiles) and the
``consistent_range`` (the range of the samples whose likelihood ratio to the best sample is at least
:data:`CONSISTENT_LIKELIHOOD_RATIO`, Wilks' 95 % level for one parameter: the inputs the field does not rule out).

The probability estimator (an approximation, tested against brute-force sampling in ``tests/studies``): common random
numbers for every ``theta`` (so that ``p(theta)`` is smooth and the comparison between samples is not noise), the
damper states summed analytically (``p = sum_s P(s) p_s``) and, per engine, the hours of the band that contributes
most integrated in closed form (conditional Monte Carlo: the walk-off condition is ``h_b >= (D - rest) / r_b`` with
``h_b`` log-normal), which resolves probabilities far below ``1 / samples``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from scipy import special

from ..data import System, joint_record, system_of
from ..errors import GearoptInputError
from ..validation import check_range

#: Likelihood ratio to the best prior sample at or above which a sample is "consistent with the field":
#: exp(-chi2_1(0.95)/2), the 95 % likelihood-ratio interval of one parameter (Wilks' theorem).
CONSISTENT_LIKELIHOOD_RATIO = math.exp(-0.5 * 3.841458820694124)

SHOULDER_SIDES = ("as_modelled", "flipped")
"""The two sides of a gear its shaft shoulder can be on: ``as_modelled`` (the data's: the helical thrust of the
modelled rotation pushes the gear off the shaft nose) and ``flipped`` (the thrust presses it onto the shoulder)."""

FLIPPED_PREFIX = "shoulder_flipped:"
"""Envelope label prefix of a joint's copy with the shoulder on the other side (thrust scale -1)."""

DAMPER_STATE_NAMES = ("nominal", "degraded", "seized")
SPEED_BANDS = ("rated", "high_idle", "overspeed_test", "motoring_overspeed")


@dataclass(frozen=True)
class FieldEvidence:
    """Observed failures of one joint in a fleet: ``failures`` of ``fleet_size`` units within ``period_months``
    (the warranty period of the model's exposure hours), with the ``source`` of the record."""

    joint: str
    failures: int
    fleet_size: int
    period_months: float
    source: str = ""

    def __post_init__(self):
        check_range(f"fleet_size of {self.joint!r}", self.fleet_size, 1, None)
        check_range(f"failures of {self.joint!r}", self.failures, 0, self.fleet_size)
        check_range(f"period_months of {self.joint!r}", self.period_months, 0.0, None, low_inclusive=False,
                    unit="months")

    @property
    def rate(self) -> float:
        return self.failures / self.fleet_size


@dataclass(frozen=True)
class UncertainInput:
    """One estimated input of the failure model with its prior range: ``low``..``high`` (uniform, or log-uniform
    for ``scale="log"``), the value the uncalibrated model uses (``nominal``) and the ``source`` of the range."""

    name: str
    low: float
    high: float
    nominal: float
    unit: str = "-"
    scale: str = "linear"
    source: str = ""

    def __post_init__(self):
        if self.scale not in ("linear", "log"):
            raise GearoptInputError(f"scale={self.scale!r} of {self.name!r} must be 'linear' or 'log'")
        check_range(f"high of {self.name!r}", self.high, self.low, None, low_inclusive=False, unit=self.unit)
        if self.scale == "log":
            check_range(f"low of {self.name!r}", self.low, 0.0, None, low_inclusive=False, unit=self.unit)
        check_range(f"nominal of {self.name!r}", self.nominal, self.low, self.high, unit=self.unit)

    def from_unit(self, u: np.ndarray) -> np.ndarray:
        if self.scale == "log":
            return self.low * (self.high / self.low) ** u
        return self.low + (self.high - self.low) * u


@dataclass(frozen=True)
class FieldRecord:
    """The ``[field_record]`` section of a data file with the joints' ``field_failures``: the fleet (``fleet_size``
    units over ``period_months``), the duty the failure model's probability rests on (``exposure_hours`` {speed
    band: (median h, sigma of ln)}, ``damper_probabilities`` {state: share}, ``walk_off_distance_mm``), the
    ``evidence`` per joint with a count, and the provenance string of every key (``sources``)."""

    fleet_size: int
    period_months: float
    walk_off_distance_mm: float
    damper_probabilities: dict
    exposure_hours: dict
    evidence: tuple
    sources: dict

    def nominal_theta(self) -> dict:
        """The uncalibrated inputs of the record (the defaults of :func:`default_uncertain_inputs`' nominals)."""
        return {"damper_degraded_probability": self.damper_probabilities["degraded"],
                "damper_seized_probability": self.damper_probabilities["seized"],
                "walk_off_distance_mm": self.walk_off_distance_mm}


def field_record(system: System) -> FieldRecord:
    """The :class:`FieldRecord` of ``system`` (raises naming the section when the data file has no
    ``[field_record]``)."""
    from ..data import require_section
    system = system_of(system, "field_record")
    f = system.section("field_record", "the walk-off calibration")
    raw = require_section(system, "field_record", "the walk-off calibration")
    damper = {"degraded": float(f["damper_degraded_probability"]), "seized": float(f["damper_seized_probability"])}
    damper["nominal"] = 1.0 - damper["degraded"] - damper["seized"]
    if damper["nominal"] < 0.0:
        raise GearoptInputError(f"{system.source}: [field_record] damper_degraded_probability + "
                                f"damper_seized_probability = {1.0 - damper['nominal']:g} must be <= 1")
    exposure = {b: (float(f[f"{b}_hours_median_h"]), float(f[f"{b}_hours_sigma"])) for b in SPEED_BANDS}
    joints_raw = require_section(system, "joints", "the walk-off calibration")
    evidence = tuple(FieldEvidence(name, int(j.entries["field_failures"]), int(f["fleet_size"]),
                                   float(f["period_months"]), str(joints_raw[name].get("field_failures_source", "")))
                     for name, j in system.joints.items() if "field_failures" in j.entries)
    return FieldRecord(int(f["fleet_size"]), float(f["period_months"]), float(f["walk_off_distance_mm"]), damper,
                       exposure, evidence, {k[:-len("_source")]: v for k, v in raw.items()
                                            if isinstance(v, str) and k.endswith("_source")})


def default_uncertain_inputs(joints, record: FieldRecord | None = None) -> list[UncertainInput]:
    """The estimated ([E]) inputs of the walk-off model and their prior ranges, for ``joints``; the nominal damper
    probabilities and walk-off distance from ``record`` when given."""
    nominal = record.nominal_theta() if record is not None else {}
    out = [UncertainInput(f"{j}.interference_shift_um", -20.0, 60.0, 0.0, "um", source=(
        "[E] the fit's real interference against the ISO 286 band of the data: fretting wear and a softer seat "
        "lower it, a tighter production fit (up to about two ISO 286 fit classes, e.g. r6 -> u6) raises it"))
        for j in joints]
    out += [UncertainInput(f"{j}.interference_spread_scale", 0.5, 2.0, 1.0, "-", "log", source=(
        "[E] the spread of the fits in production against the data's normal law (the ISO 286 band = +-3 sigma, "
        "truncated there): a capable process is narrower, one that fills the band or wears widens it"))
        for j in joints]
    return out + [
        UncertainInput("friction_coefficient_mean", 0.06, 0.20, 0.12, "-", source=(
            "[V]/[E] DIN 7190-1 adhesion coefficients steel-steel 0.12 (oiled) to 0.20 (degreased); oiled pressed "
            "fits lower; each engine +-1/3 of the mean (the uncalibrated model's 0.08-0.16)")),
        UncertainInput("smoothing_factor_mean", 0.3, 0.9, 0.6, "-", source=(
            "[V]/[E] DIN 7190 smoothing loss factor of (Rz_shaft + Rz_hub): 0.4 (2017) to 0.8 (2001); each engine "
            "+-0.2 about the mean")),
        UncertainInput("damper_degraded_probability", 0.0, 0.3, nominal.get("damper_degraded_probability", 0.05), "-", source=(
            "[E] share of engines whose viscous damper is degraded within the period; no public statistics")),
        UncertainInput("damper_seized_probability", 0.0, 0.1, nominal.get("damper_seized_probability", 0.01), "-", source=(
            "[E] share of engines whose damper is seized (gelled fluid) within the period; no public statistics")),
        UncertainInput("overspeed_exposure_scale", 0.1, 10.0, 1.0, "-", "log", source=(
            "[E] factor on the median hours at the overspeed-test and motoring-overspeed speeds (duty data not "
            "public)")),
        UncertainInput("running_exposure_scale", 0.3, 3.0, 1.0, "-", "log", source=(
            "[E] factor on the median hours at rated speed and high idle")),
        UncertainInput("walk_off_distance_mm", 1.5, 6.0, nominal.get("walk_off_distance_mm", 3.0), "mm", source=(
            "[E] axial travel at which a walked gear fails (leaves a useful part of its seat, reaches the cover)")),
    ]


class WalkOffModel:
    """Walk-off probabilities of ``joints`` as functions of the uncertain inputs, built once on an envelope
    (module docstring: common random numbers, damper states summed, one band's hours in closed form).

    ``envelope``: rows of :func:`~gearopt.dynamics.walk_off_envelope.joint_envelope` with every joint of ``joints``
    (and, for a joint whose shoulder side is uncertain, its copy labelled ``shoulder_flipped:<joint>``) at every
    (speed, damper state) of the speed bands; ``system``: the data's :class:`~gearopt.data.System` (fits,
    roughness, speeds); ``exposure_hours`` {band: (median h, sigma of ln)}; ``samples`` engines per probability;
    ``seed`` the common random numbers; ``speed_bands_rpm`` {band: speed} (default the engine's,
    :func:`~gearopt.dynamics.walk_off_envelope.envelope_speeds_rpm`): the bands of ``exposure_hours``, each
    with its runs in the envelope. Joint fits come from ``system.joints`` (press fits: interference range,
    roughness, materials).
    """

    def __init__(self, envelope: pd.DataFrame, system: System, joints, *, exposure_hours: dict, samples: int = 4000,
                 seed: int = 0, speed_bands_rpm: dict | None = None):
        from .failure import CREEP_NOISE_UM, capacity_line
        check_range("samples", samples, 16, None)
        system = system_of(system, "WalkOffModel")
        self.system = system
        self.joints = tuple(joints)
        missing = {"joint", "speed_rpm", "damper_state", "capacity_N", "axial_creep_um_per_cycle"} - set(envelope)
        if missing:
            raise GearoptInputError(f"the envelope has no columns {sorted(missing)}")
        speeds = set(envelope["speed_rpm"].astype(float))
        if speed_bands_rpm is None:
            from ..dynamics.walk_off_envelope import envelope_speeds_rpm
            speed_bands_rpm = {b: v for b, (v, _) in envelope_speeds_rpm(system).items()}
        bands = {b: float(v) for b, v in speed_bands_rpm.items() if float(v) in speeds}
        if not bands:
            raise GearoptInputError(f"the envelope's speeds {sorted(speeds)} contain no speed band of "
                                    f"{speed_bands_rpm}")
        for b in bands:
            if b not in exposure_hours:
                raise GearoptInputError(f"exposure_hours has no band {b!r} (bands: {list(bands)})")
        self.bands = bands
        self.exposure = {b: (float(exposure_hours[b][0]), float(exposure_hours[b][1])) for b in bands}
        rng = np.random.default_rng(seed)
        self.samples = int(samples)
        self.z_fit = {j: np.clip(rng.standard_normal(samples), -3.0, 3.0) for j in self.joints}
        self.u_mu = {j: rng.uniform(-1.0, 1.0, samples) for j in self.joints}
        self.u_smooth = {j: rng.uniform(-1.0, 1.0, samples) for j in self.joints}
        self.z_hours = {b: rng.standard_normal(samples) for b in bands}
        self.fits, self.tables, self._creep_free = {}, {}, {}
        states = sorted(envelope["damper_state"].astype(str).unique())
        self.states = tuple(s for s in DAMPER_STATE_NAMES if s in states) + tuple(
            s for s in states if s not in DAMPER_STATE_NAMES)
        for j in self.joints:
            rec = joint_record(system, j, "WalkOffModel").entries
            lo, hi = float(rec["diametral_interference_min_um"]), float(rec["diametral_interference_max_um"])
            rz = float(rec["shaft_roughness_Rz_um"]) + float(rec["hub_roughness_Rz_um"])
            lines = {b: capacity_line(system, j, speed) for b, speed in bands.items()}
            self.fits[j] = (0.5 * (lo + hi), (hi - lo) / 6.0, rz, lines)
        for (label, speed, state), g in envelope.groupby(["joint", "speed_rpm", "damper_state"]):
            g = g.sort_values("capacity_N")
            cap, c = g["capacity_N"].to_numpy(), g["axial_creep_um_per_cycle"].to_numpy()
            c = np.where(np.abs(c) < CREEP_NOISE_UM, 0.0, c)
            if "max_rigid_utilisation" in g:
                # a fit whose capacity exceeds the peak demand of the stuck gear never slips: no creep from there
                # on (exact in the one-way coupled model: the demand does not depend on the capacity)
                demand = float(np.median(g["max_rigid_utilisation"].to_numpy() * cap))
                c = np.where(cap >= demand, 0.0, c)
                if cap[0] < demand < cap[-1]:
                    k = int(np.searchsorted(cap, demand))
                    cap, c = np.insert(cap, k, demand), np.insert(c, k, 0.0)
            self.tables[(str(label), float(speed), str(state))] = (np.log(cap), c)
            if np.any(c > 0.0):
                self._creep_free[(str(label), float(speed), str(state))] = _creep_free_capacity_N(np.log(cap), c)
        self.labels = sorted({k[0] for k in self.tables})
        for j in self.joints:
            self.check_label(j)
        self.flippable = {j: FLIPPED_PREFIX + j in self.labels for j in self.joints}

    def check_label(self, label: str) -> None:
        """Raise unless the envelope has ``label``'s creep map at every speed band and damper state."""
        if label not in self.labels:
            raise GearoptInputError(f"joint={label!r} is not in the envelope ({self.labels})")
        for speed in self.bands.values():
            for s in self.states:
                if (label, float(speed), s) not in self.tables:
                    raise GearoptInputError(f"the envelope has no run of {label!r} at {speed:g} rpm with damper "
                                            f"{s!r}")

    def capacities_N(self, joint: str, band: str, theta: dict, shifts_um=None) -> np.ndarray:
        """Fit capacity [N] of each sampled engine's ``joint`` at ``band``'s speed under the inputs ``theta``
        (``[engines]``), or for each interference shift of ``shifts_um`` (``[shifts, engines]``, replacing
        ``theta``'s)."""
        return self._capacities_N(joint, (band,), theta, shifts_um)[band]

    def _capacities_N(self, joint: str, bands, theta: dict, shifts_um=None) -> dict:
        """{band: :meth:`capacities_N`} for each of ``bands`` (the engines' interference, friction and smoothing
        drawn once)."""
        mean, sigma, rz, lines = self.fits[joint]
        shift = float(theta.get(f"{joint}.interference_shift_um", 0.0)) if shifts_um is None else \
            np.asarray(shifts_um, dtype=float)[:, None]
        spread = float(theta.get(f"{joint}.interference_spread_scale", 1.0))
        delta = mean + spread * sigma * self.z_fit[joint] + shift
        mu = float(theta.get("friction_coefficient_mean", 0.12)) * (1.0 + self.u_mu[joint] / 3.0)
        smoothing = np.maximum(float(theta.get("smoothing_factor_mean", 0.6)) + 0.2 * self.u_smooth[joint], 0.0) * rz
        held = delta - smoothing                                   # interference after smoothing [um]
        out = {}
        for band in bands:
            slope, loss, mu0 = lines[band]
            eff = np.maximum(held - loss, 0.0)
            out[band] = np.maximum(slope * eff * mu / mu0, 1e-3)
        return out

    def median_capacity_N(self, joint: str, theta: dict, band: str | None = None) -> float:
        """Axial capacity [N] of the median engine's ``joint`` fit under ``theta`` (mean interference plus the
        shift, the mean smoothing loss, the mean friction coefficient) at ``band``'s speed (default the lowest)."""
        mean, _, rz, lines = self.fits[joint]
        band = band or min(self.bands, key=self.bands.get)
        slope, loss, mu0 = lines[band]
        eff = mean + float(theta.get(f"{joint}.interference_shift_um", 0.0)) \
            - float(theta.get("smoothing_factor_mean", 0.6)) * rz - loss
        return float(max(slope * eff * float(theta.get("friction_coefficient_mean", 0.12)) / mu0, 0.0))

    def probability(self, joint: str, theta: dict, shoulder: str = "as_modelled", label: str | None = None
                    ) -> tuple[float, dict]:
        """(walk-off probability, {damper state: conditional probability}) of ``joint`` under ``theta``, with its
        shoulder on ``shoulder``'s side (:data:`SHOULDER_SIDES`); ``label`` reads another envelope label's creep
        map for an as-modelled shoulder (a variant of the joint, e.g. a lower helix angle); a flipped shoulder reads
        the base joint's flipped copy (an approximation for a variant: its thrust presses the gear onto the
        shoulder too, scaled)."""
        p, by_state = self._probabilities(joint, theta, shoulder, label, None)
        return float(p[0]), {k: float(v[0]) for k, v in by_state.items()}

    def probability_over_shifts(self, joint: str, theta: dict, shifts_um, shoulder: str = "as_modelled",
                                label: str | None = None) -> np.ndarray:
        """Walk-off probabilities of ``joint`` for each interference shift [um] of ``shifts_um`` (the other
        inputs from ``theta``), in one vectorised pass (as :meth:`probability`)."""
        return self._probabilities(joint, theta, shoulder, label, np.atleast_1d(shifts_um))[0]

    def _probabilities(self, joint, theta, shoulder, label, shifts):
        if shoulder not in SHOULDER_SIDES:
            raise GearoptInputError(f"shoulder={shoulder!r} must be one of {SHOULDER_SIDES}")
        if label is None or shoulder == "flipped":
            label = joint if shoulder == "as_modelled" else FLIPPED_PREFIX + joint
        self.check_label(label)
        distance = float(theta.get("walk_off_distance_mm", 3.0))
        check_range("walk_off_distance_mm", distance, 0.0, None, low_inclusive=False, unit="mm")
        caps = {b: np.atleast_2d(c) for b, c in self._capacities_N(joint, self.bands, theta, shifts).items()}
        shape = next(iter(caps.values())).shape
        medians, sigmas = [], []
        for b in self.bands:
            median, sigma = self.exposure[b]
            # bands whose name contains "overspeed" scale with overspeed_exposure_scale, the others with
            # running_exposure_scale
            scale = float(theta.get("overspeed_exposure_scale" if "overspeed" in b else "running_exposure_scale",
                                    1.0))
            medians.append(median * scale)
            sigmas.append(sigma)
        medians, sigmas = np.array(medians), np.array(sigmas)
        hours = medians[:, None] * np.exp(sigmas[:, None] * self._z_hours())     # [bands x engines]
        by_state = {}
        for state in self.states:
            keys = [(label, float(speed), state) for speed in self.bands.values()]
            tables = [self.tables[k] for k in keys]
            creeps = [k in self._creep_free for k in keys]           # a band with creep off the nose at some fit
            if not any(creeps):                                       # none: this state never walks off
                by_state[state] = np.zeros(shape[:-1])
                continue
            # an engine whose fit is creep-free at every band never walks off (probability exactly 0, as the full
            # computation gives it): only the others are computed
            live = np.zeros(shape, dtype=bool)
            for b, k, creeps_here in zip(self.bands, keys, creeps):
                if creeps_here:
                    free = self._creep_free[k]
                    live |= (caps[b] < free) if math.isfinite(free) else True    # creeps at any capacity
            if not live.any():
                by_state[state] = np.zeros(shape[:-1])
                continue
            rates = []
            for (b, speed), (log_c, c), creeps_here in zip(self.bands.items(), tables, creeps):
                creep = np.maximum(np.interp(np.log(caps[b][live]), log_c, c), 0.0) if creeps_here else \
                    np.zeros(np.count_nonzero(live))                          # um per engine cycle
                rates.append(creep * speed * 30.0 * 1e-3)                     # mm per hour (720 deg cycles)
            engines = np.broadcast_to(np.arange(shape[-1]), shape)[live]
            conditional = np.zeros(shape)
            conditional[live] = _conditional_walk_off(np.array(rates), medians, sigmas, hours[:, engines],
                                                      distance)
            by_state[state] = conditional.mean(axis=-1)
        weights = damper_weights(theta, self.states)
        return sum(weights[s] * by_state[s] for s in self.states), by_state

    def _z_hours(self) -> np.ndarray:
        return np.array([self.z_hours[b] for b in self.bands])


def damper_weights(theta: dict, states=DAMPER_STATE_NAMES) -> dict:
    """Probabilities of the damper states under ``theta`` (renormalised over ``states``; an envelope whose states are
    none of :data:`DAMPER_STATE_NAMES` -- a train without a damper -- weighs its states equally)."""
    p = {"degraded": float(theta.get("damper_degraded_probability", 0.05)),
         "seized": float(theta.get("damper_seized_probability", 0.01))}
    p["nominal"] = 1.0 - p["degraded"] - p["seized"]
    if p["nominal"] < 0.0:
        raise GearoptInputError(f"damper_degraded_probability + damper_seized_probability = "
                                f"{p['degraded'] + p['seized']:g} must be <= 1")
    total = sum(p.get(s, 0.0) for s in states)
    return {s: p.get(s, 0.0) / total if total > 0 else 1.0 / len(states) for s in states}


def _creep_free_capacity_N(log_capacities, creeps) -> float:
    """The capacity [N] from which a creep map (creep [um/cycle] at the log-capacities ``log_capacities``, linear in
    between, constant beyond the ends) gives no creep off the nose: the grid point after its last positive creep
    (``inf`` if that is the last point), with a relative margin of 1e-9 over its exponential (a capacity just below
    is computed in full, whose creep there is 0)."""
    last = int(np.flatnonzero(creeps > 0.0)[-1])
    return float(np.exp(log_capacities[last + 1]) * (1.0 + 1e-9)) if last + 1 < len(creeps) else math.inf


def _conditional_walk_off(rates, medians, sigmas, hours, distance):
    """P(sum_b rates_b h_b >= distance | the hours of every band but the largest contributor) per engine:
    ``rates`` [bands x ... x engines] mm/h, ``medians``/``sigmas`` per band, ``hours`` [bands x engines] the sampled
    hours ``median exp(sigma z)`` (common to every leading index of ``rates``)."""
    shape = rates.shape
    rates = rates.reshape(shape[0], -1, shape[-1])
    hours = hours[:, None, :]
    mean_hours = medians * np.exp(0.5 * sigmas ** 2)
    # the largest contributor per engine (the first of equals), band by band: cheaper than an argmax over bands
    best, star = rates[0] * mean_hours[0], np.zeros(rates.shape[1:], dtype=int)
    r_star, h_star = rates[0], np.broadcast_to(hours[0], rates.shape[1:])
    for k in range(1, rates.shape[0]):
        contribution = rates[k] * mean_hours[k]
        larger = contribution > best
        best = np.where(larger, contribution, best)
        star = np.where(larger, k, star)
        r_star = np.where(larger, rates[k], r_star)
        h_star = np.where(larger, hours[k], h_star)
    remaining = distance - ((rates * hours).sum(axis=0) - r_star * h_star)
    out = np.where(remaining <= 0.0, 1.0, 0.0)
    live = (remaining > 0.0) & (r_star > 0.0)
    if np.any(live):
        b = star[live]
        zc = (np.log(remaining[live] / r_star[live]) - np.log(medians[b])) / np.maximum(sigmas[b], 1e-12)
        out[live] = 0.5 * special.erfc(zc / math.sqrt(2.0))
    return out.reshape(shape[1:])


def _poisson_log_likelihood(k: int, lam):
    """log P(k | Poisson(lam)) (the binomial of a rare failure, p << 1)."""
    lam = np.maximum(np.asarray(lam, dtype=float), 1e-300)
    return k * np.log(lam) - lam - special.gammaln(k + 1)


def _segment_masses(k: int, fleet: int, x, p) -> tuple[np.ndarray, np.ndarray]:
    """(integral of the likelihood over each segment of the grid ``x`` [shape G-1], largest log-likelihood in each
    segment), with log p linear between the grid points of ``p`` (the failure probabilities at ``x``)."""
    lam = fleet * np.maximum(np.asarray(p, dtype=float), 1e-300)
    la, lb = lam[:-1], lam[1:]
    dx = np.diff(x)
    dy = np.abs(np.log(lb) - np.log(la))
    if k >= 1:
        cdf = special.gammainc(k, lam) / k
        integral = np.abs(cdf[1:] - cdf[:-1])
    else:
        e1 = special.exp1(lam)
        integral = np.abs(e1[:-1] - e1[1:])
    flat = dy < 1e-9
    mass = np.where(flat, np.exp(_poisson_log_likelihood(k, 0.5 * (la + lb))) * dx,
                    dx * integral / np.where(flat, 1.0, dy))
    lo, hi = np.minimum(la, lb), np.maximum(la, lb)
    peak = np.maximum(_poisson_log_likelihood(k, la), _poisson_log_likelihood(k, lb))
    best = _poisson_log_likelihood(k, max(k, 1e-300))
    return mass, np.where((lo <= k) & (k <= hi), best, peak)


SUBPOINTS = 64
"""Points per grid segment at which the posterior within the segment is resolved (the likelihood at the log-linear
probability there): the shift's quantiles and the predicted probabilities read them, not the segment's midpoint,
which overstated a probability that changes by a large factor across a segment (+27 % on the cam's at 25 grid
points, ``benchmarks/bench_calibration.py``)."""


def _within_segments(evidence, x, p) -> tuple[np.ndarray, np.ndarray]:
    """(points [G-1, S], weights [G-1, S]) inside each segment of the grid ``x`` (centres of :data:`SUBPOINTS`
    equal parts) with the relative likelihood of ``evidence`` (a :class:`FieldEvidence` or None: uniform) at the
    log-linear probability ``p`` there; each row of weights sums to 1."""
    t = (np.arange(SUBPOINTS) + 0.5) / SUBPOINTS
    xs = x[:-1, None] + np.diff(x)[:, None] * t
    if evidence is None:
        return xs, np.full(xs.shape, 1.0 / SUBPOINTS)
    log_p = _log_linear(x, p, t)
    ll = _poisson_log_likelihood(evidence.failures, evidence.fleet_size * np.exp(log_p))
    w = np.exp(ll - ll.max(axis=1, keepdims=True))
    return xs, w / w.sum(axis=1, keepdims=True)


def _log_linear(x, p, t) -> np.ndarray:
    """log p at the fractions ``t`` of each segment of the grid (log-linear between the grid values)."""
    log_p = np.log(np.maximum(np.asarray(p, dtype=float), 1e-300))
    return log_p[:-1, None] + np.diff(log_p)[:, None] * t


MOUNTINGS = ("as_modelled", "flipped", "retained")
"""How a gear can be held on its shaft, the discrete unknowns of the calibration: ``as_modelled`` (the shaft
shoulder on the data's side, the helical thrust pushes the gear off the nose), ``flipped`` (the shoulder on the
other side) and ``retained`` (an axial retainer -- a plate and bolt, or a hub clamped against the gear -- holds it:
it cannot walk off, probability 0)."""


def joint_mountings(system: System, joint: str, model: "WalkOffModel") -> tuple:
    """The mountings :data:`MOUNTINGS` possible for ``joint``: ``retained`` unless ``[joints.<joint>]
    axial_retention`` says ``"none"`` (``"retained"``: only that), ``flipped`` when the envelope has the joint's
    flipped copy."""
    retention = str(joint_record(system_of(system, "joint_mountings"), joint, "joint_mountings").entries.get(
        "axial_retention", "unknown"))
    if retention == "retained":
        return ("retained",)
    sides = ("as_modelled", "flipped") if model.flippable.get(joint) else ("as_modelled",)
    return sides if retention == "none" else sides + ("retained",)


@dataclass
class Calibration:
    """Result of :func:`calibrate_walk_off`.

    ``samples``: one row per prior sample of the inputs that are not marginalised, with ``log_likelihood`` (the
    marginal one, over the joints' interference shifts and mountings), ``profile_log_likelihood`` (the best over
    them), ``likelihood_ratio`` (profile, to the best sample) and ``weight``; ``grid``: the interference shifts
    [um] of the marginalised joints; ``detail`` {(joint, mounting): (prior weight x marginal likelihood
    [samples], segment masses [samples x G-1], segment peak log-likelihoods [samples x G-1], probabilities
    [samples x G])}; ``inputs``, ``evidence``, ``mountings`` {joint: options} and the ``model``."""

    samples: pd.DataFrame
    grid: dict
    detail: dict
    inputs: list
    evidence: list
    mountings: dict
    model: "WalkOffModel" = field(repr=False)

    @property
    def weights(self) -> np.ndarray:
        return self.samples["weight"].to_numpy()

    @property
    def _evidence(self) -> dict:
        return {e.joint: e for e in self.evidence}

    @property
    def effective_samples(self) -> float:
        w = self.weights
        return float(w.sum() ** 2 / np.sum(w ** 2)) if w.sum() > 0 else 0.0

    def _mounting_share(self, joint: str, mounting: str) -> np.ndarray:
        """P(mounting | sample) of ``joint`` per sample."""
        total = sum(self.detail[(joint, m)][0] for m in self.mountings[joint])
        return np.where(total > 0, self.detail[(joint, mounting)][0] / np.where(total > 0, total, 1.0), 0.0)

    def _pivot_mixture(self, joint: str):
        """(shifts [um], weights) of the posterior of ``joint``'s interference shift, resolved within each grid
        segment (:func:`_within_segments`)."""
        x = self.grid[joint]
        evidence = self._evidence.get(joint)
        values, weights = [], []
        for m in self.mountings[joint]:
            masses, probs = self.detail[(joint, m)][1], self.detail[(joint, m)][3]
            share = self.weights * self._mounting_share(joint, m)
            for i in np.flatnonzero(share > 0):
                total = masses[i].sum()
                if total <= 0:
                    continue
                xs, w = _within_segments(evidence, x, probs[i])
                values.append(xs.ravel())
                weights.append((share[i] * (masses[i] / total)[:, None] * w).ravel())
        if not values:
            return np.array([np.nan]), np.array([1.0])
        return np.concatenate(values), np.concatenate(weights)

    def _consistent_segments(self, joint: str) -> list:
        """(mounting, lower, upper shift) of each grid segment of ``joint`` inside the consistent region."""
        best = float(self.samples["profile_log_likelihood"].max())
        own = self.samples[f"{joint}.profile_log_likelihood"].to_numpy()
        rest = self.samples["profile_log_likelihood"].to_numpy() - own
        x, out = self.grid.get(joint), []
        for m in self.mountings[joint]:
            peak = self.detail[(joint, m)][2]
            ok = (rest[:, None] + peak) >= best + math.log(CONSISTENT_LIKELIHOOD_RATIO)
            for i, s in zip(*np.nonzero(ok)):
                out.append((m, float(x[s]), float(x[s + 1])) if x is not None else (m, math.nan, math.nan))
        return out

    def consistent(self) -> pd.DataFrame:
        """The prior samples consistent with the field (profile likelihood ratio at or above
        :data:`CONSISTENT_LIKELIHOOD_RATIO`)."""
        return self.samples[self.samples["likelihood_ratio"] >= CONSISTENT_LIKELIHOOD_RATIO]

    def input_summary(self, u: UncertainInput) -> dict:
        """``prior``, ``nominal``, ``posterior`` (weighted median, 5 and 95 % quantiles) and ``consistent_range`` of
        one input."""
        joint = u.name.split(".")[0]
        if u.name.endswith(".interference_shift_um") and joint in self.grid:
            x, w = self._pivot_mixture(joint)
            seg = self._consistent_segments(joint)
            cons = [min(a for _, a, _ in seg), max(b for _, _, b in seg)] if seg else [float("nan")] * 2
        else:
            x, w = self.samples[u.name].to_numpy(), self.weights
            c = self.consistent()[u.name]
            cons = [float(c.min()), float(c.max())]
        return {"prior": [u.low, u.high], "prior_scale": u.scale, "nominal": u.nominal, "unit": u.unit,
                "source": u.source, "posterior": dict(zip(("median", "q05", "q95"),
                                                          _weighted_quantiles(x, w, (0.5, 0.05, 0.95)))),
                "consistent_range": cons}

    def mounting_summary(self, joint: str) -> dict:
        options = self.mountings[joint]
        post = {m: float(np.sum(self.weights * self._mounting_share(joint, m))) for m in options}
        total = sum(post.values()) or 1.0
        return {"prior": {m: 1.0 / len(options) for m in options},
                "posterior": {m: v / total for m, v in post.items()},
                "consistent": sorted({m for m, _, _ in self._consistent_segments(joint)})}

    def capacity_summary(self) -> dict:
        """Per joint whose shift is calibrated: the median engine's fit capacity [N] at the lowest speed band
        (:meth:`WalkOffModel.median_capacity_N`) with the data's inputs (``nominal``), the calibrated ones
        (``calibrated``) and at the ends of the shift's consistent range (the other inputs calibrated)."""
        cal = self.calibrated_inputs()
        out = {}
        for j in self.grid:
            name = f"{j}.interference_shift_um"
            lo, hi = self.input_summary(next(u for u in self.inputs if u.name == name))["consistent_range"]
            out[j] = {"nominal": self.model.median_capacity_N(j, {u.name: u.nominal for u in self.inputs}),
                      "calibrated": self.model.median_capacity_N(j, cal),
                      "consistent_range": [self.model.median_capacity_N(j, {**cal, name: v}) if math.isfinite(v)
                                           else float("nan") for v in (lo, hi)]}
        return out

    def calibrated_inputs(self) -> dict:
        """The calibrated inputs: each input's posterior median, each joint's most probable mounting."""
        out = {u.name: self.input_summary(u)["posterior"]["median"] for u in self.inputs}
        for j in self.mountings:
            post = self.mounting_summary(j)["posterior"]
            out[f"{j}.mounting"] = max(post, key=post.get)
        return out

    def predict(self, joint: str, label: str | None = None, model: "WalkOffModel | None" = None,
                theta_offsets: dict | None = None) -> dict:
        """Posterior predictive walk-off probability of ``joint``: its weighted mean and 5/95 % quantiles over
        the posterior (samples x mountings x points within the shift's grid segments, :func:`_within_segments`;
        the probability log-linear between the grid values), on ``model`` (default the calibration's) with
        ``label``'s creep map for an as-modelled shoulder (a variant); ``theta_offsets`` are added to the inputs
        (e.g. a stronger fit: ``{"cam.interference_shift_um": 25}``). On a model without the joint's flipped copy
        (a train without thrust) a flipped mounting reads the as-modelled map; a retained gear never walks off."""
        model = model or self.model
        offsets = dict(theta_offsets or {})
        w = self.weights
        keep = np.flatnonzero(w >= 1e-9 * w.max())
        x = self.grid.get(joint)
        columns = {u.name: self.samples[u.name].to_numpy(dtype=float) for u in self.inputs
                   if u.name in self.samples}
        values, weights = [], []
        for m in self.mountings[joint]:
            share = w * self._mounting_share(joint, m)
            for i in keep:
                if share[i] <= 0:
                    continue
                if m == "retained":
                    values.append(np.zeros(1))
                    weights.append(np.array([share[i]]))
                    continue
                theta = {name: float(column[i]) for name, column in columns.items()}
                for k, v in offsets.items():
                    theta[k] = theta.get(k, 0.0) + float(v)
                side = m if (m == "as_modelled" or model.flippable.get(joint)) else "as_modelled"
                if x is None:
                    values.append(np.array([model.probability(joint, theta, side, label=label)[0]]))
                    weights.append(np.array([share[i]]))
                    continue
                reuse = model is self.model and label is None and not offsets
                own = self.detail[(joint, m)][3][i]
                p = own if reuse else model.probability_over_shifts(
                    joint, theta, x + offsets.get(f"{joint}.interference_shift_um", 0.0), side, label=label)
                masses = self.detail[(joint, m)][1][i]
                if masses.sum() <= 0:
                    continue
                _, within = _within_segments(self._evidence.get(joint), x, own)
                t = (np.arange(SUBPOINTS) + 0.5) / SUBPOINTS
                v = np.exp(_log_linear(x, p, t)).ravel()
                values.append(np.where(v < 1e-250, 0.0, v))      # the floor of log(0): a probability of 0
                weights.append((share[i] * (masses / masses.sum())[:, None] * within).ravel())
        if not values:
            return {"walk_off_probability": 0.0, "interval_90": [0.0, 0.0]}
        v, wt = np.concatenate(values), np.concatenate(weights)
        wt = wt / wt.sum()
        return {"walk_off_probability": float(np.sum(wt * v)),
                "interval_90": _weighted_quantiles(v, wt, (0.05, 0.95))}

    def rules_out(self) -> list[str]:
        """What the field evidence rules out, in words: each mounting whose posterior probability is below 1 %, and
        every input whose consistent range is at most 80 % of its prior range."""
        out = []
        words = {"as_modelled": "held by its press fit with the helical thrust pushing it off the shaft nose",
                 "flipped": "held by its press fit with its shoulder on the other side",
                 "retained": "axially retained"}
        for j in self.mountings:
            summary = self.mounting_summary(j)
            for m, p in summary["posterior"].items():
                if p < 0.01 and len(summary["posterior"]) > 1:
                    out.append(f"{j} gear {words[m]} (posterior probability {p:.2g})")
        for u in self.inputs:
            r = self.input_summary(u)
            lo, hi = r["consistent_range"]
            if not (math.isfinite(lo) and math.isfinite(hi)):
                continue
            span = (math.log(max(hi, 1e-300) / max(lo, 1e-300)) / math.log(u.high / u.low)) if u.scale == "log" \
                else (hi - lo) / (u.high - u.low)
            if span <= 0.8:
                text = f"{u.name} outside {lo:.3g}..{hi:.3g} {u.unit} (prior {u.low:g}..{u.high:g})"
                joint = u.name.split(".")[0]
                if u.name.endswith(".interference_shift_um") and joint in self.grid:
                    c_lo, c_hi = self.capacity_summary()[joint]["consistent_range"]
                    speed = min(self.model.bands.values())
                    text += (f": a median {joint} fit capacity outside {c_lo:.3g}..{c_hi:.3g} N at {speed:g} rpm "
                             f"(the data's fit: {self.model.median_capacity_N(joint, {}):.3g} N)")
                out.append(text)
        return out

    def to_json(self) -> dict:
        """``field`` (the evidence), ``inputs`` (per input: ``prior``, ``nominal``, ``posterior``,
        ``consistent_range``, ``unit``, ``source``), ``mounting`` per joint (prior and posterior probability of each
        of :data:`MOUNTINGS` it may have, the consistent ones), ``rules_out``, ``predicted`` (posterior predictive
        probability per joint of the model), ``calibrated_inputs``, ``effective_samples``, ``prior_samples`` and
        ``method``."""
        return {"field": [{"joint": e.joint, "failures": e.failures, "fleet_size": e.fleet_size,
                           "period_months": e.period_months, "rate": e.rate, "source": e.source}
                          for e in self.evidence],
                "inputs": {u.name: self.input_summary(u) for u in self.inputs},
                "mounting": {j: self.mounting_summary(j) for j in self.mountings},
                "rules_out": self.rules_out(),
                "predicted": {j: self.predict(j) for j in self.model.joints},
                "calibrated_inputs": self.calibrated_inputs(),
                "median_capacity_N": self.capacity_summary(),
                "effective_samples": self.effective_samples, "prior_samples": int(len(self.samples)),
                "max_log_likelihood": float(self.samples["log_likelihood"].max()),
                "method": ("the binomial (Poisson) likelihood of the field counts; each joint's interference shift "
                           "and mounting marginalised exactly on a grid, the other inputs by importance sampling of "
                           "the prior (scrambled Sobol'); consistent range: profile likelihood ratio >= "
                           f"{CONSISTENT_LIKELIHOOD_RATIO:.3f} to the best (Wilks, 95 %)"),
                "not_calibrated": {"key_clearance_um": "held at the data's estimate: each value needs its own "
                                   "dynamics runs (the creep maps), not a re-weighting"}}


def _weighted_quantiles(x, w, qs) -> list[float]:
    """The weighted quantiles ``qs`` of the values ``x`` with weights ``w`` (the first value whose cumulative
    weight reaches q of the total; NaN without weight), from one sort."""
    x, w = np.asarray(x, dtype=float), np.asarray(w, dtype=float)
    order = np.argsort(x)
    cw = np.cumsum(w[order])
    if len(x) == 0 or cw[-1] <= 0:
        return [float("nan")] * len(qs)
    ordered = x[order]
    return [float(ordered[min(np.searchsorted(cw, q * cw[-1]), len(x) - 1)]) for q in qs]


def calibrate_walk_off(model: "WalkOffModel", evidence, inputs=None, *, prior_samples: int = 256,
                       pivot_points: int = 25, mountings: dict | None = None, seed: int = 0) -> Calibration:
    """Calibrate the uncertain ``inputs`` (default :func:`default_uncertain_inputs` of the model's joints) of
    ``model`` against ``evidence`` (a sequence of :class:`FieldEvidence`, each joint a joint of the model).

    Each joint's ``<joint>.interference_shift_um`` (when an input) and mounting (``mountings`` {joint: options of
    :data:`MOUNTINGS`}, default :func:`joint_mountings`; each option equally likely a priori) are marginalised
    exactly: the probability on ``pivot_points`` shifts over the prior range, log-linear between them, the
    Poisson likelihood integrated in closed form per segment. The other inputs are ``prior_samples`` (a power of
    two) scrambled-Sobol' prior samples, weighted by the marginal likelihood."""
    evidence = list(evidence)
    if not evidence:
        raise GearoptInputError("evidence is empty: at least one joint's field count is needed")
    for e in evidence:
        if e.joint not in model.joints:
            raise GearoptInputError(f"evidence joint {e.joint!r} is not a joint of the model {model.joints}")
    check_range("prior_samples", prior_samples, 2, 2 ** 16)
    if prior_samples & (prior_samples - 1):
        raise GearoptInputError(f"prior_samples={prior_samples} must be a power of two (a balanced Sobol' set)")
    check_range("pivot_points", pivot_points, 3, 1000)
    inputs = list(default_uncertain_inputs(model.joints) if inputs is None else inputs)
    names = [u.name for u in inputs]
    if len(set(names)) != len(names):
        raise GearoptInputError(f"uncertain inputs {names} repeat a name")
    options = {j: tuple(mountings[j]) if mountings and j in mountings else
               joint_mountings(model.system, j, model) for j in model.joints}
    for j, opts in options.items():
        bad = set(opts) - set(MOUNTINGS)
        if bad or not opts:
            raise GearoptInputError(f"mountings of {j!r} {opts} must be a non-empty subset of {MOUNTINGS}")
    pivots = {j: next(u for u in inputs if u.name == f"{j}.interference_shift_um") for j in model.joints
              if f"{j}.interference_shift_um" in names}
    grid = {j: np.linspace(u.low, u.high, pivot_points) for j, u in pivots.items()}
    sampled = [u for u in inputs if u.name.split(".")[0] not in pivots or
               not u.name.endswith(".interference_shift_um")]
    from scipy.stats import qmc   # imported here, not by `import gearopt.studies` (as in design.scene_search)

    unit = qmc.Sobol(max(len(sampled), 1), scramble=True, seed=seed).random(prior_samples)
    thetas = [{u.name: float(u.from_unit(unit[i, k])) for k, u in enumerate(sampled)} for i in range(prior_samples)]
    counts = {e.joint: e for e in evidence}
    n = len(thetas)
    detail, joint_log, joint_profile = {}, {}, {}
    for j in model.joints:
        e = counts.get(j)
        per_mounting, profiles = [], []
        for m in options[j]:
            prior = 1.0 / len(options[j])
            marg, mass, peak = np.zeros(n), None, None
            probs = None
            if j in grid:
                g = len(grid[j])
                mass, peak, probs = np.zeros((n, g - 1)), np.zeros((n, g - 1)), np.zeros((n, g))
            for i, theta in enumerate(thetas):
                if _infeasible_damper(theta):
                    marg[i] = 0.0
                    if peak is not None:
                        peak[i] = -np.inf
                    continue
                if j in grid:
                    p = np.zeros(len(grid[j])) if m == "retained" else model.probability_over_shifts(
                        j, theta, grid[j], m)
                    probs[i] = p
                    if e is None:
                        mass[i] = np.diff(grid[j])
                        peak[i] = 0.0
                    else:
                        mass[i], peak[i] = _segment_masses(e.failures, e.fleet_size, grid[j], p)
                    marg[i] = mass[i].sum() / (grid[j][-1] - grid[j][0])
                else:
                    p = 0.0 if m == "retained" else model.probability(j, theta, m)[0]
                    log_l = 0.0 if e is None else float(_poisson_log_likelihood(e.failures, e.fleet_size * p))
                    marg[i] = math.exp(log_l)
                    peak = np.full((n, 1), -np.inf) if peak is None else peak
                    peak[i, 0] = log_l
            detail[(j, m)] = (prior * marg, mass, peak, probs)
            per_mounting.append(prior * marg)
            profiles.append(peak.max(axis=1))
        joint_log[j] = np.log(np.maximum(np.sum(per_mounting, axis=0), 1e-300))
        joint_profile[j] = np.max(profiles, axis=0)
    table = pd.DataFrame(thetas)
    table["log_likelihood"] = sum(joint_log.values())
    for j in model.joints:
        table[f"{j}.profile_log_likelihood"] = joint_profile[j]
    table["profile_log_likelihood"] = sum(joint_profile.values())
    best = table["profile_log_likelihood"].max()
    if not np.isfinite(best) or not np.isfinite(table["log_likelihood"].max()):
        raise GearoptInputError("no prior sample gives the field counts a finite likelihood: widen the priors")
    table["likelihood_ratio"] = np.exp(table["profile_log_likelihood"] - best)
    w = np.exp(table["log_likelihood"] - table["log_likelihood"].max())
    if w.sum() <= 0:
        raise GearoptInputError("every prior sample has zero likelihood: widen the priors")
    table["weight"] = w / w.sum()
    return Calibration(table, grid, detail, inputs, evidence, options, model)


def calibrated_system(system: System, calibrated_inputs: dict) -> System:
    """``system`` with the calibrated joint inputs: each joint's ISO 286 interference (nominal, minimum, maximum)
    shifted by its ``<joint>.interference_shift_um`` and, when calibrated, every such press fit's friction
    coefficient set to ``friction_coefficient_mean``. The other calibrated inputs (duty, damper shares,
    distance, mounting) are not data of the joint capacity models."""
    system = system_of(system, "calibrated_system")
    changes = {}
    for name, value in calibrated_inputs.items():
        joint, _, key = name.partition(".")
        if key != "interference_shift_um" or not math.isfinite(float(value)):
            continue
        j = joint_record(system, joint, "calibrated_system").entries
        if j.get("joint_type") != "press_fit":
            continue
        changes[joint] = {k: float(j[k]) + float(value) for k in ("diametral_interference_um",
                                                                  "diametral_interference_min_um",
                                                                  "diametral_interference_max_um")}
        if "friction_coefficient_mean" in calibrated_inputs:
            changes[joint]["friction_coefficient"] = float(calibrated_inputs["friction_coefficient_mean"])
    return system.with_joint_entries(changes, note="calibrated to the field record") if changes else system


def recheck_on_calibrated_inputs(system: System, design, check, calibrated_inputs: dict, *, dynamic=None,
                                 contact_meshes=None, groups=("joints", "dynamics")) -> pd.DataFrame:
    """The rows of ``check`` (a :class:`~gearopt.design.requirements.RequirementsCheck` of ``design`` on
    ``system``) judged again on :func:`calibrated_system` (``groups`` of
    :func:`~gearopt.design.requirements.evaluate_requirements`; ``dynamic`` the design's dynamic peaks, given a
    function of the design and the system, or peaks). One row per requirement of ``check``: ``requirement``,
    ``value_estimates``, ``verdict_estimates``, ``value_calibrated``, ``verdict_calibrated`` and ``status``:
    ``"FAIL remains"``, ``"FAIL was an artefact of the estimates"``, ``"new FAIL"``, ``"PASS"`` or ``"not affected"``
    (a row outside ``groups``: it does not depend on the calibrated inputs)."""
    from ..design.requirements import evaluate_requirements
    cal = calibrated_system(system, calibrated_inputs)
    peaks = dynamic(design, cal) if callable(dynamic) else dynamic
    again = evaluate_requirements(cal, design, contact_meshes=contact_meshes, dynamic=peaks, groups=groups)
    by_key = {(r.quantity, r.target, r.name): r for r in again.rows}
    rows = []
    for r in check.rows:
        new = by_key.get((r.quantity, r.target, r.name))
        if new is None:
            status = ("FAIL remains (not affected by the calibrated inputs)" if r.verdict == "FAIL"
                      else "not affected")
        elif r.verdict == "FAIL":
            status = "FAIL remains" if new.verdict == "FAIL" else "FAIL was an artefact of the estimates"
        else:
            status = "new FAIL" if new.verdict == "FAIL" else "PASS"
        rows.append({"requirement": r.name, "worst_case": r.worst_case, "unit": r.unit, "sense": r.sense,
                     "limit": r.limit, "value_estimates": r.value, "verdict_estimates": r.verdict,
                     "value_calibrated": new.value if new is not None else r.value,
                     "worst_case_calibrated": new.worst_case if new is not None else r.worst_case,
                     "verdict_calibrated": new.verdict if new is not None else r.verdict, "status": status})
    return pd.DataFrame(rows)


def _infeasible_damper(theta: dict) -> bool:
    return theta.get("damper_degraded_probability", 0.0) + theta.get("damper_seized_probability", 0.0) > 1.0


__all__ = ["FieldEvidence", "FieldRecord", "field_record", "UncertainInput", "WalkOffModel", "Calibration",
           "calibrate_walk_off", "default_uncertain_inputs", "calibrated_system", "recheck_on_calibrated_inputs", "damper_weights", "joint_mountings",
           "CONSISTENT_LIKELIHOOD_RATIO", "MOUNTINGS", "SHOULDER_SIDES", "FLIPPED_PREFIX"]
