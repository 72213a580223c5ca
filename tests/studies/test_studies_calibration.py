"""The walk-off calibration (gearopt.studies.calibration): its probability estimator against the plain Monte Carlo
of gearopt.studies.failure (an independent code path: categorical damper states, sampled hours), the recovery of
known inputs from counts the model itself generated (issue 30's validation), the field record of the packaged data
and the errors. The creep maps here are synthetic (an analytic creep that falls to zero with the fit's capacity),
so no dynamics run: the calibration only re-weights, whatever made the maps."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from gearopt.data import load_default_data, system_from_data
from gearopt.dynamics.walk_off_envelope import envelope_speeds_rpm, fit_cases
from gearopt.errors import GearoptInputError, MissingSectionError
from gearopt.studies.calibration import (FLIPPED_PREFIX, FieldEvidence, UncertainInput, WalkOffModel,
                                         calibrate_walk_off, default_uncertain_inputs, field_record)
from gearopt.studies.failure import walk_off_probability

SYSTEM = system_from_data(load_default_data())
RECORD = field_record(SYSTEM)
STATES = ("nominal", "degraded", "seized")


def synthetic_envelope(creep_scale: dict, flipped_scale: dict | None = None) -> pd.DataFrame:
    """Creep maps per joint label: creep [um/cycle] = scale x speed factor (0 up to 2900 rpm, 1 at 3300) x damper
    factor x
    max(0, 1 - ln(C / C_weak) / ln(C_nominal / C_weak)) -- creeping at the weakest fit, zero from the nominal fit
    up -- on 8 capacities from a quarter of the weakest to the strongest fit."""
    rows = []
    damper = {"nominal": 0.2, "degraded": 1.0, "seized": 2.0}
    labels = {j: (j, k) for j, k in creep_scale.items()}
    labels.update({FLIPPED_PREFIX + j: (j, k) for j, k in (flipped_scale or {}).items()})
    for band, (speed, _) in envelope_speeds_rpm(SYSTEM).items():
        for label, (joint, k) in labels.items():
            cases = fit_cases(SYSTEM, joint, speed)
            weak, nominal = max(cases["weakest"], 1.0), cases["nominal"]
            for state in STATES:
                for i, c in enumerate(np.geomspace(0.25 * weak, cases["strongest"], 8)):
                    creep = k * max(0.0, (speed - 2900.0) / 400.0) * damper[state] * max(
                        0.0, 1.0 - np.log(c / weak) / np.log(nominal / weak))
                    rows.append({"joint": label, "speed_rpm": speed, "damper_state": state, "level": i,
                                 "capacity_N": c, "axial_creep_um_per_cycle": creep})
    return pd.DataFrame(rows)


def test_estimator_agrees_with_plain_monte_carlo():
    """At the data's inputs, the conditional estimator (damper states summed, one band's hours in closed form,
    4 000 engines) gives the probability of gearopt.studies.failure.walk_off_probability's plain sampling (400 000
    engines) within 4 standard errors of the plain estimate plus 10 %."""
    env = synthetic_envelope({"cam": 0.05})
    model = WalkOffModel(env, SYSTEM, ["cam"], exposure_hours=RECORD.exposure_hours, samples=4000)
    p_model, _ = model.probability("cam", RECORD.nominal_theta())
    plain = walk_off_probability(env.assign(fit_case=""), SYSTEM, "cam", samples=400_000, seed=3,
                                 distance_mm=RECORD.walk_off_distance_mm,
                                 damper_probabilities=RECORD.damper_probabilities,
                                 exposure_hours=RECORD.exposure_hours)["walk_off_probability"]
    se = np.sqrt(plain * (1 - plain) / 400_000)
    assert 1e-4 < plain < 0.2                               # a probability the plain sampling resolves
    assert abs(p_model - plain) <= 4 * se + 0.1 * plain


def test_estimator_resolves_small_probabilities_smoothly():
    """Common random numbers: the probability falls monotonically as the fit gets stronger, and resolves values far
    below 1/samples (where plain sampling would return 0)."""
    env = synthetic_envelope({"cam": 0.05})
    model = WalkOffModel(env, SYSTEM, ["cam"], exposure_hours=RECORD.exposure_hours, samples=1000)
    p = [model.probability("cam", {**RECORD.nominal_theta(), "cam.interference_shift_um": s})[0]
         for s in (0.0, 10.0, 20.0, 30.0)]
    assert all(a >= b for a, b in zip(p, p[1:])) and p[0] > p[-1]
    assert 0.0 < min(p[:3])
    assert min(x for x in p if x > 0) < 1.0 / 1000


def test_calibration_recovers_known_inputs_from_synthetic_counts():
    """Issue 30's validation: counts drawn from the model at known inputs (cam fit 10 um weaker than the data,
    overspeed hours x3, the crank's shoulder flipped so its thrust cannot walk it off) are calibrated back: the true
    shift and exposure lie in the consistent ranges, the flipped crank side is the probable one, and the predicted
    probabilities bracket the true ones."""
    env = synthetic_envelope({"cam": 0.05, "crank": 0.5}, {"crank": 0.0})
    model = WalkOffModel(env, SYSTEM, ["cam", "crank"], exposure_hours=RECORD.exposure_hours, samples=1000)
    truth = {**RECORD.nominal_theta(), "cam.interference_shift_um": -10.0, "crank.interference_shift_um": 0.0,
             "overspeed_exposure_scale": 3.0, "friction_coefficient_mean": 0.12, "smoothing_factor_mean": 0.6,
             "running_exposure_scale": 1.0}
    p_cam = model.probability("cam", truth)[0]
    p_crank_modelled = model.probability("crank", truth)[0]
    p_crank = model.probability("crank", truth, "flipped")[0]
    assert p_crank == 0.0 and p_crank_modelled > 1e-3 and 1e-4 < p_cam < 0.1
    fleet = 200_000
    rng = np.random.default_rng(11)
    evidence = [FieldEvidence("cam", int(rng.binomial(fleet, p_cam)), fleet, 24.0),
                FieldEvidence("crank", int(rng.binomial(fleet, p_crank)), fleet, 24.0)]
    inputs = [u for u in default_uncertain_inputs(["cam", "crank"], RECORD)
              if u.name in ("cam.interference_shift_um", "overspeed_exposure_scale")]
    cal = calibrate_walk_off(model, evidence, inputs, prior_samples=256, seed=1)
    out = cal.to_json()
    for name in ("cam.interference_shift_um", "overspeed_exposure_scale"):
        lo, hi = out["inputs"][name]["consistent_range"]
        assert lo <= truth[name] <= hi, (name, lo, hi)
        prior = out["inputs"][name]["prior"]
        assert (lo, hi) != tuple(prior)
    assert out["mounting"]["crank"]["posterior"]["as_modelled"] < 0.01
    assert "as_modelled" not in out["mounting"]["crank"]["consistent"]
    pred = out["predicted"]["cam"]
    assert pred["interval_90"][0] <= p_cam * 1.3 and pred["interval_90"][1] >= p_cam / 1.3
    assert 0.5 < pred["walk_off_probability"] / p_cam < 2.0
    assert out["predicted"]["crank"]["walk_off_probability"] < 1e-5
    assert any(r.startswith("crank") and "off the shaft nose" in r for r in out["rules_out"])


def test_field_record_of_the_packaged_data():
    """The source study's record (thesis sec. 1): 213 cam walk-offs of 247 853 engines in 24 months, no crank."""
    got = {e.joint: (e.failures, e.fleet_size) for e in RECORD.evidence}
    assert got["cam"] == (213, 247853) and got["crank"] == (0, 247853)
    assert abs(RECORD.evidence[0].period_months - 24.0) < 1e-12
    assert set(RECORD.exposure_hours) == set(envelope_speeds_rpm(SYSTEM))
    assert "[T]" in [e for e in RECORD.evidence if e.joint == "cam"][0].source


