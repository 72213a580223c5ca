"""Hertzian line contact of two elastic bodies and the tooth compressions built on it, dual-typed.

Shared by the strength ratings (contact stress, flash temperature) and the tooth-contact models (tip relief, LTCA)
below both. Lengths in mm, loads per unit face width in N/mm, moduli in MPa, approaches in um.
"""

from __future__ import annotations

import math
from typing import Any

from .. import numerics as nm
from ..errors import GearoptInputError
from ..validation import check_range, per_gear
from ..units import UM_PER_MM

#: Young's modulus [MPa] and Poisson's ratio of gear steel used by default (ISO 6336-1 reference steel).
E_STEEL_MPA = 206000.0
POISSON_STEEL = 0.3

# smallest squared half-width [mm^2] used inside logarithms: keeps ln(1/b) finite when a symbolic load reaches 0
HALF_WIDTH_SQ_FLOOR_MM2 = 1e-24

Number = Any  # float, ndarray or CasADi expression


def check_elastic_material(E_MPa, poisson) -> tuple[tuple, tuple]:
    """Young's moduli [MPa] and Poisson's ratios as per-gear 2-tuples, each checked (E > 0, 0 <= nu < 0.5)."""
    E = per_gear(E_MPa, "E_MPa")
    nu = per_gear(poisson, "poisson")
    for i in range(2):
        check_range(f"E_MPa[{i}]", E[i], 0.0, None, low_inclusive=False, unit="MPa")
        check_range(f"poisson[{i}]", nu[i], 0.0, 0.5, high_inclusive=False)
    return E, nu


def plane_strain_compliance_per_MPa(E_MPa, poisson):
    """(1 - nu^2)/E [1/MPa]: the plane-strain compliance of a body in line contact (dual-typed)."""
    return (1.0 - poisson * poisson) / E_MPa


# ----------------------------------------------------------------------------------------------------------------
# Hertzian line contact
# ----------------------------------------------------------------------------------------------------------------

def hertz_half_width_mm(load_per_width_N_per_mm, radius1_mm, radius2_mm, E_MPa=E_STEEL_MPA, poisson=POISSON_STEEL):
    """Half-width b_H [mm] of the contact band of two parallel elastic cylinders (Hertz line contact).

    ``b_H = sqrt( (2 w / pi) [(1-nu1^2)/E1 + (1-nu2^2)/E2] / (1/d1 + 1/d2) )`` with d_i = 2 R_i, i.e.
    ``b_H = sqrt(8 w R (1-nu^2)/(pi E))`` for one material and 1/R = 1/R1 + 1/R2.

    Args: ``load_per_width_N_per_mm`` normal load per unit length w [N/mm] (>= 0); ``radius1_mm``, ``radius2_mm``
    radii of curvature at the contact [mm] (for involute flanks: the roll lengths rho_1, rho_2 of the contact point);
    ``E_MPa`` Young's modulus [MPa] and ``poisson`` nu, each a scalar or a 2-tuple (body 1, body 2).
    Returns b_H [mm]; the peak pressure is ``p_H = 2 w/(pi b_H)``.

    Source: thesis Eq. 3.37 = Shigley's Mechanical Engineering Design, contact stresses of cylinders (b and
    p_max = 2F/(pi b l)); Johnson, Contact Mechanics (1985) ch. 4 (a^2 = 4 P R/(pi E*)). Valid for b_H << R_i, linear
    elastic, frictionless, plane strain (face width >> b_H).
    """
    E, nu = check_elastic_material(E_MPa, poisson)
    check_range("load_per_width_N_per_mm", load_per_width_N_per_mm, 0.0, None, unit="N/mm")
    check_range("radius1_mm", radius1_mm, 0.0, None, low_inclusive=False, unit="mm")
    check_range("radius2_mm", radius2_mm, 0.0, None, low_inclusive=False, unit="mm")
    compliance = plane_strain_compliance_per_MPa(E[0], nu[0]) + plane_strain_compliance_per_MPa(E[1], nu[1])
    curvature = 1.0 / (2.0 * radius1_mm) + 1.0 / (2.0 * radius2_mm)
    return nm.sqrt_safe(2.0 * load_per_width_N_per_mm / math.pi * compliance / curvature, HALF_WIDTH_SQ_FLOOR_MM2)


