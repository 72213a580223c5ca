"""Torsional network builder and linear analysis (gearopt.dynamics.network, gearopt.dynamics.modes)."""

import math

import numpy as np
import pytest
import scipy.linalg

from gearopt import numerics as nm
from gearopt.dynamics import TorsionalNetwork
from gearopt.dynamics.modes import (
    campbell_diagram,
    damped_modes,
    forced_response,
    linear_matrices,
    mode_shapes,
    natural_frequencies_Hz,
)
from gearopt.errors import GearoptInputError

# Mendes, Meirelles & Zampieri (2008), Proc. IMechE K 222:155, Fig. 4 chain as in openTorsion
# examples/ICE_example.py (docs/default-data.md sec. 2.2): pulley, gear-train node, six throws, flywheel.
MENDES_J = [0.0170, 0.0090, 0.0467, 0.0327, 0.0467, 0.0467, 0.0327, 0.0487, 2.0750]
MENDES_K = [1.106e6, 1.631e6, 1.253e6, 1.253e6, 1.678e6, 1.253e6, 1.253e6, 1.976e6]


def mendes_chain(ring=None, hub_extra=0.0):
    net = TorsionalNetwork("Mendes 2008")
    if ring is not None:
        net.add_inertia("ring", ring[0])
    for i, j in enumerate(MENDES_J):
        net.add_inertia(f"n{i}", j + (hub_extra if i == 0 else 0.0))
    if ring is not None:
        net.add_damper("ring", "n0", ring[1])
    for i, k in enumerate(MENDES_K):
        net.add_shaft(f"n{i}", f"n{i + 1}", k)
    return net


def test_acceptance_two_inertias_free_free():
    # issue 5 acceptance interface; closed form f = sqrt(k (J1 + J2) / (J1 J2)) / (2 pi)
    net = TorsionalNetwork()
    net.add_inertia("pulley", inertia_kgm2=0.017)
    net.add_inertia("gear", inertia_kgm2=0.009)
    net.add_shaft("pulley", "gear", stiffness_Nm_per_rad=1.106e6, damping_Nms_per_rad=0.0)
    f = net.natural_frequencies_Hz()
    assert f[0] == pytest.approx(0.0, abs=1e-6)
    assert f[1] == pytest.approx(math.sqrt(1.106e6 * (0.017 + 0.009) / (0.017 * 0.009)) / (2 * math.pi), rel=1e-12)


def test_chain_eigenfrequencies_match_numpy_eig_of_the_same_matrices():
    # required check of issue 5: the generalized symmetric solution against numpy's general eigen-solver
    net = mendes_chain()
    mats = linear_matrices(net)
    lam = np.linalg.eigvals(np.linalg.solve(mats["M"], mats["K"]))
    ref = np.sort(np.sqrt(np.clip(lam.real, 0, None))) / (2 * math.pi)
    np.testing.assert_allclose(net.natural_frequencies_Hz(), ref, rtol=1e-9, atol=1e-6)
    # stiffness matrix of a chain: tridiagonal, rows sum to zero (free-free)
    np.testing.assert_allclose(mats["K"].sum(axis=1), 0.0, atol=1e-6)


def test_mendes_chain_modes_and_published_resonance_speed():
    # [C] docs/default-data.md sec. 2.2: free-free modes 216.6, 592.7, 984.9 Hz (computed for this data set, not published)
    f = mendes_chain().natural_frequencies_Hz()
    assert f[0] == pytest.approx(0.0, abs=1e-6)
    np.testing.assert_allclose(f[1:4], [216.6, 592.7, 984.9], atol=0.05)
    # published: Mendes et al. 2008 Figs. 31/32 (digitised in openTorsion torsional_vibration_data_fig31.csv /
    # fig32.csv) peak at 2149 rpm (9477 N m flywheel-shaft, 841 N m pulley-gear shaft vibratory torque): the order-6
    # (major order of an I6) crossing of our first mode must fall there
    camp = campbell_diagram(mendes_chain(), np.arange(1000, 2600, 50), orders=[4.5, 6.0, 7.5], boundary="free")
    crossings = camp["crossings"]
    n6 = crossings[(crossings["mode"] == 2) & (crossings["order"] == 6.0)]["speed_rpm"].item()
    assert n6 == pytest.approx(2149.0, rel=0.02)
    assert crossings[(crossings["mode"] == 2) & (crossings["order"] == 7.5)]["speed_rpm"].item() == \
        pytest.approx(60 * f[1] / 7.5, rel=1e-12)


