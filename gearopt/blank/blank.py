"""Gear blank mass and polar moment of inertia in closed form (solid, webbed, pocketed), and the rim backup ratio.

The blank is a stack of coaxial annuli (thesis sec. 3.10: webs and pockets reduce the inertia -- "dead torque" --
of the large cam and fuel-pump gears):

* teeth: the annulus from the root diameter d_f to the tip diameter d_a over the face width, times a
  ``tooth_fill_factor`` (tooth area / annulus area; 0.5 by default as in the default data's [C] inertias: a tooth
  about as thick as its space at mid-height);
* rim: d_f - 2 t_R to d_f over the face width (t_R = rim thickness below the root);
* web: hub outer diameter to the rim over the web thickness, less lightening pockets -- either an area fraction
  spread evenly over the web annulus (removes that fraction of the web's mass *and* inertia; exact when the
  pockets' area is distributed like the annulus, e.g. sector-shaped pockets), or ``hole_count`` round holes of
  ``hole_diameter_mm`` on ``hole_pitch_diameter_mm`` (exact: each hole a disc, parallel-axis theorem);
* hub: bore to hub outer diameter over the hub length.

A solid blank is the annulus from the bore to d_f (plus the teeth). Annulus: ``m = rho pi/4 (D^2 - d^2) L``,
``J = m (D^2 + d^2)/8``; round hole at pitch radius R: ``J = m_h (d_h^2/8 + R^2)``.

Rim backup ratio ``m_B = t_R / h_t`` (h_t whole depth): Bibel et al. (1994, cited in thesis sec. 2; the thesis
quotes 1.3 as the ratio above which the root stress equals the solid gear's) -- AGMA uses 1.2 in its rim thickness
factor ``K_B = 1.6 ln(2.242/m_B)`` for m_B < 1.2, else 1 ([M] AGMA 2101 / Shigley's MED Eq. 14-40, not re-read
here; the constants make K_B continuous at 1.2, which the tests check).

Units: mm, kg, kg m^2, kg/m^3. Dual-typed: every dimension may be a CasADi symbol (inertia as a design objective).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .. import numerics as nm
from ..errors import GearoptInputError
from ..validation import check_range

STEEL_DENSITY_KG_M3 = 7850.0
_MM3_TO_M3 = 1e-9
_MM2_TO_M2 = 1e-6


def annulus_mass_kg(outer_diameter_mm, inner_diameter_mm, length_mm, density_kg_m3=STEEL_DENSITY_KG_M3):
    """Mass [kg] of a hollow cylinder: ``rho pi/4 (D^2 - d^2) L``."""
    return density_kg_m3 * math.pi / 4.0 * (outer_diameter_mm ** 2 - inner_diameter_mm ** 2) * length_mm * _MM3_TO_M3


def annulus_inertia_kgm2(outer_diameter_mm, inner_diameter_mm, length_mm, density_kg_m3=STEEL_DENSITY_KG_M3):
    """Polar moment of inertia [kg m^2] of a hollow cylinder about its axis: ``rho pi/32 (D^4 - d^4) L``."""
    return density_kg_m3 * math.pi / 32.0 * (outer_diameter_mm ** 4 - inner_diameter_mm ** 4) * length_mm \
        * _MM3_TO_M3 * _MM2_TO_M2


def rim_backup_ratio(rim_thickness_mm, whole_depth_mm):
    """Backup ratio m_B = t_R / h_t [-] (rim thickness below the root over the tooth whole depth)."""
    return rim_thickness_mm / whole_depth_mm


def rim_thickness_factor(backup_ratio):
    """AGMA rim thickness factor K_B [-]: ``1.6 ln(2.242/m_B)`` below m_B = 1.2, 1 above ([M], module docstring).
    Valid for m_B >= 0.5 (AGMA's range); numeric input below raises."""
    check_range("backup_ratio", backup_ratio, 0.5, None)
    return nm.where(backup_ratio < 1.2, 1.6 * nm.log(2.242 / nm.fmin(backup_ratio, 1.2)), 1.0)


@dataclass(frozen=True)
class GearBlank:
    """A gear blank (see the module docstring). Solid when ``web_thickness_mm`` is None.

    ``tip_diameter_mm`` d_a, ``root_diameter_mm`` d_f, ``face_width_mm`` b, ``bore_diameter_mm``; webbed:
    ``hub_outer_diameter_mm``, ``hub_length_mm`` (>= web thickness), ``web_thickness_mm``, ``rim_thickness_mm``
    (below the root), pockets by ``pocket_area_fraction`` (0..0.8) *or* round holes (``hole_count``,
    ``hole_diameter_mm``, ``hole_pitch_diameter_mm``); ``density_kg_m3``; ``tooth_fill_factor`` (0..1).
    """

    tip_diameter_mm: object
    root_diameter_mm: object
    face_width_mm: object
    bore_diameter_mm: object
    hub_outer_diameter_mm: object = None
    hub_length_mm: object = None
    web_thickness_mm: object = None
    rim_thickness_mm: object = None
    pocket_area_fraction: object = 0.0
    hole_count: int = 0
    hole_diameter_mm: object = 0.0
    hole_pitch_diameter_mm: object = 0.0
    density_kg_m3: object = STEEL_DENSITY_KG_M3
    tooth_fill_factor: object = 0.5

    def __post_init__(self):
        check_range("tip_diameter_mm", self.tip_diameter_mm, 0.0, None, low_inclusive=False, unit="mm")
        check_range("root_diameter_mm", self.root_diameter_mm, 0.0, None, low_inclusive=False, unit="mm")
        check_range("face_width_mm", self.face_width_mm, 0.0, None, low_inclusive=False, unit="mm")
        check_range("bore_diameter_mm", self.bore_diameter_mm, 0.0, None, unit="mm")
        check_range("tooth_fill_factor", self.tooth_fill_factor, 0.0, 1.0)
        check_range("pocket_area_fraction", self.pocket_area_fraction, 0.0, 0.8)
        self._order("root_diameter_mm", self.root_diameter_mm, "tip_diameter_mm", self.tip_diameter_mm)
        if self.web_thickness_mm is None:
            self._order("bore_diameter_mm", self.bore_diameter_mm, "root_diameter_mm", self.root_diameter_mm)
            if self.hole_count or _num_positive(self.pocket_area_fraction):
                raise GearoptInputError("pockets or holes need a web: give web_thickness_mm (and the hub and rim)")
            return
        for name in ("hub_outer_diameter_mm", "hub_length_mm", "rim_thickness_mm"):
            if getattr(self, name) is None:
                raise GearoptInputError(f"a webbed blank needs {name}")
        check_range("web_thickness_mm", self.web_thickness_mm, 0.0, None, low_inclusive=False, unit="mm")
        check_range("hub_outer_diameter_mm", self.hub_outer_diameter_mm, 0.0, None, low_inclusive=False, unit="mm")
        check_range("hub_length_mm", self.hub_length_mm, 0.0, None, low_inclusive=False, unit="mm")
        check_range("rim_thickness_mm", self.rim_thickness_mm, 0.0, None, low_inclusive=False, unit="mm")
        self._order("bore_diameter_mm", self.bore_diameter_mm, "hub_outer_diameter_mm", self.hub_outer_diameter_mm)
        self._order("hub_outer_diameter_mm", self.hub_outer_diameter_mm, "rim inner diameter (d_f - 2 t_R)",
                    self.rim_inner_diameter_mm)
        self._order("web_thickness_mm", self.web_thickness_mm, "hub_length_mm", self.hub_length_mm, strict=False)
        self._order("web_thickness_mm", self.web_thickness_mm, "face_width_mm", self.face_width_mm, strict=False)
        if self.hole_count:
            if _num_positive(self.pocket_area_fraction):
                raise GearoptInputError("give pockets either as pocket_area_fraction or as holes, not both")
            if not isinstance(self.hole_count, int) or self.hole_count < 1:
                raise GearoptInputError(f"hole_count={self.hole_count!r} must be a positive integer")
            check_range("hole_diameter_mm", self.hole_diameter_mm, 0.0, None, low_inclusive=False, unit="mm")
            if nm.is_numeric(self.hole_diameter_mm, self.hole_pitch_diameter_mm, self.hub_outer_diameter_mm,
                             self.rim_inner_diameter_mm):
                dh, dp = nm.to_float(self.hole_diameter_mm), nm.to_float(self.hole_pitch_diameter_mm)
                lo, hi = nm.to_float(self.hub_outer_diameter_mm), nm.to_float(self.rim_inner_diameter_mm)
                if dp - dh < lo or dp + dh > hi:
                    raise GearoptInputError(f"holes of {dh:g} mm on a {dp:g} mm pitch circle leave the web "
                                            f"({lo:g}..{hi:g} mm)")
                spacing = dp * math.sin(math.pi / self.hole_count)
                if self.hole_count > 1 and spacing <= dh:
                    raise GearoptInputError(f"hole_count={self.hole_count} holes of {dh:g} mm overlap on the {dp:g} "
                                            f"mm pitch circle (spacing {spacing:.3g} mm)")

    @staticmethod
    def _order(name_lo, lo, name_hi, hi, strict=True):
        if nm.is_numeric(lo, hi):
            a, b = nm.to_float(lo), nm.to_float(hi)
            if a > b or (strict and a == b):
                rel = "<" if strict else "<="
                raise GearoptInputError(f"{name_lo}={a:g} mm must be {rel} {name_hi}={b:g} mm")

    # ------------------------------------------------------------------------------------------------------------

    @property
    def kind(self) -> str:
        if self.web_thickness_mm is None:
            return "solid"
        return "pocketed" if (self.hole_count or _num_positive(self.pocket_area_fraction)) else "webbed"

    @property
    def rim_inner_diameter_mm(self):
        """Inner diameter of the rim (webbed) or the bore (solid) [mm]."""
        if self.web_thickness_mm is None:
            return self.bore_diameter_mm
        return self.root_diameter_mm - 2.0 * self.rim_thickness_mm

    @property
    def whole_depth_mm(self):
        return 0.5 * (self.tip_diameter_mm - self.root_diameter_mm)

    @property
    def backup_ratio(self):
        """Rim backup ratio m_B (a solid blank: the whole body below the root over the whole depth)."""
        return rim_backup_ratio(0.5 * (self.root_diameter_mm - self.rim_inner_diameter_mm), self.whole_depth_mm)

    def components(self) -> dict[str, tuple]:
        """{part: (mass_kg, inertia_kgm2)}; removed material (pockets/holes) has negative entries."""
        rho, b = self.density_kg_m3, self.face_width_mm
        d_a, d_f = self.tip_diameter_mm, self.root_diameter_mm
        fill = self.tooth_fill_factor
        parts = {"teeth": (fill * annulus_mass_kg(d_a, d_f, b, rho), fill * annulus_inertia_kgm2(d_a, d_f, b, rho))}
        if self.web_thickness_mm is None:
            parts["body"] = (annulus_mass_kg(d_f, self.bore_diameter_mm, b, rho),
                             annulus_inertia_kgm2(d_f, self.bore_diameter_mm, b, rho))
            return parts
        d_r, d_h, t = self.rim_inner_diameter_mm, self.hub_outer_diameter_mm, self.web_thickness_mm
        parts["rim"] = (annulus_mass_kg(d_f, d_r, b, rho), annulus_inertia_kgm2(d_f, d_r, b, rho))
        web_m, web_j = annulus_mass_kg(d_r, d_h, t, rho), annulus_inertia_kgm2(d_r, d_h, t, rho)
        parts["web"] = (web_m, web_j)
        parts["hub"] = (annulus_mass_kg(d_h, self.bore_diameter_mm, self.hub_length_mm, rho),
                        annulus_inertia_kgm2(d_h, self.bore_diameter_mm, self.hub_length_mm, rho))
        if self.hole_count:
            n, dh, dp = self.hole_count, self.hole_diameter_mm, self.hole_pitch_diameter_mm
            m_h = annulus_mass_kg(dh, 0.0, t, rho)
            parts["pockets"] = (-n * m_h, -n * m_h * (dh ** 2 / 8.0 + dp ** 2 / 4.0) * _MM2_TO_M2)
        elif _num_positive(self.pocket_area_fraction) or nm.is_symbolic(self.pocket_area_fraction):
            f = self.pocket_area_fraction
            parts["pockets"] = (-f * web_m, -f * web_j)
        return parts

    def mass_kg(self):
        return nm.sum1(m for m, _ in self.components().values())

    def inertia_kgm2(self):
        return nm.sum1(j for _, j in self.components().values())

    def solid_equivalent(self) -> GearBlank:
        """The solid blank with the same teeth, face width and bore (for the inertia reduction)."""
        return GearBlank(self.tip_diameter_mm, self.root_diameter_mm, self.face_width_mm, self.bore_diameter_mm,
                         density_kg_m3=self.density_kg_m3, tooth_fill_factor=self.tooth_fill_factor)


def _num_positive(x) -> bool:
    return nm.is_numeric(x) and nm.to_float(x) > 0.0


__all__ = ["GearBlank", "annulus_mass_kg", "annulus_inertia_kgm2", "rim_backup_ratio", "rim_thickness_factor",
           "STEEL_DENSITY_KG_M3"]
