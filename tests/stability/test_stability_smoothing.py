"""The microgeometry NLP with the smooth LTCA's contact smoothing width towards zero
(LTCAModel(smoothing_um=0.01, 0.005)): it must converge or fail typed, and when it converges the exact LTCA check
holds (stability_cases.py tolerances). As the width shrinks the smooth model tends to the exact contact law, so the
exact PPTE of the optimum must not degrade (it may move to another local optimum: compared within 0.5 um).
"""

from __future__ import annotations

import math
import os
import sys

import pytest

sys.path.insert(0, os.path.dirname(__file__))

import stability_cases as sc

WIDTHS_UM = (0.05, 0.01, 0.005)


@pytest.fixture(scope="module")
def outcomes():
    return {w: sc.run_case("microgeometry_smoothing", {"smoothing_um": w, "torque_Nm": sc.DESIGN_TORQUE_NM})
            for w in WIDTHS_UM}


@pytest.mark.parametrize("width", WIDTHS_UM[1:])
def test_small_smoothing_converges_or_fails_typed(outcomes, width):
    outcome = outcomes[width]
    sc.assert_finite_or_typed(outcome)


def test_small_smoothing_designs_agree_with_the_default_width(outcomes):
    solved = {w: o for w, o in outcomes.items() if o.kind == "solved"}
    assert 0.05 in solved, outcomes[0.05].describe()
    for w, o in solved.items():
        assert math.isfinite(o.details["ppte_um"])
        assert abs(o.details["ppte_um"] - solved[0.05].details["ppte_um"]) < 0.5, (w, o.details)


@pytest.mark.parametrize("width", [0.0, -0.01])
def test_zero_or_negative_width_is_a_typed_input_error(width):
    outcome = sc.run_case("microgeometry_smoothing", {"smoothing_um": width})
    assert outcome.kind == "typed_failure" and "smoothing_um" in outcome.message