def hertz_compression_weber_um(load_per_width_N_per_mm, half_width_mm, depth_mm, E_MPa=E_STEEL_MPA,
                               poisson=POISSON_STEEL):
    """Compression [um] of ONE elastic body between the centre of a Hertz line contact and a point at depth ``d``
    below it (Weber 1949; Weber & Banaschek 1953)::

        delta = 2 w (1-nu^2)/(pi E) [ ln(2 d / b_H) - nu / (2 (1-nu)) ]

    This is the integral of the plane-strain normal strain along the load axis under the Hertz pressure (the
    classical subsurface stresses of a line contact, e.g. Shigley's sigma_x, sigma_z on the z axis), exact up to
    terms of order (b_H/d)^2 (checked by quadrature in the tests). For a gear tooth ``d`` is the distance from the
    contact point to the tooth centreline along the load line, the reference of the tooth-deflection fit.

    Args: ``load_per_width_N_per_mm`` w [N/mm]; ``half_width_mm`` b_H [mm] (:func:`hertz_half_width_mm`);
    ``depth_mm`` d [mm]; ``E_MPa`` [MPa]; ``poisson`` nu. Valid for d >~ 3 b_H (the log form needs d >> b_H).
    """
    check_range("depth_mm", depth_mm, 0.0, None, low_inclusive=False, unit="mm")
    check_range("half_width_mm", half_width_mm, 0.0, None, low_inclusive=False, unit="mm")
    bracket = nm.log(2.0 * depth_mm / half_width_mm) - poisson / (2.0 * (1.0 - poisson))
    return UM_PER_MM * 2.0 * load_per_width_N_per_mm * plane_strain_compliance_per_MPa(E_MPa, poisson) / math.pi \
        * bracket


def hertz_approach_cylinders_um(load_per_width_N_per_mm, radius1_mm, radius2_mm, E_MPa=E_STEEL_MPA,
                                poisson=POISSON_STEEL):
    """Approach [um] of the axes of two parallel elastic cylinders in line contact (plane strain)::

        delta = sum_i  w (1-nu_i^2)/(pi E_i) [ 2 ln(4 R_i / b_H) - 1 ]
              = 2 w (1-nu^2)/(pi E) [ ln(4 R1/b_H) + ln(4 R2/b_H) - 1 ]     (one material)

    Source: Johnson, Contact Mechanics (1985), compression of cylinders. Each cylinder's share is half the
    diametral compression of a disc squeezed between two such Hertz contacts: the strain integrated along the
    diameter of the two half-plane Hertz fields plus the uniform tension P/(pi R) that frees the disc boundary
    (the Hertz/Timoshenko & Goodier disc solution), which the tests do by quadrature. Valid for b_H << R_i.

    For gear teeth with R_i = roll lengths this measures the deformation down to the centres of the osculating
    cylinders, which lie on the line of action far outside the tooth; it therefore counts material that is not
    there and overlaps the tooth deflection. :func:`min_tip_relief_um` uses it only with ``hertz_model="cylinders"``.
    """
    E, nu = check_elastic_material(E_MPa, poisson)
    b = hertz_half_width_mm(load_per_width_N_per_mm, radius1_mm, radius2_mm, E, nu)
    total = 0.0
    for radius, Ei, nui in ((radius1_mm, E[0], nu[0]), (radius2_mm, E[1], nu[1])):
        total = total + plane_strain_compliance_per_MPa(Ei, nui) * (2.0 * nm.log(4.0 * radius / b) - 1.0)
    return UM_PER_MM * load_per_width_N_per_mm / math.pi * total


def hertz_approach_thesis_um(load_per_width_N_per_mm, half_width_mm, module_mm, E_MPa=E_STEEL_MPA,
                             poisson=POISSON_STEEL):
    """Hertzian deformation as printed in the thesis, Eq. 3.28 [um] -- for comparison only::

        delta_H = 2 w (1-nu^2)/(pi E) [1.27 + 0.78 ln(m / b_H)]

    Not used by default: its log coefficient 0.78 is not that of an elastic two-body approach (2, one per body; see
    the module docstring), so its load dependence is too weak (0.39 of the elastic value). For m/b_H of 20..100 it
    is within 12 % of Weber's compression of ONE tooth to a depth 0.785 m (= pi m/4, the half tooth thickness at the
    pitch circle), i.e. it looks like a one-flank value, while Eq. 3.38 halves it as if it were both flanks'. Args as :func:`hertz_compression_weber_um`, ``module_mm`` m [mm].
    """
    check_range("half_width_mm", half_width_mm, 0.0, None, low_inclusive=False, unit="mm")
    bracket = 1.27 + 0.78 * nm.log(module_mm / half_width_mm)
    return UM_PER_MM * 2.0 * load_per_width_N_per_mm * plane_strain_compliance_per_MPa(E_MPa, poisson) / math.pi \
        * bracket
