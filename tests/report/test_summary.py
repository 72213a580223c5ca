"""Verdict-first summary and honest contact headlines: worst cases, PASS/FAIL, units, engineering precision."""

import numpy as np
import pytest

import gearopt as go
from gearopt.design import optimise_microgeometry
from gearopt.report import contact_headlines as ch
from gearopt.cases.timing_train.summary import build_summary, eng, headlines_markdown, summary_markdown


def test_engineering_precision():
    assert [eng(v) for v in (0.19541036, 1049.5978, 4.088605, 0.0009999, "inf", float("inf"))] == \
        ["0.195", "1050", "4.09", "1.00e-03", "inf", "inf"]


def _result(crank_margin):
    joint = lambda m, y: {"spur": {"nominal": {"torque_margin": 2.0, "hub_yield_safety": y},
                                   "weakest": {"torque_margin": m}}}
    return {"joints": {"crank": joint(crank_margin, 5.0), "ac": joint(3.0, 0.83)},
            "rating": {"spur": {"crank-cam": {"S_H": 1.95, "S_F_1": 5.2, "S_F_2": 1.3}}},
            "meshes": {"spur": {"crank-cam": {"worst_case_transverse_contact_ratio": 1.54}}}}


def test_worst_instance_decides_and_every_failure_is_named():
    s = build_summary(_result(0.195))
    rows = {r["requirement"].split(" (")[0].split(",")[0]: r for r in s["requirements"]}
    slip = rows["Joint slip margin at design load"]
    assert (slip["value"], slip["worst_case"], slip["verdict"], slip["failing"]) == (0.195, "crank", "FAIL", ["crank"])
    hub = rows["Hub yield safety"]
    assert (hub["value"], hub["worst_case"], hub["verdict"]) == (0.83, "ac", "FAIL")
    root = rows["Root safety S_F"]
    assert (root["worst_case"], root["limit"], root["verdict"]) == ("crank-cam gear 2", 1.4, "FAIL")
    assert rows["Contact safety S_H"]["verdict"] == "PASS"
    assert s["verdict"] == "FAIL" and len(s["failed"]) == 3
    # stages not run are said, not silently passed
    assert any("dynamics" in x for x in s["left_out"]) and any("contact" in x for x in s["left_out"])
    text = summary_markdown(s)
    assert text.startswith("## Summary: FAIL (3 of 5 requirements fail)") and "| 0.195 | >= 1.00 |" in text
    # the limits are the caller's
    assert build_summary(_result(1.2), limits={"min_S_F": 1.2, "min_hub_yield_safety": 0.8})["verdict"] == "PASS"


def test_computed_factor_rating_decides_over_the_unit_factor_one():
    # with every ISO 6336 factor computed, that rating is the one judged (both gears' S_H), not the K = 1 table
    r = _result(2.0)
    r["rating"]["spur_computed_factors"] = {"crank-cam": {"S_H_1": 1.3, "S_H_2": 0.9, "S_F_1": 2.0, "S_F_2": 1.6}}
    rows = {x["requirement"].split(" (")[0]: x for x in build_summary(r)["requirements"]}
    assert "computed factors" in next(x["requirement"] for x in build_summary(r)["requirements"]
                                      if x["requirement"].startswith("Contact safety"))
    assert (rows["Contact safety S_H"]["value"], rows["Contact safety S_H"]["worst_case"]) == (0.9, "crank-cam gear 2")
    assert rows["Contact safety S_H"]["verdict"] == "FAIL" and rows["Root safety S_F"]["verdict"] == "PASS"


def test_ratings_at_the_dynamic_peak_torque_are_judged_too():
    # issue 17: the ratings at the loads that occur (the dynamics' peak mesh torque), beside the static rating
    r = _result(2.0)
    r["rating"]["spur_dynamic_peak"] = {"crank-cam": {"S_H_1": 1.1, "S_H_2": 1.2, "S_F_1": 1.3, "S_F_2": 2.0}}
    rows = {x["requirement"]: x for x in build_summary(r)["requirements"]}
    sh, sf = rows["Contact safety S_H at the dynamic peak torque"], rows["Root safety S_F at the dynamic peak torque"]
    assert (sh["value"], sh["worst_case"], sh["verdict"]) == (1.1, "crank-cam gear 1", "PASS")
    assert (sf["value"], sf["worst_case"], sf["verdict"]) == (1.3, "crank-cam gear 1", "FAIL")


