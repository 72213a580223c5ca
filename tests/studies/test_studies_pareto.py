"""Trade-off fronts: the ends are the two single-objective optima (solved independently), the front is monotone and
not dominated by any sampled feasible design, its slope agrees with the ε multipliers, and failed points are
recorded with their typed failure."""

from dataclasses import replace

import numpy as np
import pytest

from gearopt.design.scene import Objective
from gearopt.errors import GearoptInputError
from gearopt.studies import pareto_front
from gearopt.studies.epsilon import FrontSpec
from gearopt.studies.evaluator import scene_evaluator
from gearopt.studies.pareto import OK, run_segment
from studies_scenes import MESH, RELIEF, relief_scene

LCR = "loaded_contact_ratio"


def front_scene():
    return relief_scene(min_lcr=1.2, stress_limit=False)


@pytest.fixture(scope="module")
def scene():
    return front_scene()


@pytest.fixture(scope="module")
def front(scene):
    return pareto_front(scene, LCR, MESH, points=5, starts=4)


def test_front_table_has_every_variable_quantity_and_a_status(front):
    t = front.table
    assert len(t) == 5 and (t["status"] == OK).all()
    for name in RELIEF:
        assert f"{MESH}.{name}" in t.columns
    for case in ("T150", "T450"):
        assert f"ppte_um[{MESH}]@{case}" in t.columns and f"{LCR}[{MESH}]@{case}" in t.columns
    assert front.sense == "max"           # the scene's lower limit on the quantity: the front makes it large


def test_front_ends_are_the_single_objective_optima(scene, front):
    # end A: a minimum of the scene itself without its limit on the quantity. The problem has several local minima
    # (which one four starts find depends on the path), so the independent solve starts from the end's design and
    # must stay there: the end is a local optimum of the objective alone, not a point the front constraint holds
    first, last = front.table.iloc[0], front.table.iloc[-1]
    design = {f"{MESH}.{v}": float(first[f"{MESH}.{v}"]) for v in RELIEF}
    free = replace(scene, limits=[]).build(initial=design).solve(check=False)
    ppte_a = free.quantities.query("quantity == 'ppte_um'")["value"].max()
    assert first[front.objective_column] == pytest.approx(ppte_a, rel=1e-5)
    # end B: an independent scene maximising the smallest loaded contact ratio over the load cases
    best = replace(scene, objectives=[Objective(LCR, MESH, sense="max")], limits=[]).build().solve(check=False)
    lcr_b = best.quantities.query("quantity == @LCR")["value"].min()
    assert last[front.quantity_column] == pytest.approx(lcr_b, rel=1e-5)
    assert front.ends["quantity"]["quantity"] == pytest.approx(lcr_b, rel=1e-5)


def test_front_is_monotone(front):
    t = front.solved
    q, f = t[front.quantity_column].to_numpy(), t[front.objective_column].to_numpy()
    assert np.all(np.diff(q) > 0) and np.all(np.diff(f) >= -1e-7)


def test_front_slope_from_the_multiplier_matches_re_solves_with_epsilon_moved(front):
    # d PPTE*/d ε from the ε multiplier against a central difference of two re-solves on the same branch of the
    # front (each started from the point itself)
    spec = FrontSpec(front_scene(), LCR, MESH, "max")
    eps, h = 1.45, 2e-3
    point = run_segment((spec, [eps], None))[0]
    lo, hi = (run_segment((spec, [e], point["_values"]))[0] for e in (eps - h, eps + h))
    assert point["status"] == lo["status"] == hi["status"] == OK
    difference = (hi["_objective"] - lo["_objective"]) / (2 * h)
    assert point["front_slope"] == pytest.approx(difference, rel=0.03)


