"""Web stress (closed form, stated model) and Goodman / EFR fatigue margins (thesis sec. 3.10, 4.6): equilibrium of the
shear models, the annular-plate moment against a numerical solution of the plate equation and its narrow-ring limit,
Goodman-line identities and a published fully-reversed case, derivatives."""

import math

import casadi as ca
import numpy as np
import pytest
from scipy.integrate import quad, solve_bvp

from gearopt.blank.web import (
    clamped_annular_plate_moment_Nmm_per_mm,
    forward_reverse_from_history,
    goodman_equivalent_fully_reversed_MPa,
    web_fatigue,
    web_stress,
    web_torsion_shear_MPa,
    web_transverse_shear_MPa,
)
from gearopt.errors import GearoptInputError


def test_shear_models_carry_the_loads():
    # torsion: the shear flow round a circle returns the torque, tau 2 pi r t r = T
    tau = web_torsion_shear_MPa(300.0, 35.0, 12.0)
    assert tau * 2 * math.pi * 35.0 * 12.0 * 35.0 / 1000 == pytest.approx(300.0, rel=1e-12)
    # transverse force on a thin ring: q(theta) = q_max sin(theta), the resultant of q sin(theta) r dtheta is F
    q_max = web_transverse_shear_MPa(8000.0, 35.0, 12.0) * 12.0
    F = quad(lambda th: q_max * math.sin(th) ** 2 * 35.0, 0.0, 2 * math.pi)[0]
    assert F == pytest.approx(8000.0, rel=1e-10)


def _plate_moment_numeric(P, a, b, nu):
    """Clamped-free annular plate under an edge line load: d/dr[(1/r) d(r phi)/dr] = P/(2 pi D r), phi = dw/dr,
    with phi(a) = 0 and M_r(b) = -D (phi' + nu phi/r) = 0; returns |M_r(a)| = D |phi'(a)| (D = 1)."""
    c = P / (2 * math.pi)

    def f(r, y):  # y = [phi, psi], psi = phi' + phi/r
        return np.vstack([y[1] - y[0] / r, c / r])

    def bc(ya, yb):
        return np.array([ya[0], yb[1] - yb[0] / b + nu * yb[0] / b])

    r = np.linspace(a, b, 100)
    sol = solve_bvp(f, bc, r, np.zeros((2, r.size)), tol=1e-9, max_nodes=100000)
    assert sol.success
    ya = sol.sol(a)
    return abs(ya[1] - ya[0] / a)


@pytest.mark.parametrize("a, b, nu", [(35.0, 100.0, 0.3), (30.0, 45.0, 0.3), (20.0, 120.0, 0.25)])
def test_annular_plate_moment_against_numerical_plate_solution(a, b, nu):
    m = clamped_annular_plate_moment_Nmm_per_mm(1000.0, a, b, nu)
    assert m == pytest.approx(_plate_moment_numeric(1000.0, a, b, nu), rel=1e-6)


def test_annular_plate_narrow_ring_is_a_cantilever_strip():
    # b -> a: each unit of circumference is a cantilever of length b - a under P/(2 pi a)
    a, P = 50.0, 1000.0
    errs = []
    for w in (5.0, 1.0, 0.2):
        m = clamped_annular_plate_moment_Nmm_per_mm(P, a, a + w, 0.3)
        errs.append(abs(m / (P / (2 * math.pi * a) * w) - 1))
    assert errs[-1] < 3e-3 and errs[0] > errs[1] > errs[2]


def test_web_stress_combines_and_pockets_raise_shear():
    plain = web_stress(300.0, hub_outer_diameter_mm=70.0, rim_inner_diameter_mm=200.0, web_thickness_mm=12.0,
                       in_plane_force_N=6000.0, axial_force_N=400.0)
    assert plain["shear_MPa"] == pytest.approx(plain["shear_torsion_hub_MPa"] + plain["shear_force_hub_MPa"])
    assert plain["von_mises_MPa"] == pytest.approx(math.sqrt(plain["bending_MPa"] ** 2 + 3 * plain["shear_MPa"] ** 2))
    pocketed = web_stress(300.0, hub_outer_diameter_mm=70.0, rim_inner_diameter_mm=200.0, web_thickness_mm=12.0,
                          in_plane_force_N=6000.0, axial_force_N=400.0, pocket_area_fraction=0.7,
                          pocket_pitch_diameter_mm=80.0, stress_concentration=2.0)
    assert pocketed["shear_pocket_MPa"] > plain["shear_MPa"]
    assert pocketed["shear_MPa"] == pocketed["shear_pocket_MPa"]
    with pytest.raises(GearoptInputError, match="rim_inner_diameter_mm=60 mm must exceed"):
        web_stress(1.0, hub_outer_diameter_mm=70.0, rim_inner_diameter_mm=60.0, web_thickness_mm=12.0)
    with pytest.raises(GearoptInputError, match="stress_concentration=0.5 is below"):
        web_stress(1.0, hub_outer_diameter_mm=70.0, rim_inner_diameter_mm=200.0, web_thickness_mm=12.0,
                   stress_concentration=0.5)


