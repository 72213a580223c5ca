"""The lifted contact form (``ltca_options={"approach": "lifted"}``): each position's approach an NLP variable held by
the force balance as an equality constraint, against the nested form (Newton's root inside the model) -- the same
equations, so the same smooth outputs at a design and the same optimum from the same start; starts of other designs
get consistent approaches."""

import numpy as np
import pytest
import casadi as ca

import gearopt as go
from gearopt.contact.ltca_smooth import LTCAModel
from gearopt.contact.microgeometry import Microgeometry
from gearopt.design.scene import DesignVariable, Limit, LoadCase, Objective, Scene
from gearopt.errors import GearoptInputError

MESH = "crank-cam"
RELIEF = ("tip_relief_1_um", "tip_relief_2_um", "tip_relief_1_start_roll_deg", "tip_relief_2_start_roll_deg")
TORQUES = (150.0, 300.0, 450.0)


def scene(approach: str) -> Scene:
    return Scene("relief", train=go.load_default_train("spur"),
                 load_cases=[LoadCase(f"T{t:g}", t) for t in TORQUES],
                 variables=[DesignVariable(v, MESH) for v in RELIEF],
                 objectives=[Objective("ppte_um", MESH, aggregate="max")],
                 limits=[Limit("max_contact_stress_MPa", MESH, upper=1150.0), Limit("loaded_contact_ratio", MESH,
                                                                                     lower=1.2)],
                 ltca_options={"positions": 24, "approach": approach})


@pytest.fixture(scope="module")
def model():
    return LTCAModel(go.load_default_train("spur").pairs[MESH], positions=24, root_stress=True, speed_rpm=1000.0)


def test_lifted_evaluation_at_the_newton_approach_equals_the_nested_one(model):
    mods = Microgeometry(tip_relief_um=(12.0, 9.0), tip_relief_start_roll_deg=(23.0, 22.0))
    nested = model.evaluate(mods, list(TORQUES))
    start = model.approach_start(mods, TORQUES)
    d = ca.MX.sym("d", start.size)
    lifted = model.evaluate(mods, ca.MX(np.array(TORQUES)), approach_um=d)
    at = ca.Function("lifted", [d], [lifted.approach_residual_N, lifted.approach_floor_um,
                                     lifted.contact_stress_squared_MPa2, lifted.flash_temperature_rise_K,
                                     lifted.root_stress_MPa[0]])
    residual, floor, stress, flash, root = (np.asarray(v, dtype=float) for v in at(start))
    force = max(TORQUES) * model.layout.force_per_torque_N_per_Nm
    assert np.abs(residual).max() <= 1e-8 * force           # the Newton root balances the force
    assert floor.min() > 0.0                                # a loaded mesh closes its smallest gap
    np.testing.assert_allclose(stress, nested.contact_stress_squared_MPa2, rtol=1e-10, atol=1e-6)
    np.testing.assert_allclose(flash, nested.flash_temperature_rise_K, rtol=1e-10, atol=1e-9)
    np.testing.assert_allclose(root, nested.root_stress_MPa[0], rtol=1e-10, atol=1e-9)


def test_lifted_approach_is_for_symbolic_evaluations_of_the_right_size(model):
    with pytest.raises(GearoptInputError, match="symbolic"):
        model.evaluate(None, 300.0, approach_um=np.zeros(24))
    with pytest.raises(GearoptInputError, match="positions x load cases"):
        model.evaluate(None, 300.0, approach_um=ca.MX.sym("d", 5))


def test_the_nested_optimum_is_an_optimum_of_the_lifted_nlp():
    # the same equations: started at the nested form's optimum, the lifted NLP stays there (the relief problem has
    # several local optima, so from the declared start the two forms' paths may end at different ones)
    nested = scene("nested").build().solve(check=False, tol=1e-10)
    built = scene("lifted").build(initial=nested.values)
    assert "crank-cam.approach_um" in built.problem.variable_names
    lifted = built.solve(check=False, tol=1e-10)
    for name, value in nested.values.items():
        assert lifted.values[name] == pytest.approx(value, rel=1e-5, abs=1e-5)
    q_n, q_l = (r.quantities.set_index(["quantity", "load_case"])["value"] for r in (nested, lifted))
    np.testing.assert_allclose(q_l.loc[q_n.index].to_numpy(), q_n.to_numpy(), rtol=1e-5)


