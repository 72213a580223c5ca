"""problems/failure_reproduction.py runs with --quick in-process and writes its creep statistics."""

import pandas as pd


def test_failure_reproduction_creep_statistics(run_quick):
    # at half the weakest toleranced fit's capacity, 3300 rpm, degraded damper, both cam gears slip; the spur cam
    # gear cannot creep (no thrust), whatever the rattle does
    out = run_quick("failure_reproduction")
    df = pd.read_csv(out / "creep_statistics.csv")
    below = df[df["fit_case"] == "0.5x_weakest"].set_index("train")
    assert below.loc["spur", "slip_um_per_cycle"] > 1.0
    assert below.loc["spur", "axial_creep_um_per_cycle"] == 0.0
    assert below.loc["helical", "max_rigid_utilisation"] > 1.0
    assert (out / "report.md").read_text().startswith("# Friction-joint creep")
