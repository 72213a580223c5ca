"""Macro geometry of an external cylindrical gear pair, spur or helical (ISO 21771:2007), dual-typed.

A :class:`GearPair` holds the defining data (teeth, normal module, normal pressure angle, helix angle, profile-shift
coefficients, working centre distance, face widths, basic rack, optional tip diameters and allowances). Any of the
continuous inputs may be CasADi symbols; :meth:`GearPair.geometry` then returns CasADi expressions, and the design
checks are available as named constraint expressions (:meth:`GearPair.constraints`, ``g >= 0``). With numbers,
:meth:`GearPair.check` raises a :class:`~gearopt.errors.GeometryError` naming every violated limit.

Conventions: lengths in mm, angles in degrees at the public surface (radians inside), gear 1 first in every 2-tuple.
Transverse quantities (subscript t) lie in the plane of rotation; for spur gears they equal the normal ones.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field, fields, replace
from functools import cached_property
from typing import Any

from .. import numerics as nm
from ..errors import GearoptInputError, GeometryError
from ..validation import check_int, check_names, check_per_gear, check_range, check_result, per_gear
from ..units import DEG_PER_RAD, RAD_PER_DEG
from . import involute as inv
from .shift import (check_centre_distance_reachable, iso_tr_4467_shift_limits, shift_split_iso_tr_4467,
                    sum_of_profile_shifts, working_pressure_angle_from_centre_distance,
                    working_pressure_angle_from_shifts)
from .record import PairGeometry
from .tolerances import PairTolerances, transverse_backlash_mm

Number = Any  # float, numpy scalar or CasADi expression


NUMERIC_RECORD_CACHE_SIZE = 4096
"""Geometry records of numeric pairs kept per process, keyed by the pair's defining values (oldest dropped first)."""
_NUMERIC_RECORDS: dict[tuple, Any] = {}
MAX_TEETH = 10000  # plausibility limit of a tooth count (large ring gears have a few hundred)


def _check_teeth(teeth) -> tuple[int, int]:
    if not isinstance(teeth, (tuple, list)) or len(teeth) != 2:
        raise GearoptInputError(f"teeth={teeth!r} must be a 2-tuple of integers (gear 1, gear 2)")
    out = []
    for i, z in enumerate(teeth):
        z = check_int(f"teeth[{i}]", z, None, MAX_TEETH)
        if z < 5:
            raise GearoptInputError(f"teeth[{i}]={z} is below the limit 5 for an external involute gear")
        out.append(z)
    return out[0], out[1]


