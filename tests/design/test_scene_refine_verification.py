"""What the semi-infinite refinement verifies. Stress limits are semi-infinite too: the maximum contact and root stress of a mesh are maxima over the continuum
of mesh positions, like PPTE. The refinement adds the exact LTCA's stress peak positions where the smooth maximum
misses the exact one (reference: the exact numeric LTCA of the same design, gearopt.contact.ltca, itself validated
against ISO 6336 and the analytic constant-stiffness PPTE in tests/contact). A minimax PPTE objective is verified
by its largest PPTE, the number the design is judged by."""

import dataclasses

import numpy as np
import pytest

import gearopt as go
from gearopt.contact.ltca import ltca
from gearopt.design.scene import DesignVariable, Limit, LoadCase, Objective, Scene
from gearopt.design.scene_contact import peak_fractions

MESH = "crank-cam"


@pytest.fixture(scope="module")
def helical_train():
    return dataclasses.replace(go.load_default_train("spur"), helix_angle_deg=8.0)


def test_peak_fractions_are_the_positions_of_the_exact_stress_maxima(helical_train):
    pair = helical_train.pairs[MESH]
    r = ltca(pair, 300.0, positions=40, slices=13)
    fractions = np.arange(40) / 40
    got = peak_fractions([r.contact_stress_MPa, r.root_stress_MPa[0]], fractions, neighbours=1)
    for a in (r.contact_stress_MPa, r.root_stress_MPa[0]):
        i = int(np.argmax(np.asarray(a).reshape(40, -1).max(axis=1)))
        assert {fractions[(i - 1) % 40], fractions[i], fractions[(i + 1) % 40]} <= set(got)
    assert len(got) <= 6


def test_a_stress_that_misses_its_exact_peak_is_refined_until_it_agrees(helical_train):
    """8 deg crank-cam over three torques, 16 positions, a tight tolerance (0.2 %) on a stress and an absolute PPTE
    floor (1 um) so loose that PPTE alone never asks for a re-solve: the first solve's root stress is off by more
    than the tolerance, the stress peaks join the set and the re-solve agrees."""
    scene = Scene("stress", train=helical_train, load_cases=[LoadCase(f"{f}x", f * 300.0) for f in (0.5, 1.0, 1.5)],
                  variables=[DesignVariable("tip_relief_1_um", MESH), DesignVariable("tip_relief_2_um", MESH)],
                  objectives=[Objective("ppte_um", MESH, aggregate="max")],
                  limits=[Limit("max_root_stress_MPa", MESH, upper=1000.0)],
                  ltca_options={"positions": 16, "helical_slices": 11, "max_refinements": 4,
                                "refine_stress_tolerance": 0.002, "refine_abs_tolerance_um": 1.0})
    result = scene.build().solve()
    ref = result.refinement
    assert ref["max_stress_error"].iloc[0] > 0.002 and not ref["admissible"].iloc[0]
    assert len(ref) >= 2 and ref["positions"].iloc[-1] > ref["positions"].iloc[0]
    assert ref.attrs["status"] == "converged" and ref.attrs["verified"]
    assert result.exact_check.filter(like="stress_MPa_error").to_numpy().max() <= 0.002


def _agreement_case(objective_aggregate: str, limits=()):
    """Two meshes, one load case: crank-cam sets the largest PPTE (smooth 3.00 vs exact 3.03 um, 1 %); cam-ac lies
    below it and its smooth PPTE misses the exact one by 18 % (1.00 vs 1.22 um)."""
    from types import SimpleNamespace

    import pandas as pd

    from gearopt.design.scene import Objective

    objectives = [Objective("ppte_um", m) for m in ("crank-cam", "cam-ac")]
    built = SimpleNamespace(scene=SimpleNamespace(objectives=objectives, objective_aggregate=objective_aggregate,
                                                  limits=list(limits)))
    quantities = pd.DataFrame({"role": "objective", "quantity": "ppte_um", "target": ["crank-cam", "cam-ac"],
                               "load_case": "design", "value": [3.00, 1.00]})
    exact = pd.DataFrame({"mesh": ["crank-cam", "cam-ac"], "load_case": "design", "ppte_um": [3.03, 1.22],
                          "smooth_ppte_um": [3.00, 1.00]})
    return built, quantities, exact


def test_a_minimax_objective_is_verified_by_its_largest_ppte():
    """For the largest PPTE of several meshes the verified number is that maximum: the smooth and exact objectives
    agree within 2 % although a mesh below the maximum differs by 18 %. Summed PPTE, or a PPTE limit, needs every
    mesh to agree."""
    from gearopt.design.scene import Limit
    from gearopt.design.scene_refine import ppte_agrees

    assert ppte_agrees(*_agreement_case("max"), tol=0.02, abs_tol_um=0.01)
    assert not ppte_agrees(*_agreement_case("sum"), tol=0.02, abs_tol_um=0.01)
    assert not ppte_agrees(*_agreement_case("max", [Limit("ppte_um", "cam-ac", upper=2.0)]), tol=0.02,
                           abs_tol_um=0.01)
    built, quantities, exact = _agreement_case("max")
    exact.loc[1, "ppte_um"] = 3.5                     # cam-ac is the largest after all: the objectives disagree
    assert not ppte_agrees(built, quantities, exact, tol=0.02, abs_tol_um=0.01)


