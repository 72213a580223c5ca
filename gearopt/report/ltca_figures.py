"""Figures of loaded tooth contact results in the style of the thesis' Figs. 4.9-4.12 (LDP plots): transmission
error over the mesh cycle, flank maps (load intensity, contact stress, flash temperature, root stress) over roll angle
x face width, and the Harris map (PPTE against torque).

Plotting only: every function takes finished results (:class:`~gearopt.contact.ltca.LTCAResult`, DataFrames) and
returns a matplotlib ``Figure``; nothing here runs a model.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from ..errors import GearoptInputError  # noqa: E402
from . import figure_writer  # noqa: E402

#: Line styles cycled with the colours so that overlapping curves stay distinguishable.
LINE_STYLES = ("-", "--", "-.", ":")
MARKERS = ("o", "s", "^", "D", "v")

#: Readable names of result columns for chart labels (unit in brackets).
COLUMN_LABELS = {"ppte_um": "PPTE [µm]", "max_contact_stress_MPa": "max contact stress [MPa]",
                 "max_root_stress_1_MPa": "max root stress, gear 1 [MPa]",
                 "max_root_stress_2_MPa": "max root stress, gear 2 [MPa]",
                 "max_flash_temperature_C": "max contact temperature [°C]",
                 "max_load_intensity_N_per_mm": "max load intensity [N/mm]",
                 "loaded_contact_ratio": "loaded contact ratio"}

#: Face colour of flank-map panels: what shows where a design has no contact on the common roll-angle axis.
NO_CONTACT_COLOUR = "0.82"

FLANK_QUANTITIES = {
    "load_intensity": ("load intensity [N/mm]", lambda r: r.load_intensity_N_per_mm),
    "contact_stress": ("contact stress [MPa]", lambda r: r.contact_stress_MPa),
    "flash_temperature": ("contact temperature [°C]", lambda r: r.contact_temperature_C),
    "root_stress_1": ("root stress, gear 1 [MPa]", lambda r: r.root_stress_MPa[0]),
    "root_stress_2": ("root stress, gear 2 [MPa]", lambda r: r.root_stress_MPa[1]),
}


def plot_transmission_error(results: dict, *, align: str = "mean", title: str = "", ax=None):
    """Static TE [um] over one mesh cycle, one line per labelled result (e.g. several torques or designs).

    ``align="mean"`` (default) removes each curve's mean, so curves of different mean deflection share one scale and
    their PPTE compares at a glance; ``"none"`` draws the absolute TE. The cycle is drawn once, its positions sorted
    along the roll angle of gear 1 from the smallest (a refined position set comes in any order, and gear 2 driving
    walks the roll angle backwards): no segment back to the start of the cycle."""
    if align not in ("mean", "none"):
        raise GearoptInputError(f"align={align!r} must be 'mean' or 'none'")
    fig, ax = _axes(ax, (6.4, 3.8))
    for i, (label, r) in enumerate(results.items()):
        roll = np.asarray(r.position_roll_deg, dtype=float)
        order = np.argsort(roll, kind="stable")
        x = roll[order] - roll[order[0]]
        te = np.asarray(r.transmission_error_um, dtype=float)[order]
        if align == "mean":
            te = te - te.mean()
        ax.plot(x, te, lw=1.4, ls=LINE_STYLES[i % len(LINE_STYLES)], label=f"{label}: PPTE {r.ppte_um:.2f} µm")
    ylabel = "TE minus its mean [µm]" if align == "mean" else "transmission error [µm]"
    return _finish_line_plot(fig, ax, "mesh position, roll angle of gear 1 [deg]", ylabel,
                             title or "static transmission error over one mesh cycle")


def flank_map(result, quantity: str = "load_intensity", gear: int = 1, points: int = 200):
    """A quantity over the active flank of ``gear``: (roll angle grid [deg], face positions [mm], values
    (faces, roll)). Each face slice's samples from all positions and tooth pairs are sorted by the contact's roll
    angle on ``gear`` and interpolated on a common grid (a spur pair's one slice spans the whole face)."""
    if quantity not in FLANK_QUANTITIES:
        raise GearoptInputError(f"quantity={quantity!r} must be one of {tuple(FLANK_QUANTITIES)}")
    lay = result.layout
    values = np.asarray(FLANK_QUANTITIES[quantity][1](result), dtype=float)
    rho = lay.rho1_mm if gear == 1 else lay.rho2_mm
    roll = rho / (0.5 * lay.base_diameter_mm[gear - 1]) * 180.0 / np.pi
    on = lay.on_path
    grid = np.linspace(roll[on].min(), roll[on].max(), points)
    rows = []
    for j in range(lay.slices):
        m = on[:, :, j]
        x, v = roll[:, :, j][m], values[:, :, j][m]
        order = np.argsort(x)
        rows.append(np.interp(grid, x[order], v[order]))
    z = np.array(rows)
    b = lay.face_width_mm
    if lay.slices == 1:
        return grid, np.array([-0.25 * b, 0.25 * b]), np.vstack([z, z])   # cell centres: cells span the face
    return grid, lay.slice_y_mm, z


def plot_flank_map(result, quantity: str = "load_intensity", *, gear: int = 1, title: str = "", ax=None):
    """Colour map of a quantity over roll angle x face width of ``gear``'s flank (thesis Figs. 4.10-4.12 style)."""
    fig, ax = _axes(ax, (6.4, 3.2))
    x, y, z = flank_map(result, quantity, gear)
    mesh = ax.pcolormesh(x, y, z, shading="auto", cmap="viridis")
    fig.colorbar(mesh, ax=ax, label=FLANK_QUANTITIES[quantity][0])
    ax.set_xlabel(f"roll angle of gear {gear} [deg]")
    ax.set_ylabel("face position [mm]")
    ax.set_title(title or f"{FLANK_QUANTITIES[quantity][0].split(' [')[0]} over the flank of gear {gear}")
    fig.set_layout_engine("tight")      # laid out when drawn, not here
    return fig


def plot_flank_grid(results: dict, quantities=("load_intensity", "contact_stress", "flash_temperature",
                                                "root_stress_1"), *, gear: int = 1, title: str = ""):
    """Flank maps side by side: one row per quantity, one column per labelled result (design). Every panel has the
    same roll-angle and face axes, and each row one colour scale with its own colour bar, so designs compare at a
    glance (as the thesis' Figs. 4.10-4.15). Where a design's active flank is shorter than the common roll-angle axis
    the panel shows grey (no contact there), and the title says so."""
    rows, cols = len(quantities), len(results)
    fig, axes = plt.subplots(rows, cols, figsize=(3.3 * cols + 1.0, 2.0 * rows + 0.6), squeeze=False,
                             sharex=True, sharey=True, layout="constrained")
    data = {label: [flank_map(r, q, gear) for q in quantities] for label, r in results.items()}
    for i, q in enumerate(quantities):
        lo = min(float(np.min(d[i][2])) for d in data.values())
        hi = max(float(np.max(d[i][2])) for d in data.values())
        for j, (label, maps) in enumerate(data.items()):
            x, y, z = maps[i]
            axes[i, j].set_facecolor(NO_CONTACT_COLOUR)
            mesh = axes[i, j].pcolormesh(x, y, z, shading="auto", cmap="viridis", vmin=lo, vmax=hi)
            if i == 0:
                axes[i, j].set_title(label, fontsize=9)
            axes[i, j].tick_params(labelsize=7)
            if i == rows - 1:
                axes[i, j].set_xlabel(f"roll angle, gear {gear} [deg]", fontsize=7)
            if j == 0:
                axes[i, j].set_ylabel("face [mm]", fontsize=7)
        cb = fig.colorbar(mesh, ax=axes[i, :].tolist(), shrink=0.95, aspect=12, pad=0.01)
        cb.set_label(FLANK_QUANTITIES[q][0], fontsize=7)
        cb.ax.tick_params(labelsize=7)
    spans = [(float(m[0][0].min()), float(m[0][0].max())) for m in data.values()]
    partial = len(set(spans)) > 1
    note = "grey: outside the design's active flank (no contact)" if partial else ""
    title = title or f"flank maps of gear {gear}"
    fig.suptitle("\n".join(t for t in (title, note) if t), fontsize=9)
    return fig


def plot_harris_map(maps: dict[str, pd.DataFrame], *, design_range_Nm: tuple[float, float] | None = None,
                    design_torque_Nm: float | None = None, title: str = "", ax=None):
    """PPTE [um] against torque [N m], one line per labelled Harris map (DataFrame from
    :func:`gearopt.contact.harris.harris_map`). ``design_range_Nm`` (low, high) is shaded and ``design_torque_Nm``
    marked, so the map shows where the design has to work; each curve has its own line style and marker, so curves
    that lie on top of each other stay visible."""
    fig, ax = _axes(ax, (6.4, 3.8))
    if design_range_Nm is not None:
        lo, hi = sorted(float(v) for v in design_range_Nm)
        ax.axvspan(lo, hi, color="0.85", zorder=0, label=f"design range {lo:g}-{hi:g} N m")
    if design_torque_Nm is not None:
        ax.axvline(float(design_torque_Nm), color="0.4", lw=0.8, ls="--", zorder=1,
                   label=f"design torque {float(design_torque_Nm):g} N m")
    n = len(maps)
    for i, (label, df) in enumerate(maps.items()):
        ax.plot(df["torque_Nm"], df["ppte_um"], ls=LINE_STYLES[i % len(LINE_STYLES)], marker=MARKERS[i % len(MARKERS)],
                ms=7 - 4 * i / max(n - 1, 1), lw=2.6 - 1.4 * i / max(n - 1, 1), mfc="none" if i == 0 else None,
                label=label, zorder=2 + i)
    return _finish_line_plot(fig, ax, "torque on the driving gear [N m]", "PPTE [µm]",
                             title or "Harris map: PPTE against torque")


def plot_percentage_change(table: pd.DataFrame, baseline: str, *, by: str | None = None, title: str = "", ax=None):
    """Horizontal bar chart of the percentage change of every numeric column of ``table`` (rows = designs, indexed
    by name) relative to the row ``baseline`` (thesis Figs. 4.22/4.29 style), each bar labelled with its value.

    ``by``: a column of ``table`` (e.g. ``"torque_Nm"``) whose every value gets its own panel -- the change at each
    load case; ``table`` then holds one row per design and value of ``by``."""
    groups = [(None, table)] if by is None else [(v, g.drop(columns=[by])) for v, g in table.groupby(by, sort=True)]
    if by is not None and ax is not None:
        raise GearoptInputError("by= draws one panel per value; give no ax")
    if ax is None:
        n_cols = len(table.select_dtypes("number").columns) - (by is not None)
        fig, axes = plt.subplots(1, len(groups), figsize=(4.6 * len(groups) + 1.4, 0.55 * n_cols * 1.6 + 1.4),
                                 squeeze=False, sharey=True, layout="constrained")
        axes = axes[0]
    else:
        fig, axes = ax.figure, [ax]
    extent = [0.0, 0.0]
    for panel, (value, group) in zip(axes, groups):
        if baseline not in group.index:
            raise GearoptInputError(f"baseline={baseline!r} is not a row of the table {list(group.index)}")
        numeric = group.select_dtypes("number")
        change = ((numeric / numeric.loc[baseline] - 1.0) * 100.0).drop(index=baseline)
        labels = [COLUMN_LABELS.get(c, c.replace("_", " ")) for c in change.columns]
        ys = np.arange(len(labels))
        height = 0.8 / max(len(change.index), 1)
        for i, name in enumerate(change.index):
            vals = change.loc[name].to_numpy(dtype=float)
            bars = panel.barh(ys + (i - (len(change.index) - 1) / 2) * height, vals, height, label=name)
            panel.bar_label(bars, labels=[f"{v:+.1f} %" if abs(v) >= 0.05 else "0" for v in vals], fontsize=7,
                            padding=2)
        panel.axvline(0.0, color="k", lw=0.8)
        panel.set_yticks(ys)
        panel.set_yticklabels(labels, fontsize=8)
        panel.invert_yaxis()
        panel.set_xlabel(f"change against {baseline.replace('_', ' ')} [%]", fontsize=8)
        panel.grid(axis="x", alpha=0.3)
        extent[0], extent[1] = min(extent[0], float(np.min(change.to_numpy()))), max(extent[1], float(np.max(change.to_numpy())))
        if value is not None:
            panel.set_title(f"{by.replace('_Nm', '')} {value:g}{' N m' if by.endswith('_Nm') else ''}", fontsize=9)
    pad = 0.22 * max(extent[1] - extent[0], 1.0)        # room for the value labels on both sides
    for panel in axes:
        panel.set_xlim(extent[0] - (pad if extent[0] < 0 else 0.3 * pad), extent[1] + pad)
    if ax is None:          # own figure: the legend below the panels, where it can cover no bar or value label
        fig.legend(*axes[0].get_legend_handles_labels(), loc="outside lower center", fontsize=8,
                   ncol=min(len(change.index), 4))
    else:
        axes[0].legend(fontsize=7, loc="best")
    default = f"percentage change against {baseline.replace('_', ' ')}"
    if ax is None or title:
        fig.suptitle(title or default, fontsize=10)
    elif not ax.get_title():
        ax.set_title(default, fontsize=9)        # the caller's figure: no figure title imposed on it
    return fig


def save(fig, path: str | Path, dpi: int | None = None) -> Path:
    """Write ``fig`` to ``path`` (directories created) and close it (in the background inside
    :func:`gearopt.report.figure_writer.background_figures`; ``dpi`` default: the writer's)."""
    return figure_writer.save(fig, path, dpi=dpi)


def _finish_line_plot(fig, ax, xlabel: str, ylabel: str, title: str):
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.set_layout_engine("tight")      # laid out when drawn (in the figure writer's worker), not here
    return fig


def _axes(ax, size):
    if ax is None:
        fig, ax = plt.subplots(figsize=size)
        return fig, ax
    return ax.figure, ax


__all__ = ["plot_transmission_error", "flank_map", "plot_flank_map", "plot_flank_grid", "plot_harris_map",
           "plot_percentage_change", "save", "FLANK_QUANTITIES", "COLUMN_LABELS"]
