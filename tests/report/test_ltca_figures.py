"""Figures people read: TE with the mean removed and no wrap-around segment, Harris map with the design range
shaded and every curve distinguishable, change chart per load case with readable labels, flank maps with common
axes and one colour scale (and bar) per quantity row."""

import matplotlib
import numpy as np
import pandas as pd
import pytest

import gearopt as go
from gearopt.report import ltca_figures as figs
from gearopt.report.figure_checks import readability_issues


@pytest.fixture(scope="module")
def results():
    pair = go.load_default_train("spur").pairs["crank-cam"]
    mods = go.Microgeometry(tip_relief_um=(10.0, 10.0), tip_relief_start_roll_deg=(25.0, 22.0))
    common = dict(positions=40, speed_rpm=2500.0)
    return {"unmodified": go.ltca(pair, 300.0, **common), "relieved": go.ltca(pair, 300.0, microgeometry=mods, **common)}


def test_te_mean_removed_without_wrap_segment(results):
    fig = figs.plot_transmission_error(results)
    lines = fig.axes[0].get_lines()
    for line, r in zip(lines, results.values()):
        y = line.get_ydata()
        assert len(y) == len(r.transmission_error_um)           # one cycle, no segment back to the start
        assert abs(np.mean(y)) < 1e-9 and np.ptp(y) == pytest.approx(r.ppte_um)
    raw = figs.plot_transmission_error(results, align="none").axes[0].get_lines()[0].get_ydata()
    np.testing.assert_allclose(raw, results["unmodified"].transmission_error_um)
    assert readability_issues(fig) == []
    matplotlib.pyplot.close("all")


def test_te_of_a_refined_position_set_and_of_gear_2_driving_is_one_forward_pass():
    """A refined set comes in any order and gear 2 driving walks gear 1's roll angle backwards: the line must
    still run once forward over the cycle, not jump back and forth (segments that join far-apart positions)."""
    pair = go.load_default_train("spur").pairs["crank-cam"]
    fractions = [0.55, 0.05, 0.95, 0.35, 0.75, 0.15, 0.65]
    cases = {"refined": go.ltca(pair, 300.0, positions=fractions, speed_rpm=2500.0),
             "gear 2 driving": go.ltca(pair, 300.0, positions=12, driving_gear=2, speed_rpm=2500.0)}
    pitch_deg = np.degrees(cases["refined"].layout.base_pitch_mm / (0.5 * cases["refined"].layout.base_diameter_mm[0]))
    fig = figs.plot_transmission_error(cases, align="none")
    for line, r in zip(fig.axes[0].get_lines(), cases.values()):
        x, y = line.get_xdata(), line.get_ydata()
        assert x[0] == 0.0 and np.all(np.diff(x) > 0.0)             # forward only: no segment back to the start
        assert x[-1] < pitch_deg                                      # within one mesh cycle
        for xi, yi in zip(x, y):                                      # every point keeps its own TE
            k = np.argmin(np.abs(r.position_roll_deg - r.position_roll_deg.min() - xi))
            assert yi == r.transmission_error_um[k]
    matplotlib.pyplot.close("all")


def test_harris_map_shades_the_design_range_and_keeps_curves_apart():
    torques = np.array([100.0, 200.0, 300.0, 400.0])
    same = pd.DataFrame({"torque_Nm": torques, "ppte_um": torques / 50.0})
    maps = {"helical": same, "spur_unmodified": same.copy(), "spur_optimised": same.assign(ppte_um=1.0)}
    fig = figs.plot_harris_map(maps, design_range_Nm=(150.0, 450.0), design_torque_Nm=300.0)
    ax = fig.axes[0]
    span = ax.patches[0]                                            # Rectangle (matplotlib >= 3.9) or Polygon
    xs = ([span.get_x(), span.get_x() + span.get_width()] if hasattr(span, "get_width")
          else np.asarray(span.get_xy())[:, 0])
    assert (min(xs), max(xs)) == (150.0, 450.0)
    curves = [l for l in ax.get_lines() if len(l.get_xdata()) == len(torques)]
    assert len(curves) == 3
    styles = {(l.get_linestyle(), l.get_marker()) for l in curves}
    assert len(styles) == 3                                        # identical data stay distinguishable
    assert any(np.allclose(l.get_xdata(), 300.0) for l in ax.get_lines() if l not in curves)
    assert readability_issues(fig) == []
    matplotlib.pyplot.close("all")


