"""Position-dependent single-pair tooth stiffness of a cylindrical gear pair by the potential-energy method (numeric).

Model (Yang & Lin 1987; Tian 2004; Chen & Shao 2011; Sainsot, Velex & Duverger 2004 for the gear body):

    1/k(rho) = 1/k_h + sum over both gears (1/k_b + 1/k_s + 1/k_a + 1/k_f)

for one pair of teeth in contact at the position rho on the path of contact (roll length on gear 1, mm), all per unit
face width (``L = 1 mm``), k in N/(mm*um). Each tooth is a cantilever of variable section, loaded at the contact
point (x_c, y_c) by the normal force F along the line of action, at the angle ``alpha1 = alpha_c - psi_c`` to the
perpendicular of the tooth centreline (alpha_c: pressure angle, psi_c: half tooth angle at the contact radius):

* bending  1/k_b = int [cos(alpha1) (y_c - y) - x_c sin(alpha1)]^2 / (E I(y)) dy,  I = (2h)^3 L / 12,
* shear    1/k_s = int 1.2 cos^2(alpha1) / (G A(y)) dy,  A = 2 h L,  G = E / (2 (1 + nu)),
* axial    1/k_a = int sin^2(alpha1) / (E A(y)) dy,

where h(y) is the half chord of the tooth section perpendicular to the centreline at the height y above the gear
centre, integrated from the root circle up to the contact point (y_c); the tooth above the load stores no energy.
The tooth is the real tooth of each gear: the exact involute of the profile-shifted tooth (half angle
psi(r) = s_t/(2r) + inv(alpha_t) - inv(alpha_r), from ISO 21771 eq. 57 with zero thickness allowance) from its start
up to the load point, plus a root section between the root circle and the involute start (``root_section``):

* ``"trochoid"`` (default): the fillet the basic rack (h_fP*, rho_fP*) generates, computed exactly (envelope of the
  rack's tip rounding: the contact normal passes through the pitch point), from the root circle up to the root form
  circle where the involute starts. The beam then starts at the root circle like Sainsot's foundation model assumes
  (the approach of Ma et al. 2014 / the ross ``gear_mesh_TVMS`` model).
* ``"constant"``: Chen & Shao (2011): the involute starts at the base circle (or at the root circle when that lies
  above the base circle), and between the root circle and the involute start the tooth is a straight section of
  the constant half thickness h_0 of the involute start, from the height sqrt(r_f^2 - h_0^2) where its corners
  meet the root circle (``constant_section_start="chord"``) or from y = r_f (``"root_radius"``). Gauss-Legendre
  integrates it exactly. With ``ANCHOR_CONVENTIONS`` this reproduces docs/default-data.md sec. 1.2's [C] anchor values.

Hertz (line contact, load independent): k_h = pi E L / (4 (1 - nu^2)) (Yang & Lin 1987).

Gear-body ("fillet-foundation") term of Sainsot et al. (2004):
1/k_f = cos^2(alpha1) / (E L) [L* (u_f/S_f)^2 + M* (u_f/S_f) + P* (1 + Q* tan^2(alpha1))], with the polynomial
coefficients X* = A/theta_f^2 + B h_f^2 + C h_f/theta_f + D/theta_f + E h_f + F of :data:`SAINSOT_COEFFICIENTS`
(checked against three independent public codes: petrobras/ross ``gear_mesh_TVMS.py`` and two MATLAB/Python TVMS
codes), h_f = r_f / r_int (r_int: bore radius, default 0.5 r_f), S_f = 2 r_f theta_f, theta_f the half angle of the
tooth at the root circle (``root_half_angle="generated"``: b_c/r, the rack rounding centre's offset b_c = pi m/4 +
(h_fP - rho_fP) m tan(alpha) + rho_fP m/cos(alpha), exact for the generated tooth; ``"addendum"``: the ross
formula, which uses the gear addendum h_aP instead of h_fP and so gives theta_f smaller by c tan(alpha)/r), and
u_f the distance from the root circle to the point where the load line cuts the tooth centreline (Sainsot's
definition, u_f = y_c - x_c tan(alpha1) - r_f); ``fillet_height="contact"`` uses the contact height y_c - r_f as
the ross code does. Sainsot's fit covers 1.4 <= h_f <= 7 and 0.01 <= theta_f <= 0.12; outside, the polynomial is
extrapolated (:attr:`ToothData.sainsot_in_range` reports it; z = 24 teeth have theta_f = 0.126).

Quadrature: Gauss-Legendre with ``quadrature_nodes`` (default :data:`DEFAULT_QUADRATURE_NODES` = 16) on each
section, in the involute's roll length (smooth down to the base circle) and in the rack-rounding angle on the
fillet. Converged: 16 nodes agree with 64 nodes to better than 1e-6 relative (tested; ~1e-10 in practice). The
involute integrals equal Tian's (2004) closed forms and the generated fillet equals the published transition curve
of Ma et al. (2014) to machine precision (tests/validation/test_potential_energy_published.py).

Helical pairs: thin-slice model in the transverse section. The beam terms are those of the transverse tooth profile
(z, m_t, alpha_t, s_t) loaded in its plane by the transverse force per unit face width (the axial force component
does not deflect the slice); the Hertzian approach acts along the normal over the contact-line length b/cos(beta_b),
so along the transverse line of action k_h,t = cos(beta_b) pi E/(4(1 - nu^2)) per unit face width. The stiffness is
that of the transverse line of action per unit face width, the quantity :mod:`gearopt.contact.ltca` uses.

Validity and approximations: linear elastic steel teeth of solid gears (the Sainsot term stands for the body with a
bore of radius r_int); plane stress/strain distinction ignored (E, not E/(1-nu^2), in the beam terms, as in all the
cited works); nominal tooth thickness (no thickness allowance, no profile modification); load exactly on the
involute within the path of contact A..E; no coupling between neighbouring teeth; friction neglected.
Accuracy against ISO 6336-1 method B (whose c_gamma_alpha includes the empirical theory-to-measurement factor
C_M = 0.8): the mean mesh stiffness over a base pitch lies within -10 %/+15 % of c_gamma_alpha when both gears have
z >= 38 (the packaged 38/76 pair: +1.7 %), and within -10 %/+25 % for all pairs tested (z 20..76, x -0.1..0.88,
beta 0 and 6 deg; 20/20: +21 %): the potential-energy model is a theoretical stiffness like ISO's c'_th and grows
stiffer relative to ISO for few teeth. Against docs/default-data.md sec. 1.2's independent [C] implementation with its
conventions (``ANCHOR_CONVENTIONS``) it agrees to the quoted rounding; the default model is 1-3 % stiffer.

Units: lengths mm, E in MPa, stiffness per unit face width N/(mm*um) (numerically GN/m^2).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, fields

import numpy as np

from ..errors import GearoptInputError
from ..validation import check_range
from ..geometry.pair import GearPair

#: Sainsot, Velex & Duverger (2004) coefficients (A, B, C, D, E, F) of L*, M*, P*, Q* (docs/default-data.md sec. 1.2; identical
#: in petrobras/ross ``gear_mesh_TVMS.py`` and two other public TVMS codes).
SAINSOT_COEFFICIENTS = {
    "L": (-5.574e-5, -1.9986e-3, -2.3015e-4, 4.7702e-3, 0.0271, 6.8045),
    "M": (60.111e-5, 28.100e-3, -83.431e-4, -9.9256e-3, 0.1624, 0.9086),
    "P": (-50.952e-5, 185.50e-3, 0.0538e-4, 53.300e-3, 0.2895, 0.9236),
    "Q": (-6.2042e-5, 9.0889e-3, -4.0964e-4, 7.8297e-3, -0.1472, 0.6904),
}
#: Fit range of Sainsot's polynomials (ross): h_f = r_f/r_int and theta_f [rad].
SAINSOT_RANGE = {"h_f": (1.4, 7.0), "theta_f": (0.01, 0.12)}
#: Timoshenko shear correction factor of a rectangular section used by the potential-energy literature.
SHEAR_FACTOR = 1.2
#: Gauss-Legendre nodes per section (converged to < 1e-6 relative, see tests).
DEFAULT_QUADRATURE_NODES = 16
#: Chebyshev nodes of the interpolated profile (max relative interpolation error < 1e-6, see tests).
DEFAULT_PROFILE_NODES = 17
#: Default bore radius as a fraction of the root radius (h_f = 2, inside Sainsot's fit range).
DEFAULT_BORE_RATIO = 0.5

_ROOT_SECTIONS = ("trochoid", "constant")
_FILLET_HEIGHTS = ("load_line", "contact")
_ROOT_HALF_ANGLES = ("generated", "addendum")
_CONSTANT_STARTS = ("chord", "root_radius")
# N/mm^2 (per mm of face width) -> N/(mm*um)
_TO_N_PER_MM_UM = 1e-3


@dataclass(frozen=True)
class PotentialEnergyOptions:
    """Modelling choices of the potential-energy stiffness (defaults: the most faithful geometry).

    ``fillet``: include Sainsot's gear-body term. ``root_section``: ``"trochoid"`` (generated fillet, involute from
    the root form circle) or ``"constant"`` (Chen & Shao 2011). ``constant_section_start`` (``"constant"`` only):
    the straight section starts at the height where its corners meet the root circle, sqrt(r_f^2 - h_0^2)
    (``"chord"``), or at y = r_f on the centreline (``"root_radius"``). ``root_half_angle``: theta_f of the generated
    tooth (``"generated"``: the rack rounding centre, b_c/r with the rack dedendum h_fP*) or the ross formula
    [pi/2 + 2 tan(alpha)(h_aP* - rho_fP*) + 2 rho_fP*/cos(alpha)]/z with the gear addendum h_aP* (``"addendum"``).
    ``fillet_height``: u_f from the load line's intersection with the centreline (``"load_line"``, Sainsot) or from
    the contact height (``"contact"``, ross). ``bore_diameter_mm``: scalar or 2-tuple [mm] for Sainsot's
    h_f = r_f/r_int; ``None`` (or a ``None`` entry) uses r_int = 0.5 r_f. ``quadrature_nodes``: Gauss-Legendre
    nodes per section.
    """

    fillet: bool = True
    root_section: str = "trochoid"
    constant_section_start: str = "chord"
    root_half_angle: str = "generated"
    fillet_height: str = "load_line"
    bore_diameter_mm: object = None
    quadrature_nodes: int = DEFAULT_QUADRATURE_NODES

    def __post_init__(self):
        _check_options(self.root_section, self.fillet_height, self.root_half_angle, self.constant_section_start)
        check_range("quadrature_nodes", self.quadrature_nodes, 2, 200)
        if not float(self.quadrature_nodes).is_integer():
            raise GearoptInputError(f"quadrature_nodes={self.quadrature_nodes!r} must be an integer")

    @classmethod
    def build(cls, **options) -> PotentialEnergyOptions:
        """Options from keywords; an unknown keyword raises :class:`GearoptInputError`."""
        unknown = set(options) - {f.name for f in fields(cls)}
        if unknown:
            raise GearoptInputError(f"unknown option(s) {sorted(unknown)}; allowed: "
                                    f"{sorted(f.name for f in fields(cls))}")
        return cls(**options)


#: The conventions of docs/default-data.md sec. 1.2's [C] anchor values (someone else's implementation): constant section from
#: y = r_f, the ross root half angle, Sainsot's u_f; with the default bore r_int = 0.5 r_f.
ANCHOR_CONVENTIONS = {"root_section": "constant", "constant_section_start": "root_radius",
                      "root_half_angle": "addendum"}


@dataclass(frozen=True)
class ToothData:
    """Numeric transverse data of one tooth for the potential-energy model (lengths mm, angles rad).

    ``base_radius_mm`` r_b, ``root_radius_mm`` r_f, ``tip_radius_mm`` r_a, ``pitch_radius_mm`` r,
    ``involute_start_roll_mm`` roll length where the involute part of the beam starts, ``half_angle_constant_rad``
    s_t/(2r) + inv(alpha_t) (so psi(r) = constant - inv(alpha_r)), ``root_half_angle_rad`` theta_f,
    ``bore_radius_mm`` r_int, rack data for the generated fillet (``rack_centre_depth_mm`` a_c below the rolling
    line, ``rack_centre_offset_mm`` b_c transverse, ``rack_tip_radius_mm`` rho_fP, ``helix_angle_rad`` beta,
    ``pressure_angle_rad`` alpha_n), ``root_section`` and ``constant_section_start``.
    """

    teeth: int
    base_radius_mm: float
    root_radius_mm: float
    tip_radius_mm: float
    pitch_radius_mm: float
    involute_start_roll_mm: float
    half_angle_constant_rad: float
    root_half_angle_rad: float
    bore_radius_mm: float
    rack_centre_depth_mm: float
    rack_centre_offset_mm: float
    rack_tip_radius_mm: float
    helix_angle_rad: float
    pressure_angle_rad: float
    root_section: str
    constant_section_start: str = "chord"

    @property
    def sainsot_in_range(self) -> bool:
        """Whether h_f = r_f/r_int and theta_f lie inside Sainsot's fit range."""
        h_f = self.root_radius_mm / self.bore_radius_mm
        lo_h, hi_h = SAINSOT_RANGE["h_f"]
        lo_t, hi_t = SAINSOT_RANGE["theta_f"]
        return lo_h <= h_f <= hi_h and lo_t <= self.root_half_angle_rad <= hi_t


