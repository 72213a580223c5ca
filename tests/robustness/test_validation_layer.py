"""The validation layer and the five gaps of issue 18, one reported case each (named rejection, finite result or a
typed budget error; never NaN, an untyped exception or a hang)."""

from __future__ import annotations

import contextlib
import io
import math
import re
import time
import warnings

import casadi as ca
import numpy as np
import pytest

import gearopt as go
from gearopt.engine import crank_torque
from gearopt.nlp import Problem
from gearopt.rating import contact_stress_iso6336, root_stress_iso6336
from gearopt.errors import (BudgetExceededError, GearoptInputError, GeometryError, IterationLimitError,
                            NonFiniteResultError)
from gearopt.validation import (check_array, check_int, check_names, check_per_gear, check_range, check_result,
                                per_gear)

NAN, INF = float("nan"), float("inf")


def _pair(**kw):
    args = dict(teeth=(38, 76), profile_shifts=(0.3124, 0.1118), module_mm=3.0)
    args.update(kw)
    return go.GearPair.from_profile_shifts(**args)


# ------------------------------------------------------------------------------------------------------------------
# 1. the layer: NaN, infinities, strings, bools, 1e300, counts, shapes; symbols pass
# ------------------------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("value, words", [
    (INF, "module_mm=inf mm is infinite"),
    (NAN, "module_mm=nan is NaN"),
    ("3", "module_mm='3' is not a number"),
    (True, "module_mm=True is not a number"),
    (None, "module_mm=None is not a number"),
    (1e300, "module_mm=1e+300 mm is beyond the plausible magnitude"),
    ((3.0, 3.0), "module_mm=(3.0, 3.0) must be a scalar"),
])
def test_check_range_rejects_what_arithmetic_would_choke_on(value, words):
    with pytest.raises(GearoptInputError) as info:
        check_range("module_mm", value, 0.0, None, low_inclusive=False, unit="mm")
    assert words in str(info.value)


def test_check_range_limits_infinity_and_symbols():
    check_range("release_speed_rpm", INF, 0.0, None, allow_inf=True)  # meaningful infinity, opted in
    with pytest.raises(GearoptInputError, match="low limit of x is NaN"):
        check_range("x", 1.0, NAN)
    check_range("x", ca.SX.sym("x"), 0.0, 1.0)  # a symbol passes untouched: the NLP imposes it
    check_range("x", ca.DM(0.5), 0.0, 1.0)      # a constant DM is a number and is checked
    with pytest.raises(GearoptInputError):
        check_range("x", ca.DM(2.0), 0.0, 1.0)


def test_counts_tuples_names_arrays_and_results():
    assert check_int("slices", 3.0, 1) == 3
    for bad in (2.5, "3", True, NAN, INF):
        with pytest.raises(GearoptInputError, match="slices"):
            check_int("slices", bad, 1)
    assert per_gear(2.0, "b") == (2.0, 2.0)
    with pytest.raises(GearoptInputError, match=r"face_width_mm=\(1, 2, 3\) must be a scalar or a 2-tuple"):
        check_per_gear("face_width_mm", (1, 2, 3), 0.0)
    with pytest.raises(GearoptInputError, match="names=.*must be a tuple of 2 names"):
        check_names("names", ("a", "b", "c"))
    with pytest.raises(GearoptInputError, match=r"x\[1\]=nan is NaN"):
        check_array("x", [1.0, NAN], 0.0)
    with pytest.raises(GearoptInputError, match="shape"):
        check_array("x", np.zeros((2, 3)), shape=(2, None, 1))
    with pytest.raises(NonFiniteResultError, match=r"stress\.a\[1\] is NaN.*inputs: torque_Nm=5"):
        check_result("stress", {"a": (1.0, NAN)}, {"torque_Nm": 5})


