"""Gear blank mass and inertia (thesis sec. 3.10): solid-disc formula, annulus subtraction, holes by numerical
integration over the web, the default data's [C] inertias, the backup ratio and AGMA rim factor, errors, derivatives."""

import math

import casadi as ca
import numpy as np
import pytest

import gearopt as go
from gearopt.blank import GearBlank, annulus_inertia_kgm2, annulus_mass_kg, blank_from_data, rim_thickness_factor
from gearopt.errors import GearoptInputError


def test_solid_disc_and_annulus_formulas():
    # textbook solid disc J = m D^2/8 and annulus J = m (D^2 + d^2)/8, m = rho pi/4 (D^2 - d^2) L
    m = annulus_mass_kg(200.0, 0.0, 20.0)
    assert m == pytest.approx(7850 * math.pi / 4 * 0.2 ** 2 * 0.02, rel=1e-12)
    assert annulus_inertia_kgm2(200.0, 0.0, 20.0) == pytest.approx(m * 0.2 ** 2 / 8, rel=1e-12)
    ma = annulus_mass_kg(200.0, 80.0, 20.0)
    assert annulus_inertia_kgm2(200.0, 80.0, 20.0) == pytest.approx(ma * (0.2 ** 2 + 0.08 ** 2) / 8, rel=1e-12)
    # subtraction: annulus = big disc - small disc
    assert annulus_inertia_kgm2(200.0, 80.0, 20.0) == pytest.approx(
        annulus_inertia_kgm2(200.0, 0.0, 20.0) - annulus_inertia_kgm2(80.0, 0.0, 20.0), rel=1e-12)


def test_solid_blank_equals_disc_minus_bore_plus_fill_times_teeth():
    b = GearBlank(234.67, 221.17, 25.0, 42.0)
    expected = annulus_inertia_kgm2(221.17, 42.0, 25.0) + 0.5 * annulus_inertia_kgm2(234.67, 221.17, 25.0)
    assert b.inertia_kgm2() == pytest.approx(expected, rel=1e-12)
    assert b.kind == "solid"


@pytest.mark.parametrize("args, expected, rel", [
    # default_train.toml [gears.*] solid_disc_inertia_kgm2 / inertia_kgm2 [C] notes (their diameters, bores, b)
    ((121.88, 108.38, 30.0, 65.0), 0.00373, 2e-3),   # crank, solid
    ((234.67, 221.17, 25.0, 42.0), 0.0522, 1e-3),    # cam, solid reference
    ((237.99, 224.49, 25.0, 25.0), 0.0554, 1e-3),    # fp, solid reference
    ((125.27, 111.77, 25.0, 30.0), 0.00386, 2e-3),   # ac, solid reference
    ((79.67, 66.17, 20.0, 38.0), 0.00043, 1e-2),     # lpi (data rounds to 2 digits)
    ((82.05, 68.55, 20.0, 22.0), 0.00052, 1e-2),     # lpg
])
def test_default_data_solid_inertias(args, expected, rel):
    assert GearBlank(*args).inertia_kgm2() == pytest.approx(expected, rel=rel)


def test_default_data_webbed_cam_and_recessed_ac():
    # cam [C] note: rim 3.5 m_n + teeth 0.0214, 12 mm web 40 % pocketed 0.0088, hub 0.0003 -> 0.0305
    cam = GearBlank(234.67, 221.17, 25.0, 42.0, hub_outer_diameter_mm=70.0, hub_length_mm=25.0, web_thickness_mm=12.0,
                    rim_thickness_mm=10.5, pocket_area_fraction=0.4)
    c = cam.components()
    assert c["teeth"][1] + c["rim"][1] == pytest.approx(0.0214, abs=1e-4)  # the note rounds to 3 digits
    assert c["web"][1] + c["pockets"][1] == pytest.approx(0.0088, abs=5e-5)
    assert cam.inertia_kgm2() == pytest.approx(0.0305, rel=5e-3)
    assert cam.kind == "pocketed"
    # ac [C] note: 0.0033 (rim 3.5 m_n, half tooth annulus, 12 mm web to a 60 mm hub of 30 mm length, bore 30)
    ac = GearBlank(125.27, 111.77, 25.0, 30.0, hub_outer_diameter_mm=60.0, hub_length_mm=30.0, web_thickness_mm=12.0,
                   rim_thickness_mm=10.5)
    assert ac.inertia_kgm2() == pytest.approx(0.0033, rel=2e-2) and ac.kind == "webbed"
    assert ac.inertia_kgm2() < ac.solid_equivalent().inertia_kgm2()


def test_round_holes_against_numerical_integration_over_the_web():
    blank = GearBlank(234.67, 221.17, 25.0, 42.0, hub_outer_diameter_mm=70.0, hub_length_mm=25.0,
                      web_thickness_mm=12.0, rim_thickness_mm=10.5, hole_count=6, hole_diameter_mm=40.0,
                      hole_pitch_diameter_mm=136.0)
    m_h, j_h = blank.components()["pockets"]
    # midpoint-rule integration of rho t r^2 over the area inside the six holes (polar grid)
    n_r, n_t = 800, 1440
    r = np.linspace(35.0, 100.085, n_r + 1)
    r = 0.5 * (r[1:] + r[:-1])
    t = (np.arange(n_t) + 0.5) * 2 * np.pi / n_t
    R, T = np.meshgrid(r, t, indexing="ij")
    x, y = R * np.cos(T), R * np.sin(T)
    inside = np.zeros_like(R, dtype=bool)
    for k in range(6):
        cx, cy = 68.0 * math.cos(k * math.pi / 3), 68.0 * math.sin(k * math.pi / 3)
        inside |= (x - cx) ** 2 + (y - cy) ** 2 < 20.0 ** 2
    dA = (r[1] - r[0]) * R * (2 * np.pi / n_t)
    rho_t = 7850 * 12.0 * 1e-9
    assert -m_h == pytest.approx(rho_t * np.sum(dA[inside]), rel=2e-3)
    assert -j_h == pytest.approx(rho_t * np.sum((dA * R ** 2)[inside]) * 1e-6, rel=2e-3)


