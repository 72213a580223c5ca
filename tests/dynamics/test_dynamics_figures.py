"""Campbell diagram table and figure (gearopt.report.dynamics_figures)."""

import math

import matplotlib
import numpy as np
import pytest

from gearopt.cases.timing_train import default_timing_model
from gearopt.dynamics import TorsionalNetwork
from gearopt.errors import GearoptInputError
from gearopt.report.dynamics_figures import DEFAULT_ORDERS, campbell_table, plot_campbell
from gearopt.report.figure_checks import readability_issues


def _two_mass_chain(j1=0.01, j2=0.02, k1=2.0e4, k2=1.0e4):
    # held boundary -- k1 -- J1 -- k2 -- J2 (torsional chain)
    net = TorsionalNetwork("chain", cycle_deg=720.0)
    net.add_inertia("ground", 1.0).add_inertia("a", j1).add_inertia("b", j2)
    net.add_shaft("ground", "a", k1).add_shaft("a", "b", k2)
    net.set_speed_boundary("ground")
    return net


def test_crossings_match_the_hand_computation():
    # closed form of the two-mass chain (det(K - w^2 M) = 0): J1 J2 w^4 - (J1 k2 + J2 (k1 + k2)) w^2 + k1 k2 = 0,
    # then each crossing at n = 60 f / order (f_mode = order x rpm / 60) inside the speed range
    j1, j2, k1, k2 = 0.01, 0.02, 2.0e4, 1.0e4
    a, b, c = j1 * j2, j1 * k2 + j2 * (k1 + k2), k1 * k2
    w2 = sorted([(b - math.sqrt(b * b - 4 * a * c)) / (2 * a), (b + math.sqrt(b * b - 4 * a * c)) / (2 * a)])
    f = [math.sqrt(v) / (2 * math.pi) for v in w2]                     # 89.05 and 355.6 Hz
    speeds = (600.0, 3000.0)
    expected = sorted((60.0 * fm / o, m + 1, o) for m, fm in enumerate(f) for o in DEFAULT_ORDERS
                      if speeds[0] <= 60.0 * fm / o <= speeds[1])
    table = campbell_table(_two_mass_chain(j1, j2, k1, k2), np.linspace(*speeds, 5))
    assert len(table) == len(expected) > 10
    np.testing.assert_allclose(table["speed_rpm"], [e[0] for e in expected], rtol=1e-9)
    assert list(table["mode"]) == [e[1] for e in expected]
    assert list(table["order"]) == [e[2] for e in expected]
    np.testing.assert_allclose(table["frequency_Hz"], table["order"] * table["speed_rpm"] / 60.0, rtol=1e-12)
    # mode 1: both inertias in phase, the far mass b moves most; mode 2: the stiffly held a moves most
    assert set(table[table["mode"] == 1]["dominant_node"]) == {"b"}
    assert set(table[table["mode"] == 2]["dominant_node"]) == {"a"}


def test_campbell_figure_of_the_default_model():
    model = default_timing_model("spur")
    fig = plot_campbell(model, np.arange(700.0, 3001.0, 100.0), max_frequency_Hz=700.0)
    assert isinstance(fig, matplotlib.figure.Figure)
    ax = fig.axes[0]
    table = campbell_table(model, [700.0, 3000.0], max_frequency_Hz=700.0)
    # the markers are the table's crossings
    offsets = ax.collections[0].get_offsets()
    np.testing.assert_allclose(np.asarray(offsets), table[["speed_rpm", "frequency_Hz"]].to_numpy())
    freqs = model.natural_frequencies_Hz()        # the first is the damper ring's zero-stiffness mode (0 Hz)
    first = freqs[freqs > 1e-3][0]
    mode = int(np.nonzero(freqs > 1e-3)[0][0]) + 1
    row = table[(table["mode"] == mode) & (table["order"] == 6.0)].iloc[0]   # 1st crank mode vs firing order 6
    assert row["speed_rpm"] == pytest.approx(60.0 * first / 6.0, rel=1e-12) and 1000 < row["speed_rpm"] < 3000
    with pytest.raises(GearoptInputError, match="speeds_rpm"):
        plot_campbell(model, [1000.0])
    with pytest.raises(GearoptInputError, match="TorsionalNetwork"):
        campbell_table(object(), [700.0, 3000.0])
    matplotlib.pyplot.close(fig)


def test_campbell_markers_are_weighted_by_how_hard_the_order_drives_the_mode():
    """Marker area and colour follow the crossing's modal excitation (the order's harmonic of the engine torques
    projected on the mode shape): a strong order's crossing is drawn larger than a weak one's, and the mode labels
    cover no crossing marker."""
    model = default_timing_model("spur")
    speeds = np.linspace(750.0, 3000.0, 50)
    fig = plot_campbell(model, speeds, title="spur train: Campbell diagram")
    ax = fig.axes[0]
    points = ax.collections[0]
    table = campbell_table(model, speeds, max_frequency_Hz=1.1 * max(DEFAULT_ORDERS) * 3000.0 / 60.0)
    excitation = table["modal_excitation_Nm"].to_numpy()
    sizes = points.get_sizes()
    np.testing.assert_allclose(points.get_array(), excitation)
    assert np.ptp(excitation) > 0.5 * excitation.max()               # the orders differ in strength ...
    assert np.all(np.diff(sizes[np.argsort(excitation)]) >= 0.0)      # ... and the marker areas follow them
    assert sizes.max() > 5.0 * sizes.min()
    strongest = table.iloc[int(np.argmax(excitation))]
    # order 6: the inline six's 2nd firing harmonic (firing order 3) and the valve train's 12 lobe events per cam
    # revolution (default data, docs/default-data.md sec. 2.6) act together
    assert strongest["order"] == 6.0
    labelled = {t.get_text() for t in ax.texts}
    assert "6" in labelled
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    centres = ax.transData.transform(np.asarray(points.get_offsets()))
    radii = 0.5 * np.sqrt(sizes) * fig.dpi / 72.0
    for text in (t for t in ax.texts if t.get_text().startswith("mode ")):
        box = text.get_window_extent(renderer)
        nearest_x = np.clip(centres[:, 0], box.x0, box.x1)
        nearest_y = np.clip(centres[:, 1], box.y0, box.y1)
        assert np.all(np.hypot(centres[:, 0] - nearest_x, centres[:, 1] - nearest_y) > radii), text.get_text()
    assert readability_issues(fig) == []
    matplotlib.pyplot.close(fig)
