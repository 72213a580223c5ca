"""The figure writer: figures saved or built in the background worker are the files the same calls write at once
(same pixel size), the block's resolution applies to figures saved without one, and bad input is named."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import pytest  # noqa: E402

from gearopt.errors import GearoptInputError  # noqa: E402
from gearopt.report import figure_writer  # noqa: E402
from gearopt.report.ltca_figures import plot_percentage_change  # noqa: E402


def line_figure():
    fig, ax = plt.subplots(figsize=(4.0, 3.0))
    ax.plot([0, 1, 2], [1, 0, 2])
    return fig


def test_background_files_equal_the_direct_ones_and_the_block_dpi_applies(tmp_path):
    import pandas as pd

    table = pd.DataFrame({"ppte_um": [2.0, 1.0], "max_contact_stress_MPa": [900.0, 950.0]},
                         index=pd.Index(["helical", "spur"], name="design"))
    figure_writer.save(line_figure(), tmp_path / "direct.png", dpi=50)
    with figure_writer.background_figures(dpi=50):
        figure_writer.save(line_figure(), tmp_path / "background.png")
        figure_writer.plot_later(plot_percentage_change, tmp_path / "built_there.png", table, "helical")
        figure_writer.save(line_figure(), tmp_path / "explicit.png", dpi=100)
    direct, background = mpimg.imread(tmp_path / "direct.png"), mpimg.imread(tmp_path / "background.png")
    assert direct.shape == background.shape == (150, 200, 4)            # 4 x 3 in at 50 dpi
    assert mpimg.imread(tmp_path / "explicit.png").shape == (300, 400, 4)
    assert (tmp_path / "built_there.png").stat().st_size > 1000
    figure_writer.save(line_figure(), tmp_path / "after.png")           # the block's dpi ends with it
    assert mpimg.imread(tmp_path / "after.png").shape[:2] == (3 * figure_writer.DEFAULT_DPI,
                                                               4 * figure_writer.DEFAULT_DPI)


@pytest.mark.parametrize("dpi", [0, 5000, 72.5, True])
def test_bad_dpi_is_named(dpi):
    with pytest.raises(GearoptInputError, match="dpi"):
        with figure_writer.background_figures(dpi=dpi):
            pass
