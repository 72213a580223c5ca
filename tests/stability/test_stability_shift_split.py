"""Stability of the profile-shift split NLP (gearopt.design.shift_distribution.optimise_shift_split) over random
scenes and at the edges of feasibility around the default crank-cam pair.

Contract (project standard): every case either solves, and the exact re-check of GearPair.constraints at the
returned split meets every limit within 1e-6, or raises a typed gearopt error whose message names a constraint or
parameter. References for "feasible"/"infeasible" are brute-force scans over the split computed in
stability_cases.py (grid 1e-4 in x1), not the solver.
"""

from __future__ import annotations

import os
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.dirname(__file__))

import stability_cases as sc

RANDOM = sc.shift_split_random_cases(12, seed=2024)
EXTREME = sc.shift_split_extreme_cases(8, seed=7)


def test_feasible_centre_distance_range_brackets_the_nominal_centre_distance():
    lo, hi = sc.feasible_centre_distance_range()
    nominal = float(sc.default_pair().centre_distance_mm)
    assert lo < nominal < hi
    assert 5.0 < hi - lo < 10.0           # sum of shifts from about -0.7 to +1.9 at m = 3 mm


@pytest.mark.parametrize("k", range(len(RANDOM)))
def test_random_scene_solves_or_fails_typed(k):
    outcome = sc.run_case("shift_split_random", RANDOM[k])
    sc.assert_finite_or_typed(outcome)
    # every random scene lies inside the brute-force feasible range of centre distances, so it must solve
    assert outcome.kind == "solved", outcome.describe()
    assert outcome.details["worst_margin"] >= -sc.MARGIN_TOL


EXPECTED_NAMES = {"min_contact_ratio": "contact_ratio_margin", "min_tip_thickness_ratio": "tip_thickness_margin"}


@pytest.mark.parametrize("k", range(len(EXTREME)))
def test_edge_of_feasibility(k):
    """Limits 0.002 below / above the brute-force maximum, centre distances just inside / 0.05 mm outside the
    feasible range: the feasible side must solve, the infeasible side must fail typed, naming the limit."""
    case = EXTREME[k]
    outcome = sc.run_case("shift_split_extreme", case)
    sc.assert_finite_or_typed(outcome)
    if case["expected"] == "feasible":
        assert outcome.kind == "solved", outcome.describe()
    else:
        assert outcome.kind == "typed_failure", outcome.describe()
        assert outcome.error == "InfeasibleProblemError"
        for key, name in EXPECTED_NAMES.items():
            if key in case:
                assert name in outcome.message, outcome.describe()


def test_elastic_relaxation_of_a_just_infeasible_contact_ratio_is_the_gap():
    """Contact-ratio limit 0.002 above the achievable maximum: the least relaxation is 0.002 (brute force)."""
    best = sc.split_limits(sc.default_pair())["max_contact_ratio"]
    p = sc.shift_split_problem(sc.default_pair(), min_contact_ratio=best + 0.002)
    res = p.solve_elastic()
    assert not res.feasible
    assert res.table.iloc[0]["name"] == "contact_ratio_margin"
    assert res.relaxation("contact_ratio_margin") == pytest.approx(0.002, abs=2e-6)


def test_generic_multistart_on_the_split_finds_one_optimum_from_every_start():
    """Eight Latin-hypercube starts over x1 in [-1, 2] and the epigraph variable: the optimum of the maximin tip
    thickness is unique, so every start must converge to the same split (the library's own solve from lambda 0.5)."""
    p = sc.shift_split_problem(sc.default_pair())
    ms = p.multistart(8, seed=3)
    direct = sc.run_case("shift_split_random", {"centre_distance_mm": None})
    assert ms.success_rate == 1.0, ms.table[["status", "error"]]
    x1 = [r.values["profile_shift_1"] for r in ms.results]
    np.testing.assert_allclose(x1, direct.details["profile_shift_1"], atol=1e-6)
