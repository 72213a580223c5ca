"""Manufacturing allowances of a gear pair and the backlash they produce (ISO 21771 section 5.5, ISO/TR 10064-2).

Backlash is computed exactly from involute geometry: at an actual centre distance a' the transverse working pressure
angle follows from cos(alpha_wt') = a_d cos(alpha_t)/a', each gear's tooth thickness (with its allowance) is carried
to the working pitch circle, and the circumferential backlash is the working circular pitch minus both thicknesses.
It is zero at the nominal centre distance with zero allowances (tested). Lengths in mm, allowances as named.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .. import numerics as nm
from ..errors import GearoptInputError


@dataclass(frozen=True)
class PairTolerances:
    """Allowances of a gear pair (all may be floats; sign conventions of ISO 21771 / DIN 3967).

    centre_distance_allowance_mm: (lower A_ai, upper A_as), e.g. (-0.025, 0.025).
    tooth_thickness_upper_allowance_um: normal tooth thickness upper allowance E_sns per gear (<= 0 gives backlash).
    tooth_thickness_lower_allowance_um: lower allowance E_sni per gear (<= E_sns).
    tip_diameter_allowance_mm: (lower, upper) tip diameter allowance per gear, e.g. ((-0.2, 0.0), (-0.2, 0.0)).
    """

    centre_distance_allowance_mm: tuple[float, float] = (0.0, 0.0)
    tooth_thickness_upper_allowance_um: tuple[float, float] = (0.0, 0.0)
    tooth_thickness_lower_allowance_um: tuple[float, float] = (0.0, 0.0)
    tip_diameter_allowance_mm: tuple[tuple[float, float], tuple[float, float]] = ((0.0, 0.0), (0.0, 0.0))

    def __post_init__(self):
        lo, hi = self.centre_distance_allowance_mm
        if nm.is_numeric(lo, hi) and nm.to_float(lo) > nm.to_float(hi):
            raise GearoptInputError(f"centre_distance_allowance_mm=({lo}, {hi}): lower exceeds upper")
        for i in range(2):
            es, ei = self.tooth_thickness_upper_allowance_um[i], self.tooth_thickness_lower_allowance_um[i]
            if nm.is_numeric(es, ei) and nm.to_float(ei) > nm.to_float(es):
                raise GearoptInputError(
                    f"tooth_thickness_lower_allowance_um[{i}]={ei} exceeds the upper allowance {es} of gear {i + 1}")
            dlo, dhi = self.tip_diameter_allowance_mm[i]
            if nm.is_numeric(dlo, dhi) and nm.to_float(dlo) > nm.to_float(dhi):
                raise GearoptInputError(f"tip_diameter_allowance_mm[{i}]=({dlo}, {dhi}): lower exceeds upper")


def transverse_backlash_mm(teeth, reference_diameters_mm, base_diameters_mm, transverse_thickness_mm,
                           transverse_pressure_angle_rad, reference_centre_distance_mm, centre_distance_mm):
    """Circumferential (transverse) backlash on the working pitch circle j_wt and the transverse base-tangent
    backlash j_bt = j_wt cos(alpha_wt') at the actual centre distance ``centre_distance_mm`` [mm].

    ``transverse_thickness_mm`` are both gears' transverse arc thicknesses on their reference circles, already
    including the thickness allowances. Negative backlash means the teeth would jam (interference of flanks).
    """
    z1, z2 = teeth
    alpha_w = nm.acos_safe(reference_centre_distance_mm * nm.cos(transverse_pressure_angle_rad) / centre_distance_mm)
    d_w1 = 2.0 * centre_distance_mm * z1 / (z1 + z2)
    thickness_sum = 0.0
    for i, z in enumerate(teeth):
        d_w = 2.0 * centre_distance_mm * z / (z1 + z2)
        thickness_sum = thickness_sum + d_w * (transverse_thickness_mm[i] / reference_diameters_mm[i]
                                               + nm.involute(transverse_pressure_angle_rad) - nm.involute(alpha_w))
    j_wt = math.pi * d_w1 / z1 - thickness_sum
    return j_wt, j_wt * nm.cos(alpha_w)
