"""Figures of the torsional dynamics of a timing train: the Campbell diagram of the linearised model.

:func:`campbell_table` lists every crossing of a natural frequency with an engine-order line inside a speed range
(speed = 60 f / order) and the node that dominates the mode's shape; :func:`plot_campbell` draws the natural
frequencies against engine speed with the order lines and marks those crossings. The linear model is
:mod:`gearopt.dynamics.modes` (mean mesh stiffness, both flanks in contact, speed boundary held), so its natural
frequencies do not depend on speed: the Campbell lines are horizontal. Plotting only; the eigenvalue problem is
solved by :func:`gearopt.dynamics.modes.campbell_diagram`.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")      # pyplot itself is imported by the functions that draw: 0.3 s to import
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from ..dynamics.modes import campbell_diagram, mode_shapes  # noqa: E402
from ..dynamics.order_strength import crossing_excitation_Nm  # noqa: E402
from ..errors import GearoptInputError  # noqa: E402

#: Engine orders of a four-stroke engine's Campbell diagram by default: 0.5 ... 12 in half orders.
DEFAULT_ORDERS = tuple(np.arange(0.5, 12.01, 0.5))


#: Crossing marker area [pt^2] = first + second x relative strength; the mode labels keep clear of the largest.
_MARKER_AREA_PT2 = (8.0, 160.0)
_LABEL_CLEARANCE_PT = 0.5 * float(np.sqrt(sum(_MARKER_AREA_PT2))) + 2.0


def _network(model):
    """A TimingModel's network, or the network itself."""
    net = getattr(model, "network", model)
    if not hasattr(net, "speed_ratios"):
        raise GearoptInputError(f"model={type(model).__name__} must be a TorsionalNetwork or a TimingModel")
    return net


def campbell_table(model, speeds_rpm, orders=DEFAULT_ORDERS, *, max_frequency_Hz: float | None = None,
                   boundary: str = "network") -> pd.DataFrame:
    """Crossings of natural frequencies with engine orders inside the speed range.

    ``model``: a :class:`~gearopt.dynamics.default_model.TimingModel` or a
    :class:`~gearopt.dynamics.network.TorsionalNetwork`; ``speeds_rpm`` [rpm] (its min and max set the range);
    ``orders`` engine orders (cycles per crank revolution; 0.5 = once per engine cycle of a four-stroke);
    ``max_frequency_Hz`` drops higher modes; ``boundary`` as :func:`gearopt.dynamics.modes.linear_matrices`.
    Returns a DataFrame with ``mode`` (1-based, ascending frequency, rigid-body modes left out),
    ``frequency_Hz``, ``order``, ``speed_rpm`` = 60 f / order, ``dominant_node`` (largest |angle| of the
    undamped mode shape), ``modal_excitation_Nm`` (how hard the order drives the mode at that speed,
    :func:`gearopt.dynamics.order_strength.crossing_excitation_Nm`; only with ``boundary="network"``) and
    ``relative_strength`` (that over the table's largest), sorted by speed.
    """
    net = _network(model)
    camp = campbell_diagram(net, speeds_rpm, orders, boundary=boundary, max_frequency_Hz=max_frequency_Hz)
    return _crossing_table(net, camp["crossings"], mode_shapes(net, boundary=boundary), boundary)


def _crossing_table(net, crossings: pd.DataFrame, shapes: pd.DataFrame, boundary: str) -> pd.DataFrame:
    """:func:`campbell_table` from the crossings of :func:`~gearopt.dynamics.modes.campbell_diagram` and the
    :func:`~gearopt.dynamics.modes.mode_shapes` of the same network and boundary."""
    crossings = crossings.copy()
    shapes = shapes.drop(index="frequency_Hz")
    crossings["dominant_node"] = [str(shapes[f"mode_{int(m)}"].abs().idxmax()) for m in crossings["mode"]]
    if boundary == "network" and len(crossings):
        strength = crossing_excitation_Nm(net, crossings)
        crossings["modal_excitation_Nm"] = strength
        crossings["relative_strength"] = strength / max(float(strength.max()), 1e-300)
    return crossings.sort_values(["speed_rpm", "mode"]).reset_index(drop=True)