@dataclass(frozen=True)
class GearPair:
    """An external cylindrical gear pair. Build it with :meth:`from_profile_shifts` or :meth:`from_centre_distance`.

    Attributes (units in the names): ``teeth`` (z1, z2); ``module_mm`` normal module m_n; ``pressure_angle_deg``
    normal pressure angle alpha_n of the basic rack; ``helix_angle_deg`` reference helix angle beta (0 = spur);
    ``profile_shifts`` (x1, x2); ``centre_distance_mm`` working centre distance a; ``face_width_mm`` (b1, b2);
    basic-rack coefficients (addendum h_aP*, dedendum h_fP*, root radius rho_fP*, all per m_n);
    ``tip_diameters_mm`` explicit tip diameters (``None``: from the rack, with tip shortening if
    ``tip_shortening``); ``tolerances`` manufacturing allowances; ``names`` of the two gears; ``helix_hands``
    ("right"/"left") for helical pairs.
    """

    teeth: tuple[int, int]
    module_mm: Number
    pressure_angle_deg: Number
    helix_angle_deg: Number
    profile_shifts: tuple[Number, Number]
    centre_distance_mm: Number
    face_width_mm: tuple[Number, Number]
    addendum_coefficient: float = 1.0
    dedendum_coefficient: float = 1.25
    root_radius_coefficient: float = 0.38
    tip_diameters_mm: tuple[Number, Number] | None = None
    tip_shortening: bool = True
    tolerances: PairTolerances = field(default_factory=PairTolerances)
    names: tuple[str, str] = ("gear 1", "gear 2")
    helix_hands: tuple[str, str] | None = None

    def __getstate__(self) -> dict:
        """The fields only: the geometry a pair caches once computed is not part of its value, so a pair pickles
        the same before and after use (pickles key the ε-constraint models of :mod:`gearopt.studies.epsilon`)."""
        return {f.name: getattr(self, f.name) for f in fields(self)}

    # ------------------------------------------------------------------------------------------------------------
    # construction
    # ------------------------------------------------------------------------------------------------------------

    @classmethod
    def from_profile_shifts(cls, teeth, profile_shifts, module_mm, pressure_angle_deg=20.0, helix_angle_deg=0.0,
                            face_width_mm=20.0, **options) -> "GearPair":
        """Pair from its profile-shift coefficients; the working centre distance follows from ISO 21771 eq. 44
        (``inv alpha_wt = inv alpha_t + 2 tan(alpha_n)(x1 + x2)/(z1 + z2)``) and a = a_d cos(alpha_t)/cos(alpha_wt).

        ``options``: ``addendum_coefficient``, ``dedendum_coefficient``, ``root_radius_coefficient``,
        ``tip_diameters_mm``, ``tip_shortening``, ``tolerances``, ``names``, ``helix_hands``.
        """
        teeth = _check_teeth(teeth)
        _check_scalars(module_mm, pressure_angle_deg, helix_angle_deg, face_width_mm)
        x = per_gear(profile_shifts, "profile_shifts")
        for i, xi in enumerate(x):
            check_range(f"profile_shifts[{i}]", xi, -3.0, 3.0)
        alpha_n = pressure_angle_deg * RAD_PER_DEG
        beta = helix_angle_deg * RAD_PER_DEG
        alpha_t = inv.transverse_pressure_angle(alpha_n, beta)
        alpha_wt = working_pressure_angle_from_shifts(teeth[0] + teeth[1], x[0] + x[1], alpha_t, alpha_n)
        a_d = 0.5 * (teeth[0] + teeth[1]) * inv.transverse_module(module_mm, beta)
        a = a_d * nm.cos(alpha_t) / nm.cos(alpha_wt)
        return cls._build(teeth, module_mm, pressure_angle_deg, helix_angle_deg, x, a, face_width_mm, options)

    @classmethod
    def from_centre_distance(cls, teeth, centre_distance_mm, module_mm, pressure_angle_deg=20.0,
                             helix_angle_deg=0.0, face_width_mm=20.0, shift_split=0.5, profile_shift1=None,
                             **options) -> "GearPair":
        """Pair that fits a given working centre distance: the sum of profile shifts follows from ISO 21771
        eqs. 44 and 46 (thesis Eqs. 3.2-3.5 generalised to helical gears), split between the gears either by
        ISO/TR 4467 with ``shift_split`` = lambda (thesis Eq. 3.6) or by giving ``profile_shift1`` (x2 is the rest).
        """
        teeth = _check_teeth(teeth)
        _check_scalars(module_mm, pressure_angle_deg, helix_angle_deg, face_width_mm)
        check_range("centre_distance_mm", centre_distance_mm, 0.0, None, low_inclusive=False, unit="mm")
        alpha_n = pressure_angle_deg * RAD_PER_DEG
        beta = helix_angle_deg * RAD_PER_DEG
        alpha_t = inv.transverse_pressure_angle(alpha_n, beta)
        a_d = 0.5 * (teeth[0] + teeth[1]) * inv.transverse_module(module_mm, beta)
        check_centre_distance_reachable(a_d, centre_distance_mm, alpha_t)
        alpha_wt = working_pressure_angle_from_centre_distance(a_d, centre_distance_mm, alpha_t)
        sum_x = sum_of_profile_shifts(teeth[0] + teeth[1], alpha_wt, alpha_t, alpha_n)
        if profile_shift1 is not None:
            check_range("profile_shift1", profile_shift1, -3.0, 3.0)
            x = (profile_shift1, sum_x - profile_shift1)
        else:
            x = shift_split_iso_tr_4467(teeth, sum_x, shift_split)
        return cls._build(teeth, module_mm, pressure_angle_deg, helix_angle_deg, x, centre_distance_mm,
                          face_width_mm, options)

    @classmethod
    def _build(cls, teeth, module_mm, pressure_angle_deg, helix_angle_deg, x, a, face_width_mm, options):
        allowed = {"addendum_coefficient", "dedendum_coefficient", "root_radius_coefficient", "tip_diameters_mm",
                   "tip_shortening", "tolerances", "names", "helix_hands"}
        unknown = set(options) - allowed
        if unknown:
            raise GearoptInputError(f"unknown option(s) {sorted(unknown)}; allowed: {sorted(allowed)}")
        opts = dict(options)
        if opts.get("tip_diameters_mm") is not None:
            opts["tip_diameters_mm"] = per_gear(opts["tip_diameters_mm"], "tip_diameters_mm")
            for i, da in enumerate(opts["tip_diameters_mm"]):
                check_range(f"tip_diameters_mm[{i}]", da, 0.0, None, low_inclusive=False, unit="mm")
        if opts.get("tolerances") is None:
            opts.pop("tolerances", None)
        if "names" in opts:
            opts["names"] = check_names("names", opts["names"])
        if "tip_shortening" in opts and not isinstance(opts["tip_shortening"], bool):
            raise GearoptInputError(f"tip_shortening={opts['tip_shortening']!r} must be True or False")
        for key in ("addendum_coefficient", "dedendum_coefficient"):
            if key in opts:
                check_range(key, opts[key], 0.0, 3.0, low_inclusive=False)
        if "root_radius_coefficient" in opts:
            check_range("root_radius_coefficient", opts["root_radius_coefficient"], 0.0, 1.0)
        if nm.is_numeric(helix_angle_deg) and nm.to_float(helix_angle_deg) != 0.0 and not opts.get("helix_hands"):
            opts["helix_hands"] = ("right", "left")
        if opts.get("helix_hands"):
            hands = tuple(opts["helix_hands"])
            if len(hands) != 2 or any(h not in ("right", "left") for h in hands) or hands[0] == hands[1]:
                raise GearoptInputError(f"helix_hands={hands!r}: an external helical pair needs one 'right' and one "
                                        f"'left' hand")
            opts["helix_hands"] = hands
        return cls(teeth=teeth, module_mm=module_mm, pressure_angle_deg=pressure_angle_deg,
                   helix_angle_deg=helix_angle_deg, profile_shifts=tuple(x), centre_distance_mm=a,
                   face_width_mm=per_gear(face_width_mm, "face_width_mm"), **opts)

    def with_options(self, **changes) -> "GearPair":
        """Copy with some fields replaced (e.g. ``tolerances=...``, ``tip_diameters_mm=...``)."""
        return replace(self, **changes)

    # ------------------------------------------------------------------------------------------------------------
    # geometry
    # ------------------------------------------------------------------------------------------------------------

    @property
    def is_symbolic(self) -> bool:
        return nm.is_symbolic(self.module_mm, self.pressure_angle_deg, self.helix_angle_deg, *self.profile_shifts,
                              self.centre_distance_mm, *self.face_width_mm, *(self.tip_diameters_mm or ()))

    @cached_property
    def _core(self) -> dict:
        """Quantities that do not depend on tip diameters or centre-distance deviations (radians inside)."""
        z1, z2 = self.teeth
        m = self.module_mm
        alpha_n = self.pressure_angle_deg * RAD_PER_DEG
        beta = self.helix_angle_deg * RAD_PER_DEG
        alpha_t = inv.transverse_pressure_angle(alpha_n, beta)
        beta_b = inv.base_helix_angle(alpha_n, beta)
        m_t = inv.transverse_module(m, beta)
        d = tuple(inv.reference_diameter(z, m_t) for z in self.teeth)
        d_b = tuple(inv.base_diameter(di, alpha_t) for di in d)
        a_d = 0.5 * (z1 + z2) * m_t
        a = self.centre_distance_mm
        alpha_wt = working_pressure_angle_from_centre_distance(a_d, a, alpha_t)
        x1, x2 = self.profile_shifts
        sum_x = x1 + x2
        y = (a - a_d) / m
        k = sum_x - y  # tip shortening coefficient (>= 0 shortens the tips)
        s_t = tuple(inv.transverse_tooth_thickness_reference(m_t, xi, alpha_n) for xi in self.profile_shifts)
        h_ff = inv.tool_form_height_coefficient(self.dedendum_coefficient, self.root_radius_coefficient, alpha_n)
        if self.tip_diameters_mm is not None:
            d_a = self.tip_diameters_mm
        else:
            shortening = k if self.tip_shortening else 0.0
            d_a = tuple(di + 2.0 * m * (self.addendum_coefficient + xi - shortening)
                        for di, xi in zip(d, self.profile_shifts))
        d_f = tuple(di - 2.0 * m * (self.dedendum_coefficient - xi) for di, xi in zip(d, self.profile_shifts))
        return dict(alpha_n=alpha_n, beta=beta, alpha_t=alpha_t, beta_b=beta_b, m_t=m_t, d=d, d_b=d_b, a_d=a_d,
                    a=a, alpha_wt=alpha_wt, sum_x=sum_x, y=y, k=k, s_t=s_t, h_ff=h_ff, d_a=d_a, d_f=d_f)

    def _contact(self, centre_distance_mm, tip_diameters_mm) -> dict:
        """Path of contact at a given centre distance and tip diameters (transverse plane, mm).

        Roll lengths of gear 1 are measured from its base-circle tangent point T1 along the line of action:
        A (start of active profile of gear 1), B (lowest point of single contact of gear 1), C (pitch point),
        D (highest point of single contact of gear 1), E (end of contact, gear 1 tip); for gear 2 rho2 = T1T2 - rho1.
        """
        c = self._core
        alpha_wt = working_pressure_angle_from_centre_distance(c["a_d"], centre_distance_mm, c["alpha_t"])
        t1t2 = centre_distance_mm * nm.sin(alpha_wt)
        rho_a = tuple(inv.roll_length_at(da, db) for da, db in zip(tip_diameters_mm, c["d_b"]))
        p_bt = math.pi * c["m_t"] * nm.cos(c["alpha_t"])
        g_alpha = rho_a[0] + rho_a[1] - t1t2
        A = t1t2 - rho_a[1]
        E = rho_a[0]
        return dict(alpha_wt=alpha_wt, t1t2=t1t2, rho_a=rho_a, p_bt=p_bt, g_alpha=g_alpha,
                    eps_alpha=g_alpha / p_bt, A=A, B=E - p_bt, C=0.5 * c["d_b"][0] * nm.tan(alpha_wt),
                    D=A + p_bt, E=E)

    @cached_property
    def _geometry(self) -> dict:
        c = self._core
        z1, z2 = self.teeth
        m = self.module_mm
        ct = self._contact(c["a"], c["d_a"])
        d, d_b, d_a, d_f = c["d"], c["d_b"], c["d_a"], c["d_f"]
        b = self.face_width_mm
        b_common = nm.fmin(b[0], b[1])
        eps_beta = b_common * nm.fabs(nm.sin(c["beta"])) / (math.pi * m)

        def per_gear_roll(rho1):  # a point of the path as roll length on each gear
            return (rho1, ct["t1t2"] - rho1)

        points = {"sap": (ct["A"], ct["t1t2"] - ct["E"]), "eap": (ct["E"], ct["t1t2"] - ct["A"]),
                  "lpstc": (ct["B"], ct["t1t2"] - ct["D"]), "hpstc": (ct["D"], ct["t1t2"] - ct["B"]),
                  "pitch_point": per_gear_roll(ct["C"])}
        s_at = tuple(inv.transverse_tooth_thickness_at(d_a[i], d[i], d_b[i], c["s_t"][i], c["alpha_t"])
                     for i in range(2))
        beta_a = tuple(inv.helix_angle_at(d_a[i], d[i], c["beta"]) for i in range(2))
        s_an = tuple(s_at[i] * nm.cos(beta_a[i]) for i in range(2))
        rho_ff = tuple(inv.form_roll_length(d[i], c["alpha_t"], self.profile_shifts[i], m, c["h_ff"])
                       for i in range(2))
        d_w = tuple(2.0 * c["a"] * z / (z1 + z2) for z in self.teeth)
        # specific sliding at the roots (gear 1 at A, gear 2 at E): zeta = 1 - (z_i rho_j)/(z_j rho_i)
        zeta1 = 1.0 - (z1 * (ct["t1t2"] - ct["A"])) / (z2 * ct["A"])
        zeta2 = 1.0 - (z2 * ct["E"]) / (z1 * (ct["t1t2"] - ct["E"]))
        g = {
            "teeth": self.teeth,
            "names": self.names,
            "module_mm": m,
            "transverse_module_mm": c["m_t"],
            "pressure_angle_deg": self.pressure_angle_deg,
            "transverse_pressure_angle_deg": c["alpha_t"] * DEG_PER_RAD,
            "helix_angle_deg": self.helix_angle_deg,
            "base_helix_angle_deg": c["beta_b"] * DEG_PER_RAD,
            "virtual_teeth": tuple(inv.virtual_teeth(z, c["beta"], c["beta_b"]) for z in self.teeth),
            "gear_ratio": z2 / z1,
            "speed_ratio": z1 / z2,
            "reference_centre_distance_mm": c["a_d"],
            "centre_distance_mm": c["a"],
            "working_pressure_angle_deg": c["alpha_wt"] * DEG_PER_RAD,
            "sum_profile_shift": c["sum_x"],
            "centre_distance_modification": c["y"],
            "tip_shortening": c["k"],
            "profile_shifts": self.profile_shifts,
            "pitch_diameter_mm": d,
            "base_diameter_mm": d_b,
            "working_pitch_diameter_mm": d_w,
            "tip_diameter_mm": d_a,
            "root_diameter_mm": d_f,
            "root_form_diameter_mm": tuple(inv.diameter_at_roll_length(nm.fmax(r, 0.0), db)
                                           for r, db in zip(rho_ff, d_b)),
            "addendum_mm": tuple(0.5 * (d_a[i] - d[i]) for i in range(2)),
            "dedendum_mm": tuple(0.5 * (d[i] - d_f[i]) for i in range(2)),
            "whole_depth_mm": tuple(0.5 * (d_a[i] - d_f[i]) for i in range(2)),
            "bottom_clearance_mm": (c["a"] - 0.5 * (d_a[1] + d_f[0]), c["a"] - 0.5 * (d_a[0] + d_f[1])),
            "tooth_thickness_mm": tuple(st * nm.cos(c["beta"]) for st in c["s_t"]),
            "transverse_tooth_thickness_mm": c["s_t"],
            "tip_thickness_mm": s_an,
            "transverse_tip_thickness_mm": s_at,
            "base_pitch_mm": ct["p_bt"],
            "normal_base_pitch_mm": math.pi * m * nm.cos(c["alpha_n"]),
            "length_of_path_of_contact_mm": ct["g_alpha"],
            "transverse_contact_ratio": ct["eps_alpha"],
            "overlap_contact_ratio": eps_beta,
            "total_contact_ratio": ct["eps_alpha"] + eps_beta,
            "face_width_mm": b,
            "undercut_limit_profile_shift": tuple(
                inv.undercut_limit_profile_shift(z, c["alpha_t"], c["beta"], c["h_ff"]) for z in self.teeth),
            "specific_sliding_root": (zeta1, zeta2),
        }
        for key, (r1, r2) in points.items():
            g[f"{key}_roll_length_mm"] = (r1, r2)
            g[f"{key}_diameter_mm"] = (inv.diameter_at_roll_length(r1, d_b[0]),
                                       inv.diameter_at_roll_length(r2, d_b[1]))
            g[f"{key}_roll_deg"] = (inv.roll_angle_deg(r1, d_b[0]), inv.roll_angle_deg(r2, d_b[1]))
        g["root_form_roll_length_mm"] = rho_ff
        g.update(self._tolerance_geometry())
        return g

    def _tolerance_geometry(self) -> dict:
        """Backlash range and worst-case contact ratio from the allowances (ISO 21771 5.5; exact involute form)."""
        c = self._core
        tol = self.tolerances
        a_lo = c["a"] + tol.centre_distance_allowance_mm[0]
        a_hi = c["a"] + tol.centre_distance_allowance_mm[1]
        cos_b = nm.cos(c["beta"])

        def thickness(allowances_um):
            return tuple(c["s_t"][i] + allowances_um[i] * 1e-3 / cos_b for i in range(2))

        cos_bb = nm.cos(c["beta_b"])
        jt_min, jbt_min = transverse_backlash_mm(self.teeth, c["d"], c["d_b"],
                                                 thickness(tol.tooth_thickness_upper_allowance_um), c["alpha_t"],
                                                 c["a_d"], a_lo)
        jt_max, jbt_max = transverse_backlash_mm(self.teeth, c["d"], c["d_b"],
                                                 thickness(tol.tooth_thickness_lower_allowance_um), c["alpha_t"],
                                                 c["a_d"], a_hi)
        d_a_min = tuple(c["d_a"][i] + tol.tip_diameter_allowance_mm[i][0] for i in range(2))
        worst = self._contact(a_hi, d_a_min)
        return {
            "centre_distance_range_mm": (a_lo, a_hi),
            "circumferential_backlash_min_mm": jt_min,
            "circumferential_backlash_max_mm": jt_max,
            "normal_backlash_min_mm": jbt_min * cos_bb,
            "normal_backlash_max_mm": jbt_max * cos_bb,
            "worst_case_transverse_contact_ratio": worst["eps_alpha"],
            "worst_case_tip_diameter_mm": d_a_min,
        }

    def geometry(self) -> PairGeometry:
        """Every derived dimension as one frozen :class:`~gearopt.geometry.record.PairGeometry` record, computed
        once per pair and shared by every model that reads it (floats with numbers in; CasADi expressions with
        symbols in).

        Scalars, or 2-tuples (gear 1, gear 2) for per-gear values. Units in the field names; angles in degrees;
        ``profile_shifts``, ``sum_profile_shift``, ``centre_distance_modification`` (y), ``tip_shortening``
        (k = sum_x - y, ISO 21771's tip alteration with opposite sign) and the contact ratios are dimensionless.
        ``*_roll_deg`` are roll angles (rho / r_b) of SAP, EAP, LPSTC, HPSTC and the pitch point on each gear.
        ``specific_sliding_root`` are gear 1's specific sliding at A and gear 2's at E (their roots; negative).
        Fields are read as attributes (``g.centre_distance_mm``) or, as a read-only mapping, by key.
        A numeric pair whose geometry would hold NaN or an infinity raises
        :class:`~gearopt.errors.NonFiniteResultError` naming the quantity and the pair's inputs.
        """
        return self._record

    @cached_property
    def _record(self) -> PairGeometry:
        if self.is_symbolic:
            return PairGeometry(**self._geometry)
        key = self.numeric_key()
        record = _NUMERIC_RECORDS.get(key) if key is not None else None
        if record is None:
            record = PairGeometry(**self._geometry).map_values(nm.to_float)
            if not record.is_finite():                  # the full check only to name what is not finite
                check_result(f"{self._label()} geometry", record, self._inputs())
            if key is not None:
                if len(_NUMERIC_RECORDS) >= NUMERIC_RECORD_CACHE_SIZE:
                    _NUMERIC_RECORDS.pop(next(iter(_NUMERIC_RECORDS)))
                _NUMERIC_RECORDS[key] = record
        return record

    def numeric_key(self) -> tuple | None:
        """The defining values of a numeric pair (every field) as a hashable key, or None when one is unhashable:
        equal pairs built separately (a train re-propagated, a dataclass ``replace``) share one geometry record, and
        models built on equal pairs can share what depends on the pair alone."""
        key = tuple(getattr(self, f.name) for f in fields(self))
        try:
            hash(key)
        except TypeError:
            return None
        return key

    def _inputs(self) -> dict:
        """The defining numbers of a numeric pair, for error messages."""
        return {"teeth": self.teeth, "module_mm": nm.to_float(self.module_mm),
                "pressure_angle_deg": nm.to_float(self.pressure_angle_deg),
                "helix_angle_deg": nm.to_float(self.helix_angle_deg),
                "profile_shifts": tuple(round(nm.to_float(x), 6) for x in self.profile_shifts),
                "centre_distance_mm": round(nm.to_float(self.centre_distance_mm), 6),
                "face_width_mm": tuple(nm.to_float(b) for b in self.face_width_mm),
                "tip_diameters_mm": None if self.tip_diameters_mm is None
                else tuple(nm.to_float(d) for d in self.tip_diameters_mm)}

    # ------------------------------------------------------------------------------------------------------------
    # checks and constraints
    # ------------------------------------------------------------------------------------------------------------

    def constraints(self, *, min_tip_thickness_ratio: float = 0.2, min_contact_ratio: float = 1.0,
                    worst_case: bool = True, iso_tr_4467_limits: bool = True,
                    min_bottom_clearance_ratio: float = 0.0, min_backlash_mm: float | None = 0.0) -> dict:
        """Design limits as named margins ``g >= 0`` (units in the names), dual-typed.

        - ``undercut_margin_i``: x_i - x_min (generating-rack undercut).
        - ``tip_thickness_margin_i_mm``: normal tip thickness - ``min_tip_thickness_ratio`` m_n (pointed tip).
        - ``interference_margin_i_mm``: roll length of the SAP minus that of the root form circle (the mating tip
          must not reach the non-involute root).
        - ``bottom_clearance_margin_i_mm``: tip-to-root clearance - ``min_bottom_clearance_ratio`` m_n.
        - ``contact_ratio_margin``: transverse contact ratio (at maximum centre distance and minimum tip diameters if
          ``worst_case``) - ``min_contact_ratio``.
        - ``shift_upper_margin_i`` / ``shift_lower_margin_i``: ISO/TR 4467 recommended limits (thesis Eqs. 3.8-3.12).
        - ``backlash_margin_mm``: smallest normal backlash - ``min_backlash_mm`` (skip with ``None``).
        """
        _check_limits(min_tip_thickness_ratio, min_contact_ratio, worst_case, iso_tr_4467_limits,
                      min_bottom_clearance_ratio, min_backlash_mm)
        g = self._geometry
        m = self.module_mm
        out: dict[str, Any] = {}
        for i in range(2):
            n = i + 1
            out[f"undercut_margin_{n}"] = self.profile_shifts[i] - g["undercut_limit_profile_shift"][i]
            out[f"tip_thickness_margin_{n}_mm"] = g["tip_thickness_mm"][i] - min_tip_thickness_ratio * m
            out[f"interference_margin_{n}_mm"] = g["sap_roll_length_mm"][i] - nm.fmax(
                g["root_form_roll_length_mm"][i], 0.0)
            out[f"bottom_clearance_margin_{n}_mm"] = g["bottom_clearance_mm"][i] - min_bottom_clearance_ratio * m
        eps = g["worst_case_transverse_contact_ratio"] if worst_case else g["transverse_contact_ratio"]
        out["contact_ratio_margin"] = eps - min_contact_ratio
        if iso_tr_4467_limits:
            for i, z in enumerate(self.teeth):
                lower, upper = iso_tr_4467_shift_limits(z)
                if math.isfinite(upper):
                    out[f"shift_upper_margin_{i + 1}"] = upper - self.profile_shifts[i]
                if math.isfinite(lower):
                    out[f"shift_lower_margin_{i + 1}"] = self.profile_shifts[i] - lower
        if min_backlash_mm is not None:
            out["backlash_margin_mm"] = g["normal_backlash_min_mm"] - min_backlash_mm
        return out

    def check(self, **limits) -> None:
        """Raise :class:`GeometryError` naming every violated limit of :meth:`constraints` (numeric pairs only).

        Messages give the quantity, its value and its limit, e.g.
        ``profile_shift x1=1.9 exceeds the pointed-tooth limit 1.32 for z=12``.
        """
        if self.is_symbolic:
            raise GearoptInputError("check() needs numeric inputs; impose constraints() in the problem instead")
        allowed = {"min_tip_thickness_ratio", "min_contact_ratio", "worst_case", "iso_tr_4467_limits",
                   "min_bottom_clearance_ratio", "min_backlash_mm"}
        unknown = sorted(set(limits) - allowed)
        if unknown:
            raise GearoptInputError(f"unknown limit(s) {unknown} for check(); allowed: {sorted(allowed)}")
        margins = {k: nm.to_float(v) for k, v in self.constraints(**limits).items()}
        problems = [f"{name} is NaN: the geometry is undefined here ({self._inputs()})"
                    for name, value in margins.items() if value != value]
        problems += [self._explain(name, value, limits) for name, value in margins.items() if value < -1e-12]
        if problems:
            raise GeometryError(f"{self._label()}: " + "; ".join(problems))

    def _label(self) -> str:
        return f"gear pair {self.names[0]}-{self.names[1]} (z={self.teeth[0]}/{self.teeth[1]})"

    def _explain(self, name: str, margin: float, limits: dict) -> str:
        g = self.geometry()
        match = re.search(r"_(\d)(_mm)?$", name)
        i = int(match.group(1)) - 1 if match else None
        z = self.teeth[i] if i is not None else None
        x = nm.to_float(self.profile_shifts[i]) if i is not None else None
        if name.startswith("undercut"):
            return (f"profile_shift x{i + 1}={x:.4f} is below the undercut limit "
                    f"{g['undercut_limit_profile_shift'][i]:.4f} for z={z}")
        if name.startswith("tip_thickness"):
            ratio = limits.get("min_tip_thickness_ratio", 0.2)
            x_lim = self._pointed_tip_limit(i, ratio)
            lim = f"; the limit is x{i + 1} <= {x_lim:.4f}" if x_lim is not None else ""
            return (f"profile_shift x{i + 1}={x:.4f} exceeds the pointed-tooth limit for z={z}: normal tip thickness "
                    f"{g['tip_thickness_mm'][i]:.4f} mm < {ratio:g} m_n = {ratio * nm.to_float(self.module_mm):.4f} mm"
                    f"{lim}")
        if name.startswith("interference"):
            return (f"tip/root interference on gear {i + 1} (z={z}): the mating tip reaches roll length "
                    f"{g['sap_roll_length_mm'][i]:.4f} mm, below the root form circle at "
                    f"{max(g['root_form_roll_length_mm'][i], 0.0):.4f} mm")
        if name.startswith("bottom_clearance"):
            ratio = limits.get("min_bottom_clearance_ratio", 0.0)
            return (f"bottom clearance at the root of gear {i + 1} is {g['bottom_clearance_mm'][i]:.4f} mm, "
                    f"below {ratio:g} m_n")
        if name == "contact_ratio_margin":
            lim = limits.get("min_contact_ratio", 1.0)
            which = "worst_case_transverse_contact_ratio" if limits.get("worst_case", True) \
                else "transverse_contact_ratio"
            return f"{which}={g[which]:.4f} is below the limit {lim:g}"
        if name.startswith("shift_upper"):
            return (f"profile_shift x{i + 1}={x:.4f} exceeds the ISO/TR 4467 upper limit "
                    f"{iso_tr_4467_shift_limits(z)[1]:.4f} for z={z}")
        if name.startswith("shift_lower"):
            return (f"profile_shift x{i + 1}={x:.4f} is below the ISO/TR 4467 lower limit "
                    f"{iso_tr_4467_shift_limits(z)[0]:.4f} for z={z}")
        if name == "backlash_margin_mm":
            return (f"normal_backlash_min_mm={g['normal_backlash_min_mm']:.4f} is below "
                    f"{limits.get('min_backlash_mm', 0.0)} mm (teeth jam at minimum centre distance and thickest teeth)")
        return f"{name}={margin:.4g} < 0"

    def _pointed_tip_limit(self, i: int, ratio: float) -> float | None:
        """Largest x_i for which gear i's normal tip thickness equals ``ratio`` m_n, with this pair's tip
        alteration k (or its explicit tip diameter) held fixed."""
        from scipy.optimize import brentq

        c = self._core
        m = nm.to_float(self.module_mm)
        k = nm.to_float(c["k"]) if self.tip_shortening else 0.0
        d, d_b = nm.to_float(c["d"][i]), nm.to_float(c["d_b"][i])

        def margin(xi):
            d_a = nm.to_float(self.tip_diameters_mm[i]) if self.tip_diameters_mm is not None \
                else d + 2.0 * m * (self.addendum_coefficient + xi - k)
            s_t = inv.transverse_tooth_thickness_reference(c["m_t"], xi, c["alpha_n"])
            s_at = inv.transverse_tooth_thickness_at(d_a, d, d_b, s_t, c["alpha_t"])
            s_an = s_at * nm.cos(inv.helix_angle_at(d_a, d, c["beta"]))
            return nm.to_float(s_an) - ratio * m

        try:
            return brentq(margin, -1.0, 3.0, xtol=1e-6)
        except (ValueError, RuntimeError):
            return None


