"""Sensitivity reports: KKT parametric sensitivities against analytic optima and against re-solves with the datum
moved; limit sensitivities (multipliers) against re-solves with the limit moved; Hertz's square root in the
sensitivity of a contact stress to its torque."""

from dataclasses import replace

import numpy as np
import pytest

import gearopt as go
from gearopt.design.scene import DesignVariable, Limit, LoadCase, Objective, Scene
from gearopt.errors import GearoptInputError
from gearopt.nlp import Problem
from gearopt.studies import kkt_sensitivity, sensitivity_report
from studies_scenes import DATA_TORQUES as TORQUES, MESH, relief_scene


def ppte(scene) -> float:
    return scene.build().solve(check=False, tol=1e-11).quantities.query("quantity == 'ppte_um'")["value"].max()


@pytest.fixture(scope="module")
def scene():
    return relief_scene(min_lcr=1.3, torques=TORQUES, positions=40)


@pytest.fixture(scope="module")
def report(scene):
    return sensitivity_report(scene.build().solve(check=False))


def test_kkt_sensitivity_of_an_analytic_parametric_nlp():
    # min x^2 + 2 y^2 s.t. x + y >= p: x* = 2p/3, y* = p/3, f* = 2p^2/3, df*/dp = 4p/3, dx*/dp = 2/3, dy*/dp = 1/3
    pr = Problem("analytic")
    x, y = pr.variable("x", 0.0), pr.variable("y", 0.0, scale=2.0)
    p = pr.parameter("p", 3.0)
    pr.subject_to("sum", x + y - p, lower=0.0)
    pr.minimize(x ** 2 + 2 * y ** 2)
    pr.solve()
    s = kkt_sensitivity(pr.opti)
    assert s.df_dp[0] == pytest.approx(4.0, rel=1e-7)
    np.testing.assert_allclose(s.dx_dp[:, 0], [2 / 3, (1 / 3) / 2.0], rtol=1e-7)    # y is scaled by 2
    assert s.expression_derivative(pr.opti, x + y)[0, 0] == pytest.approx(1.0, rel=1e-7)


def test_report_columns_and_order(report):
    t = report.table
    for col in ("name", "kind", "value", "unit", "sensitivity", "log_sensitivity"):
        assert col in t.columns
    assert set(t["kind"]) == {"limit", "parameter"}
    mags = np.abs(t["log_sensitivity"].to_numpy())
    assert np.all(np.diff(mags) <= 1e-15)
    assert report.objective_name == f"ppte_um[{MESH}]" and report.objective_unit == "um"
    md = report.markdown(rows=3)
    assert md.count("\n") == 4 and "log_sensitivity" in md


def test_torque_sensitivities_match_re_solves_with_the_torque_moved(scene, report):
    t = report.table.set_index("name")
    for i, torque in ((0, TORQUES[0]), (2, TORQUES[2])):     # the two ends of the range hold the PPTE maximum
        h = 1.0
        moved = []
        for sign in (-1, 1):
            cases = [LoadCase(f"T{tq:g}", tq + (sign * h if j == i else 0.0)) for j, tq in enumerate(TORQUES)]
            moved.append(ppte(replace(scene, load_cases=cases)))
        difference = (moved[1] - moved[0]) / (2 * h)
        kkt = t.loc[f"torque_Nm[{MESH}]@T{torque:g}", "sensitivity"]
        assert kkt == pytest.approx(difference, rel=0.02, abs=1e-5)
        assert t.loc[f"torque_Nm[{MESH}]@T{torque:g}", "log_sensitivity"] == pytest.approx(
            kkt * torque / report.objective, rel=1e-12)


def test_limit_sensitivity_matches_a_re_solve_with_the_limit_moved(scene, report):
    row = report.table.set_index("name").loc[f"loaded_contact_ratio[{MESH}]@T150 (lower)"]
    assert row["active"]
    # the optimum curves strongly in this bound (the central difference is 0.2485 at h = 2e-3, 0.2399 at 2e-4)
    h = 2e-4
    moved = [ppte(replace(scene, limits=[scene.limits[0], Limit("loaded_contact_ratio", MESH, lower=1.3 + s * h)]))
             for s in (-1, 1)]
    assert row["sensitivity"] == pytest.approx((moved[1] - moved[0]) / (2 * h), rel=2e-3)
    # the contact-stress limit has a large margin: no sensitivity
    stress = report.table[report.table["name"].str.startswith("max_contact_stress_MPa")]
    assert len(stress) == 3 and (stress["sensitivity"].abs() < 1e-6).all() and not stress["active"].any()