# ----------------------------------------------------------------------------------------------------------------
# geometry of one tooth
# ----------------------------------------------------------------------------------------------------------------

def _check_options(root_section="trochoid", fillet_height="load_line", root_half_angle="generated",
                   constant_section_start="chord"):
    for name, value, allowed in (("root_section", root_section, _ROOT_SECTIONS),
                                 ("fillet_height", fillet_height, _FILLET_HEIGHTS),
                                 ("root_half_angle", root_half_angle, _ROOT_HALF_ANGLES),
                                 ("constant_section_start", constant_section_start, _CONSTANT_STARTS)):
        if value not in allowed:
            raise GearoptInputError(f"{name}={value!r} must be one of {allowed}")


def tooth_data(pair: GearPair, options: PotentialEnergyOptions | None = None) -> tuple[ToothData, ToothData]:
    """Transverse tooth data of both gears of a numeric ``pair`` (see :class:`ToothData`) for ``options``.

    With ``root_section="trochoid"`` the involute starts at the root form circle (the generated fillet below it);
    an undercut gear (root form roll length < 0) is rejected. With ``"constant"`` it starts at the base circle, or at
    the root circle when that lies above (Chen & Shao 2011).
    """
    opt = options or PotentialEnergyOptions()
    if pair.is_symbolic:
        raise GearoptInputError("the potential-energy stiffness needs a numeric GearPair (got CasADi symbols)")
    g = pair.geometry()
    bore_diameter_mm = opt.bore_diameter_mm
    bores = bore_diameter_mm if isinstance(bore_diameter_mm, (tuple, list)) else (bore_diameter_mm,) * 2
    if len(bores) != 2:
        raise GearoptInputError(f"bore_diameter_mm={bore_diameter_mm!r} must be a scalar or a 2-tuple")
    alpha_n = math.radians(float(g["pressure_angle_deg"]))
    alpha_t = math.radians(float(g["transverse_pressure_angle_deg"]))
    beta = math.radians(float(g["helix_angle_deg"]))
    m_n = float(g["module_mm"])
    inv_t = math.tan(alpha_t) - alpha_t
    h_fp = float(pair.dedendum_coefficient) * m_n
    h_ap = float(pair.addendum_coefficient) * m_n
    rho_fp = float(pair.root_radius_coefficient) * m_n
    out = []
    for i in range(2):
        z = int(g["teeth"][i])
        x = float(g["profile_shifts"][i])
        r = 0.5 * float(g["pitch_diameter_mm"][i])
        r_b = 0.5 * float(g["base_diameter_mm"][i])
        r_f = 0.5 * float(g["root_diameter_mm"][i])
        r_a = 0.5 * float(g["tip_diameter_mm"][i])
        s_t = float(g["transverse_tooth_thickness_mm"][i])
        rho_form = float(g["root_form_roll_length_mm"][i])
        if opt.root_section == "trochoid":
            if rho_form < 0.0:
                raise GearoptInputError(
                    f"gear {i + 1} (z={z}, x={x:.4f}) is undercut (root form roll length {rho_form:.4f} mm < 0): the "
                    f"generated-fillet root section needs an involute above the base circle; use "
                    f"root_section='constant'")
            rho_start = rho_form
        else:
            rho_start = math.sqrt(max(r_f * r_f - r_b * r_b, 0.0))
        bore = bores[i]
        if bore is None:
            r_int = DEFAULT_BORE_RATIO * r_f
        else:
            check_range(f"bore_diameter_mm[{i}]", bore, 0.0, 2.0 * r_f, low_inclusive=False, high_inclusive=False,
                        unit="mm")
            r_int = 0.5 * float(bore)
        # rack rounding centre: depth below the rolling line and transverse offset from the tooth centreline
        # (the offset does not depend on x: the shift moves the rack radially only)
        a_c = h_fp - rho_fp - x * m_n
        b_c = (0.25 * math.pi * m_n + (h_fp - rho_fp) * math.tan(alpha_n) + rho_fp / math.cos(alpha_n)) / math.cos(beta)
        if opt.root_half_angle == "generated":
            theta_f = b_c / r
        else:  # ross gear_mesh_TVMS / docs/default-data.md sec. 1.2 formula with the gear addendum
            theta_f = ((0.25 * math.pi * m_n + (h_ap - rho_fp) * math.tan(alpha_n) + rho_fp / math.cos(alpha_n))
                       / math.cos(beta) / r)
        out.append(ToothData(
            teeth=z, base_radius_mm=r_b, root_radius_mm=r_f, tip_radius_mm=r_a, pitch_radius_mm=r,
            involute_start_roll_mm=rho_start, half_angle_constant_rad=s_t / (2.0 * r) + inv_t,
            root_half_angle_rad=theta_f, bore_radius_mm=r_int, rack_centre_depth_mm=a_c, rack_centre_offset_mm=b_c,
            rack_tip_radius_mm=rho_fp, helix_angle_rad=beta, pressure_angle_rad=alpha_n,
            root_section=opt.root_section, constant_section_start=opt.constant_section_start))
    return out[0], out[1]


