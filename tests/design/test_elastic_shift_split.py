"""Elastic mode on a real gear NLP: the profile-shift split of the default crank-cam pair (gearopt.nlp.elastic on
gearopt.design.shift_distribution). The reference is a brute-force scan computed here."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import gearopt as go
from gearopt.nlp import Problem
from gearopt.design.shift_distribution import shift_split_problem as build_shift_split_problem
from gearopt.errors import InfeasibleProblemError


# --------------------------------------------------------------------------- a real case: the shift split

def shift_split_problem(pair, min_contact_ratio: float) -> Problem:
    """The NLP of optimise_shift_split ('max_min_tip_thickness'), unsolved, started at x1 = 0.2."""
    return build_shift_split_problem(pair, min_contact_ratio=min_contact_ratio, init=0.2)


def test_shift_split_with_impossible_contact_ratio_reports_the_contact_ratio_gap():
    """Default crank-cam pair (z 38/76, a = 172.24 mm): the worst-case transverse contact ratio over the free split
    x1 (x1 + x2 fixed) peaks near 1.62, so min_contact_ratio = 1.9 is infeasible. The least relaxation is
    1.9 - max over x1 of the worst-case contact ratio, found here by brute force over x1 in [-1, 2] (step 1e-4)
    among splits that meet every other limit."""
    pair = go.load_default_train("spur").pairs["crank-cam"]
    total = pair.profile_shifts[0] + pair.profile_shifts[1]
    grid = np.arange(-1.0, 2.0 + 1e-12, 1e-4)
    trial = replace(pair, profile_shifts=(grid, total - grid), tip_diameters_mm=None)
    margins = trial.constraints(min_tip_thickness_ratio=0.2, min_contact_ratio=0.0, worst_case=True,
                                iso_tr_4467_limits=True, min_backlash_mm=None)
    eps = np.asarray(margins.pop("contact_ratio_margin"), dtype=float)
    others_ok = np.all([np.asarray(v, dtype=float) >= 0.0 for v in margins.values()], axis=0)
    best_eps = eps[others_ok].max()
    best_x1 = grid[others_ok][eps[others_ok].argmax()]
    assert 1.55 < best_eps < 1.7                                 # a plausible spur contact ratio

    with pytest.raises(InfeasibleProblemError) as info:
        shift_split_problem(pair, 1.9).solve(elastic_on_failure=True)
    err = info.value
    top = err.relaxations.iloc[0]
    assert top["name"] == "contact_ratio_margin"
    assert top["relaxation"] == pytest.approx(1.9 - best_eps, abs=1e-5)
    assert err.relaxations["relaxation"].iloc[1:].max() < 1e-6   # nothing else has to move
    assert "contact_ratio_margin: lower bound 0 -> " in str(err)
    # phase 2 may trade up to 1e-6 of contact ratio for tip thickness: |dx1| <~ sqrt(2e-6 / eps'') ~ 1e-2
    assert err.elastic.values["profile_shift_1"] == pytest.approx(best_x1, abs=1e-2)


def test_shift_split_feasible_limit_reports_no_relaxation():
    pair = go.load_default_train("spur").pairs["crank-cam"]
    direct = shift_split_problem(pair, 1.2).solve()
    elastic = shift_split_problem(pair, 1.2).solve_elastic()
    assert elastic.feasible
    assert elastic.values["profile_shift_1"] == pytest.approx(direct.values["profile_shift_1"], abs=1e-4)
    assert elastic.objective == pytest.approx(direct.objective, rel=1e-5)
