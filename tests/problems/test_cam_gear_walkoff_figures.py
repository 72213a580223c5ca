"""Every figure the main job writes is readable (gearopt.report.figure_checks: nothing cut off or drawn over
another, titled, axes labelled with units, no empty axes), checked on the figure objects where they are drawn --
the main process, the figure writer's worker or the side process (``GEAROPT_FIGURE_CHECKS``, set by the shared
quick run of the main job)."""

import pytest

from conftest import figure_checks


@pytest.fixture(scope="module")
def checked(run_quick):
    out = run_quick("cam_gear_walkoff")
    return figure_checks(out), out


def test_every_figure_of_the_main_job_is_readable(checked):
    found, out = checked
    written = {p.name for p in (out / "figures").glob("*.png")}
    assert written == set(found)                       # every file went through the check
    assert {"campbell_spur.png", "harris_crank_cam.png", "te_crank_cam.png", "flank_maps_crank_cam.png",
            "change_load_cases_crank_cam.png", "failure_reproduction_creep_map.png",
            "trade_off_crank_cam.png"} <= written
    assert {name: r["issues"] for name, r in found.items() if r["issues"]} == {}


def test_creep_map_has_one_legend_for_both_joints(checked):
    found, _ = checked
    record = found["failure_reproduction_creep_map.png"]
    assert record["figure_legends"] == 1 and record["axes_legends"] == 0
    assert record["suptitle"]
