"""problems/helix_front.py --quick in-process: the front of crank-cam PPTE against the cam joint's walk-off demand
makes physical sense (a larger helix angle lowers the PPTE and raises the thrust; at the high-margin end the train is
spur), the exact PPTE it reports is re-derived here by the exact LTCA, and failed points stay in the table with their
status."""

import dataclasses
import json

import numpy as np
import pandas as pd
import pytest
from conftest import load_script

import gearopt as go
from gearopt.contact.ltca import ltca

pytestmark = pytest.mark.filterwarnings("ignore::UserWarning")

Q, OBJ, BETA = "axial_utilisation[cam]", "ppte_um[crank-cam]", "train.helix_angle_deg"


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory):
    """``problems/helix_front.py --quick --out <tmp>`` run in-process through its ``main`` (exit code 0), with what
    its ``run`` returned (front, verification, merged table, settings) kept for the tests that start from the
    traced front: the script module, the output directory and that tuple."""
    script = load_script("helix_front")
    traced = []
    run = script.run

    def kept(*args, **kwargs):
        traced.append(run(*args, **kwargs))
        return traced[-1]

    out = tmp_path_factory.mktemp("helix_front")
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(script, "run", kept)
        assert script.main(["--quick", "--out", str(out)]) == 0
    assert len(traced) == 1
    return script, out, traced[0]


@pytest.fixture(scope="module")
def out(quick_run):
    return quick_run[1]


@pytest.fixture(scope="module")
def table(out):
    return pd.read_csv(out / "front.csv")


def test_outputs_and_every_point_with_a_status(out, table):
    assert {"front.csv", "front.png", "summary.json"} <= {p.name for p in out.iterdir()}
    summary = json.loads((out / "summary.json").read_text())
    assert len(table) == summary["settings"]["points"] == len(summary["points"]) == 4
    assert table["point"].tolist() == list(range(4)) and table["status"].notna().all()
    assert summary["failed"] == int((table["status"] != "ok").sum())
    assert summary["verified"] == int(table["verified"].sum())
    assert (table.loc[table["status"] == "ok", "verification"] == "ok").all()


def test_front_makes_physical_sense(table):
    s = table[table["status"] == "ok"]
    assert len(s) >= 3
    u, ppte, beta = s[Q].to_numpy(), s[OBJ].to_numpy(), s[BETA].to_numpy()
    # ordered from the PPTE optimum to the walk-off optimum: the required margin rises (utilisation falls) ...
    assert np.all(np.diff(u) < 0)
    # ... the PPTE does not fall and the helix angle moves monotonically to 0 (a spur train, no thrust)
    assert np.all(np.diff(ppte) >= -1e-6) and np.all(np.diff(beta) <= 1e-6)
    assert beta[-1] < 0.01 and u[-1] < 1e-5 and beta[0] > 2.0
    # the thrust grows with tan(beta): utilisation / tan(beta) nearly constant along the front (the working helix
    # angles at the fixed centre distances move a little with the root shift, so not exactly)
    helical = beta > 0.5
    ratio = u[helical] / np.tan(np.radians(beta[helical]))
    assert np.ptp(ratio) <= 0.05 * ratio.mean()
    # the margin column is the inverse of the utilisation
    np.testing.assert_allclose(s["axial_margin[cam]"].to_numpy()[helical], 1.0 / u[helical], rtol=1e-12)
    # on the exact LTCA too, the spur end has the larger transmission error
    assert s["exact_objective"].iloc[-1] > s["exact_objective"].iloc[0] > 0.0


def test_reported_exact_ppte_is_the_exact_ltca_of_the_reported_design(table, out):
    settings = json.loads((out / "summary.json").read_text())["settings"]
    torque = settings["load_cases_Nm"]["1x"]["crank-cam"]
    for _, r in table[table["verification"] == "ok"].iterrows():
        train = dataclasses.replace(go.load_default_train("spur"), helix_angle_deg=r[f"verified:{BETA}"],
                                    root_profile_shift=r["verified:train.root_profile_shift"])
        flanks = ("crank:driving", "cam:driven")
        mg = go.Microgeometry(tip_relief_um=tuple(r[f"verified:{f}.tip_relief_um"] for f in flanks),
                              tip_relief_start_roll_deg=tuple(r[f"verified:{f}.tip_relief_start_roll_deg"]
                                                              for f in flanks),
                              relief_smoothing_deg=0.1)
        assert ltca(train.pairs["crank-cam"], torque, microgeometry=mg).ppte_um == pytest.approx(
            r["exact_objective"], rel=1e-9)


def test_failed_points_are_reported_not_dropped(quick_run, tmp_path):
    """A front point that failed stays as "front point failed"; a re-solve that fails (Ipopt stopped after one
    iteration) is recorded with its typed error's name; both rows reach front.csv and the counts of summary.json.
    Starts from the front the quick run traced (4 points), with the interior points 1 and 2 marked failed (the two
    ends are re-solved: two scene builds, not three)."""
    from gearopt.studies.front_check import verify_front

    script, _, (front, _, _, _) = quick_run
    scene, settings = script.build_scene(go.load_system(), quick=True)
    table = front.table.copy()
    table.loc[[1, 2], "status"] = "InfeasibleProblemError"
    table.loc[[1, 2], "error"] = "injected: the ε point did not solve"
    failed = dataclasses.replace(front, table=table)
    ok = (table["status"] == "ok").to_numpy()             # the two ends always (an end that fails raises)
    check = verify_front(failed, scene, ltca_options={"max_refinements": 0}, max_iter=1)
    assert check["point"].tolist() == [0, 1, 2, 3]
    assert (check.loc[[1, 2], "verification"] == "front point failed").all()
    assert (check.loc[~ok, "verification"] == "front point failed").all()
    assert set(check.loc[ok, "verification"]) == {"IterationLimitError"} and ok[[0, 3]].all()
    assert not check["verified"].any()
    merged = failed.table.merge(check.drop(columns=["status", "error"]), on="point", how="left")
    merged.insert(merged.columns.get_loc(failed.quantity_column) + 1, "axial_margin[cam]",
                  1.0 / merged[failed.quantity_column])
    summary = script.write(failed, merged, {**settings, "points": 4}, tmp_path, 0.0)
    written = pd.read_csv(tmp_path / "front.csv")
    assert len(written) == 4 and (written.loc[[1, 2], "status"] == "InfeasibleProblemError").all()
    assert summary["failed"] == int((~ok).sum()) and summary["verification_failed"] == 4