def test_a_numeric_geometry_record_is_finite_in_one_pass_and_a_bad_number_is_named():
    """A numeric pair's geometry record is checked in one pass (``PairGeometry.is_finite``); only a record that
    fails it goes through ``check_result``, which names the field and element."""
    import dataclasses

    record = _pair().geometry()
    assert record.is_finite()
    for field, bad in (("transverse_contact_ratio", NAN), ("tip_diameter_mm", (200.0, INF))):
        spoiled = dataclasses.replace(record, **{field: bad})
        assert not spoiled.is_finite()
        element = "[1] is an infinity" if isinstance(bad, tuple) else " is NaN"
        with pytest.raises(NonFiniteResultError, match=re.escape(f"geometry.{field}{element}")):
            check_result("geometry", spoiled)


def test_geometry_entry_points_reject_bad_input_by_name():
    with pytest.raises(GearoptInputError, match="module_mm=inf"):
        _pair(module_mm=INF)
    with pytest.raises(GearoptInputError, match=r"teeth\[0\]='38' must be an integer|teeth\[0\]='38' is not a number"):
        _pair(teeth=("38", 76))
    with pytest.raises(GearoptInputError, match="names"):
        _pair(names=("crank",))
    pair = _pair()
    with pytest.raises(GearoptInputError, match="min_contact_ratio=nan is NaN"):
        pair.check(min_contact_ratio=NAN)
    with pytest.raises(GearoptInputError, match="unknown limit"):
        pair.check(min_contact_ration=1.2)


def test_cli_rejects_infinite_module_instead_of_printing_nan_rows():
    from gearopt.cli import main
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(["pair", "--teeth", "38", "76", "--module-mm", "inf", "--profile-shifts", "0.3", "0.1"])
    assert code == 2 and "module_mm=inf" in err.getvalue()
    assert "nan" not in out.getvalue() and "check: ok" not in out.getvalue()


# ------------------------------------------------------------------------------------------------------------------
# 2. secondary parameters
# ------------------------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("kw, name", [
    (dict(poisson=1.0), "poisson"), (dict(E_MPa=-1.0), "E_MPa"), (dict(positions=2.5), "positions"),
    (dict(slices=1.5), "slices"), (dict(friction_coefficient=NAN), "friction_coefficient"),
    (dict(bulk_temperature_C=-300.0), "bulk_temperature_C"), (dict(driving_gear=3), "driving_gear"),
])
def test_ltca_secondary_parameters_are_named(kw, name):
    with pytest.raises(GearoptInputError, match=name):
        go.ltca(_pair(), 100.0, **kw)


@pytest.mark.parametrize("kw, name", [
    (dict(shaft_temperature_C=-300.0), "shaft_temperature_C"), (dict(hub_yield_MPa=-5.0), "hub_yield_MPa"),
    (dict(shaft_yield_MPa="700"), "shaft_yield_MPa"), (dict(hub_expansion_per_K=NAN), "hub_expansion_per_K"),
    (dict(smoothing_rule="din"), "smoothing_rule"), (dict(axial_force_N=-1.0), "axial_force_N"),
])
def test_press_fit_secondary_parameters_are_named(kw, name):
    with pytest.raises(GearoptInputError, match=name):
        go.press_fit(42.0, 0.0, 70.0, 25.0, 65.5, 210000.0, 0.3, 206000.0, 0.3, 0.12, **kw)


def test_crank_torque_angle_and_pressures_are_checked():
    base = dict(speed_rpm=2000.0, bore_mm=107.0, stroke_mm=124.0, rod_length_mm=192.0, reciprocating_mass_kg=2.5,
                cylinder_pressure_bar=100.0)
    for kw, name in ((dict(crank_angle_deg=(4.0, 4.0)), "crank_angle_deg"),
                     (dict(crank_angle_deg="30"), "crank_angle_deg"),
                     (dict(crank_angle_deg=30.0, crankcase_pressure_bar=NAN), "crankcase_pressure_bar")):
        with pytest.raises(GearoptInputError, match=name):
            crank_torque(**dict(base, **kw))
    gas, inertia = crank_torque(crank_angle_deg=np.array([0.0, 30.0]), **base)  # arrays stay supported
    assert np.all(np.isfinite(gas)) and np.all(np.isfinite(inertia))


