"""The derived geometry of a gear pair as one frozen, typed record (ISO 21771:2007 quantities).

:meth:`gearopt.geometry.pair.GearPair.geometry` computes it once per pair and every model reads that one record.
Fields carry their unit in the name (lengths in mm, angles in degrees); dimensionless quantities (teeth, profile-shift
coefficients, contact ratios, specific sliding) carry none. Per-gear values are 2-tuples (gear 1, gear 2). With
numeric inputs the values are floats; with CasADi symbols in the pair they are CasADi expressions.

Attribute access is the typed way (``g.centre_distance_mm``); string keys (``g["centre_distance_mm"]``), ``keys()``,
``items()`` and ``dict(g)`` are a read-only view on the same record for code that iterates over it. A misspelled name
fails at once, listing the nearest valid names.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, fields
from typing import Any

Number = Any  # float or CasADi expression
PerGear = tuple  # (gear 1, gear 2)


@dataclass(frozen=True, eq=False)
class PairGeometry(Mapping):
    """Every derived dimension of an external cylindrical gear pair (see the module docstring for conventions)."""

    teeth: tuple[int, int]
    """z1, z2."""
    names: tuple[str, str]
    """Names of the two gears."""
    module_mm: Number
    """Normal module m_n."""
    transverse_module_mm: Number
    """m_t = m_n / cos(beta)."""
    pressure_angle_deg: Number
    """Normal pressure angle alpha_n of the basic rack."""
    transverse_pressure_angle_deg: Number
    """alpha_t."""
    helix_angle_deg: Number
    """Reference helix angle beta (0 = spur)."""
    base_helix_angle_deg: Number
    """beta_b."""
    virtual_teeth: PerGear
    """z_n = z / (cos^2(beta_b) cos(beta)), ISO 6336-3's virtual spur gear."""
    gear_ratio: Number
    """u = z2 / z1."""
    speed_ratio: Number
    """n2 / n1 = z1 / z2."""
    reference_centre_distance_mm: Number
    """a_d = (z1 + z2) m_t / 2."""
    centre_distance_mm: Number
    """Working centre distance a."""
    working_pressure_angle_deg: Number
    """alpha_wt."""
    sum_profile_shift: Number
    """x1 + x2."""
    centre_distance_modification: Number
    """y = (a - a_d) / m_n."""
    tip_shortening: Number
    """k = (x1 + x2) - y (>= 0 shortens the tips; ISO 21771's tip alteration with opposite sign)."""
    profile_shifts: PerGear
    """x1, x2."""
    pitch_diameter_mm: PerGear
    """Reference diameters d."""
    base_diameter_mm: PerGear
    """d_b."""
    working_pitch_diameter_mm: PerGear
    """d_w."""
    tip_diameter_mm: PerGear
    """d_a."""
    root_diameter_mm: PerGear
    """d_f."""
    root_form_diameter_mm: PerGear
    """d_Ff, where the generated involute ends at the root."""
    addendum_mm: PerGear
    """h_a = (d_a - d) / 2."""
    dedendum_mm: PerGear
    """h_f = (d - d_f) / 2."""
    whole_depth_mm: PerGear
    """h = (d_a - d_f) / 2."""
    bottom_clearance_mm: PerGear
    """Tip-to-root clearance at the root of gear 1 and of gear 2."""
    tooth_thickness_mm: PerGear
    """Normal tooth thickness at the reference circle s_n (no thickness allowance)."""
    transverse_tooth_thickness_mm: PerGear
    """s_t."""
    tip_thickness_mm: PerGear
    """Normal tooth thickness at the tip s_an."""
    transverse_tip_thickness_mm: PerGear
    """s_at."""
    base_pitch_mm: Number
    """Transverse base pitch p_bt."""
    normal_base_pitch_mm: Number
    """p_bn = pi m_n cos(alpha_n)."""
    length_of_path_of_contact_mm: Number
    """g_alpha."""
    transverse_contact_ratio: Number
    """epsilon_alpha."""
    overlap_contact_ratio: Number
    """epsilon_beta."""
    total_contact_ratio: Number
    """epsilon_gamma = epsilon_alpha + epsilon_beta."""
    face_width_mm: PerGear
    """b1, b2."""
    undercut_limit_profile_shift: PerGear
    """Smallest profile shift free of generating-rack undercut."""
    specific_sliding_root: PerGear
    """Specific sliding of gear 1 at A and of gear 2 at E (their roots; negative)."""
    sap_roll_length_mm: PerGear
    """Start of active profile: roll length on each gear (from its base tangent point)."""
    sap_diameter_mm: PerGear
    """Start of active profile: diameter on each gear."""
    sap_roll_deg: PerGear
    """Start of active profile: roll angle rho / r_b on each gear."""
    eap_roll_length_mm: PerGear
    """End of active profile: roll length on each gear."""
    eap_diameter_mm: PerGear
    """End of active profile: diameter on each gear."""
    eap_roll_deg: PerGear
    """End of active profile: roll angle on each gear."""
    lpstc_roll_length_mm: PerGear
    """Lowest point of single tooth contact: roll length on each gear."""
    lpstc_diameter_mm: PerGear
    """Lowest point of single tooth contact: diameter on each gear."""
    lpstc_roll_deg: PerGear
    """Lowest point of single tooth contact: roll angle on each gear."""
    hpstc_roll_length_mm: PerGear
    """Highest point of single tooth contact: roll length on each gear."""
    hpstc_diameter_mm: PerGear
    """Highest point of single tooth contact: diameter on each gear."""
    hpstc_roll_deg: PerGear
    """Highest point of single tooth contact: roll angle on each gear."""
    pitch_point_roll_length_mm: PerGear
    """Pitch point: roll length on each gear."""
    pitch_point_diameter_mm: PerGear
    """Pitch point: diameter on each gear (= working pitch diameter)."""
    pitch_point_roll_deg: PerGear
    """Pitch point: roll angle on each gear."""
    root_form_roll_length_mm: PerGear
    """Roll length of the root form circle (negative: the involute starts at the base circle)."""
    centre_distance_range_mm: PerGear
    """Smallest and largest centre distance from the allowances (not per gear: (min, max))."""
    circumferential_backlash_min_mm: Number
    """Smallest circumferential backlash at the reference circle (thickest teeth, smallest centre distance)."""
    circumferential_backlash_max_mm: Number
    """Largest circumferential backlash (thinnest teeth, largest centre distance)."""
    normal_backlash_min_mm: Number
    """Smallest normal backlash j_bn."""
    normal_backlash_max_mm: Number
    """Largest normal backlash j_bn."""
    worst_case_transverse_contact_ratio: Number
    """epsilon_alpha at the largest centre distance and the smallest tip diameters."""
    worst_case_tip_diameter_mm: PerGear
    """Smallest tip diameters from the allowances."""

    # ---------------------------------------------------------------- read-only mapping view

    def __getitem__(self, key: str) -> Any:
        if key in _FIELD_NAMES:
            return getattr(self, key)
        raise KeyError(_unknown(key))

    def __iter__(self) -> Iterator[str]:
        return iter(_FIELD_ORDER)

    def __len__(self) -> int:
        return len(_FIELD_ORDER)

    def __getattr__(self, name: str) -> Any:  # only called for names that are not fields
        if name.startswith("__"):
            raise AttributeError(name)
        raise AttributeError(_unknown(name))

    def __repr__(self) -> str:
        return f"PairGeometry({self.names[0]}-{self.names[1]}, z={self.teeth[0]}/{self.teeth[1]})"

    def is_finite(self) -> bool:
        """Whether every number is finite (one pass; :func:`gearopt.validation.check_result` names a bad one)."""
        isfinite = math.isfinite
        for k in _FIELD_ORDER:
            v = getattr(self, k)
            if isinstance(v, tuple):
                if not all(isinstance(e, (str, int)) or e is None or isfinite(e) for e in _flat(v)):
                    return False
            elif not (isinstance(v, (str, int)) or v is None or isfinite(v)):
                return False
        return True

    def map_values(self, fn) -> "PairGeometry":
        """A copy with ``fn`` applied to every number (tuples element-wise; teeth and names untouched)."""
        def apply(v):
            if isinstance(v, tuple):
                return tuple(apply(e) for e in v)
            if isinstance(v, (str, int)):
                return v
            return fn(v)
        return PairGeometry(**{k: apply(getattr(self, k)) for k in _FIELD_ORDER})


def _flat(values: tuple):
    for v in values:
        if isinstance(v, tuple):
            yield from _flat(v)
        else:
            yield v


_FIELD_ORDER = tuple(f.name for f in fields(PairGeometry))
_FIELD_NAMES = frozenset(_FIELD_ORDER)


def _unknown(name: str) -> str:
    near = difflib.get_close_matches(name, _FIELD_ORDER, n=3, cutoff=0.6)
    hint = f"; did you mean {', '.join(near)}?" if near else ""
    return (f"PairGeometry has no quantity {name!r}{hint} Valid names: {', '.join(_FIELD_ORDER)}")