def involute_point(tooth: ToothData, roll_length_mm):
    """Flank point of the involute at roll length rho [mm]: (half chord h, height y above the gear centre) [mm],
    the load angle alpha1 = alpha - psi [rad] of a normal force there, and dy/drho (vectorised)."""
    rho = np.asarray(roll_length_mm, dtype=float)
    r_b = tooth.base_radius_mm
    r = np.sqrt(r_b * r_b + rho * rho)
    alpha = np.arctan(rho / r_b)
    psi = tooth.half_angle_constant_rad - (np.tan(alpha) - alpha)
    h = r * np.sin(psi)
    y = r * np.cos(psi)
    dy = (rho / r) * np.cos(psi) + np.sin(psi) * rho * rho / (r_b * r)
    return h, y, alpha - psi, dy


def fillet_point(tooth: ToothData, tool_angle_rad):
    """Point of the generated root fillet, (half chord h, height y) [mm], for the rack rounding's normal angle
    psi_tool in [0, pi/2 - alpha_n] (0: the root circle, pi/2 - alpha_n: the root form circle where the involute
    starts). The generated point is the point of the rounding whose normal passes through the pitch point.
    Works with complex arguments (complex-step derivatives)."""
    psi = tool_angle_rad
    r = tooth.pitch_radius_mm
    rho = tooth.rack_tip_radius_mm
    cb = math.cos(tooth.helix_angle_rad)
    # rounding point in the transverse section (the normal-section circle is stretched tangentially by 1/cos(beta))
    q_y = r - tooth.rack_centre_depth_mm - rho * np.cos(psi)
    q_x = tooth.rack_centre_offset_mm - rho * np.sin(psi) / cb
    s_x = (q_y - r) * np.tan(psi) * cb  # position when its normal passes through the pitch point (0, r)
    phi = (s_x - q_x) / r  # gear rotation angle at that rack position
    h = s_x * np.cos(phi) - q_y * np.sin(phi)
    y = s_x * np.sin(phi) + q_y * np.cos(phi)
    return h, y