def test_viscous_damper_mode_and_its_limits():
    # [C] docs/default-data.md sec. 2.3: chain + housing 0.03 on the pulley + ring 0.08 by c = 80: mode 1 174.3 Hz, zeta 0.120
    net = mendes_chain(ring=(0.08, 80.0), hub_extra=0.03)
    modes = damped_modes(net, boundary="free")
    assert modes["frequency_Hz"].iloc[0] == pytest.approx(174.3, abs=0.1)
    assert modes["damping_ratio"].iloc[0] == pytest.approx(0.120, abs=0.001)
    # limits (closed form in the sense of the model): c -> infinity locks the ring to the hub (158.5 Hz [C]);
    # c -> 0 frees it (the chain with the heavier hub alone, undamped)
    locked = mendes_chain(hub_extra=0.03 + 0.08).natural_frequencies_Hz()[1]
    assert locked == pytest.approx(158.5, abs=0.1)
    stiff = damped_modes(mendes_chain(ring=(0.08, 1e7), hub_extra=0.03), boundary="free")
    assert stiff["frequency_Hz"].iloc[0] == pytest.approx(locked, rel=1e-4)
    assert stiff["damping_ratio"].iloc[0] < 1e-3
    loose = damped_modes(mendes_chain(ring=(0.08, 1e-3), hub_extra=0.03), boundary="free")
    free = mendes_chain(hub_extra=0.03).natural_frequencies_Hz()[1]
    assert loose["frequency_Hz"].iloc[0] == pytest.approx(free, rel=1e-6)


def geared_pair(k_mesh=4e8, boundary=False):
    net = TorsionalNetwork("pair")
    net.add_inertia("g1", 0.01).add_inertia("g2", 0.04)
    net.add_mesh("g1", "g2", base_radii_mm=(40.0, 80.0), teeth=(30, 60), stiffness_N_per_m=k_mesh)
    if boundary:
        net.add_inertia("drive", 1.0).add_shaft("drive", "g1", 2e5).set_speed_boundary("drive")
    return net


def test_gear_mesh_mode_is_the_equivalent_mass_frequency():
    # two gears on a mesh: f = sqrt(k / m_eq) / (2 pi), m_eq = 1 / (r_b1^2/J1 + r_b2^2/J2) (thesis Eq. 3.27;
    # Kahraman & Singh 1990 single-DOF mesh model)
    net = geared_pair()
    m_eq = 1.0 / (0.04 ** 2 / 0.01 + 0.08 ** 2 / 0.04)
    f = net.natural_frequencies_Hz()
    assert f[0] == pytest.approx(0.0, abs=1e-6)
    assert f[1] == pytest.approx(math.sqrt(4e8 / m_eq) / (2 * math.pi), rel=1e-10)
    # the rigid-body mode is the speed-ratio vector: gear 2 turns back at half the speed
    assert net.speed_ratios() == {"g1": 1.0, "g2": -0.5}
    shapes = mode_shapes(net)
    assert shapes.loc["g2", "mode_1"] / shapes.loc["g1", "mode_1"] == pytest.approx(-0.5, rel=1e-9)


def test_geared_chain_reduces_to_referred_inertias():
    # a very stiff mesh makes the pair one rigid body: drive shaft k with the gears' inertia referred to g1,
    # J1 + J2 (r_b1/r_b2)^2, against the held boundary: f = sqrt(k / J_ref) / (2 pi)
    net = geared_pair(k_mesh=1e14, boundary=True)
    j_ref = 0.01 + 0.04 * 0.25
    assert net.natural_frequencies_Hz()[0] == pytest.approx(math.sqrt(2e5 / j_ref) / (2 * math.pi), rel=1e-5)


def test_den_hartog_untuned_damper_fixed_point():
    # Lanchester/Houdaille damper (Den Hartog, Mechanical Vibrations): main inertia J on a spring k to ground,
    # ring mu J coupled by viscous c. Closed form (derived from the two limits c -> 0 and c -> inf, which must give
    # equal |X|): every response curve passes through w^2 = 2 k / ((2 + mu) J) with |X| / X_static = 1 + 2/mu.
    j, k, mu = 0.1, 1e5, 0.25
    wn = math.sqrt(k / j)
    w_fixed = wn * math.sqrt(2 / (2 + mu))
    for c in (0.5, 5.0, 50.0):
        net = TorsionalNetwork(cycle_deg=360.0)
        net.add_inertia("ground", 1.0).add_inertia("main", j).add_inertia("ring", mu * j)
        net.add_shaft("ground", "main", k).add_damper("main", "ring", c)
        net.set_speed_boundary("ground")
        net.add_torque("main", lambda t, a, w: nm.cos(a), name="harmonic")
        speed_rpm = w_fixed * 30 / math.pi          # order 1 = the speed
        fr = forced_response(net, [speed_rpm], max_order=1.0)
        amp = fr["orders"].query("quantity == 'shaft_torque_Nm' and element == 'ground-main'")["amplitude"].item()
        assert amp / 1.0 == pytest.approx(1 + 2 / mu, rel=1e-9)   # shaft torque / k = |X|; static X = T / k


