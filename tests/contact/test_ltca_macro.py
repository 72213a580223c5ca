"""Macro-symbolic smooth LTCA against the exact numeric solver (our reference, itself validated against the analytic
constant-stiffness PPTE and ISO 6336-1 in test_ltca_numeric): convergence as both smoothing widths shrink, the same
answers at geometries far from the template (another root shift, a helix angle), derivatives with respect to the
macro and micro inputs and through a symbolic gear train against central differences, one graph for every value."""

import dataclasses
import math

import casadi as ca
import numpy as np
import pytest

import gearopt as go
from gearopt.contact.ltca import ltca
from gearopt.contact.ltca_macro import MICRO_INPUTS, MacroLTCAModel, macro_vector, micro_vector
from gearopt.contact.microgeometry import Microgeometry
from gearopt.errors import GearoptInputError

MODS = Microgeometry(tip_relief_um=(10.0, 8.0), tip_relief_start_roll_deg=(26.0, 24.0), profile_crown_um=(1.0, 0.5))
FRACTIONS = (np.arange(24) + 0.37) / 24          # off the path ends (a contact exactly on A or E weighs 1/2)


@pytest.fixture(scope="module")
def train():
    return go.load_default_train("spur")


@pytest.fixture(scope="module")
def template(train):
    return train.pairs["crank-cam"]


def _shifted(train, x=None, beta=None):
    kw = {k: v for k, v in (("root_profile_shift", x), ("helix_angle_deg", beta)) if v is not None}
    return dataclasses.replace(train, **kw).pairs["crank-cam"]


def test_smooth_model_converges_to_the_exact_ltca_as_the_widths_shrink(template):
    exact = ltca(template, 300.0, microgeometry=MODS, positions=FRACTIONS)
    errors = []
    for w in (1.0, 0.3, 0.1):
        m = MacroLTCAModel(template, positions=FRACTIONS, smoothing_um=w, engagement_width_mm=w / 100.0)
        r = m.evaluate(None, micro_vector(MODS, template.geometry()), [300.0])
        err = np.abs(r.transmission_error_um[:, 0] - exact.transmission_error_um)
        # each softplus over-estimates its spring's load by <= c db w ln2: the approach is low by at most w ln 2
        assert err.max() <= w * math.log(2) + 1e-9
        errors.append(err.max())
    assert errors[0] > errors[1] > errors[2] > 0.0


def test_other_macro_values_reproduce_the_exact_ltca_of_that_geometry(train, template):
    """The template is the data's spur mesh; the inputs describe another root shift (every output) and a helical
    geometry at 8 deg (sliced face): the model must give that geometry's exact LTCA, not the template's."""
    m = MacroLTCAModel(template, positions=FRACTIONS, smoothing_um=1e-4, engagement_width_mm=1e-6, root_stress=True,
                       speed_rpm=2000.0, count_width_um=1e-4)
    pair = _shifted(train, x=0.05)
    ex = ltca(pair, 300.0, microgeometry=MODS, positions=FRACTIONS, speed_rpm=2000.0)
    r = m.evaluate(macro_vector(pair), micro_vector(MODS, template.geometry()), [300.0])
    np.testing.assert_allclose(r.transmission_error_um[:, 0], ex.transmission_error_um, atol=1e-3)
    assert r.max_contact_stress_MPa[0] == pytest.approx(ex.max_contact_stress_MPa, rel=1e-4)
    assert r.max_root_stress_MPa[0] == pytest.approx(max(ex.max_root_stress_MPa), rel=1e-4)
    assert r.max_flash_temperature_C[0] == pytest.approx(ex.max_flash_temperature_C, rel=1e-3)
    assert r.loaded_contact_ratio[0] == pytest.approx(ex.loaded_contact_ratio, abs=1e-3)

    helical = MacroLTCAModel(template, positions=FRACTIONS, slices=7, helical=True, smoothing_um=1e-4,
                             engagement_width_mm=1e-6, max_overlap_ratio=0.6)
    pair = _shifted(train, beta=8.0)
    ex = ltca(pair, 300.0, microgeometry=MODS, positions=FRACTIONS, slices=7)
    r = helical.evaluate(macro_vector(pair), micro_vector(MODS, template.geometry()), [300.0])
    np.testing.assert_allclose(r.transmission_error_um[:, 0], ex.transmission_error_um, atol=2e-3)
    assert r.ppte_um[0] == pytest.approx(ex.ppte_um, abs=3e-3)