def _gauss(n: int):
    t, w = np.polynomial.legendre.leggauss(int(n))
    return t, w


def cantilever_compliances(h_mm, y_mm, weights_mm, y_c_mm, x_c_mm, alpha1_rad, E_MPa, G_MPa):
    """Bending, shear and axial compliances [mm/N per mm of face width] of a cantilever section by quadrature.

    ``h_mm``, ``y_mm``: half chord and height of the section at the quadrature points (shape (..., n));
    ``weights_mm``: quadrature weights times dy/dt (so that sum(weights * f) = integral f dy); the load (normal force,
    angle ``alpha1_rad`` to the section plane) acts at (``x_c_mm``, ``y_c_mm``) (shape (..., 1) or scalars).
    1/k_b = int 12 [cos a1 (y_c - y) - x_c sin a1]^2 / (E (2h)^3) dy, 1/k_s = int 1.2 cos^2 a1 / (G 2h) dy,
    1/k_a = int sin^2 a1 / (E 2h) dy. A constant section of length l with alpha1 = x_c = 0 gives l^3/(3 E I).
    """
    ca, sa = np.cos(alpha1_rad), np.sin(alpha1_rad)
    two_h = 2.0 * h_mm
    moment_arm = ca * (y_c_mm - y_mm) - x_c_mm * sa
    bend = np.sum(weights_mm * 12.0 * moment_arm ** 2 / (E_MPa * two_h ** 3), axis=-1)
    shear = np.sum(weights_mm * SHEAR_FACTOR * ca ** 2 / (G_MPa * two_h), axis=-1)
    axial = np.sum(weights_mm * sa ** 2 / (E_MPa * two_h), axis=-1)
    return bend, shear, axial


