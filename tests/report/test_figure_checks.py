"""The readability check finds each kind of problem it names, from the figure's artists, and passes a clean figure."""

import matplotlib.pyplot as plt
import numpy as np

from gearopt.report.figure_checks import readability_issues


def _clean():
    fig, ax = plt.subplots(figsize=(5.0, 3.5), layout="constrained")
    ax.plot([0.0, 1.0, 2.0], [1.0, 3.0, 2.0], label="curve")
    ax.set_xlabel("torque [N m]")
    ax.set_ylabel("PPTE [µm]")
    ax.set_title("clean")
    ax.legend(loc="lower right", fontsize=8)
    return fig, ax


def test_a_clean_figure_has_no_issue():
    fig, _ = _clean()
    assert readability_issues(fig) == []
    plt.close(fig)


def test_each_problem_is_found():
    fig, ax = _clean()
    ax.set_xlabel("torque")                                        # no unit
    ax.annotate("left", (1.0, 2.0), fontsize=9)
    ax.annotate("right", (1.0, 2.0), xytext=(2, 0), textcoords="offset points", fontsize=9)   # on top of "left"
    ax.annotate("far out", (0.0, 0.0), xytext=(-400, 0), textcoords="offset points",
                annotation_clip=False).set_in_layout(False)
    ax.text(1.5, 1.5, "tiny", fontsize=4)
    ax.text(2.0, 2.0, "over the edge of the panel", fontsize=8)
    issues = readability_issues(fig)
    assert any("'torque' has no unit" in i for i in issues)
    assert any("'left' and 'right' overlap" in i for i in issues)
    assert any("'far out' is cut off" in i for i in issues)
    assert any("'tiny' is 4 pt" in i for i in issues)
    assert any("'over the edge of the panel' spills out of its panel" in i for i in issues)
    plt.close(fig)


def test_empty_axes_untitled_panels_and_unlabelled_colour_bars_are_found():
    fig, (a, b) = plt.subplots(1, 2, figsize=(8.0, 3.0), layout="constrained")
    mesh = a.pcolormesh(np.arange(4.0).reshape(2, 2))
    a.set_xlabel("x [mm]")
    a.set_ylabel("y [mm]")
    a.set_title("filled")
    fig.colorbar(mesh, ax=a, label="stress")
    b.set_xlabel("x [mm]")
    b.set_ylabel("y [mm]")
    issues = readability_issues(fig)
    assert any("axes 1 (untitled) is empty" in i for i in issues)
    assert any(i.startswith("no title") for i in issues)
    assert any("colour bar label 'stress'" in i for i in issues)
    plt.close(fig)


def test_a_legend_over_a_bar_is_found():
    fig, ax = plt.subplots(figsize=(4.0, 3.0), layout="constrained")
    ax.barh([0, 1], [10.0, 9.0], label="design")
    ax.set_yticks([0, 1], ["PPTE [µm]", "stress [MPa]"])        # categorical axis: its tick labels name it
    ax.set_xlabel("change [%]")
    ax.set_title("bars")
    ax.legend(loc="center")
    assert any("the legend covers a bar" in i for i in readability_issues(fig))
    plt.close(fig)
