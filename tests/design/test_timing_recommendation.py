"""The timing case's recommendation checks that the dynamic peaks it judged are the recommended design's own
(issue 27, dynamics in the design loop): the torsional model of the design's own train simulated again."""

import dataclasses

import pytest

import gearopt as go
from gearopt.cases.timing_train.recommendation import DYNAMICS_AGREEMENT, design_peak_torques_Nm, dynamics_check
from gearopt.design.requirements import DynamicPeaks, TrainDesign

RUN = dict(cycles=1, run_in_cycles=0, rtol=1e-3)
SPEEDS = (3000.0,)


@pytest.fixture(scope="module")
def system():
    return go.load_system()


@pytest.fixture(scope="module")
def judged(system):
    """The peaks of the packaged spur train, as the main job's dynamics give them."""
    return DynamicPeaks(mesh_torques_Nm=design_peak_torques_Nm(system, TrainDesign(system.train("spur")), SPEEDS,
                                                               **RUN))


def test_the_packaged_spur_macro_needs_no_second_simulation(system, judged):
    check = dynamics_check(system, TrainDesign(system.train("spur")), judged, SPEEDS, **RUN)
    assert check["simulated"] is False and check["agrees"]


def test_another_root_shift_is_simulated_again_and_compared(system, judged):
    moved = TrainDesign(dataclasses.replace(system.train("spur"), root_profile_shift=0.25))
    check = dynamics_check(system, moved, judged, SPEEDS, **RUN)
    assert check["simulated"] is True
    own = check["own"]
    assert set(own) == set(judged.mesh_torques_Nm)
    change = max(abs(own[m][0] / t - 1.0) for m, (t, _) in judged.mesh_torques_Nm.items())
    assert check["max_change_percent"] == pytest.approx(100 * change, rel=1e-12)
    assert check["agrees"] == (change <= DYNAMICS_AGREEMENT)
    # the same train simulated twice gives the same peaks: the comparison measures the design, not the solver
    again = design_peak_torques_Nm(system, moved, SPEEDS, **RUN)
    assert {m: v[0] for m, v in again.items()} == pytest.approx({m: v[0] for m, v in own.items()}, rel=1e-9)