def sainsot_coefficients(root_half_angle_rad: float, h_f: float) -> dict:
    """Sainsot et al. (2004) L*, M*, P*, Q* for theta_f [rad] and h_f = r_f / r_int (dimensionless)."""
    t = root_half_angle_rad
    return {k: a / t ** 2 + b * h_f ** 2 + c * h_f / t + d / t + e * h_f + f
            for k, (a, b, c, d, e, f) in SAINSOT_COEFFICIENTS.items()}


def _tooth_compliances(tooth: ToothData, rho_c, E_MPa, G_MPa, nodes, fillet, fillet_height):
    """Compliances (b, s, a, f) [mm/N per mm face] of one tooth loaded at roll lengths ``rho_c`` (1-D array)."""
    t, w = _gauss(nodes)
    rho_c = np.asarray(rho_c, dtype=float)
    x_c, y_c, alpha1, _ = involute_point(tooth, rho_c)
    x_c, y_c, a1 = x_c[:, None], y_c[:, None], alpha1[:, None]
    # involute part, roll length from the involute start to the contact point
    rho0 = tooth.involute_start_roll_mm
    half = 0.5 * (rho_c[:, None] - rho0)
    rho = rho0 + half * (t + 1.0)
    h, y, _, dy = involute_point(tooth, rho)
    b, s, a = cantilever_compliances(h, y, w * half * dy, y_c, x_c, a1, E_MPa, G_MPa)
    # root section
    if tooth.root_section == "constant":
        h0, y0, _, _ = involute_point(tooth, rho0)
        h0, y0 = float(h0), float(y0)
        if tooth.constant_section_start == "chord":
            y_root = math.sqrt(max(tooth.root_radius_mm ** 2 - h0 ** 2, 0.0))
        else:
            y_root = tooth.root_radius_mm
        half_y = 0.5 * max(y0 - y_root, 0.0)
        yq = y_root + half_y * (t + 1.0)
        rb, rs, ra = cantilever_compliances(np.full_like(yq, h0), yq, w * half_y, y_c, x_c, a1, E_MPa, G_MPa)
    else:
        psi_end = 0.5 * math.pi - tooth.pressure_angle_rad
        psi = 0.5 * psi_end * (t + 1.0)
        hq, yq = fillet_point(tooth, psi)
        eps = 1e-20
        dyq = np.imag(fillet_point(tooth, psi + 1j * eps)[1]) / eps  # complex-step derivative dy/dpsi
        rb, rs, ra = cantilever_compliances(hq, yq, w * 0.5 * psi_end * dyq, y_c, x_c, a1, E_MPa, G_MPa)
    b, s, a = b + rb, s + rs, a + ra
    if fillet:
        r_f = tooth.root_radius_mm
        theta_f = tooth.root_half_angle_rad
        c = sainsot_coefficients(theta_f, r_f / tooth.bore_radius_mm)
        height = y_c - x_c * np.tan(a1) if fillet_height == "load_line" else y_c
        u = (height[:, 0] - r_f) / (2.0 * r_f * theta_f)
        f = np.cos(alpha1) ** 2 / E_MPa * (c["L"] * u ** 2 + c["M"] * u + c["P"] * (1.0 + c["Q"] * np.tan(alpha1) ** 2))
    else:
        f = np.zeros_like(rho_c)
    return b, s, a, f