def test_speed_ratios_and_input_errors():
    net = TorsionalNetwork()
    net.add_inertia("a", 1.0).add_inertia("b", 1.0).add_inertia("c", 1.0)
    net.add_mesh("a", "b", base_radii_mm=(20.0, 60.0), teeth=(20, 60), stiffness_N_per_m=1e8)
    net.add_shaft("b", "c", 1e4)
    assert net.speed_ratios() == pytest.approx({"a": 1.0, "b": -1 / 3, "c": -1 / 3})
    with pytest.raises(GearoptInputError, match="inertia_kgm2 of 'x'=-1"):
        net.add_inertia("x", -1.0)
    with pytest.raises(GearoptInputError, match="already exists"):
        net.add_inertia("a", 1.0)
    with pytest.raises(GearoptInputError, match="node_b='zz'"):
        net.add_shaft("a", "zz", 1.0)
    with pytest.raises(GearoptInputError, match="tooth ratio"):
        net.add_mesh("a", "c", base_radii_mm=(20.0, 30.0), teeth=(20, 60), stiffness_N_per_m=1e8)
    with pytest.raises(GearoptInputError, match="backlash_mm of 'a-c'=-0.1"):
        net.add_mesh("a", "c", base_radii_mm=(20.0, 60.0), teeth=(20, 60), stiffness_N_per_m=1e8, backlash_mm=-0.1)
    net.add_mesh("a", "c", base_radii_mm=(20.0, 40.0), teeth=(20, 40), stiffness_N_per_m=1e8)
    with pytest.raises(GearoptInputError, match="inconsistent loop"):
        net.speed_ratios()
    lone = TorsionalNetwork()
    lone.add_inertia("a", 1.0).add_inertia("b", 1.0)
    with pytest.raises(GearoptInputError, match="not connected"):
        lone.speed_ratios()
    with pytest.raises(GearoptInputError, match="unknown parameter"):
        geared_pair().parameter_vector(1000.0, {"nope": 1.0})


def test_linear_matrices_hold_the_boundary_and_are_symmetric():
    net = geared_pair(boundary=True)
    mats = linear_matrices(net)
    assert mats["nodes"] == ["g1", "g2"]
    for key in ("M", "K", "C"):
        np.testing.assert_allclose(mats[key], mats[key].T)
    assert np.all(scipy.linalg.eigvalsh(mats["K"]) > 0)            # held: no rigid-body mode
    free = linear_matrices(net, boundary="free")
    assert free["nodes"] == ["g1", "g2", "drive"]
    assert natural_frequencies_Hz(net, boundary="free")[0] == pytest.approx(0.0, abs=1e-5)


def test_user_stiffness_function_equals_the_same_fourier_shape():
    # the LTCA's stiffness over the mesh cycle can be plugged in as a callable of the mesh angle (mean 1)
    from gearopt.dynamics.mesh import MeshStiffnessShape
    from gearopt.dynamics.simulate import simulate

    def build(shape):
        net = TorsionalNetwork(cycle_deg=360.0)
        net.add_inertia("drive", 1.0).add_inertia("g1", 0.01).add_inertia("g2", 0.04)
        net.add_shaft("drive", "g1", 2e5, 5.0)
        net.add_mesh("g1", "g2", base_radii_mm=(40.0, 80.0), teeth=(30, 60), stiffness_N_per_m=4e8,
                     damping_N_s_per_m=2000.0, stiffness_shape=shape)
        net.add_torque("g2", lambda t, a, w: -100.0 + 0.0 * a, name="load")
        return net.set_speed_boundary("drive")

    fourier = simulate(build(MeshStiffnessShape((0.2, 0.0), (0.0, -0.05))), 1500.0, 1, backlash=False, rtol=1e-9)
    user = simulate(build(lambda psi: 1.0 + 0.2 * nm.cos(psi) - 0.05 * nm.sin(2 * psi)), 1500.0, 1, backlash=False,
                    rtol=1e-9)
    np.testing.assert_allclose(user.mesh_force_N["g1-g2"], fourier.mesh_force_N["g1-g2"], rtol=1e-7)
    k = user.mesh_stiffness_N_per_m["g1-g2"]
    psi = np.linspace(0, 2 * np.pi, 10001)
    shape = 1.0 + 0.2 * np.cos(psi) - 0.05 * np.sin(2 * psi)
    assert k.max() / k.min() == pytest.approx(shape.max() / shape.min(), rel=0.01)   # the variation reaches k(t)
    with pytest.raises(GearoptInputError, match="mean 1"):
        build(lambda psi: 2.0 + 0.0 * psi)
