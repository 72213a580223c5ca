"""ISO 6336-2/-3:2006 life factors Z_NT (pitting) and Y_NT (tooth root) from the number of load cycles, and the
finite-life interpolation of the other strength factors, dual-typed.

The standard's curves (ISO 6336-2:2006 Table 2, ISO 6336-3:2006 Table 3) are straight lines on log-log axes
between the static value (at and below N_static), 1.0 at the reference number N_ref and the long-life value at
10^10 cycles (0.85 "normal" ... 1.0 "optimum" material, process and lubrication; held beyond 10^10):

=================================================  ========  =======  =======  =====
Z_NT                                                N_static  static   N_ref    ref
=================================================  ========  =======  =======  =====
St, V, GGG (perl.), GTS, Eh, IF, pitting not allowed  1e5     1.6      5e7      1.0
St, V, GGG, GTS with limited pitting allowed           6e5     1.6      1e9 (1.3 at 1e7)  1.0
GG, GGG (ferr.), NT, NV (nitrided)                    1e5     1.3      2e6      1.0
NV (nitrocarburised)                                  1e5     1.1      2e6      1.0
=================================================  ========  =======  =======  =====

Y_NT: St, V, GGG (perl.), GTS: 2.5 at <= 1e4; Eh, IF: 2.5 at <= 1e3; GG, GGG (ferr.), NT, NV: 1.6 at <= 1e3;
all 1.0 at 3e6. Bad input: load cycles below one raise :class:`~gearopt.errors.GearoptInputError`.
"""

from __future__ import annotations

import math

from .. import numerics as nm
from ..validation import check_range
from .material_groups import iso6336_material_group

LONG_LIFE_CYCLES = 1e10

_ZNT_CURVES = {  # group -> [(N, value), ...] up to N_ref (value 1.0); 1e10 -> long-life value appended
    "no_pitting": [(1e5, 1.6), (5e7, 1.0)],
    "limited_pitting": [(6e5, 1.6), (1e7, 1.3), (1e9, 1.0)],
    "nitrided": [(1e5, 1.3), (2e6, 1.0)],
}
_YNT_CURVES = {
    "steel": [(1e4, 2.5), (3e6, 1.0)],
    "surface_hardened": [(1e3, 2.5), (3e6, 1.0)],
    "nitrided": [(1e3, 1.6), (3e6, 1.0)],
}


def _zn_curve_name(group: str, limited_pitting: bool) -> str:
    if group in ("NT", "GG"):
        return "nitrided"
    if limited_pitting and group in ("St", "V", "GGG"):
        return "limited_pitting"
    return "no_pitting"


def _yn_curve_name(group: str) -> str:
    return {"St": "steel", "V": "steel", "GGG": "steel", "Eh": "surface_hardened"}.get(group, "nitrided")


def log_log_curve(load_cycles, knots):
    """Piecewise straight line in (log N, log value) through ``knots`` [(N, value), ...] ascending in N, constant
    below the first and beyond the last knot. Dual-typed in ``load_cycles``."""
    n = nm.fmax(load_cycles, 1.0)
    ln_n = nm.log(n)
    out = knots[-1][1]
    for (n0, v0), (n1, v1) in reversed(list(zip(knots[:-1], knots[1:]))):
        slope = math.log(v1 / v0) / math.log(n1 / n0)
        seg = v0 * nm.exp(slope * (ln_n - math.log(n0)))
        out = nm.where(n <= n1, seg, out)
    return nm.where(n <= knots[0][0], knots[0][1], out)


def check_load_cycles(name, load_cycles) -> None:
    """Load cycles must be >= 1 (a GearoptInputError names the value and the limit)."""
    check_range(name, load_cycles, 1.0, None)


def check_long_life_factor(long_life_factor) -> None:
    check_range("long_life_factor", long_life_factor, 0.85, 1.0)


def life_factor_contact(load_cycles, material, *, long_life_factor=0.85, limited_pitting: bool = False):
    """ISO 6336-2:2006 clause 10 life factor Z_NT of one gear (see the module docstring) for ``load_cycles`` N_L >= 1
    and a catalogue ``material``; ``long_life_factor`` = Z_NT at 1e10 (0.85 normal .. 1.0 optimum), held beyond.
    Dual-typed in N_L."""
    check_load_cycles("load_cycles", load_cycles)
    check_long_life_factor(long_life_factor)
    knots = _ZNT_CURVES[_zn_curve_name(iso6336_material_group(material), limited_pitting)]
    return log_log_curve(load_cycles, knots + [(LONG_LIFE_CYCLES, long_life_factor)])


def life_factor_root(load_cycles, material, *, long_life_factor=0.85):
    """ISO 6336-3:2006 clause 12 life factor Y_NT of one gear (module docstring). Dual-typed in N_L."""
    check_load_cycles("load_cycles", load_cycles)
    check_long_life_factor(long_life_factor)
    knots = _YNT_CURVES[_yn_curve_name(iso6336_material_group(material))]
    return log_log_curve(load_cycles, knots + [(LONG_LIFE_CYCLES, long_life_factor)])


def reference_cycles(material, kind: str, *, limited_pitting: bool = False) -> tuple[float, float]:
    """(N_static, N_ref) of the Z_NT (``kind="contact"``) or Y_NT (``"root"``) curve of a material."""
    group = iso6336_material_group(material)
    knots = (_ZNT_CURVES[_zn_curve_name(group, limited_pitting)] if kind == "contact"
             else _YNT_CURVES[_yn_curve_name(group)])
    return knots[0][0], knots[-1][0]


def finite_life_value(load_cycles, static_value, reference_value, N_static, N_ref):
    """ISO 6336-2/-3 method B interpolation of a strength factor between its static value (N_L <= N_static) and its
    reference (endurance) value (N_L >= N_ref), log-linear in N_L, as the standard does for Z_L Z_v Z_R, Z_W, Z_X,
    Y_deltarelT, Y_RrelT and Y_X in the finite-life range. Dual-typed."""
    frac = nm.clip(nm.log(nm.fmax(load_cycles, 1.0) / N_static) / math.log(N_ref / N_static), 0.0, 1.0)
    return static_value * (reference_value / static_value) ** frac


def load_cycles_from_life(life_h, speed_rpm, contacts_per_revolution=1):
    """N_L = 60 life_h n contacts_per_revolution (one mesh per revolution unless an idler/planet). Dual-typed."""
    check_range("life_h", life_h, 0.0, None, low_inclusive=False, unit="h")
    return 60.0 * life_h * nm.fabs(speed_rpm) * contacts_per_revolution


__all__ = ["LONG_LIFE_CYCLES", "log_log_curve", "check_load_cycles", "life_factor_contact", "life_factor_root",
           "reference_cycles", "finite_life_value", "load_cycles_from_life"]