# ----------------------------------------------------------------------------------------------------------------
# public API
# ----------------------------------------------------------------------------------------------------------------

def _check_material(E_MPa, poisson):
    check_range("E_MPa", E_MPa, 0.0, None, low_inclusive=False, unit="MPa")
    check_range("poisson", poisson, 0.0, 0.5, low_inclusive=False, high_inclusive=False)


def _path(pair: GearPair) -> dict:
    if pair.is_symbolic:
        raise GearoptInputError("the potential-energy stiffness needs a numeric GearPair (got CasADi symbols)")
    g = pair.geometry()
    A = float(g["sap_roll_length_mm"][0])
    E = float(g["eap_roll_length_mm"][0])
    t1t2 = A + float(g["eap_roll_length_mm"][1])
    return {"A": A, "E": E, "t1t2": t1t2, "p_bt": float(g["base_pitch_mm"]),
            "cos_beta_b": math.cos(math.radians(float(g["base_helix_angle_deg"])))}


def _compliances(pair, path, rho1, E_MPa, poisson, opt: PotentialEnergyOptions) -> dict:
    """All compliances [mm/N per mm face] at roll lengths rho1 (validated 1-D array)."""
    teeth = tooth_data(pair, opt)
    G = E_MPa / (2.0 * (1.0 + poisson))
    parts = {"h": np.full_like(rho1, 4.0 * (1.0 - poisson ** 2) / (math.pi * E_MPa * path["cos_beta_b"]))}
    for i, rho in enumerate((rho1, path["t1t2"] - rho1)):
        tooth = teeth[i]
        if np.any(rho < tooth.involute_start_roll_mm - 1e-9):
            raise GearoptInputError(
                f"contact below the involute start of gear {i + 1}: roll length {float(np.min(rho)):.4f} mm < "
                f"{tooth.involute_start_roll_mm:.4f} mm (tip/root interference; check the pair)")
        b, s, a, f = _tooth_compliances(tooth, rho, E_MPa, G, int(opt.quadrature_nodes), opt.fillet,
                                        opt.fillet_height)
        n = i + 1
        parts.update({f"b{n}": b, f"s{n}": s, f"a{n}": a, f"f{n}": f})
    return parts


