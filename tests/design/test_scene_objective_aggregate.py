"""Several objectives combined by their largest (``Scene(objective_aggregate="max")``): the epigraph bound equals the
largest scaled objective at the optimum, and started from the sum's optimum the minimax design has a largest PPTE no
higher than the sum's."""

from dataclasses import replace

import pytest

import gearopt as go
from gearopt.design.scene import DesignVariable, LoadCase, Objective, Scene
from gearopt.errors import GearoptInputError

MESHES = ("crank-cam", "cam-ac")


def scene(aggregate: str) -> Scene:
    return Scene("two meshes", train=go.load_default_train("spur"),
                 load_cases=[LoadCase("design", {"crank-cam": 300.0, "cam-ac": 240.0})],
                 variables=[DesignVariable(v, m) for m in MESHES for v in ("tip_relief_1_um", "tip_relief_2_um")],
                 objectives=[Objective("ppte_um", m) for m in MESHES], objective_aggregate=aggregate,
                 ltca_options={"positions": 24})


def largest_ppte(result) -> float:
    return float(result.quantities.query("quantity == 'ppte_um'")["value"].max())


def test_minimax_of_two_meshes_is_no_worse_than_the_sum_on_its_own_measure():
    total = scene("sum").build().solve(check=False)
    built = scene("max").build(initial=total.values)
    assert "objectives.max" in built.problem.variable_names
    minimax = built.solve(check=False)
    assert largest_ppte(minimax) <= largest_ppte(total) * (1 + 1e-6)
    # the bound is the largest objective (PPTE over its scale, weight 1) at the optimum
    ppte = minimax.quantities.query("quantity == 'ppte_um'")["value"].to_numpy()
    scale = go.design.scene_terms.quantity_kind("ppte_um").scale
    assert minimax.solve.values["objectives.max"] == pytest.approx(ppte.max() / scale, rel=1e-6)
    # with reliefs of their own the meshes do not trade: the larger one is at its own minimum, as in the sum
    assert largest_ppte(minimax) == pytest.approx(largest_ppte(total), rel=1e-5)


def test_objective_aggregate_is_checked():
    with pytest.raises(GearoptInputError, match="objective_aggregate"):
        scene("mean").build()
    bad = replace(scene("max"), objectives=[Objective("ppte_um", "crank-cam"),
                                            Objective("loaded_contact_ratio", "cam-ac", sense="max")])
    with pytest.raises(GearoptInputError, match="minimised"):
        bad.build()
