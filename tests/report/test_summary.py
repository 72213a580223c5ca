"""Verdict-first summary and honest contact headlines: worst cases, PASS/FAIL, units, engineering precision."""

import math
from pathlib import Path

import numpy as np
import pytest

import gearopt as go
from gearopt.cases.timing_train.summary import build_summary, eng, headlines_markdown, summary_markdown
from gearopt.contact.microgeometry import Microgeometry
from gearopt.design import optimise_microgeometry
from gearopt.design.recommendation import recommend
from gearopt.design.requirements import DynamicPeaks, TrainDesign, evaluate_requirements
from gearopt.report import contact_headlines as ch


def test_engineering_precision():
    assert [eng(v) for v in (0.19541036, 1049.5978, 4.088605, 0.0009999, "inf", float("inf"))] == \
        ["0.195", "1050", "4.09", "1.00e-03", "inf", "inf"]


MINIMAL = Path(go.__file__).parent / "data" / "minimal_train.toml"


@pytest.fixture(scope="module")
def recommended():
    """The minimal pair's recommendation between two tip reliefs, as result.json holds it."""
    system = go.load_system(MINIMAL)
    train = system.train("spur")
    start = tuple(float(v) for v in train.pairs["pinion-wheel"].geometry()["hpstc_roll_deg"])
    designs = [TrainDesign(train, {"pinion-wheel": Microgeometry(tip_relief_um=(a, a), tip_relief_start_roll_deg=start,
                                                                  relief_smoothing_deg=0.1)}, name=f"relief {a:g}")
               for a in (6.0, 12.0)]
    return recommend(system, designs).as_json()


def test_the_verdict_is_the_recommended_designs_requirement_list(recommended):
    s = build_summary(recommended)
    assert [r["name"] for r in s["requirements"]] == [r["name"] for r in recommended["requirements"]]
    assert s["failed"] == [r["name"] for r in recommended["requirements"] if r["verdict"] == "FAIL"]
    assert s["verdict"] == recommended["verdict"] == ("FAIL" if s["failed"] else "PASS")
    for r in s["requirements"]:                          # engineering precision: three significant figures
        if isinstance(r["value"], float) and r["value"] != 0:
            assert r["value"] == float(eng(r["value"]))
        assert r["verdict"] == "PASS" or r["what_it_would_take"]


def test_report_opening_holds_the_verdict_and_the_flank_reliefs_with_start_diameters(recommended):
    text = summary_markdown(build_summary(recommended, quick=True), recommended)
    head = text.splitlines()[:40]
    assert head[0].startswith(f"## Verdict: {recommended['verdict']}")
    assert f"Recommended design: {recommended['design']}" in head[2]
    rows = [line for line in head if line.startswith("| pinion | driving |") or line.startswith("| wheel | driven |")]
    assert len(rows) == 2
    for f, line in zip(recommended["flanks"], rows):
        assert f"| {f['tip_relief_start_diameter_mm']:.2f} |" in line and "blended over 0.1 deg" in line
    assert "| requirement | worst case | value | limit | unit | verdict | what it would take |" in text
    assert "µm" in text


def test_margins_over_speed_carry_their_spread_over_the_recorded_cycles():
    """A rattling backlash response: the requirement is judged on the worst cycle, and the row and its Markdown say
    how the per-cycle worst margins spread (median, best) at that worst instance."""
    system = go.load_system(MINIMAL)

    def entry(joint, speed, worst, median, best):
        return {"joint": joint, "speed_rpm": speed, "torque_margin": worst, "axial_margin": math.inf,
                "peak_torque_Nm": 100.0, "peak_axial_force_N": 0.0, "cycles": 5,
                "torque_margin_cycle_worst": worst, "torque_margin_cycle_median": median,
                "torque_margin_cycle_best": best}
    dyn = DynamicPeaks(joint_margins=[entry("pinion", 1500.0, 0.62, 0.70, 0.81), entry("pinion", 1800.0, 0.66, 0.71,
                                                                                         0.75),
                                      entry("wheel", 1500.0, 3.1, 3.3, 3.6)])
    check = evaluate_requirements(system, TrainDesign(system.train("spur")), dynamic=dyn)
    slip = check.row("slip_margin_over_speed", "all joints")
    assert (slip.value, slip.worst_case, slip.verdict) == (0.62, "pinion at 1500 rpm", "FAIL")
    assert slip.detail["cycle_spread"] == {"cycles": 5, "worst": 0.62, "median": 0.7, "best": 0.81}
    assert slip.fixed                                     # no design variable moves a dynamics result
    axial = check.row("axial_margin_over_speed", "all joints")    # spur meshes: no thrust on any joint
    assert math.isinf(axial.value) and axial.verdict == "PASS"
    assert axial.worst_case == "no joint carries an axial tooth force (spur meshes)"
    rec = {"verdict": check.verdict, "design": "design", "option": "", "why": "test", "requirements": check.as_json(),
           "macro": {"root_gear": "pinion", "root_profile_shift": 0.2, "helix_angle_deg": 0.0}, "flanks": [],
           "gears": {}}
    assert "per-cycle worst over 5 cycles: median 0.700, best 0.810" in summary_markdown(build_summary(rec), rec)


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
    nlp = ch.nlp_constraint_margins(d)
    assert set(nlp) == {"contact_stress_MPa", "loaded_contact_ratio", "root_stress_MPa"}
    q = d.scene.quantities
    rows = q[q["quantity"] == "max_contact_stress_MPa"]
    assert nlp["contact_stress_MPa"] == pytest.approx(np.min(rows["upper"] - rows["value"]))
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