def potential_energy_single_stiffness(pair: GearPair, roll_length_1_mm, *, E_MPa: float = 206000.0,
                                      poisson: float = 0.3, fillet: bool = True, parts: bool = False, **options):
    """Single-pair mesh stiffness per unit face width k(rho) [N/(mm*um)] by the potential-energy method.

    ``roll_length_1_mm``: contact position(s) on the path as roll length on gear 1 from its base tangent point T1
    (the ``sap``/``eap_roll_length_mm`` convention of :meth:`GearPair.geometry`), within [A, E] [mm]; scalar or
    array. ``E_MPa`` Young's modulus [MPa] and ``poisson`` of both gears. ``fillet``: include Sainsot's gear-body
    term. ``options``: the other fields of :class:`PotentialEnergyOptions` (``root_section``,
    ``constant_section_start``, ``root_half_angle``, ``fillet_height``, ``bore_diameter_mm``,
    ``quadrature_nodes``); ``**ANCHOR_CONVENTIONS`` reproduces docs/default-data.md sec. 1.2's conventions.

    Returns an array shaped like ``roll_length_1_mm``; with ``parts=True`` a dict of arrays [N/(mm*um)]:
    ``k_h`` (Hertz), ``k_b1``, ``k_s1``, ``k_a1``, ``k_f1`` (gear 1: bending, shear, axial, gear body; ``inf`` without
    the fillet term), the same for gear 2, and ``single_stiffness`` (the series sum). Model, sources and validity:
    see the module docstring. Raises :class:`GearoptInputError` for positions outside the path, E <= 0, poisson
    outside (0, 0.5), symbolic pairs and unknown options.
    """
    _check_material(E_MPa, poisson)
    opt = PotentialEnergyOptions.build(fillet=fillet, **options)
    path = _path(pair)
    rho1 = np.asarray(roll_length_1_mm, dtype=float)
    shape = rho1.shape
    rho1 = rho1.reshape(-1)
    if rho1.size == 0 or not np.all(np.isfinite(rho1)):
        raise GearoptInputError(f"roll_length_1_mm={roll_length_1_mm!r} must be finite numbers")
    tol = 1e-9 * max(1.0, path["E"])
    lo, hi = float(np.min(rho1)), float(np.max(rho1))
    if lo < path["A"] - tol:
        raise GearoptInputError(f"roll_length_1_mm={lo:.6g} mm lies below the start of contact A: the path of "
                                f"contact is [{path['A']:.6g}, {path['E']:.6g}] mm")
    if hi > path["E"] + tol:
        raise GearoptInputError(f"roll_length_1_mm={hi:.6g} mm lies above the end of contact E: the path of "
                                f"contact is [{path['A']:.6g}, {path['E']:.6g}] mm")
    rho1 = np.clip(rho1, path["A"], path["E"])
    c = _compliances(pair, path, rho1, E_MPa, poisson, opt)
    total = sum(c.values())
    k = (_TO_N_PER_MM_UM / total).reshape(shape)
    if not parts:
        return k
    with np.errstate(divide="ignore"):
        out = {f"k_{key}": (_TO_N_PER_MM_UM / val).reshape(shape) for key, val in c.items()}
    out["single_stiffness"] = k
    return out


def potential_energy_stiffness_profile(pair: GearPair, *, E_MPa: float = 206000.0, poisson: float = 0.3,
                                       nodes: int = DEFAULT_PROFILE_NODES, **options) -> Callable:
    """Single-pair stiffness per unit face width c(s) [N/(mm*um)] over the normalised path position s in [0, 1]
    (A -> E), the contract of :func:`gearopt.contact.ltca.single_pair_stiffness_profile`.

    The stiffness is computed once at ``nodes`` Chebyshev points of the path and interpolated by the barycentric
    formula (the profile is smooth along the path): with the default 17 nodes the interpolant agrees with the direct
    evaluation to better than 1e-6 relative (tested; about 1e-9 for the default train). Building takes about 2 ms;
    the callable is vectorised (about 50 us for 40 positions); s outside [0, 1] raises :class:`GearoptInputError`.
    ``options`` go to :func:`potential_energy_single_stiffness` (``fillet`` and the fields of
    :class:`PotentialEnergyOptions`).
    """
    check_range("nodes", nodes, 3, 200)
    nodes = int(nodes)
    path = _path(pair)
    j = np.arange(nodes)
    s_nodes = 0.5 * (1.0 - np.cos(math.pi * j / (nodes - 1)))  # Chebyshev points of the 2nd kind on [0, 1]
    k_nodes = potential_energy_single_stiffness(pair, path["A"] + s_nodes * (path["E"] - path["A"]), E_MPa=E_MPa,
                                                poisson=poisson, **options)
    weights = np.where(j % 2 == 0, 1.0, -1.0)
    weights[0] *= 0.5
    weights[-1] *= 0.5

    def profile(s):
        s_arr = np.asarray(s, dtype=float)
        if s_arr.size and (np.nanmin(s_arr) < -1e-12 or np.nanmax(s_arr) > 1.0 + 1e-12 or np.isnan(s_arr).any()):
            raise GearoptInputError(f"path position s must lie in [0, 1] (A -> E); got min {np.nanmin(s_arr):.6g}, "
                                    f"max {np.nanmax(s_arr):.6g}")
        flat = s_arr.reshape(-1)
        diff = flat[:, None] - s_nodes[None, :]
        exact = diff == 0.0
        with np.errstate(divide="ignore", invalid="ignore"):
            q = weights / diff
            val = (q @ k_nodes) / np.sum(q, axis=1)
        hit = exact.any(axis=1)
        if hit.any():
            val[hit] = k_nodes[np.argmax(exact[hit], axis=1)]
        return val.reshape(s_arr.shape)

    return profile