def test_contact_stress_follows_hertz_square_root_of_its_torque(report):
    # at the largest torque the maximum contact stress sits in single-pair contact, where the tip relief does not
    # act: sigma_H ~ sqrt(F) (Hertz), so d ln sigma / d ln T = 1/2
    q = report.quantity_table.set_index(["quantity", "parameter"])
    own = q.loc[(f"max_contact_stress_MPa[{MESH}]@T450", f"torque_Nm[{MESH}]@T450"), "log_sensitivity"]
    other = q.loc[(f"max_contact_stress_MPa[{MESH}]@T450", f"torque_Nm[{MESH}]@T150"), "log_sensitivity"]
    assert own == pytest.approx(0.5, abs=1e-6) and abs(other) < 1e-6


def test_report_needs_a_solved_scene(tmp_path, report):
    with pytest.raises(GearoptInputError, match="SceneResult"):
        sensitivity_report(object())
    path = report.to_csv(tmp_path / "s.csv")
    assert path.read_text().startswith("name,kind,value,unit,sensitivity,log_sensitivity")


def joint_scene(demand_Nm: float = 400.0, margin: float = 2.0) -> Scene:
    return Scene("joint", train=go.load_default_train("spur"),
                 load_cases=[LoadCase("design", speed_rpm=2500.0, joint_torque_Nm={"cam": demand_Nm},
                                      joint_axial_force_N={"cam": 2000.0})],
                 variables=[DesignVariable("interference_um", "cam", 10.0, 150.0)],
                 objectives=[Objective("torque_capacity_Nm", "cam")],
                 limits=[Limit("torque_margin", "cam", lower=margin)])


def test_joint_demand_and_margin_sensitivities_match_re_solves():
    # least capacity with capacity(2500 rpm) / demand >= margin: the capacity scales with demand x margin, so both
    # log sensitivities are ~1 (not exactly: the objective is the capacity at rest, the limit the one at speed)
    def capacity(**kw):
        return joint_scene(**kw).build().solve(check=False).quantities.query("role == 'objective'")["value"].item()

    t = sensitivity_report(joint_scene().build().solve(check=False)).table.set_index("name")
    assert set(t.index) >= {"joint_torque_Nm[cam]@design", "torque_margin[cam]@design (lower)"}
    assert "joint_axial_force_N[cam]@design" not in t.index      # no quantity of this scene uses it
    demand = (capacity(demand_Nm=401.0) - capacity(demand_Nm=399.0)) / 2.0
    margin = (capacity(margin=2.001) - capacity(margin=1.999)) / 0.002
    assert t.loc["joint_torque_Nm[cam]@design", "sensitivity"] == pytest.approx(demand, rel=1e-5)
    assert t.loc["torque_margin[cam]@design (lower)", "sensitivity"] == pytest.approx(margin, rel=1e-5)
    assert t.loc["joint_torque_Nm[cam]@design", "log_sensitivity"] == pytest.approx(1.0, abs=0.01)


def test_contact_temperature_sensitivities_to_oil_temperature_and_friction():
    # theta_B = theta_oil + theta_fl with Blok's flash temperature proportional to the friction coefficient:
    # d theta_B / d theta_oil = 1 and d theta_B / d mu = theta_fl / mu (the limit is inactive: the design stays)
    scene = Scene("hot", train=go.load_default_train("spur"),
                  load_cases=[LoadCase("design", 300.0, speed_rpm=2500.0)],
                  variables=[DesignVariable(v, MESH) for v in ("tip_relief_1_um", "tip_relief_2_um")],
                  objectives=[Objective("ppte_um", MESH)],
                  limits=[Limit("max_contact_temperature_C", MESH, upper=400.0)], ltca_options={"positions": 24})
    report = sensitivity_report(scene.build().solve(check=False))
    q = report.quantity_table.set_index("parameter")
    q = q[q["quantity"] == f"max_contact_temperature_C[{MESH}]@design"]
    theta = q["value"].iloc[0]
    assert q.loc[f"oil_temperature_C[{MESH}]", "sensitivity"] == pytest.approx(1.0, abs=1e-9)
    assert q.loc[f"friction_coefficient[{MESH}]", "sensitivity"] == pytest.approx((theta - 100.0) / 0.06, rel=1e-9)