def test_missing_field_record_names_the_section():
    from gearopt.data import default_data_path, load_system
    minimal = load_system(default_data_path().parent / "minimal_train.toml")
    with pytest.raises(MissingSectionError, match="field_record"):
        field_record(minimal)


def test_bad_input_is_named():
    env = synthetic_envelope({"cam": 0.05})
    model = WalkOffModel(env, SYSTEM, ["cam"], exposure_hours=RECORD.exposure_hours, samples=64)
    with pytest.raises(GearoptInputError, match="failures"):
        FieldEvidence("cam", 10, 5, 24.0)
    with pytest.raises(GearoptInputError, match="not a joint of the model"):
        calibrate_walk_off(model, [FieldEvidence("fp", 1, 100, 24.0)])
    with pytest.raises(GearoptInputError, match="power of two"):
        calibrate_walk_off(model, [FieldEvidence("cam", 1, 100, 24.0)], prior_samples=100)
    with pytest.raises(GearoptInputError, match="crank"):
        WalkOffModel(env, SYSTEM, ["cam", "crank"], exposure_hours=RECORD.exposure_hours)
    with pytest.raises(GearoptInputError, match="exposure_hours has no band"):
        WalkOffModel(env, SYSTEM, ["cam"], exposure_hours={"rated": (1.0, 1.0)})
    with pytest.raises(GearoptInputError, match="shoulder_flipped:cam"):
        model.probability("cam", {}, "flipped")
    with pytest.raises(GearoptInputError, match="high of 'x'"):
        UncertainInput("x", 1.0, 0.5, 0.7)