@pytest.fixture(scope="module")
def design():
    pair = go.load_default_train("spur").pairs["crank-cam"]
    return pair, optimise_microgeometry(pair, [300.0, 150.0, 450.0], positions=20, check_positions=80,
                                        max_root_stress_MPa=500.0, min_loaded_contact_ratio=1.2)


def test_ppte_over_range_is_the_worst_exact_value(design):
    _, d = design
    rng = ch.ppte_over_range(d)
    for name, runs in d.exact.items():
        assert rng["by_design"][name]["worst_ppte_um"] == max(r.ppte_um for r in runs.values())
        assert rng["by_design"][name]["design_torque_ppte_um"] == runs[300.0].ppte_um
    worse = [t for t in d.torques_Nm if d.exact["optimised"][t].ppte_um > d.exact["unmodified"][t].ppte_um]
    assert rng["worse_than_unmodified_Nm"] == sorted(worse)


def test_margins_named_in_their_own_units(design):
    pair, d = design
    nlp = ch.nlp_constraint_margins(d.solve.constraints)
    assert set(nlp) == {"contact_stress_MPa", "loaded_contact_ratio", "root_stress_1_MPa", "root_stress_2_MPa"}
    c = d.solve.constraints
    rows = c[c["base"] == "contact_stress"]
    assert nlp["contact_stress_MPa"] == pytest.approx(
        np.min(np.sqrt(rows["upper"]) - np.sqrt(np.maximum(rows["value"], 0))))
    verified = ch.verified_margins(d)
    worst_t = max(d.exact["optimised"], key=lambda t: d.exact["optimised"][t].max_contact_stress_MPa)
    cs = verified["contact_stress_MPa"]
    assert cs["value"] == d.exact["optimised"][worst_t].max_contact_stress_MPa and cs["worst_torque_Nm"] == worst_t
    assert cs["margin"] == pytest.approx(cs["limit"] - cs["value"])
    assert verified["root_stress_1_MPa"]["limit"] == 500.0
    gap = ch.smooth_exact_gap(d)
    assert gap["exact_worst_ppte_um"] == max(r.ppte_um for r in d.exact["optimised"].values())
    assert gap["flagged"] == (gap["gap_percent"] > 2.0)
    relief = ch.tip_relief_drawing(pair, d.values)
    assert set(relief) == {"gear_1", "gear_2"}
    entry = {"ppte_over_range": ch.ppte_over_range(d), "smooth_exact_gap": gap, "tip_relief_drawing": relief,
             "verified_margins": verified}
    text = "\n".join(headlines_markdown(entry))
    assert "worst over 150-450 N m" in text and "start diameter [mm]" in text


def test_margins_over_speed_carry_their_spread_over_the_recorded_cycles():
    """A rattling backlash response: the requirement is judged on the worst cycle, and the row and its Markdown say
    how the per-cycle worst margins spread (median, best) at that worst instance."""
    entry = lambda speed, worst, median, best: {
        "speed_rpm": speed, "torque_margin": worst, "axial_margin": "inf", "cycles": 5,
        "torque_margin_cycle_worst": worst, "torque_margin_cycle_median": median, "torque_margin_cycle_best": best,
        "axial_margin_cycle_worst": "inf", "axial_margin_cycle_median": "inf", "axial_margin_cycle_best": "inf"}
    result = {"dynamics": {"joint_margins_over_speed": {
        "crank": {"spur": [entry(2500.0, 0.62, 0.70, 0.81), entry(3000.0, 0.66, 0.71, 0.75)]},
        "cam": {"spur": [entry(2500.0, 3.1, 3.3, 3.6)]}}}}
    s = build_summary(result)
    slip = next(r for r in s["requirements"] if r["requirement"].startswith("Joint slip margin over speed"))
    assert (slip["value"], slip["worst_case"], slip["verdict"]) == (0.62, "crank at 2500 rpm", "FAIL")
    assert slip["cycle_spread"] == {"cycles": 5, "worst": 0.62, "median": 0.7, "best": 0.81}
    assert "per-cycle worst over 5 cycles: median 0.700, best 0.810" in summary_markdown(s)
