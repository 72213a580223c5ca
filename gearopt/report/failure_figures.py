"""Figure of the failure reproduction (``gearopt.studies.failure``): the joints' axial creep per engine cycle against
the fit's friction capacity. A module-level builder, so the figure writer's worker can build it
(:func:`gearopt.report.figure_writer.plot_later`) from the envelope alone."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")      # pyplot itself is imported by the functions that draw: 0.3 s to import
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402


def plot_failure_creep_map(envelope: pd.DataFrame):
    """Cam and crank joints: axial creep per cycle against the fit's capacity for the helical train, colour by
    speed, line style by damper state; the weakest..strongest toleranced range shaded. The spur train's creep is
    drawn only where it is not zero (it has no thrust), and the panel title says so. ``envelope``: the rows of
    :func:`gearopt.studies.failure.failure_reproduction`'s envelopes with a ``train`` column. Returns the
    ``Figure`` (a builder for :func:`gearopt.report.figure_writer.plot_later`)."""
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), layout="constrained")
    styles = {"nominal": "-", "degraded": "--", "seized": ":"}
    for ax, joint in zip(axes, ("cam", "crank")):
        rows = envelope[(envelope["joint"] == joint) & envelope["train"].isin(["helical", "spur"])]
        if rows.empty:
            ax.set_visible(False)                  # no such joint in the envelope: no empty panel
            continue
        tol = rows[rows["fit_case"].isin(["weakest", "strongest"])]["capacity_N"]
        ax.axvspan(tol.min() * 1e-3, tol.max() * 1e-3, color="0.92", label="toleranced fits")
        speeds = sorted(rows["speed_rpm"].unique())
        colours = dict(zip(speeds, plt.cm.viridis(np.linspace(0.0, 0.85, len(speeds)))))
        spur_zero = bool((rows[rows["train"] == "spur"]["axial_creep_um_per_cycle"].abs() < 1e-9).all())
        for (train, speed, state), g in rows.groupby(["train", "speed_rpm", "damper_state"]):
            if train == "spur" and spur_zero:
                continue
            g = g.sort_values("capacity_N")
            ax.plot(g["capacity_N"] * 1e-3, g["axial_creep_um_per_cycle"].clip(lower=0.0),
                    styles.get(state, "-."), marker="." if train == "helical" else "x",
                    color=colours[speed] if train == "helical" else "0.5", lw=1.2,
                    label=f"{train} {speed:g} rpm, damper {state}")
        ax.set_xscale("log")
        ax.set_yscale("symlog", linthresh=1e-2)
        ax.set_ylim(bottom=0.0)
        ax.set_xlabel("friction capacity C [kN]")
        ax.set_ylabel("axial creep off the nose [µm per engine cycle]")
        ax.set_title(f"{joint} gear" + (" (spur: zero creep everywhere)" if spur_zero else ""))
        ax.grid(alpha=0.3, which="both")
    handles = {}                                   # one legend for both panels (the same speeds and damper states)
    for ax in axes:
        handles.update(zip(*reversed(ax.get_legend_handles_labels())))
    fig.legend(list(handles.values()), list(handles), loc="outside lower center", fontsize=7,
               ncol=min(len(handles), 4))
    fig.suptitle("Failure reproduction: axial creep of the joints against the fit's friction capacity")
    return fig


__all__ = ["plot_failure_creep_map"]