def test_change_chart_has_a_panel_per_load_case_with_readable_labels():
    table = pd.DataFrame({"design": ["unmodified", "optimised"] * 2, "torque_Nm": [150.0, 150.0, 300.0, 300.0],
                          "ppte_um": [3.0, 3.3, 6.0, 1.5], "max_contact_stress_MPa": [550.0, 550.0, 770.0, 770.0]})
    fig = figs.plot_percentage_change(table.set_index("design"), "unmodified", by="torque_Nm")
    panels = [a for a in fig.axes if a.get_title()]
    assert [a.get_title() for a in panels] == ["torque 150 N m", "torque 300 N m"]
    assert [t.get_text() for t in panels[0].get_yticklabels()] == ["PPTE [µm]", "max contact stress [MPa]"]
    widths = [p.get_width() for p in panels[1].patches]
    assert widths[0] == pytest.approx(-75.0)                         # PPTE 6.0 -> 1.5 um at 300 N m
    texts = [t.get_text() for t in panels[0].texts]
    assert "+10.0 %" in texts                                        # the worse low-load case is labelled
    assert len(fig.legends) == 1 and all(a.get_legend() is None for a in panels)   # below the panels, on no bar
    assert readability_issues(fig) == []                             # no label cut off or drawn over another
    matplotlib.pyplot.close("all")


def test_change_chart_labels_stay_readable_with_long_names_and_large_changes():
    names = ["helical", "spur_unmodified", "spur_optimised"]
    table = pd.DataFrame({"ppte_um": [6.8, 6.7, 0.75], "max_contact_stress_MPa": [770.0, 765.0, 771.0],
                          "max_root_stress_1_MPa": [170.0, 178.0, 197.0],
                          "max_root_stress_2_MPa": [150.0, 157.0, 162.0],
                          "max_flash_temperature_C": [127.0, 119.0, 119.0],
                          "max_load_intensity_N_per_mm": [220.0, 220.2, 220.2]}, index=names)
    fig = figs.plot_percentage_change(table, "helical", title="crank-cam: change against helical")
    assert readability_issues(fig) == []
    assert len(fig.axes[0].texts) == 2 * len(table.columns)          # every bar labelled
    matplotlib.pyplot.close("all")


def test_flank_grid_rows_share_axes_and_colour_scale(results):
    quantities = ("load_intensity", "contact_stress")
    fig = figs.plot_flank_grid(results, quantities)
    panels = [a for a in fig.axes if a.get_label() != "<colorbar>"]
    assert len(panels) == len(quantities) * len(results)
    assert len({a.get_xlim() for a in panels}) == 1                  # comparable axes
    for i in range(len(quantities)):
        row = panels[i * len(results):(i + 1) * len(results)]
        assert len({a.collections[0].get_clim() for a in row}) == 1  # one colour scale per quantity row
    colorbars = [a for a in fig.axes if a.get_label() == "<colorbar>"]
    assert [a.get_ylabel() for a in colorbars] == [figs.FLANK_QUANTITIES[q][0] for q in quantities]   # one per row
    for i, cb in enumerate(colorbars):                               # each bar shows its row's scale
        row = panels[i * len(results):(i + 1) * len(results)]
        assert cb.get_ylim() == pytest.approx(row[0].collections[0].get_clim())
    assert readability_issues(fig) == []
    matplotlib.pyplot.close("all")


def test_flank_grid_marks_where_a_design_has_no_contact():
    """A helical and a spur pair have different active flanks: on the common roll-angle axis the shorter one leaves
    part of its panel without data, which shows in the no-contact colour and is explained in the title."""
    helical = go.ltca(go.load_default_train("helical").pairs["crank-cam"], 300.0, positions=20, slices=3,
                      speed_rpm=2500.0)
    spur = go.ltca(go.load_default_train("spur").pairs["crank-cam"], 300.0, positions=20, speed_rpm=2500.0)
    fig = figs.plot_flank_grid({"helical": helical, "spur": spur}, ("load_intensity",), title="crank-cam")
    panels = [a for a in fig.axes if a.get_label() != "<colorbar>"]
    spans = [(m.get_coordinates()[0, 0, 0], m.get_coordinates()[0, -1, 0]) for m in (a.collections[0] for a in panels)]
    assert spans[0] != spans[1]
    assert all(matplotlib.colors.same_color(a.get_facecolor(), figs.NO_CONTACT_COLOUR) for a in panels)
    assert "no contact" in fig.get_suptitle() and fig.get_suptitle().startswith("crank-cam")
    matplotlib.pyplot.close("all")