def test_goodman_identities_and_published_fully_reversed_case():
    Se, Sut = 276.0, 551.0
    # fully reversed: the EFR stress is the alternating stress. Shigley's MED solutions 6-15 (coursehero excerpt
    # "9-ch-06 budynas SM ch06"): sigma_a = 358.5 MPa, sigma_m = 0, S_e = 276 MPa -> modified Goodman n_f = 0.77
    efr = goodman_equivalent_fully_reversed_MPa(358.5, 0.0, Sut)
    assert Se / efr == pytest.approx(0.77, abs=0.005)
    # any point on the Goodman line sigma_a/S_e + sigma_m/S_ut = 1 has EFR = S_e (margin 1)
    for sm in (50.0, 200.0, 400.0):
        sa = Se * (1 - sm / Sut)
        assert goodman_equivalent_fully_reversed_MPa(sa, sm, Sut) == pytest.approx(Se, rel=1e-12)
    # compressive mean: no credit
    assert goodman_equivalent_fully_reversed_MPa(100.0, -200.0, Sut) == 100.0
    with pytest.raises(GearoptInputError, match="static failure"):
        goodman_equivalent_fully_reversed_MPa(10.0, 600.0, Sut)


def test_forward_reverse_cases():
    r = web_fatigue(200.0, 80.0, endurance_limit_MPa=500.0, ultimate_strength_MPa=1000.0, yield_strength_MPa=700.0)
    f, rv, fr = r["forward"], r["reverse"], r["forward_reverse"]
    assert (f["alternating_MPa"], f["mean_MPa"]) == (100.0, 100.0)
    assert f["efr_MPa"] == pytest.approx(100.0 / 0.9) and f["fatigue_margin"] == pytest.approx(4.5)
    assert (rv["alternating_MPa"], rv["mean_MPa"]) == (40.0, 40.0)
    assert (fr["alternating_MPa"], fr["mean_MPa"]) == (140.0, 60.0)
    assert fr["fatigue_margin"] < f["fatigue_margin"] < rv["fatigue_margin"]  # the combined case is the worst
    assert fr["yield_margin"] == pytest.approx(3.5)
    # symmetric forward-reverse is fully reversed
    s = web_fatigue(150.0, 150.0, endurance_limit_MPa=500.0, ultimate_strength_MPa=1000.0)["forward_reverse"]
    assert s["mean_MPa"] == 0.0 and s["efr_MPa"] == 150.0
    # an unloaded direction has no finite margin: inf, not a stand-in number
    z = web_fatigue(150.0, 0.0, endurance_limit_MPa=500.0, ultimate_strength_MPa=1000.0)["reverse"]
    assert z["fatigue_margin"] == math.inf
    assert forward_reverse_from_history([-30.0, 120.0, 5.0]) == (120.0, 30.0)
    assert forward_reverse_from_history([10.0, 20.0]) == (20.0, 0.0)


def test_web_stress_derivatives():
    x = ca.SX.sym("x", 3)  # torque, web thickness, axial force

    def vm(v):
        return web_stress(v[0], hub_outer_diameter_mm=70.0, rim_inner_diameter_mm=200.0, web_thickness_mm=v[1],
                          in_plane_force_N=5000.0, axial_force_N=v[2], pocket_area_fraction=0.4)["von_mises_MPa"]

    J = np.array(ca.Function("J", [x], [ca.jacobian(vm(x), x)])([300.0, 12.0, 400.0])).ravel()
    x0 = np.array([300.0, 12.0, 400.0])
    for k in range(3):
        h = 1e-6 * max(x0[k], 1.0)
        e = np.zeros(3)
        e[k] = h
        assert J[k] == pytest.approx((float(vm(x0 + e)) - float(vm(x0 - e))) / (2 * h), rel=1e-6)


def test_fatigue_margin_derivatives():
    x = ca.SX.sym("x", 2)  # forward and reverse equivalent stresses

    def margins(v):
        r = web_fatigue(v[0], v[1], endurance_limit_MPa=500.0, ultimate_strength_MPa=1000.0)
        return [r[c]["fatigue_margin"] for c in ("forward", "reverse", "forward_reverse")]

    f = ca.Function("f", [x], [ca.vertcat(*margins(x))])
    J = np.array(ca.Function("J", [x], [ca.jacobian(f(x), x)])([200.0, 80.0]))
    x0 = np.array([200.0, 80.0])
    assert np.allclose(np.array(f(x0)).ravel(), [float(m) for m in margins(x0)], rtol=1e-12)
    for k in range(2):
        e = np.zeros(2)
        e[k] = 1e-4
        fd = (np.array([float(m) for m in margins(x0 + e)]) - np.array([float(m) for m in margins(x0 - e)])) / 2e-4
        assert np.allclose(J[:, k], fd, rtol=1e-6, atol=1e-10), k
