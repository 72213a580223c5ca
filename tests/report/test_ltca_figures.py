"""Figures people read: TE with the mean removed and no wrap-around segment, Harris map with the design range
shaded and every curve distinguishable, change chart per load case with readable labels, flank maps with common
axes and one colour scale (and bar) per quantity row."""

import matplotlib
import numpy as np
import pandas as pd
import pytest

import gearopt as go
from gearopt.report import ltca_figures as figs


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
    assert {a.get_ylabel() for a in colorbars} >= {figs.FLANK_QUANTITIES[q][0] for q in quantities}
    matplotlib.pyplot.close("all")