def test_train_blanks_near_the_data_values():
    # tip diameters of the train are shortened a little (tip shortening), so allow a few per cent
    system, train = go.load_system(), go.load_default_train("spur")
    expected = {"crank": (0.00373, 0.01), "cam": (0.0305, 0.01), "ac": (0.0033, 0.02), "lpi": (0.00043, 0.04),
                "lpg": (0.00052, 0.04)}
    for gear, (j, rel) in expected.items():
        blank, _ = blank_from_data(system, train, gear)
        assert blank.inertia_kgm2() == pytest.approx(j, rel=rel), gear
    fp, _ = blank_from_data(system, train, "fp")
    assert 0.031 <= fp.inertia_kgm2() <= 0.032  # the fp [C] check: 0.031-0.032


def test_backup_ratio_and_agma_rim_factor():
    cam = GearBlank(234.34, 221.17, 25.0, 42.0, hub_outer_diameter_mm=70.0, hub_length_mm=25.0,
                    web_thickness_mm=12.0, rim_thickness_mm=10.5)
    assert cam.backup_ratio == pytest.approx(10.5 / ((234.34 - 221.17) / 2))
    assert rim_thickness_factor(1.5) == 1.0
    # the printed AGMA constants make K_B continuous at m_B = 1.2 (to the 4 digits of 2.242)
    assert rim_thickness_factor(1.2 - 1e-9) == pytest.approx(1.0, abs=2e-4)
    assert rim_thickness_factor(0.5) == pytest.approx(1.6 * math.log(2.242 / 0.5))
    ks = [float(rim_thickness_factor(m)) for m in (0.5, 0.7, 0.9, 1.1)]
    assert all(b < a for a, b in zip(ks, ks[1:]))  # thinner rims, larger factor
    with pytest.raises(GearoptInputError, match="backup_ratio=0.4 is below"):
        rim_thickness_factor(0.4)


@pytest.mark.parametrize("kw, match", [
    ({"hub_outer_diameter_mm": 210.0}, "hub_outer_diameter_mm=210 mm must be < rim inner diameter"),
    ({"web_thickness_mm": 30.0}, "web_thickness_mm=30 mm must be <= hub_length_mm=25"),
    ({"hole_count": 12, "hole_diameter_mm": 40.0, "hole_pitch_diameter_mm": 136.0}, "overlap"),
    ({"hole_count": 6, "hole_diameter_mm": 40.0, "hole_pitch_diameter_mm": 90.0}, "leave the web"),
    ({"hole_count": 6, "hole_diameter_mm": 20.0, "hole_pitch_diameter_mm": 136.0, "pocket_area_fraction": 0.2},
     "not both"),
    ({"pocket_area_fraction": 0.9}, "pocket_area_fraction=0.9 exceeds"),
])
def test_invalid_blanks_raise(kw, match):
    args = {"hub_outer_diameter_mm": 70.0, "hub_length_mm": 25.0, "web_thickness_mm": 12.0, "rim_thickness_mm": 10.5}
    args.update(kw)
    with pytest.raises(GearoptInputError, match=match):
        GearBlank(234.67, 221.17, 25.0, 42.0, **args)
    with pytest.raises(GearoptInputError, match="need a web"):
        GearBlank(234.67, 221.17, 25.0, 42.0, pocket_area_fraction=0.3)
    with pytest.raises(GearoptInputError, match="needs rim_thickness_mm"):
        GearBlank(234.67, 221.17, 25.0, 42.0, hub_outer_diameter_mm=70.0, hub_length_mm=25.0, web_thickness_mm=12.0)


def test_inertia_derivatives_for_an_objective():
    x = ca.SX.sym("x", 3)  # web thickness, pocket fraction, rim thickness

    def inertia(v):
        return GearBlank(234.67, 221.17, 25.0, 42.0, hub_outer_diameter_mm=70.0, hub_length_mm=25.0,
                         web_thickness_mm=v[0], pocket_area_fraction=v[1], rim_thickness_mm=v[2]).inertia_kgm2()

    J = np.array(ca.Function("J", [x], [ca.jacobian(inertia(x), x)])([12.0, 0.4, 10.5])).ravel()
    x0 = np.array([12.0, 0.4, 10.5])
    for k in range(3):
        h = 1e-6 * max(x0[k], 1.0)
        e = np.zeros(3)
        e[k] = h
        fd = (float(inertia(x0 + e)) - float(inertia(x0 - e))) / (2 * h)
        assert J[k] == pytest.approx(fd, rel=1e-6)
    assert J[0] > 0 and J[1] < 0 and J[2] > 0  # thicker web/rim heavier, more pockets lighter