def potential_energy_mesh_stiffness(pair: GearPair, positions=200, *, E_MPa: float = 206000.0, poisson: float = 0.3,
                                    **options) -> dict:
    """Mesh stiffness per unit face width over one base pitch: the tooth pairs in contact act in parallel.

    ``positions``: number of equally spaced positions of the reference pair over [A, A + p_bt) (int), or an array of
    roll lengths on gear 1 [mm] in [A, A + p_bt). At each position the pairs at rho + k p_bt inside [A, E] are
    summed. Returns ``roll_length_1_mm`` (positions), ``mesh_stiffness`` [N/(mm*um)] at them, ``mean`` (exact cycle
    mean (1/p_bt) int_A^E k(rho) drho by Gauss-Legendre quadrature of the single-pair stiffness, not the grid
    average), ``min`` and ``max`` (over the grid and both sides of the contact-number changes at B and D)
    [N/(mm*um)], ``pairs_in_contact`` (positions) and ``transverse_contact_ratio``. ``E_MPa``, ``poisson`` and
    ``options`` as in :func:`potential_energy_single_stiffness`.
    """
    path = _path(pair)
    A, E, p = path["A"], path["E"], path["p_bt"]
    if isinstance(positions, (int, np.integer)) and not isinstance(positions, bool):
        check_range("positions", positions, 2, 100000)
        rho = A + p * np.arange(int(positions)) / int(positions)
    else:
        rho = np.asarray(positions, dtype=float).reshape(-1)
        if rho.size == 0 or np.min(rho) < A - 1e-9 or np.max(rho) >= A + p + 1e-9:
            raise GearoptInputError(f"positions must be roll lengths in [A, A + p_bt) = [{A:.6g}, {A + p:.6g}) mm")
    n_max = math.ceil((E - A) / p) + 1
    # contact-number changes inside the cycle: rho + k p = E (a pair leaves) -> evaluate just before and after
    eps = 1e-9 * p
    events = [E - k * p for k in range(n_max + 1) if A < E - k * p < A + p]
    probe = np.concatenate([rho] + [np.array([e - eps, e + eps]) for e in events]) if events else rho
    all_pos = probe[:, None] + p * np.arange(n_max)[None, :]
    inside = all_pos <= E + 1e-12
    k_single = np.zeros_like(all_pos)
    k_single[inside] = potential_energy_single_stiffness(pair, np.minimum(all_pos[inside], E), E_MPa=E_MPa,
                                                         poisson=poisson, **options)
    k_mesh = k_single.sum(axis=1)
    t, w = _gauss(48)
    half = 0.5 * (E - A)
    mean = float(np.sum(w * half * potential_energy_single_stiffness(pair, A + half * (t + 1.0), E_MPa=E_MPa,
                                                                     poisson=poisson, **options)) / p)
    n = rho.size
    return {"roll_length_1_mm": rho, "mesh_stiffness": k_mesh[:n], "mean": mean, "min": float(np.min(k_mesh)),
            "max": float(np.max(k_mesh)), "pairs_in_contact": inside[:n].sum(axis=1),
            "transverse_contact_ratio": (E - A) / p}


__all__ = [
    "ANCHOR_CONVENTIONS",
    "DEFAULT_PROFILE_NODES",
    "DEFAULT_QUADRATURE_NODES",
    "SAINSOT_COEFFICIENTS",
    "PotentialEnergyOptions",
    "ToothData",
    "cantilever_compliances",
    "fillet_point",
    "involute_point",
    "potential_energy_mesh_stiffness",
    "potential_energy_single_stiffness",
    "potential_energy_stiffness_profile",
    "sainsot_coefficients",
    "tooth_data",
]
