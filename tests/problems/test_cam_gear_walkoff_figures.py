"""Every figure the main job writes is readable (gearopt.report.figure_checks: nothing cut off or drawn over
another, titled, axes labelled with units, no empty axes), checked on the figure objects before they are saved."""

import pytest

from gearopt.report import figure_writer
from gearopt.report.figure_checks import readability_issues

from conftest import load_script


@pytest.fixture(scope="module")
def checked(tmp_path_factory):
    found, save = {}, figure_writer.save

    def checking_save(fig, path, dpi=120):
        found[path.name] = (readability_issues(fig), fig)
        return save(fig, path, dpi=dpi)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(figure_writer, "save", checking_save)
        out = tmp_path_factory.mktemp("figures")
        assert load_script("cam_gear_walkoff").main(["--quick", "--out", str(out)]) == 0
    return found, out


def test_every_figure_of_the_main_job_is_readable(checked):
    found, out = checked
    written = {p.name for p in (out / "figures").glob("*.png")}
    assert written == set(found)                       # every file went through the check
    assert {"campbell_spur.png", "harris_crank_cam.png", "te_crank_cam.png", "flank_maps_crank_cam.png",
            "change_load_cases_crank_cam.png", "failure_reproduction_creep_map.png"} <= written
    assert {name: issues for name, (issues, _) in found.items() if issues} == {}


def test_creep_map_has_one_legend_for_both_joints(checked):
    found, _ = checked
    fig = found["failure_reproduction_creep_map.png"][1]
    assert len(fig.legends) == 1 and all(a.get_legend() is None for a in fig.axes)
    assert fig.get_suptitle()