def plot_campbell(model, speeds_rpm, orders=DEFAULT_ORDERS, *, max_frequency_Hz: float | None = None,
                  label_orders=(0.5, 1.5, 3.0, 4.5, 6.0, 7.5, 9.0, 12.0), annotate_above: float = 0.2,
                  title: str = "", ax=None):
    """Campbell diagram of the linearised model: natural frequencies [Hz] (horizontal lines, labelled with mode
    number and dominant node) against engine speed [rpm], engine-order lines ``f = order n / 60`` for ``orders``
    (those in ``label_orders`` drawn darker and labelled), and a marker at every crossing inside the speed range
    (:func:`campbell_table`) sized and coloured by how hard its order drives its mode (modal excitation, N m); the
    strongest crossings (``relative_strength`` >= ``annotate_above``) are labelled with their order. ``max_frequency_Hz`` (default: 1.1 x the highest order's frequency at the top speed)
    limits modes and axis. Returns the matplotlib ``Figure``."""
    return plot_campbell_data(campbell_data(model, speeds_rpm, orders, max_frequency_Hz=max_frequency_Hz),
                              label_orders=label_orders, annotate_above=annotate_above, title=title, ax=ax)


def campbell_data(model, speeds_rpm, orders=DEFAULT_ORDERS, *, max_frequency_Hz: float | None = None) -> dict:
    """What :func:`plot_campbell` draws, as plain data (picklable: drawn elsewhere by :func:`plot_campbell_data`):
    ``speeds_rpm``, ``orders``, ``max_frequency_Hz``, ``crossings`` (:func:`campbell_table`), ``modes`` (mode,
    frequency_Hz) and ``dominant_node`` per mode."""
    speeds = np.asarray(speeds_rpm, dtype=float).reshape(-1)
    orders = np.asarray(orders, dtype=float).reshape(-1)
    if speeds.size < 2:
        raise GearoptInputError("speeds_rpm needs at least two speeds")
    if orders.size == 0:
        raise GearoptInputError("orders must not be empty")
    f_top = max_frequency_Hz if max_frequency_Hz is not None else 1.1 * float(orders.max()) * speeds.max() / 60.0
    net = _network(model)
    camp = campbell_diagram(net, speeds, orders, max_frequency_Hz=f_top)   # once: the table and the modes share it
    all_shapes = mode_shapes(net)
    table = _crossing_table(net, camp["crossings"], all_shapes, "network")
    modes = camp["modes"][["mode", "frequency_Hz"]]
    shapes = all_shapes.drop(index="frequency_Hz")
    nodes = {int(m): str(shapes[f"mode_{int(m)}"].abs().idxmax()) for m in modes["mode"]}
    return {"speeds_rpm": speeds, "orders": orders, "max_frequency_Hz": float(f_top), "crossings": table,
            "modes": modes.reset_index(drop=True), "dominant_node": nodes}