def test_no_sampled_design_dominates_the_front(scene, front):
    # brute force: 400 random designs in the variable bounds, evaluated by the scene's model; none may beat a front
    # point in both PPTE (smaller) and smallest loaded contact ratio (larger)
    result = scene.build().solve(check=False)
    ev = scene_evaluator(result)
    table = result.solve.variables.set_index("name")
    rng = np.random.default_rng(0)
    values = {f"{MESH}.{v}": rng.uniform(table.loc[f"{MESH}.{v}", "lower"], table.loc[f"{MESH}.{v}", "upper"],
                                         400) for v in RELIEF}
    out = ev.evaluate(values)
    ppte = np.max([out[f"ppte_um[{MESH}]@T{t}"] for t in (150, 450)], axis=0)
    lcr = np.min([out[f"{LCR}[{MESH}]@T{t}"] for t in (150, 450)], axis=0)
    for _, row in front.solved.iterrows():
        better = (ppte < row[front.objective_column] - 1e-3) & (lcr > row[front.quantity_column] + 1e-4)
        assert not better.any()


def test_a_failed_point_is_recorded_with_its_typed_failure_and_the_study_goes_on(scene, front):
    spec = FrontSpec(front_scene(), LCR, MESH, "max")
    rows = run_segment((spec, [2.5, 1.4], None))      # LCR >= 2.5 is beyond the largest reachable (~1.63)
    assert rows[0]["status"] in ("InfeasibleProblemError", "NumericalSolveError", "IterationLimitError")
    assert rows[0]["error"]
    assert rows[1]["status"] == OK and rows[1]["_quantity"] >= 1.4 - 1e-6


def test_front_plot_draws_and_annotates_the_knee(front, tmp_path):
    fig = front.plot()
    fig.savefig(tmp_path / "front.png")
    assert (tmp_path / "front.png").stat().st_size > 5000
    knee = front.knee()
    assert knee["status"] == OK
    assert any("knee" in t.get_text() for t in fig.axes[0].texts)
    # the knee's design in words and units (not raw variable keys): "crank-cam tip relief 1 = 9.2 µm"
    note = next(t.get_text() for t in fig.axes[0].texts if "knee" in t.get_text())
    assert "tip relief 1 = " in note and "µm" in note and "_um" not in note and "start roll = " in note
    assert fig.axes[0].get_xlabel() == f"loaded contact ratio, {MESH} [-]"      # a ratio: dimensionless
    assert fig.axes[0].get_ylabel() == f"ppte, {MESH} [µm]"


def test_bad_fronts_raise_clear_errors(scene):
    with pytest.raises(GearoptInputError, match="not in the scene vocabulary"):
        pareto_front(scene, "no_such_quantity", MESH)
    with pytest.raises(GearoptInputError, match="points=2"):
        pareto_front(scene, LCR, MESH, points=2)
    with pytest.raises(GearoptInputError, match="not a mesh"):
        pareto_front(scene, LCR, "no-mesh", points=3)
    # tip relief does not change the largest contact stress (single-pair contact mid-profile): the ends coincide
    with pytest.raises(GearoptInputError, match="coinciding ends"):
        pareto_front(scene, "max_contact_stress_MPa", MESH, points=3)



def test_a_front_does_not_depend_on_what_an_earlier_front_left_in_the_cached_model():
    # the ε model is cached per process; a segment started elsewhere moves its initial guesses -- the next front
    # must still start its ends from the scene's declared start (same iterations, same points)
    scene = relief_scene(min_lcr=1.25, stress_limit=False)
    first = pareto_front(scene, LCR, MESH, points=3, refine=False)
    odd = {f"{MESH}.{v}": x for v, x in zip(RELIEF, (35.0, 2.0, 20.0, 27.0))}
    run_segment((FrontSpec(scene, LCR, MESH, "max"), [1.3], odd))
    again = pareto_front(scene, LCR, MESH, points=3, refine=False)
    cols = [c for c in first.table.columns if c != "solve_time_s"]
    assert again.table[cols].equals(first.table[cols])