def test_any_train_its_own_joint_bands_and_names(tmp_path):
    """Any train: the packaged minimal pair (no engine) with its joint renamed, the user's own speed bands and
    exposure, creep maps from the user's own source: the calibration runs on the user's names only and a larger
    failure count asks for a weaker fit."""
    import re
    from gearopt.data import default_data_path, load_system
    text = (default_data_path().parent / "minimal_train.toml").read_text(encoding="utf-8")
    path = tmp_path / "renamed.toml"
    path.write_text(re.sub(r"\bpinion\b", "sun_gear", text), encoding="utf-8")
    system = load_system(path)
    bands = {"running": 1500.0, "overspeed": 1800.0}
    rows = []
    for band, speed in bands.items():
        cases = fit_cases(system, "sun_gear", speed)
        weak, nominal = cases["weakest"], cases["nominal"]
        for i, c in enumerate(np.geomspace(0.25 * weak, cases["strongest"], 8)):
            creep = (0.02 if band == "overspeed" else 0.0) * max(0.0, 1.0 - np.log(c / weak) / np.log(nominal / weak))
            rows.append({"joint": "sun_gear", "speed_rpm": speed, "damper_state": "none", "capacity_N": c,
                         "axial_creep_um_per_cycle": creep})
    model = WalkOffModel(pd.DataFrame(rows), system, ["sun_gear"], speed_bands_rpm=bands,
                         exposure_hours={"running": (2000.0, 0.5), "overspeed": (5.0, 1.0)}, samples=500)
    inputs = [UncertainInput("sun_gear.interference_shift_um", -20.0, 20.0, 0.0, "um"),
              UncertainInput("overspeed_exposure_scale", 0.3, 3.0, 1.0, scale="log")]
    medians = []
    for failures in (5, 500):
        cal = calibrate_walk_off(model, [FieldEvidence("sun_gear", failures, 100_000, 12.0)], inputs,
                                 prior_samples=64, mountings={"sun_gear": ("as_modelled",)})
        out = cal.to_json()
        assert set(out["inputs"]) == {"sun_gear.interference_shift_um", "overspeed_exposure_scale"}
        assert "pinion" not in str(out)
        medians.append(out["inputs"]["sun_gear.interference_shift_um"]["posterior"]["median"])
        assert 0.3 < out["predicted"]["sun_gear"]["walk_off_probability"] / (failures / 100_000) < 3.0
    assert medians[1] < medians[0]


def test_predict_agrees_with_the_closed_form_within_each_segment():
    """The posterior predictive probability resolves each grid segment of the shift: against the likelihood-weighted
    mean of a log-linear probability under a Poisson likelihood in closed form (ratio of regularised incomplete
    gamma differences of orders k + 1 and k: E[lambda] over the segment), within 2 % -- also on a grid so coarse
    that the probability changes by a large factor across each segment (averaging a segment's two ends was +27 %
    at 25 points on the field record, benchmarks/bench_calibration.py)."""
    from scipy import special
    env = synthetic_envelope({"cam": 0.05})
    model = WalkOffModel(env, SYSTEM, ["cam"], exposure_hours=RECORD.exposure_hours, samples=500)
    inputs = [UncertainInput("cam.interference_shift_um", -20.0, 60.0, 0.0, "um"),
              UncertainInput("overspeed_exposure_scale", 0.3, 3.0, 1.0, scale="log")]
    k, n = 40, 100_000
    cal = calibrate_walk_off(model, [FieldEvidence("cam", k, n, 24.0)], inputs, prior_samples=32, pivot_points=9,
                             mountings={"cam": ("as_modelled",)})
    _, masses, _, probs = cal.detail[("cam", "as_modelled")]
    w = cal.weights
    total, norm = 0.0, 0.0
    for i in np.flatnonzero(w > 0):
        lam = n * np.maximum(probs[i], 1e-300)
        da, db = special.gammainc(k + 1, lam), special.gammainc(k, lam)
        den = np.abs(np.diff(db))                                      # E[lambda] = k dP(k+1) / dP(k)
        mean = np.where(den > 0, k * np.abs(np.diff(da)) / np.where(den > 0, den, 1.0), 0.5 * (lam[1:] + lam[:-1]))
        share = masses[i] / masses[i].sum()
        total += w[i] * float(np.sum(share * mean / n))
        norm += w[i]
    closed = total / norm
    got = cal.predict("cam")["walk_off_probability"]
    assert abs(got / closed - 1.0) < 0.02, (got, closed)
    assert abs(closed / (k / n) - 1.0) < 0.5          # and both near the observed rate the likelihood centres on