def plot_campbell_data(data: dict, *, label_orders=(0.5, 1.5, 3.0, 4.5, 6.0, 7.5, 9.0, 12.0),
                       annotate_above: float = 0.2, title: str = "", ax=None):
    """The Campbell diagram of :func:`plot_campbell` from :func:`campbell_data`. Returns the ``Figure``."""
    import matplotlib.pyplot as plt

    speeds, orders, f_top, table = data["speeds_rpm"], data["orders"], data["max_frequency_Hz"], data["crossings"]
    if ax is None:
        fig, ax = plt.subplots(figsize=(8.0, 5.5), layout="constrained")
    else:
        fig = ax.figure
    n = np.array([speeds.min(), speeds.max()])
    labelled = {float(o) for o in label_orders}
    for o in orders:
        strong = float(o) in labelled
        ax.plot(n, o * n / 60.0, color="0.25" if strong else "0.7", lw=0.9 if strong else 0.5, zorder=1)
        if strong and o * n[1] / 60.0 <= f_top:
            ax.annotate(f"{o:g}", (n[1], o * n[1] / 60.0), xytext=(2, 0), textcoords="offset points",
                        fontsize=7, va="center")
    for _, mode in data["modes"].iterrows():
        node = data["dominant_node"][int(mode["mode"])]
        ax.axhline(mode["frequency_Hz"], color="tab:blue", lw=1.0, zorder=2)
        below = mode["frequency_Hz"] > 0.06 * f_top       # below the line: the order labels sit above the markers
        ax.annotate(f"mode {int(mode['mode'])} ({node}) {mode['frequency_Hz']:.0f} Hz", (n[0], mode["frequency_Hz"]),
                    xytext=(3, -_LABEL_CLEARANCE_PT if below else _LABEL_CLEARANCE_PT), textcoords="offset points",
                    fontsize=7, color="tab:blue", va="top" if below else "bottom", zorder=4,
                    bbox={"boxstyle": "square,pad=0.1", "fc": "white", "ec": "none", "alpha": 0.85})
    if len(table):
        area = _MARKER_AREA_PT2[0] + _MARKER_AREA_PT2[1] * table["relative_strength"].to_numpy()
        points = ax.scatter(table["speed_rpm"], table["frequency_Hz"], s=area,
                            c=table["modal_excitation_Nm"], cmap="Reds", vmin=0.0, edgecolors="0.3",
                            linewidths=0.4, zorder=3,
                            label=f"{len(table)} crossings in {speeds.min():.0f}-{speeds.max():.0f} rpm "
                                  "(size, colour: modal excitation)")
        fig.colorbar(points, ax=ax, label="modal excitation of the crossing [N m]", shrink=0.8)
        for k in np.nonzero(table["relative_strength"].to_numpy() >= annotate_above)[0]:
            r, off = table.iloc[k], 0.35 * float(np.sqrt(area[k])) + 1.5     # beside the marker's edge
            ax.annotate(f"{r['order']:g}", (r["speed_rpm"], r["frequency_Hz"]), xytext=(off, off),
                        textcoords="offset points", fontsize=7, color="darkred")
        ax.legend(loc="upper left", fontsize=8)
    ax.set_xlim(n[0], n[1] * 1.04)
    ax.set_ylim(0.0, f_top)
    ax.set_xlabel("engine speed [rpm]")
    ax.set_ylabel("frequency [Hz]")
    ax.set_title(title or "Campbell diagram (linearised model, engine orders)")
    ax.grid(alpha=0.3)
    return fig


def plot_force_traces(traces: dict, *, quantity: str = "mesh force [kN]", title: str = ""):
    """A grid of force traces: ``traces`` maps a panel title to ``{label: (crank angle [deg], force [kN])}``,
    panels in rows of two (e.g. speeds x without/with backlash). Returns the ``Figure``."""
    import matplotlib.pyplot as plt

    if not traces:
        raise GearoptInputError("traces must hold at least one panel")
    rows = (len(traces) + 1) // 2
    fig, axes = plt.subplots(rows, 2, figsize=(11, 3.2 * rows), squeeze=False, layout="constrained")
    for ax, (panel, lines) in zip(axes.ravel(), traces.items()):
        for label, (angle, force) in lines.items():
            ax.plot(angle, force, lw=0.8, label=label)
        ax.set_title(panel, fontsize=9)
        ax.set_xlabel("crank angle [deg]")
        ax.set_ylabel(quantity)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    for ax in axes.ravel()[len(traces):]:
        ax.set_visible(False)
    if title:
        fig.suptitle(title)
    return fig


__all__ = ["DEFAULT_ORDERS", "campbell_table", "campbell_data", "plot_campbell", "plot_campbell_data",
           "plot_force_traces"]