def test_a_lower_limit_the_exact_ltca_breaks_is_named_with_its_shortfall():
    """The smooth loaded contact ratio counts a pair whose gap has just closed as partly loaded, so an optimum can
    meet the limit smoothly while the exact count lies below it (seen on the default spur crank-cam mesh: exact 1.165
    against a limit of 1.2): the refinement names each broken (mesh, load case) with its shortfall; a value within
    the relative tolerance is not broken, nor is a load case the limit does not cover."""
    from types import SimpleNamespace

    import pandas as pd

    from gearopt.design.scene import Limit
    from gearopt.design.scene_refine import exact_lower_limit_shortfalls

    limits = [Limit("loaded_contact_ratio", "crank-cam", lower=1.2),
              Limit("loaded_contact_ratio", "cam-ac", lower=1.2, load_cases=("1x",))]
    built = SimpleNamespace(scene=SimpleNamespace(limits=limits))
    exact = pd.DataFrame({"mesh": ["crank-cam", "crank-cam", "cam-ac", "cam-ac"],
                          "load_case": ["0.5x", "1x", "0.5x", "1x"],
                          "loaded_contact_ratio": [1.165, 1.1995, 1.0, 1.25]})
    got = exact_lower_limit_shortfalls(built, exact, tolerance=1e-3)
    assert got == {"loaded_contact_ratio[crank-cam]@0.5x": pytest.approx(0.035)}
    assert exact_lower_limit_shortfalls(built, exact, tolerance=0.03) == {}       # 1.165 is within 3 % of 1.2


def test_a_re_solve_budget_follows_the_longest_solve_so_far():
    """The re-solves of one refinement may grow steadily: on the co-design scene of benchmarks/bench_codesign.py
    (root shift and two reliefs, 40 positions to start) the solves took 35, 40, 138, 193, 252, 101 and 38 Ipopt
    iterations (measured, scene_refine's RESOLVE_BUDGET docstring). Every one of them fits the budget its
    predecessors give; a budget of 4 times the first solve (140) would stop the fourth. A re-solve heading for an
    infeasible stop after a short history (the low-helix co-design: 278 iterations after a first solve of 56) is
    still stopped, and the caller's own max_iter caps the budget."""
    from gearopt.design.scene_refine import RESOLVE_BUDGET_MIN_ITERATIONS, resolve_budget

    measured = [35, 40, 138, 193, 252, 101, 38]
    for k in range(1, len(measured)):
        assert measured[k] <= resolve_budget(measured[:k])
    assert resolve_budget(measured[:3]) == 4 * 138 and 193 > 4 * measured[0]
    assert resolve_budget([56]) < 278
    assert resolve_budget([5]) == RESOLVE_BUDGET_MIN_ITERATIONS
    assert resolve_budget(measured[:3], max_iter=100) == 100


def test_a_re_solve_budget_without_solves_is_refused_by_name():
    from gearopt.design.scene_refine import resolve_budget
    from gearopt.errors import GearoptInputError

    with pytest.raises(GearoptInputError, match="iterations"):
        resolve_budget([])
    with pytest.raises(GearoptInputError, match="iterations"):
        resolve_budget([12, -1])


def test_a_refinement_moving_away_from_the_design_and_the_agreement_stops_there():
    """Issue 29 item 3 (refine only while a re-solve improves): the crank-cam tip reliefs of both flanks at the data's
    design torque, the unmodified design's exact contact stress as its limit and a loaded contact ratio >= 1.2 (the
    sequential scene of ``benchmarks/bench_codesign.py``). The loop ends at the first re-solve that lowers neither
    the best exact objective nor the smallest smooth-vs-exact PPTE error before it; every re-solve before it lowered
    one of the two. Its design is within the refinement's tolerance (2 %) of the full loop's (stop_on_divergence
    off, which solves more often), both judged by the exact LTCA."""
    train = go.load_default_train("spur")
    torque = go.load_system().design_torques_Nm()[MESH]
    stress = ltca(train.pairs[MESH], torque).max_contact_stress_MPa
    scene = Scene("reliefs", train=train, load_cases=[LoadCase("design", {MESH: torque})],
                  variables=[DesignVariable(n, f) for f in ("crank:driving", "cam:driven")
                             for n in ("tip_relief_um", "tip_relief_start_roll_deg")],
                  objectives=[Objective("ppte_um", MESH)],
                  limits=[Limit("max_contact_stress_MPa", MESH, upper=stress),
                          Limit("loaded_contact_ratio", MESH, lower=1.2)])
    stopped = scene.build().solve()
    ref = stopped.refinement
    assert "stop_on_divergence" in ref.attrs["status"] and len(ref) >= 2
    tol = 0.02
    for i in range(1, len(ref)):
        before = ref.iloc[:i]
        best = before.loc[before["admissible"], "exact_objective"].min()
        lowered = bool(ref["admissible"].iloc[i]) and ref["exact_objective"].iloc[i] < best - tol * abs(best)
        closer = ref["max_ppte_error"].iloc[i] <= before["max_ppte_error"].min()
        assert (lowered or closer) == (i < len(ref) - 1)        # only the last re-solve moved away from both
    full = dataclasses.replace(scene, ltca_options={"stop_on_divergence": False}).build().solve()
    assert len(full.refinement) > len(ref)
    assert stopped.exact_check["ppte_um"].max() <= full.exact_check["ppte_um"].max() * (1 + tol)