@pytest.mark.parametrize("derivative_steps", [2, 1])
def test_derivatives_through_a_symbolic_train_match_central_differences(train, template, derivative_steps):
    """d(TE, contact stress^2, root stress)/d(root shift, helix angle, tip relief) of the crank-cam mesh of a train
    symbolic in its root shift and helix angle; one Newton step from the converged approach carries the first
    derivatives exactly too (``derivative_steps=1``, for a quasi-Newton Hessian)."""
    m = MacroLTCAModel(template, positions=12, slices=3, helical=True, max_overlap_ratio=0.6, root_stress=True,
                       smoothing_um=0.05, engagement_width_mm=0.01, derivative_steps=derivative_steps)
    x, beta, relief = ca.SX.sym("x"), ca.SX.sym("beta"), ca.SX.sym("relief")
    pair = dataclasses.replace(train, root_profile_shift=x, helix_angle_deg=beta).pairs["crank-cam"]
    micro = micro_vector(dataclasses.replace(MODS, tip_relief_um=(relief, 8.0)), template.geometry())
    out = m.kernel(ca.vertcat(*macro_vector(pair)), ca.vertcat(*micro), 300.0)
    names = m.output_names
    y = ca.vertcat(ca.vec(out[names.index("te_um")]), ca.vec(out[names.index("stress_sq_MPa2")]) / 1e4,
                   ca.vec(out[names.index("root_stress_1_MPa")]))
    p = ca.vertcat(x, beta, relief)
    jac = _derivative_against_central_differences(ca.Function("f", [p], [y, ca.jacobian(y, p)]))
    assert np.abs(jac[:, 0]).max() > 0 and np.abs(jac[:, 1]).max() > 0


def test_second_derivatives_match_central_differences_of_the_first(train, template):
    """The approach's Newton steps run without derivatives and two more steps carry them (``_build``): at the
    converged approach that gives the implicit-function Hessian exactly. The Hessian of a weighted sum of TE and
    load intensity in (root shift, helix angle, tip relief) against central differences of the Jacobian, in MX
    symbols as an NLP builds it (``SX`` symbols inline the approach and differentiate through every step)."""
    m = MacroLTCAModel(template, positions=12, slices=3, helical=True, max_overlap_ratio=0.6, smoothing_um=0.05,
                       engagement_width_mm=0.01)
    x, beta, relief = ca.MX.sym("x"), ca.MX.sym("beta"), ca.MX.sym("relief")
    pair = dataclasses.replace(train, root_profile_shift=x, helix_angle_deg=beta).pairs["crank-cam"]
    micro = micro_vector(dataclasses.replace(MODS, tip_relief_um=(relief, 8.0)), template.geometry())
    out = m.kernel(ca.vertcat(*macro_vector(pair)), ca.vertcat(*micro), 300.0)
    names = m.output_names
    weights = np.linspace(0.5, 1.5, 12)
    y = ca.dot(ca.DM(weights), ca.vec(out[names.index("te_um")])) + \
        ca.sum1(ca.sum2(out[names.index("load_N_per_mm")])) / 1e3
    p = ca.vertcat(x, beta, relief)
    hess = _derivative_against_central_differences(ca.Function("f", [p], [ca.gradient(y, p),
                                                                          ca.hessian(y, p)[0]]))
    assert np.abs(hess).max() > 0


def _derivative_against_central_differences(f, p0=(0.25, 5.0, 12.0), steps=(1e-5, 1e-4, 1e-4)) -> np.ndarray:
    """``f(p) -> (y, dy/dp)``: the derivative at ``p0`` against central differences of ``y`` (rtol 1e-4), returned."""
    p0 = np.asarray(p0, dtype=float)
    derivative = np.array(f(p0)[1])
    for i, h in enumerate(steps):
        d = np.zeros(p0.size)
        d[i] = h
        fd = (np.array(f(p0 + d)[0]) - np.array(f(p0 - d)[0])).ravel() / (2 * h)
        np.testing.assert_allclose(derivative[:, i], fd, rtol=1e-4, atol=1e-5 * max(1.0, np.abs(fd).max()))
    return derivative


def test_one_graph_for_every_macro_value_and_position_count(train, template):
    """The tooth pairs and positions are fixed at build: the same model evaluates a spur and a helical geometry
    (different numbers of pairs in contact), and the position function is the same for 20 and 400 positions."""
    m = MacroLTCAModel(template, positions=20, slices=5, helical=True, max_overlap_ratio=1.0)
    shapes = []
    for beta in (0.0, 12.0):
        r = m.evaluate(macro_vector(_shifted(train, beta=beta)), None, [300.0])
        shapes.append(r.load_intensity_N_per_mm.shape)
    assert shapes[0] == shapes[1] == (m.springs_per_position, 20)
    big = MacroLTCAModel(template, positions=400, slices=5, helical=True, max_overlap_ratio=1.0)
    assert big.springs_per_position == m.springs_per_position
    assert big.kernel.n_nodes() == m.kernel.n_nodes()


