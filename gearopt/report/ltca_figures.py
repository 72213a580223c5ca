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

FLANK_QUANTITIES = {
    "load_intensity": ("load intensity [N/mm]", lambda r: r.load_intensity_N_per_mm),
    "contact_stress": ("contact stress [MPa]", lambda r: r.contact_stress_MPa),
    "flash_temperature": ("contact temperature [°C]", lambda r: r.contact_temperature_C),
    "root_stress_1": ("root stress, gear 1 [MPa]", lambda r: r.root_stress_MPa[0]),
    "root_stress_2": ("root stress, gear 2 [MPa]", lambda r: r.root_stress_MPa[1]),
}


def plot_transmission_error(results: dict, *, title: str = "", ax=None):
    """Static TE [um] over one mesh cycle, one line per labelled result (e.g. several torques or designs)."""
    fig, ax = _axes(ax, (6.4, 3.8))
    for label, r in results.items():
        x = np.asarray(r.position_roll_deg) - r.position_roll_deg[0]
        te = np.asarray(r.transmission_error_um)
        ax.plot(np.append(x, x[-1] + (x[1] - x[0])), np.append(te, te[0]), marker=".", ms=3,
                label=f"{label}: PPTE {r.ppte_um:.2f} µm")
    return _finish_line_plot(fig, ax, "mesh position, roll angle of gear 1 [deg]", "transmission error [µm]", title)


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
    ax.set_title(title)
    fig.tight_layout()
    return fig


def plot_flank_grid(results: dict, quantities=("load_intensity", "contact_stress", "flash_temperature",
                                                "root_stress_1"), *, gear: int = 1, title: str = ""):
    """One row per labelled result, one column per quantity: flank maps side by side with a shared colour scale per
    quantity (so designs compare at a glance, as the thesis' Figs. 4.10-4.15)."""
    rows, cols = len(results), len(quantities)
    fig, axes = plt.subplots(rows, cols, figsize=(3.4 * cols, 2.1 * rows + 0.6), squeeze=False, layout="constrained")
    data = {label: [flank_map(r, q, gear) for q in quantities] for label, r in results.items()}
    for j, q in enumerate(quantities):
        lo = min(float(np.min(d[j][2])) for d in data.values())
        hi = max(float(np.max(d[j][2])) for d in data.values())
        for i, (label, maps) in enumerate(data.items()):
            x, y, z = maps[j]
            mesh = axes[i, j].pcolormesh(x, y, z, shading="auto", cmap="viridis", vmin=lo, vmax=hi)
            axes[i, j].set_title(f"{label}", fontsize=8)
            axes[i, j].tick_params(labelsize=7)
            if i == rows - 1:
                axes[i, j].set_xlabel(f"roll angle, gear {gear} [deg]", fontsize=7)
            if j == 0:
                axes[i, j].set_ylabel("face [mm]", fontsize=7)
        cb = fig.colorbar(mesh, ax=axes[:, j].tolist(), shrink=0.9)
        cb.set_label(FLANK_QUANTITIES[q][0], fontsize=7)
        cb.ax.tick_params(labelsize=7)
    fig.suptitle(title, fontsize=9)
    return fig


def plot_harris_map(maps: dict[str, pd.DataFrame], *, title: str = "", ax=None):
    """PPTE [um] against torque [N m], one line per labelled Harris map (DataFrame from
    :func:`gearopt.contact.harris.harris_map`)."""
    fig, ax = _axes(ax, (6.4, 3.8))
    for label, df in maps.items():
        ax.plot(df["torque_Nm"], df["ppte_um"], marker="o", ms=3, label=label)
    return _finish_line_plot(fig, ax, "torque on the driving gear [N m]", "PPTE [µm]", title)


def plot_percentage_change(table: pd.DataFrame, baseline: str, *, title: str = "", ax=None):
    """Bar chart of the percentage change of every numeric column of ``table`` (rows = designs, indexed by name)
    relative to the row ``baseline`` (thesis Figs. 4.22/4.29 style)."""
    if baseline not in table.index:
        raise GearoptInputError(f"baseline={baseline!r} is not a row of the table {list(table.index)}")
    numeric = table.select_dtypes("number")
    change = (numeric / numeric.loc[baseline] - 1.0) * 100.0
    change = change.drop(index=baseline)
    fig, ax = _axes(ax, (7.0, 3.8))
    n = len(change.index)
    width = 0.8 / max(n, 1)
    xs = np.arange(len(change.columns))
    for i, name in enumerate(change.index):
        ax.bar(xs + i * width, change.loc[name].to_numpy(), width, label=name)
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set_xticks(xs + 0.4 - width / 2)
    ax.set_xticklabels(change.columns, rotation=20, ha="right", fontsize=7)
    ax.set_ylabel(f"change against {baseline} [%]")
    ax.set_title(title)
    ax.legend(fontsize=7)
    fig.tight_layout()
    return fig


def save(fig, path: str | Path, dpi: int = 120) -> Path:
    """Write ``fig`` to ``path`` (directories created) and close it."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return path


def _finish_line_plot(fig, ax, xlabel: str, ylabel: str, title: str):
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    return fig


def _axes(ax, size):
    if ax is None:
        fig, ax = plt.subplots(figsize=size)
        return fig, ax
    return ax.figure, ax


__all__ = ["plot_transmission_error", "flank_map", "plot_flank_map", "plot_flank_grid", "plot_harris_map", "plot_percentage_change",
           "save", "FLANK_QUANTITIES"]