def test_stiffness_variation_cannot_make_the_mesh_stiffness_negative():
    from gearopt.dynamics import TorsionalNetwork
    from gearopt.dynamics.mesh import MeshStiffnessShape
    shape = MeshStiffnessShape.from_samples(np.linspace(0, 2 * np.pi, 64, endpoint=False),
                                            1.0 + 0.5 * np.cos(np.linspace(0, 2 * np.pi, 64, endpoint=False)),
                                            harmonics=2)
    net = TorsionalNetwork("t").add_inertia("a", 0.01).add_inertia("b", 0.04)
    with pytest.raises(GearoptInputError, match="stiffness_variation of 'a-b'=2.5 makes the mesh stiffness negative"):
        net.add_mesh("a", "b", base_radii_mm=(40.0, 80.0), teeth=(30, 60), stiffness_N_per_m=4e8,
                     stiffness_shape=shape, stiffness_variation=2.5)
    with pytest.raises(GearoptInputError, match="teeth"):
        net.add_mesh("a", "b", base_radii_mm=(40.0, 80.0), teeth=(30.5, 61), stiffness_N_per_m=4e8)


# ------------------------------------------------------------------------------------------------------------------
# 3. outputs: meaningful infinities, NaN never returned
# ------------------------------------------------------------------------------------------------------------------

def test_hollow_press_fit_that_tightens_with_speed_is_never_released():
    from gearopt.joints.press_fit import centrifugal_interference_loss_um
    # a hollow steel shaft in a light, stiff hub: the hub bore grows less than the shaft (Lame, rotating discs), so
    # the interference grows with speed; sqrt(at_rest / loss) of a negative loss was NaN before
    loss = centrifugal_interference_loss_um(1.0, 40.0, 30.0, 60.0, 210000.0, 0.3, 400000.0, 0.25, 7850.0, 2000.0)
    assert loss < 0.0
    r = go.press_fit(40.0, 30.0, 60.0, 20.0, 30.0, 210000.0, 0.3, 400000.0, 0.25, 0.12, speed_rpm=3000.0,
                     hub_density_kg_m3=2000.0)
    assert r.release_speed_rpm == INF
    assert r.effective_interference_um > 30.0 - 1e-9


def test_zero_stress_gives_an_infinite_safety_not_nan():
    r = go.press_fit(42.0, 0.0, 70.0, 25.0, 0.0, 210000.0, 0.3, 206000.0, 0.3, 0.12, hub_yield_MPa=700.0,
                     shaft_yield_MPa=650.0)
    assert r.pressure_MPa == 0.0 and r.hub_yield_safety == INF and r.shaft_yield_safety == INF


def test_contact_rating_outside_its_contact_ratio_range_raises_by_clause():
    # 100/100 teeth, 12 deg rack with 1.6 m addendum: eps_alpha = 3.94 passes check(); Z_eps = sqrt((4 - eps)/3)
    # is about to turn NaN (eps > 4). ISO 6336-1/-2 clause 1 limit the method to eps_alpha < 2.5.
    pair = go.GearPair.from_profile_shifts((100, 100), (0.0, 0.0), 2.0, pressure_angle_deg=12.0,
                                           addendum_coefficient=1.6, dedendum_coefficient=1.85)
    pair.check()
    assert pair.geometry()["transverse_contact_ratio"] > 2.5
    with pytest.raises(GeometryError, match=r"1 <= eps_alpha < 2.5 \(ISO 6336-1/-2 clause 1"):
        contact_stress_iso6336(pair, 300.0)
    with pytest.raises(GeometryError, match="eps_alpha"):
        root_stress_iso6336(pair, 300.0)


# ------------------------------------------------------------------------------------------------------------------
# 4. validity the LTCA and the ratings need
# ------------------------------------------------------------------------------------------------------------------

