"""The lubricant of a gear pair and the ISO 6336-2:2006 lubrication-film factors Z_L, Z_v, Z_R and the work
hardening factor Z_W, dual-typed.

* :class:`Lubricant` -- kinematic viscosities at 40 and 100 C, density at 15 C, oil (sump/spray) temperature, FZG
  scuffing load stage (ISO 14635-1), base oil and lubrication type; viscosity at any temperature by the
  Ubbelohde-Walther relation of ASTM D341 (log log(nu + 0.7) linear in log T), density by the linear temperature
  coefficient of ISO/TS 6336-22 / DIN 51757 (rho(theta) = rho_15 (1 - 0.0007 (theta - 15)) with rho in kg/dm^3).
* :func:`lubricant_factor` Z_L, :func:`velocity_factor` Z_v, :func:`roughness_factor` Z_R -- ISO 6336-2:2006
  clause 11 method B, with C_ZL, C_Zv = C_ZL + 0.02 and C_ZR from sigma_Hlim (the lower sigma_Hlim of the pair);
* :func:`work_hardening_factor` Z_W -- ISO 6336-2:2006 clause 12 for a surface-hardened pinion running with a
  through-hardened wheel (Brinell hardness 130..470 HB of the softer gear).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .. import numerics as nm
from ..errors import GearoptInputError
from ..validation import check_range

BASE_OILS = ("mineral", "polyalphaolefin", "polyglycol", "ester", "traction")
LUBRICATION_TYPES = ("oil_bath", "spray")
FZG_TESTS = ("A/8.3/90", "A/16.6/90", "A10/16.6R/90")
_KELVIN = 273.15

#: Library default oil (sump/spray, bulk) temperature [C]: [E] a typical heavy-duty diesel sump/gallery oil
#: temperature at rated load (90-110 C). A library default, not read from any data file: a caller with a system
#: passes its own (``system.lubrication.oil_temperature_C``). Equal to the packaged default_train.toml's
#: ``[lubrication] oil_temperature_C`` (tests/rating/test_library_defaults.py keeps them equal).
DEFAULT_OIL_TEMPERATURE_C = 100.0


@dataclass(frozen=True)
class Lubricant:
    """A gear oil. ``viscosity_40C_mm2_s`` > ``viscosity_100C_mm2_s`` > 0 [mm^2/s], ``density_15C_kg_m3`` [kg/m^3],
    ``oil_temperature_C`` sump or spray temperature [C], ``fzg_load_stage`` failure load stage of the FZG scuffing
    test (1..14, ISO 14635-1), ``fzg_test`` its variant, ``base_oil`` (mineral, polyalphaolefin, polyglycol, ester,
    traction) and ``lubrication`` ("oil_bath" or "spray")."""

    viscosity_40C_mm2_s: float
    viscosity_100C_mm2_s: float
    density_15C_kg_m3: float
    oil_temperature_C: float
    fzg_load_stage: float
    fzg_test: str = "A/8.3/90"
    base_oil: str = "mineral"
    lubrication: str = "oil_bath"

    def __post_init__(self):
        check_range("viscosity_40C_mm2_s", self.viscosity_40C_mm2_s, 0.0, None, low_inclusive=False, unit="mm^2/s")
        check_range("viscosity_100C_mm2_s", self.viscosity_100C_mm2_s, 0.0, nm.to_float(self.viscosity_40C_mm2_s),
                    low_inclusive=False, high_inclusive=False, unit="mm^2/s")
        check_range("density_15C_kg_m3", self.density_15C_kg_m3, 500.0, 1500.0, unit="kg/m^3")
        check_range("oil_temperature_C", self.oil_temperature_C, -40.0, 200.0, unit="C")
        check_range("fzg_load_stage", self.fzg_load_stage, 1.0, 14.0)
        for name, value, allowed in (("fzg_test", self.fzg_test, FZG_TESTS), ("base_oil", self.base_oil, BASE_OILS),
                                     ("lubrication", self.lubrication, LUBRICATION_TYPES)):
            if value not in allowed:
                raise GearoptInputError(f"{name}={value!r} must be one of {allowed}")

    def _walther(self):
        t1, t2 = math.log10(40.0 + _KELVIN), math.log10(100.0 + _KELVIN)
        w1 = math.log10(math.log10(self.viscosity_40C_mm2_s + 0.7))
        w2 = math.log10(math.log10(self.viscosity_100C_mm2_s + 0.7))
        b = (w1 - w2) / (t2 - t1)
        return w1 + b * t1, b

    def kinematic_viscosity_mm2_s(self, temperature_C):
        """nu(theta) [mm^2/s] by ASTM D341: log10 log10(nu + 0.7) = A - B log10(T/K) through the 40 and 100 C
        values. Dual-typed."""
        a, b = self._walther()
        return 10.0 ** (10.0 ** (a - b * nm.log(temperature_C + _KELVIN) / math.log(10.0))) - 0.7

    def density_kg_m3(self, temperature_C):
        """rho(theta) = rho_15 - 0.7 (theta - 15) kg/m^3 per K (ISO/TS 6336-22 form). Dual-typed."""
        return self.density_15C_kg_m3 - 0.7 * (temperature_C - 15.0)

    def dynamic_viscosity_mPa_s(self, temperature_C):
        """eta(theta) = nu(theta) rho(theta) [mPa s]. Dual-typed."""
        return self.kinematic_viscosity_mm2_s(temperature_C) * self.density_kg_m3(temperature_C) * 1e-3


def _c_zl(sigma_Hlim_MPa):
    s = nm.clip(sigma_Hlim_MPa, 850.0, 1200.0)
    return 0.08 * (s - 850.0) / 350.0 + 0.83


def lubricant_factor(viscosity_40C_mm2_s, sigma_Hlim_MPa):
    """ISO 6336-2:2006 clause 11 Z_L = C_ZL + 4 (1 - C_ZL) / (1.2 + 134/nu_40)^2, C_ZL = 0.83 for sigma_Hlim < 850
    MPa, 0.91 above 1200 MPa, linear between. Dual-typed."""
    check_range("viscosity_40C_mm2_s", viscosity_40C_mm2_s, 0.0, None, low_inclusive=False, unit="mm^2/s")
    c = _c_zl(sigma_Hlim_MPa)
    return c + 4.0 * (1.0 - c) / (1.2 + 134.0 / viscosity_40C_mm2_s) ** 2


def velocity_factor(pitch_line_velocity_m_s, sigma_Hlim_MPa):
    """ISO 6336-2:2006 clause 11 Z_v = C_Zv + 2 (1 - C_Zv) / sqrt(0.8 + 32/v), C_Zv = C_ZL + 0.02, v the pitch line
    velocity [m/s] > 0. Dual-typed."""
    check_range("pitch_line_velocity_m_s", pitch_line_velocity_m_s, 0.0, None, low_inclusive=False, unit="m/s")
    c = _c_zl(sigma_Hlim_MPa) + 0.02
    return c + 2.0 * (1.0 - c) / nm.sqrt(0.8 + 32.0 / pitch_line_velocity_m_s)


def relative_radius_of_curvature_mm(pair):
    """rho_red = rho1 rho2 / (rho1 + rho2) at the pitch point in the transverse section, rho_i = d_bi tan(alpha_wt)/2
    [mm] (ISO 6336-2 clause 11). Dual-typed."""
    g = pair.geometry()
    t = nm.tan(g["working_pressure_angle_deg"] * math.pi / 180.0)
    r1, r2 = 0.5 * g["base_diameter_mm"][0] * t, 0.5 * g["base_diameter_mm"][1] * t
    return r1 * r2 / (r1 + r2)


def roughness_factor(flank_roughness_Rz_um, relative_radius_mm, sigma_Hlim_MPa):
    """ISO 6336-2:2006 clause 11 Z_R = (3/R_z10)^C_ZR with R_z10 = R_z (10/rho_red)^(1/3), R_z the mean of the two
    flanks' R_z [um] (a 2-tuple or one value), C_ZR = 0.15 below sigma_Hlim 850 MPa, 0.32 - 0.0002 sigma_Hlim up to
    1200 MPa, 0.08 above. Dual-typed."""
    rz = flank_roughness_Rz_um
    if isinstance(rz, (tuple, list)):
        for i, r in enumerate(rz):
            check_range(f"flank_roughness_Rz_um[{i}]", r, 0.0, None, low_inclusive=False, unit="um")
        rz = 0.5 * (rz[0] + rz[1])
    else:
        check_range("flank_roughness_Rz_um", rz, 0.0, None, low_inclusive=False, unit="um")
    rz10 = rz * (10.0 / relative_radius_mm) ** (1.0 / 3.0)
    s = nm.clip(sigma_Hlim_MPa, 850.0, 1200.0)
    c = 0.32 - 0.0002 * s
    return (3.0 / rz10) ** c


def equivalent_roughness_Rz_um(hard_flank_Rz_um, soft_flank_Rz_um, relative_radius_mm, viscosity_40C_mm2_s,
                               pitch_line_velocity_m_s):
    """ISO 6336-2:2006 clause 12 equivalent roughness of Z_W, R_zH = R_zH1 (10/rho_red)^0.33 (R_zH1/R_zH2)^0.66 /
    (nu_40 v/1500)^0.33 [um], index 1 the hard gear. Dual-typed."""
    return (hard_flank_Rz_um * (10.0 / relative_radius_mm) ** 0.33 * (hard_flank_Rz_um / soft_flank_Rz_um) ** 0.66
            / (viscosity_40C_mm2_s * pitch_line_velocity_m_s / 1500.0) ** 0.33)


def work_hardening_factor(brinell_hardness_HB, equivalent_roughness_Rz_um=3.0):
    """ISO 6336-2:2006 clause 12 Z_W of the through-hardened gear meshing with a surface-hardened one:
    Z_W = (1.2 - (HB - 130)/1700) (3/R_zH)^0.15, HB held to [130, 470], R_zH (:func:`equivalent_roughness_Rz_um`)
    to [3, 16] um. 1 for two gears of like hardness (apply this only to the softer gear). Dual-typed."""
    check_range("brinell_hardness_HB", brinell_hardness_HB, 0.0, None, low_inclusive=False, unit="HB")
    hb = nm.clip(brinell_hardness_HB, 130.0, 470.0)
    rz = nm.clip(equivalent_roughness_Rz_um, 3.0, 16.0)
    return (1.2 - (hb - 130.0) / 1700.0) * (3.0 / rz) ** 0.15


__all__ = ["BASE_OILS", "LUBRICATION_TYPES", "FZG_TESTS", "Lubricant", "lubricant_factor", "velocity_factor",
           "relative_radius_of_curvature_mm", "roughness_factor", "equivalent_roughness_Rz_um",
           "work_hardening_factor"]


def default_lubricant(oil_temperature_C: float = DEFAULT_OIL_TEMPERATURE_C) -> Lubricant:
    """The library's default engine oil: SAE 15W-40 class mineral engine oil ([E] typical data sheet values
    nu_40 = 108 mm^2/s, nu_100 = 14.5 mm^2/s, rho_15 = 880 kg/m^3, FZG A/8.3/90 failure load stage 12) at
    ``oil_temperature_C`` [C] (default :data:`DEFAULT_OIL_TEMPERATURE_C`, 100 C, an [E] library default).

    No data file is read: a caller with a system passes its oil temperature,
    ``default_lubricant(system.lubrication.oil_temperature_C)``."""
    return Lubricant(108.0, 14.5, 880.0, oil_temperature_C, 12)


__all__ += ["default_lubricant", "DEFAULT_OIL_TEMPERATURE_C"]