def test_a_start_of_another_design_gets_its_own_approaches():
    built = scene("lifted").build()
    p = built.problem
    design = {f"{MESH}.tip_relief_1_um": 20.0, f"{MESH}.tip_relief_2_um": 5.0,
              f"{MESH}.tip_relief_1_start_roll_deg": 24.0, f"{MESH}.tip_relief_2_start_roll_deg": 22.0}
    for name, value in design.items():
        p.set_initial(name, value)
    start = p._start(False)                       # the start Ipopt gets
    expected = built.models[f"ltca_smooth:{MESH}"].approach_start(built.microgeometry_at(design, MESH), TORQUES)
    np.testing.assert_allclose(start[f"{MESH}.approach_um"] * p._variables[f"{MESH}.approach_um"].scale, expected,
                               rtol=1e-12)
    # the quantities at a design (no solve) use the approaches of that design: equal to the nested model's
    q_l = built.quantities_at(design).set_index(["quantity", "load_case"])["value"]
    q_n = scene("nested").build().quantities_at(design).set_index(["quantity", "load_case"])["value"]
    np.testing.assert_allclose(q_l.loc[q_n.index].to_numpy(), q_n.to_numpy(), rtol=1e-9)


def test_unknown_approach_is_refused():
    with pytest.raises(GearoptInputError, match="approach"):
        scene("newton").build()


def test_lifted_constraints_and_outputs_have_the_derivatives_of_central_differences(model):
    # the force balance, the gap floor and the contact stress of the lifted form, differentiated by CasADi with
    # respect to the relief amounts, starts and the approaches, against central differences (h = 1e-5)
    x = ca.MX.sym("x", 4)
    mods = Microgeometry(tip_relief_um=(x[0], x[1]), tip_relief_start_roll_deg=(x[2], x[3]))
    x0 = np.array([12.0, 9.0, 23.0, 22.0])
    d0 = model.approach_start(Microgeometry(tip_relief_um=(12.0, 9.0), tip_relief_start_roll_deg=(23.0, 22.0)),
                              TORQUES) + 0.3            # off the balance: the residual's slope, not only at zero
    d = ca.MX.sym("d", d0.size)
    res = model.evaluate(mods, list(TORQUES), approach_um=d)
    out = ca.vertcat(ca.vec(res.approach_residual_N) / 1e3, ca.vec(res.approach_floor_um),
                     ca.vec(res.contact_stress_squared_MPa2) / 1e6)
    z = ca.vertcat(x, d)
    f = ca.Function("f", [z], [out])
    J = ca.Function("J", [z], [ca.jacobian(out, z)])
    z0 = np.concatenate([x0, d0])
    jac = np.asarray(J(z0).full())
    h = 1e-5
    for k in list(range(4)) + [4, 4 + d0.size // 2, 3 + d0.size]:
        e = np.zeros(z0.size)
        e[k] = h
        fd = (np.asarray(f(z0 + e)).ravel() - np.asarray(f(z0 - e)).ravel()) / (2 * h)
        scale = max(np.max(np.abs(jac[:, k])), 1e-3)
        assert np.max(np.abs(jac[:, k] - fd)) / scale < 1e-4, k


def test_a_scene_with_more_limits_starts_from_the_multipliers_of_a_solved_one():
    """``BuiltScene.solve(warm_start=result.warm_start_point())`` (the co-design of a pinned macro after its
    sequential design): the same lifted NLP with one more limit, inactive at the optimum, built at the solved design
    and started from its multipliers by constraint name reaches the optimum of a start without them, in fewer
    Ipopt iterations."""
    from dataclasses import replace

    first = scene("lifted").build().solve(check=False)
    more = replace(scene("lifted"), limits=[*scene("lifted").limits,
                                            Limit("max_root_stress_MPa", MESH, upper=1500.0)])
    runs = {}
    for name, warm in (("cold", None), ("warm", first.warm_start_point())):
        runs[name] = more.build(initial=first.values).solve(check=False, warm_start=warm)
    for name, value in runs["cold"].values.items():
        assert runs["warm"].values[name] == pytest.approx(value, rel=1e-4, abs=1e-4)
        assert value == pytest.approx(first.values[name], rel=1e-4, abs=1e-4)
    assert runs["warm"].solve.iterations < runs["cold"].solve.iterations
    with pytest.raises(GearoptInputError, match="warm_start"):
        more.build().solve(check=False, warm_start={"x": 1.0})
    first_build = scene("lifted").build()
    with pytest.raises(GearoptInputError, match="starts=2"):            # several starts would not use it
        first_build.solve(check=False, starts=2, warm_start=first.warm_start_point())