def test_tip_below_base_circle_is_a_named_geometry_error_not_an_index_error():
    pair = _pair(tip_diameters_mm=(100.0, 235.0))  # gear 1's base circle is 107.1 mm
    with pytest.raises(GearoptInputError, match="tip"):
        go.ltca(pair, 100.0)
    with pytest.raises(GearoptInputError, match="tip"):
        contact_stress_iso6336(pair, 100.0)


def test_huge_tips_are_rejected_quickly_by_the_ltca_and_the_ratings():
    pair = _pair(tip_diameters_mm=(400.0, 600.0))
    t0 = time.perf_counter()
    for call in (lambda: go.ltca(pair, 100.0, slices=41), lambda: contact_stress_iso6336(pair, 100.0),
                 lambda: root_stress_iso6336(pair, 100.0)):
        with pytest.raises(GearoptInputError):
            call()
    assert time.perf_counter() - t0 < 5.0


# ------------------------------------------------------------------------------------------------------------------
# 5. budgets
# ------------------------------------------------------------------------------------------------------------------

def test_problem_with_a_bound_beyond_ipopt_infinity_solves_with_a_note():
    p = Problem("far bound")
    with pytest.warns(UserWarning, match="beyond Ipopt's infinity"):
        x = p.variable("x", 1.0, lower=-5.0, upper=1e200)
    p.minimize((x - 2.0) ** 2)
    result = p.solve()
    assert result.values["x"] == pytest.approx(2.0, abs=1e-6)


def test_ipopt_has_default_budgets_and_names_the_limit_hit():
    from gearopt.nlp.problem import DEFAULT_IPOPT_OPTIONS
    assert DEFAULT_IPOPT_OPTIONS["max_iter"] > 0 and DEFAULT_IPOPT_OPTIONS["max_wall_time"] > 0
    p = Problem("rosenbrock")
    x = p.variable("x", -1.2)
    y = p.variable("y", 1.0)
    p.minimize((1 - x) ** 2 + 100 * (y - x ** 2) ** 2)
    with pytest.raises(IterationLimitError, match="max_iter"):
        p.solve(max_iter=2)
    with pytest.raises(GearoptInputError, match="max_iter"):
        p.solve(max_iter=1e12)


def _net(j1=0.01, k_mesh=4e8):
    from gearopt.dynamics import TorsionalNetwork
    net = TorsionalNetwork("budget pair", cycle_deg=360.0)
    net.add_inertia("drive", 1.0).add_inertia("g1", j1).add_inertia("g2", 0.04)
    net.add_shaft("drive", "g1", 2e5, 5.0)
    net.add_mesh("g1", "g2", base_radii_mm=(40.0, 80.0), teeth=(30, 60), stiffness_N_per_m=k_mesh,
                 damping_N_s_per_m=2000.0, backlash_mm=0.1)
    net.set_speed_boundary("drive")
    return net


@pytest.mark.parametrize("kw", [dict(j1=1e-12), dict(k_mesh=1e15)])
def test_stiff_networks_stop_at_the_step_budget_before_integrating(kw):
    from gearopt.dynamics.simulate import simulate
    t0 = time.perf_counter()
    with pytest.raises(BudgetExceededError, match="max_steps_per_cycle") as info:
        simulate(_net(**kw), 1500.0, 1)
    assert info.value.limit == "max_steps_per_cycle"
    assert time.perf_counter() - t0 < 10.0


def test_simulation_wall_time_budget_is_overridable_and_named():
    from gearopt.dynamics.simulate import simulate
    with pytest.raises(BudgetExceededError, match="max_wall_time_s=1e-06") as info:
        simulate(_net(), 1500.0, 2, max_wall_time_s=1e-6)
    assert info.value.limit == "max_wall_time_s"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sim = simulate(_net(), 1500.0, 1, max_wall_time_s=math.inf)
    assert np.isfinite(sim.summary().select_dtypes("number").to_numpy()).all()
