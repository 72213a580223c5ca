"""Tolerance robustness: Monte Carlo tables identical on every executor (one two-worker Dask LocalCluster), each
sample equal to a direct evaluation of the LTCA model, limit-break probabilities counted from the table, Sobol
indices of a quantity that depends on one input, a robust design that keeps its limit over the tolerances."""

import numpy as np
import pytest

import gearopt as go
from gearopt.errors import GearoptInputError
from gearopt.executor import using_executor
from gearopt.studies import Tolerance, monte_carlo, robust_design, sobol_indices
from studies_scenes import MESH, RELIEF, relief_scene

LCR = f"loaded_contact_ratio[{MESH}]@T150"


@pytest.fixture(scope="module")
def scene():
    return relief_scene(min_lcr=1.3, stress_limit=True)


@pytest.fixture(scope="module")
def result(scene):
    return scene.build().solve(check=False)


@pytest.fixture(scope="module")
def serial(result):
    return monte_carlo(result, samples=300, seed=7, executor="serial")


def test_same_seed_same_table_on_every_executor(result, serial):
    # 300 samples = two chunks, so both workers get work
    other = monte_carlo(result, samples=300, seed=7, executor="processes", workers=2)
    assert other.table.equals(serial.table)
    # "dask": a two-worker LocalCluster; its dask.distributed.Client is accepted as the executor too
    with using_executor("dask", workers=2) as ex:
        assert len(ex.client.scheduler_info()["workers"]) == 2
        for executor in (ex, ex.client):
            assert monte_carlo(result, samples=300, seed=7, executor=executor).table.equals(serial.table)
    assert not monte_carlo(result, samples=300, seed=8).table.equals(serial.table)


def test_samples_equal_a_direct_evaluation_of_the_ltca_model(result, serial):
    model = result.source.models[f"ltca_smooth:{MESH}"]
    base = result.microgeometry[MESH]
    for i in (0, 123, 299):
        row = serial.table.iloc[i]
        x = [row[f"{MESH}.{v}"] for v in RELIEF]
        mods = go.Microgeometry(tip_relief_um=(x[0], x[1]), tip_relief_start_roll_deg=(x[2], x[3]),
                                relief_smoothing_deg=base.relief_smoothing_deg)
        r = model.evaluate(mods, [150.0, 450.0])
        np.testing.assert_allclose(np.ptp(r.transmission_error_um, axis=0),
                                   [row[f"ppte_um[{MESH}]@T150"], row[f"ppte_um[{MESH}]@T450"]], rtol=1e-9)
        np.testing.assert_allclose(r.loaded_contact_ratio, [row[LCR], row[f"loaded_contact_ratio[{MESH}]@T450"]],
                                   rtol=1e-9)


def test_summary_counts_the_broken_limits_of_the_table(result, serial):
    s = serial.summary.set_index("quantity")
    assert (serial.table["status"] == "ok").all()
    assert set(serial.inputs) == {f"{MESH}.{v}" for v in RELIEF}          # the default tolerances
    broken = (serial.table[LCR] < 1.3).mean()
    assert s.loc[LCR, "probability_broken"] == pytest.approx(broken) and 0.2 < broken < 0.8   # optimum on the limit
    assert s.loc[LCR, "nominal"] == pytest.approx(result.quantities.query(
        "quantity == 'loaded_contact_ratio' and load_case == 'T150'")["value"].item(), rel=1e-9)
    assert s.loc[LCR, "std"] == pytest.approx(serial.table[LCR].std(), rel=1e-12)


def test_operating_spread_of_torque_moves_the_stress_by_hertz(result):
    # the largest stress at 450 N m is in single-pair contact (no relief there): sigma ~ sqrt(T) (Hertz)
    name = f"torque_Nm[{MESH}]@T450"
    mc = monte_carlo(result, samples=64, seed=1, tolerances=[Tolerance(name, -45.0, 45.0, "normal")], method="sobol")
    stress = mc.table[f"max_contact_stress_MPa[{MESH}]@T450"].to_numpy()
    nominal = mc.summary.set_index("quantity").loc[f"max_contact_stress_MPa[{MESH}]@T450", "nominal"]
    np.testing.assert_allclose(stress, nominal * np.sqrt(mc.table[name] / 450.0), rtol=1e-6)


def test_sobol_indices_of_a_quantity_driven_by_one_input(result):
    tols = [Tolerance(f"torque_Nm[{MESH}]@T450", -45.0, 45.0), Tolerance.symmetric(f"{MESH}.tip_relief_1_um", 2.0)]
    s = sobol_indices(result, samples=64, seed=2, tolerances=tols).set_index(["quantity", "input"])
    stress = f"max_contact_stress_MPa[{MESH}]@T450"
    assert s.loc[(stress, tols[0].name), "ST"] == pytest.approx(1.0, abs=0.05)
    assert abs(s.loc[(stress, tols[1].name), "ST"]) < 1e-9
    # the PPTE at 150 N m does not see the 450 N m torque at all
    assert abs(s.loc[(f"ppte_um[{MESH}]@T150", tols[0].name), "ST"]) < 1e-9