def test_a_point_warm_started_from_its_neighbours_solve_reaches_the_same_optimum_in_fewer_iterations():
    # pareto_front's refinement points start from a solved neighbour: from its WarmStartPoint (primal values and
    # multipliers) rather than from its values alone -- the same optimum, fewer iterations
    scene = relief_scene(min_lcr=1.25, stress_limit=False)
    spec = FrontSpec(scene, LCR, MESH, "max")
    start = {f"{MESH}.{v}": x for v, x in zip(RELIEF, (12.0, 12.0, 26.0, 23.5))}
    (neighbour,) = run_segment((spec, [1.30], start))
    assert neighbour["status"] == OK and neighbour["_warm"] is not None
    (cold,) = run_segment((spec, [1.32], neighbour["_values"]))
    (warm,) = run_segment((spec, [1.32], neighbour["_values"], neighbour["_warm"]))
    assert cold["status"] == OK and warm["status"] == OK
    assert warm["_objective"] == pytest.approx(cold["_objective"], rel=1e-6)
    assert warm["_quantity"] == pytest.approx(cold["_quantity"], rel=1e-6)
    assert warm["iterations"] < cold["iterations"]


def test_a_front_with_refinement_on_another_train_and_other_names(renamed_minimal_path):
    # the packaged minimal pair with its gears renamed: the ends, the first grid and the refinement points (warm
    # from their neighbours) all solve, and the front trades PPTE for loaded contact ratio monotonically
    import gearopt as go
    from gearopt.data import train_from_data
    from gearopt.design.scene import DesignVariable, LoadCase, Limit, Scene

    system = go.load_system(renamed_minimal_path)
    mesh = "sun_gear-drum_gear"
    torque = system.meshes[mesh].design_torque_Nm
    scene = Scene("other train", train=train_from_data(system.data, "spur"),
                  load_cases=[LoadCase(f"T{f:g}", f * torque) for f in (0.5, 1.0)],
                  variables=[DesignVariable(v, mesh) for v in RELIEF],
                  objectives=[Objective("ppte_um", mesh, aggregate="max")],
                  limits=[Limit(LCR, mesh, lower=1.1)], ltca_options={"positions": 24})
    front = pareto_front(scene, LCR, mesh, points=5)
    table = front.table
    assert len(table) == 5 and (table["status"] == OK).all()
    q, o = table[front.quantity_column].to_numpy(), table[front.objective_column].to_numpy()
    order = np.argsort(q)
    assert np.all(np.diff(o[order]) >= -1e-6 * np.abs(o).max())      # more contact ratio costs PPTE
    assert q.max() > q.min() + 1e-3


def test_a_front_builds_one_model_and_its_ends_switch_objectives_without_a_new_nlp_solver():
    # the ε model carries both ends' objectives behind a weight parameter: the objective's end, the quantity's own
    # optimum and the lexicographic end re-solve one NLP solver (a new objective would make CasADi build another,
    # which costs about as much as a short solve); the warm-started points add one more (other Ipopt options)
    from gearopt.studies.epsilon import epsilon_model

    from gearopt.studies.epsilon import _MODELS

    scene = relief_scene(min_lcr=1.22, stress_limit=False)
    key = FrontSpec(scene, LCR, MESH, "max").key()
    front = pareto_front(scene, LCR, MESH, points=3, refine=False)
    # one model for the ends and the points: the spec's key (a pickle of the scene) is the same after the scene's
    # pairs have cached their geometry (it named a second model, built again, before)
    assert FrontSpec(scene, LCR, MESH, "max").key() == key and key in _MODELS
    model = epsilon_model(FrontSpec(scene, LCR, MESH, "max"))
    assert (front.table["status"] == OK).all()
    assert model.problem.solver_builds == 1           # three end solves and a cold first point
    pareto_front(scene, LCR, MESH, points=5, refine=False)
    assert model.problem.solver_builds == 2           # its second and third points warm from the first
    # the quantity's own optimum really optimised the quantity: no design of the front exceeds it
    assert front.table[front.quantity_column].max() == pytest.approx(front.ends["quantity"]["quantity"], rel=1e-9)
    with pytest.raises(GearoptInputError, match="objective='pressure'"):
        model.solve(None, objective="pressure")