def test_a_model_built_again_at_other_positions_reuses_its_pieces_and_gives_the_same_numbers(train, template):
    """The per-position SX functions do not depend on the positions or load cases: a model built again at other
    positions (a refinement's re-solve) takes them from ``PIECES`` -- and evaluates to the last bit as one built
    from scratch; a setting they depend on (the contact smoothing) builds new ones."""
    from gearopt.contact import ltca_macro

    options = dict(slices=5, helical=True, max_overlap_ratio=1.0, smoothing_um=0.031)
    first = MacroLTCAModel(template, positions=20, **options)
    key = first._pieces_key()
    assert key in ltca_macro.PIECES
    pieces = ltca_macro.PIECES[key]
    again = MacroLTCAModel(template, positions=33, load_cases=2, **options)
    assert ltca_macro.PIECES[key] is pieces and len(again.fractions) == 33
    ltca_macro.PIECES.clear()
    fresh = MacroLTCAModel(template, positions=33, load_cases=2, **options)
    assert ltca_macro.PIECES[key] is not pieces
    macro, micro = macro_vector(_shifted(train, x=0.4, beta=6.0)), micro_vector(MODS, template.geometry())
    a, b = again.evaluate(macro, micro, [250.0, 320.0]), fresh.evaluate(macro, micro, [250.0, 320.0])
    np.testing.assert_array_equal(a.transmission_error_um, b.transmission_error_um)
    np.testing.assert_array_equal(a.load_intensity_N_per_mm, b.load_intensity_N_per_mm)
    other = MacroLTCAModel(template, positions=20, **{**options, "smoothing_um": 0.05})
    assert other._pieces_key() != key and ltca_macro.PIECES[other._pieces_key()] is not ltca_macro.PIECES[key]


def test_bad_inputs_raise_clear_errors(template):
    with pytest.raises(GearoptInputError, match="stiffness"):
        MacroLTCAModel(template, stiffness="potential_energy")
    with pytest.raises(GearoptInputError, match="numeric template"):
        MacroLTCAModel(dataclasses.replace(template, profile_shifts=(ca.SX.sym("x"), 0.1)))
    m = MacroLTCAModel(template, positions=8)
    with pytest.raises(GearoptInputError, match="load case"):
        m.evaluate(None, None, [100.0, 200.0])
    with pytest.raises(GearoptInputError, match="micro 19"):
        m.evaluate(None, [0.0] * (len(MICRO_INPUTS) - 1), [100.0])
    with pytest.raises(GearoptInputError, match="positions"):
        MacroLTCAModel(template, positions=[0.1, 1.2])


def test_threaded_position_map_gives_the_serial_values_and_derivatives(template, monkeypatch):
    # the positions evaluated by 2 threads (and the derivatives CasADi derives from that map) equal the serial map
    macro = ca.MX.sym("macro", len(macro_vector(template)))
    kernels = [MacroLTCAModel(template, positions=12, load_cases=2, map_threads=n).kernel for n in (1, 2)]
    x0 = ca.DM(ca.vertcat(*macro_vector(template)))
    u0 = ca.DM(ca.vertcat(*micro_vector(Microgeometry(tip_relief_um=(8.0, 6.0), tip_relief_start_roll_deg=(24.0, 22.0)),
                                        template.geometry())))
    values = []
    for kernel in kernels:
        te = kernel(macro, u0, ca.DM([200.0, 400.0]))[0]
        f = ca.Function("f", [macro], [ca.vec(te), ca.jacobian(ca.vec(te), macro)])
        values.append([np.asarray(v) for v in f(x0)])
    np.testing.assert_array_equal(values[0][0], values[1][0])
    np.testing.assert_array_equal(values[0][1], values[1][1])
    monkeypatch.setenv("GEAROPT_THREADS", "3")
    assert MacroLTCAModel(template, positions=4).map_threads == 3
    monkeypatch.setenv("GEAROPT_THREADS", "many")
    with pytest.raises(GearoptInputError, match="GEAROPT_THREADS"):
        MacroLTCAModel(template, positions=4)
    with pytest.raises(GearoptInputError, match="map_threads"):
        MacroLTCAModel(template, positions=4, map_threads=0)


def test_one_derivative_step_gives_the_same_values_and_first_derivatives(template):
    """``derivative_steps=1`` against the default 2: the same outputs and the same Jacobian in every macro and micro
    input (both exact at the converged approach); 0 or 3 steps are refused."""
    pair = dataclasses.replace(template, helix_angle_deg=6.0, helix_hands=("right", "left"))
    kw = dict(positions=10, slices=5, helical=True, max_overlap_ratio=0.8, root_stress=True, speed_rpm=2500.0,
              load_cases=2)
    macro, micro = ca.MX.sym("macro", 6), ca.MX.sym("micro", len(micro_vector(MODS, template.geometry())))
    values = np.concatenate([macro_vector(pair), micro_vector(MODS, pair.geometry())]).astype(float)
    results = []
    for steps in (2, 1):
        m = MacroLTCAModel(pair, derivative_steps=steps, **kw)
        y = ca.vertcat(*[ca.vec(o) for o in m.kernel(macro, micro, ca.DM([200.0, 400.0]))])
        v = ca.vertcat(macro, micro)
        results.append([np.array(a) for a in ca.Function("f", [v], [y, ca.jacobian(y, v)])(values)])
    for a, b in zip(*results):
        np.testing.assert_allclose(b, a, rtol=1e-9, atol=1e-9 * max(1.0, np.abs(a).max()))
    for bad in (0, 3):
        with pytest.raises(GearoptInputError, match=f"derivative_steps={bad}"):
            MacroLTCAModel(pair, derivative_steps=bad, **kw)