def test_robust_design_keeps_its_limit_over_the_tolerances(scene, result, serial):
    tols = [Tolerance.symmetric(f"{MESH}.tip_relief_1_um", 2.0), Tolerance.symmetric(f"{MESH}.tip_relief_2_um", 2.0)]
    robust = robust_design(relief_scene(min_lcr=1.3, stress_limit=False), tols, check=False)
    nominal_mc = monte_carlo(result, samples=300, seed=7, tolerances=tols)
    robust_mc = monte_carlo(robust, samples=300, seed=7, tolerances=tols)
    p_nominal = nominal_mc.summary.set_index("quantity").loc[LCR, "probability_broken"]
    p_robust = robust_mc.summary.set_index("quantity").loc[LCR, "probability_broken"]
    assert p_nominal > 0.2 and p_robust == 0.0
    # the price: a larger PPTE at the nominal point
    ppte = [r.quantities.query("quantity == 'ppte_um'")["value"].max() for r in (result, robust)]
    assert ppte[1] > ppte[0]


def test_bad_monte_carlo_input(result):
    with pytest.raises(GearoptInputError, match="samples=0"):
        monte_carlo(result, samples=0)
    with pytest.raises(GearoptInputError, match="negative spread"):
        Tolerance(f"{MESH}.tip_relief_1_um", 1.0, -1.0)
    with pytest.raises(GearoptInputError, match="negative spread"):
        Tolerance.symmetric(f"{MESH}.tip_relief_1_um", -2.0)
    with pytest.raises(GearoptInputError, match="no_such_input"):
        monte_carlo(result, samples=4, tolerances=[Tolerance.symmetric("no_such_input", 1.0)])
    with pytest.raises(GearoptInputError, match="method"):
        monte_carlo(result, samples=4, method="latin")


def test_a_failed_sample_is_recorded_and_the_others_kept(result):
    from gearopt.studies.evaluator import STATUS, evaluate_chunk, scene_evaluator

    class Fussy:
        """Wraps the scene's evaluator; raises on a tip relief above 20 um (a model that fails at one sample)."""

        def __init__(self, inner):
            self.inner, self.quantities = inner, inner.quantities

        def evaluate(self, values):
            if np.any(np.asarray(values[f"{MESH}.tip_relief_1_um"]) > 20.0):
                raise FloatingPointError("relief too large")
            return self.inner.evaluate(values)

    inner = scene_evaluator(result)
    values = {f"{MESH}.tip_relief_1_um": np.array([10.0, 25.0, 12.0])}
    out = evaluate_chunk((Fussy(inner), values))
    assert list(out[STATUS]) == ["ok", "FloatingPointError", "ok"]
    ppte = out[f"ppte_um[{MESH}]@T150"]
    assert np.isnan(ppte[1]) and np.allclose(ppte[[0, 2]], inner.evaluate({k: v[[0, 2]] for k, v in values.items()})[
        f"ppte_um[{MESH}]@T150"], rtol=1e-12)


def test_the_exact_recheck_equals_the_exact_ltca_of_each_sample_and_counts_its_own_breaks(result):
    """exact_samples: the first samples re-evaluated by the exact LTCA (gearopt.ltca of the sample's flanks at the
    scene's check positions, computed here directly), their limit breaks counted from those exact values, the
    smooth model's largest miss over them reported -- on a design whose loaded contact ratio sits on its limit."""
    from gearopt.contact.ltca import ltca

    mc = monte_carlo(result, samples=40, seed=7, exact_samples=12)
    assert mc.exact_samples == 12 and mc.exact_note == ""
    column = f"exact:{LCR}"
    assert mc.table[column].iloc[:12].notna().all() and mc.table[column].iloc[12:].isna().all()
    built = result.source
    pair = go.load_default_train("spur").pairs[MESH]
    positions = built.options.check.check_positions
    for i in (0, 11):
        row = mc.table.iloc[i]
        values = {f"{MESH}.{v}": row[f"{MESH}.{v}"] for v in RELIEF}
        r = ltca(pair, 150.0, microgeometry=built.microgeometry_at(values, MESH), positions=positions,
                 driving_gear=built.graph.driving_gear(MESH))
        assert row[column] == pytest.approx(r.loaded_contact_ratio, rel=1e-9)
        assert row[f"exact:ppte_um[{MESH}]@T150"] == pytest.approx(r.ppte_um, rel=1e-9)
    s = mc.summary.set_index("quantity")
    exact = mc.table[column].iloc[:12].to_numpy(float)
    assert s.loc[LCR, "exact_probability_broken"] == pytest.approx(np.mean(exact < 1.3))
    assert s.loc[LCR, "exact_samples"] == 12
    p = s.loc[LCR, "exact_probability_broken"]
    assert s.loc[LCR, "exact_probability_broken_se"] == pytest.approx(np.sqrt(p * (1 - p) / 12))
    smooth = mc.table[LCR].iloc[:12].to_numpy(float)
    assert s.loc[LCR, "smooth_error_max"] == pytest.approx(np.max(np.abs(smooth - exact)))
    nominal = ltca(pair, 150.0, microgeometry=built.microgeometry_at(result.values, MESH), positions=positions,
                   driving_gear=built.graph.driving_gear(MESH))
    assert s.loc[LCR, "exact_nominal"] == pytest.approx(nominal.loaded_contact_ratio, rel=1e-9)