def test_a_train_without_creep_predicts_exactly_zero():
    """A creep map of zeros (a spur train: no thrust) gives a posterior predictive probability of exactly 0, not
    the floor of a logarithm."""
    env = synthetic_envelope({"cam": 0.05})
    model = WalkOffModel(env, SYSTEM, ["cam"], exposure_hours=RECORD.exposure_hours, samples=200)
    inputs = [UncertainInput("cam.interference_shift_um", -20.0, 60.0, 0.0, "um")]
    cal = calibrate_walk_off(model, [FieldEvidence("cam", 40, 100_000, 24.0)], inputs, prior_samples=8,
                             pivot_points=9, mountings={"cam": ("as_modelled",)})
    spur = WalkOffModel(env.assign(axial_creep_um_per_cycle=0.0), SYSTEM, ["cam"],
                        exposure_hours=RECORD.exposure_hours, samples=200)
    assert cal.predict("cam", model=spur) == {"walk_off_probability": 0.0, "interval_90": [0.0, 0.0]}


def test_skipping_creep_free_engines_changes_no_probability():
    """The estimator computes only the engines whose fit creeps at some speed band; the others walk off with
    probability exactly 0. Against the plain computation over every engine (each band's creep interpolated on its
    map, the conditional probability per engine, averaged), on creep maps whose creep stops inside the grid, at
    the last grid point and never: the same probabilities to the last bit, over a grid of shifts."""
    from gearopt.studies.calibration import _conditional_walk_off, damper_weights
    env = synthetic_envelope({"cam": 0.05})
    last = env["capacity_N"] == env.groupby(["joint", "speed_rpm", "damper_state"])["capacity_N"].transform("max")
    env.loc[last & (env["damper_state"] == "seized") & (env["speed_rpm"] == env["speed_rpm"].max()),
            "axial_creep_um_per_cycle"] = 0.02                       # creeps at the strongest fit: every engine live
    env.loc[env["damper_state"] == "nominal", "axial_creep_um_per_cycle"] = 0.0    # a state that never creeps
    model = WalkOffModel(env, SYSTEM, ["cam"], exposure_hours=RECORD.exposure_hours, samples=400, seed=5)
    theta = {**RECORD.nominal_theta(), "friction_coefficient_mean": 0.09}
    shifts = np.linspace(-20.0, 60.0, 7)
    got, by_state = model._probabilities("cam", theta, "as_modelled", None, shifts)

    caps = {b: np.atleast_2d(model.capacities_N("cam", b, theta, shifts)) for b in model.bands}
    medians = np.array([model.exposure[b][0] * theta.get("overspeed_exposure_scale" if "overspeed" in b else
                                                         "running_exposure_scale", 1.0) for b in model.bands])
    sigmas = np.array([model.exposure[b][1] for b in model.bands])
    hours = medians[:, None] * np.exp(sigmas[:, None] * model._z_hours())
    plain = {}
    for state in model.states:
        rates = np.array([np.maximum(np.interp(np.log(caps[b]), *model.tables[("cam", speed, state)]), 0.0)
                          * speed * 30.0 * 1e-3 for b, speed in model.bands.items()])
        plain[state] = _conditional_walk_off(rates, medians, sigmas, hours, theta["walk_off_distance_mm"]).mean(
            axis=-1)
    weights = damper_weights(theta, model.states)
    assert set(by_state) == set(plain)
    for state in plain:
        assert np.array_equal(by_state[state], plain[state]), state
    assert np.array_equal(got, sum(weights[s] * plain[s] for s in model.states))
    assert np.all(by_state["nominal"] == 0.0) and np.all(by_state["seized"] > 0.0)
    assert 0.0 < by_state["degraded"].min() < by_state["degraded"].max()