def _check_limits(min_tip_thickness_ratio, min_contact_ratio, worst_case, iso_tr_4467_limits,
                  min_bottom_clearance_ratio, min_backlash_mm) -> None:
    """The limits of :meth:`GearPair.constraints`: finite numbers in plausible ranges, flags as bools."""
    check_range("min_tip_thickness_ratio", min_tip_thickness_ratio, 0.0, 2.0)
    check_range("min_contact_ratio", min_contact_ratio, 0.0, 10.0)
    check_range("min_bottom_clearance_ratio", min_bottom_clearance_ratio, -1.0, 2.0)
    if min_backlash_mm is not None:
        check_range("min_backlash_mm", min_backlash_mm, -100.0, 100.0, unit="mm")
    for name, flag in (("worst_case", worst_case), ("iso_tr_4467_limits", iso_tr_4467_limits)):
        if not isinstance(flag, bool):
            raise GearoptInputError(f"{name}={flag!r} must be True or False")


def _check_scalars(module_mm, pressure_angle_deg, helix_angle_deg, face_width_mm) -> None:
    check_range("module_mm", module_mm, 0.0, None, low_inclusive=False, unit="mm")
    check_range("pressure_angle_deg", pressure_angle_deg, 0.0, 45.0, low_inclusive=False, high_inclusive=False,
                unit="deg")
    check_range("helix_angle_deg", helix_angle_deg, 0.0, 45.0, high_inclusive=False, unit="deg")
    check_per_gear("face_width_mm", face_width_mm, 0.0, None, low_inclusive=False, unit="mm")