def test_no_exact_recheck_over_data_tolerances_and_it_says_why(result):
    mc = monte_carlo(result, samples=8, seed=1, exact_samples=4,
                     tolerances=[Tolerance(f"torque_Nm[{MESH}]@T450", -45.0, 45.0)])
    assert mc.exact_samples == 0 and f"torque_Nm[{MESH}]@T450" in mc.exact_note
    assert "exact_probability_broken" not in mc.summary.columns
    with pytest.raises(GearoptInputError, match="exact_samples=-1"):
        monte_carlo(result, samples=4, exact_samples=-1)


@pytest.mark.filterwarnings("ignore")
def test_the_samples_spread_around_the_reported_design_after_an_exact_polish():
    """The data's crank-cam tip-relief scene (lifted contact) polishes its NLP optimum on the exact model; the
    Monte Carlo's nominal is the reported (polished) design's -- its smooth quantities equal the result's, and its
    exact re-check's nominal the result's exact check -- not the NLP optimum's it came from."""
    from gearopt.studies import relief_scene_from_data

    system = go.load_system()
    scene = relief_scene_from_data(system, go.load_default_train("spur"), MESH, ltca_options={"approach": "lifted"})
    polished = scene.build().solve()
    assert bool(polished.refinement.attrs["polish"]["accepted"].iloc[0])
    mc = monte_carlo(polished, samples=4, seed=0, exact_samples=1)
    s = mc.summary.set_index("quantity")
    q = polished.quantities.assign(label=lambda t: t["quantity"] + f"[{MESH}]@" + t["load_case"]).set_index("label")
    ex = polished.exact_check.set_index("load_case")
    for case in ("T150", "T450"):
        for quantity in ("ppte_um", "max_contact_stress_MPa", "loaded_contact_ratio"):
            label = f"{quantity}[{MESH}]@{case}"
            assert s.loc[label, "nominal"] == pytest.approx(q.loc[label, "value"], rel=1e-9)
            assert s.loc[label, "exact_nominal"] == pytest.approx(ex.loc[case, quantity], rel=1e-9)


@pytest.mark.filterwarnings("ignore")
def test_an_exact_value_that_ties_its_limit_to_rounding_does_not_break_it():
    """The data's crank-cam scene limits the largest contact stress to the unmodified pair's own maximum, which sits
    in single-pair contact where tip relief does not act: the exact stress at 450 N m equals the limit for every
    sample, one of them a rounding error (2e-16 relative) above it. That is the limit, not a break."""
    from gearopt.studies import relief_scene_from_data

    system = go.load_system()
    scene = relief_scene_from_data(system, go.load_default_train("spur"), MESH, positions=24)
    mc = monte_carlo(scene.build().solve(check=False), samples=16, seed=0, exact_samples=16)
    label = f"max_contact_stress_MPa[{MESH}]@T450"
    limit = next(lim.upper for lim in scene.limits if lim.quantity == "max_contact_stress_MPa")
    exact = mc.table[f"exact:{label}"].to_numpy(float)
    np.testing.assert_allclose(exact, limit, rtol=1e-12)
    assert (exact > limit).any()            # a strict comparison would count a break here
    assert mc.summary.set_index("quantity").loc[label, "exact_probability_broken"] == 0.0


@pytest.mark.filterwarnings("ignore")
def test_sensitivities_and_the_exact_recheck_on_another_train_with_other_names(renamed_minimal_path):
    """Any train: the packaged minimal pair with its gears renamed, its data's tip-relief scene (lifted contact,
    polished on the exact model): the sensitivity report is made at the NLP's optimum and says how far the polish
    moved the design; the Monte Carlo's exact re-check names the renamed mesh and its nominal is the result's exact
    check."""
    from gearopt.data import train_from_data
    from gearopt.studies import relief_scene_from_data, sensitivity_report

    system = go.load_system(renamed_minimal_path)
    mesh = "sun_gear-drum_gear"
    scene = relief_scene_from_data(system, train_from_data(system.data, "spur"), mesh, positions=24,
                                   ltca_options={"approach": "lifted"})
    result = scene.build().solve()
    report = sensitivity_report(result, resolve_top=1)
    assert np.isfinite(report.objective) and np.isfinite(report.exact_objective)
    assert bool(result.refinement.attrs["polish"]["accepted"].iloc[0])
    assert "the exact polish moved the reported design" in report.note and mesh in report.note
    mc = monte_carlo(result, samples=16, seed=0, exact_samples=8)
    s = mc.summary.set_index("quantity")
    ex = result.exact_check.set_index("load_case")
    for case in ex.index:
        label = f"loaded_contact_ratio[{mesh}]@{case}"
        assert s.loc[label, "exact_nominal"] == pytest.approx(ex.loc[case, "loaded_contact_ratio"], rel=1e-9)
        assert mc.table[f"exact:{label}"].iloc[:8].notna().all()
