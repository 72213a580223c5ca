"""Tooth-count candidates of a train: reference speed ratios along its tree, per-gear shift limits and per-mesh
sums of shifts (closed forms), and the candidate model (every mesh's limits as functions of the root gear's profile
shift). Part of :mod:`gearopt.design.tooth_counts`."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from fractions import Fraction
from typing import TYPE_CHECKING, Any, Mapping

import numpy as np

from ... import numerics as nm
from ...data import system_of
from ...errors import GearoptInputError
from ...validation import check_range
from ...geometry import involute as inv
from ...geometry.shift import (check_centre_distance_reachable, iso_tr_4467_shift_limits, sum_of_profile_shifts,
                               working_pressure_angle_from_centre_distance)
from ...geometry.train import GearTrain
from ...units import DEG_PER_RAD, RAD_PER_DEG

if TYPE_CHECKING:
    from ...data import System


OBJECTIVES = ("max_min_worst_case_contact_ratio", "max_min_tip_thickness")
REFERENCES = ("teeth", "data", "helical_original")
STAGES = ("speed_ratio", "centre_distance", "sum_of_shifts", "shift_limits", "precheck")

_RATIO_EPS_PERCENT = 1e-9      # floating-point slack of the tolerance comparison [%]
_PER_GEAR_CONSTRAINTS = ("undercut_margin", "tip_thickness_margin", "shift_upper_margin", "shift_lower_margin")
_NO_LIMIT = 10.0               # stands for "no ISO/TR 4467 limit" in the relaxed Bonmin model (|x| <= 3 anyway)



# ----------------------------------------------------------------------------------------------------------------
# tree and reference ratios
# ----------------------------------------------------------------------------------------------------------------

def _tree_order(train: GearTrain) -> list[tuple[str, str | None, str | None]]:
    """(gear, mesh through which it is reached, parent gear) in breadth-first order from the root gear."""
    order, seen, queue = [(train.root_gear, None, None)], {train.root_gear}, [train.root_gear]
    while queue:
        g = queue.pop(0)
        for name, mesh in train.meshes.items():
            if g in mesh.gears:
                other = mesh.gears[1] if mesh.gears[0] == g else mesh.gears[0]
                if other not in seen:
                    seen.add(other)
                    order.append((other, name, g))
                    queue.append(other)
    return order


def _ratios_from_teeth(train: GearTrain, teeth: Mapping[str, int]) -> dict[str, float]:
    """Speed of every gear relative to the root gear (magnitude): z_root / z_gear."""
    z0 = teeth[train.root_gear]
    return {g: z0 / teeth[g] for g in train.gears}


def reference_speed_ratios(train: GearTrain, reference: str | Mapping[str, float] = "teeth",
                           system: System | None = None) -> dict[str, float]:
    """Reference speed of every gear relative to the train's root gear (magnitudes, dimensionless).

    ``reference``:

    - ``"teeth"``: the train's own tooth counts, z_root / z_gear;
    - ``"data"``: the data file's ``[gears.*] speed_ratio_to_crank`` (printed to 4 decimals), each read as the
      nearest fraction with denominator <= 1000 when that is within the printed rounding (5e-5), and divided by the
      root gear's value;
    - ``"helical_original"``: the original helical train the thesis converted (Table 3.1): each mesh's reference
      ratio is the train's z1/z2 divided by (1 + ``speed_ratio_error_percent``/100) of the data's mesh table (the
      error of the spur tooth counts against the helical pair), propagated from the root;
    - a mapping gear -> ratio (every gear of the train; the root's value is divided out).

    ``system``: the :class:`~gearopt.data.System` of the data file; required for ``"data"`` and
    ``"helical_original"`` (``None`` raises naming the argument: the packaged data are never read behind the
    caller's back), unused otherwise.
    """
    if isinstance(reference, Mapping):
        missing = sorted(set(train.gears) - set(reference))
        if missing:
            raise GearoptInputError(f"reference speed ratios miss gears {missing}; limit: one ratio per gear of "
                                    f"{list(train.gears)}")
        for g in train.gears:
            check_range(f"reference[{g!r}]", reference[g], 0.0, None, low_inclusive=False)
        root = float(reference[train.root_gear])
        return {g: float(reference[g]) / root for g in train.gears}
    if reference not in REFERENCES:
        raise GearoptInputError(f"reference={reference!r} must be one of {REFERENCES} or a mapping gear -> ratio")
    teeth = {g: spec.teeth for g, spec in train.gears.items()}
    if reference == "teeth":
        return _ratios_from_teeth(train, teeth)
    if system is None:
        raise GearoptInputError(f"reference={reference!r} reads the data file: pass system=... (the System of your "
                                f"file, gearopt.load_system(path)); system=None is not read from the packaged "
                                f"default")
    system = system_of(system, f"reference_speed_ratios(reference={reference!r})")
    if reference == "data":
        out = {}
        for g in train.gears:
            try:
                v = float(system.gears[g].entries["speed_ratio_to_crank"])
            except KeyError:
                raise GearoptInputError(f"reference='data': the data has no gears.{g}.speed_ratio_to_crank") from None
            check_range(f"gears.{g}.speed_ratio_to_crank", v, 0.0, None, low_inclusive=False)
            frac = Fraction(v).limit_denominator(1000)
            out[g] = float(frac) if abs(float(frac) - v) <= 5e-5 else v
        root = out[train.root_gear]
        return {g: r / root for g, r in out.items()}
    ratios = {train.root_gear: 1.0}
    meshes = system.section("meshes", f"reference_speed_ratios(reference={reference!r})")
    for gear, mesh_name, parent in _tree_order(train)[1:]:
        try:
            err = float(meshes[mesh_name]["speed_ratio_error_percent"])
        except KeyError:
            raise GearoptInputError(f"reference='helical_original': the data has no "
                                    f"meshes.{mesh_name}.speed_ratio_error_percent") from None
        g1, g2 = train.meshes[mesh_name].gears
        q = (teeth[g1] / teeth[g2]) / (1.0 + err / 100.0)  # reference n2/n1 of this mesh
        ratios[gear] = ratios[parent] * q if parent == g1 else ratios[parent] / q
    return ratios


# ----------------------------------------------------------------------------------------------------------------
# per-gear and per-mesh closed forms
# ----------------------------------------------------------------------------------------------------------------

def _rack_angles(train: GearTrain) -> tuple[float, float, float, float]:
    alpha_n = float(train.rack.pressure_angle_deg) * RAD_PER_DEG
    beta = float(train.helix_angle_deg) * RAD_PER_DEG
    alpha_t = float(inv.transverse_pressure_angle(alpha_n, beta))
    h_ff = float(inv.tool_form_height_coefficient(train.rack.dedendum_coefficient, train.rack.root_radius_coefficient,
                                                  alpha_n))
    return alpha_n, beta, alpha_t, h_ff


def gear_shift_limits(train: GearTrain, teeth: int, *, iso_tr_4467_limits: bool = True
                      ) -> tuple[float, float, str, str]:
    """Admissible profile-shift range (lower, upper) of a gear of ``teeth`` on the train's rack, with the name of
    each limit: lower = max(undercut limit x_min = h_FfP0* - z sin^2(alpha_t)/(2 cos beta), ISO/TR 4467 lower
    limit), upper = ISO/TR 4467 upper limit (thesis Eqs. 3.8-3.12; ``inf`` where the standard gives none or
    ``iso_tr_4467_limits`` is False). The same limits as :meth:`GearPair.constraints`' undercut and shift margins."""
    _, beta, alpha_t, h_ff = _rack_angles(train)
    x_u = float(inv.undercut_limit_profile_shift(teeth, alpha_t, beta, h_ff))
    lo_iso, hi_iso = iso_tr_4467_shift_limits(teeth) if iso_tr_4467_limits else (-math.inf, math.inf)
    if lo_iso > x_u:
        return lo_iso, hi_iso, "ISO/TR 4467 lower limit", "ISO/TR 4467 upper limit"
    return x_u, hi_iso, "undercut limit", "ISO/TR 4467 upper limit"


def mesh_sum_of_shifts(train: GearTrain, mesh: str, teeth: tuple[int, int]) -> tuple[float, float]:
    """Sum of profile shifts x1 + x2 [-] and working transverse pressure angle [deg] that close ``mesh``'s housing
    centre distance with ``teeth`` (ISO 21771 eqs. 44 and 46; thesis Eqs. 3.2-3.5). Raises ``GeometryError`` if the
    centre distance is unreachable (working pressure angle outside (0, 45] deg)."""
    alpha_n, beta, alpha_t, _ = _rack_angles(train)
    a = float(train.meshes[mesh].centre_distance_mm)
    m_t = float(inv.transverse_module(float(train.rack.module_mm), beta))
    a_d = 0.5 * (teeth[0] + teeth[1]) * m_t
    check_centre_distance_reachable(a_d, a, alpha_t)
    alpha_wt = float(working_pressure_angle_from_centre_distance(a_d, a, alpha_t))
    return float(sum_of_profile_shifts(teeth[0] + teeth[1], alpha_wt, alpha_t, alpha_n)), alpha_wt * DEG_PER_RAD


def _train_with_teeth(train: GearTrain, teeth: Mapping[str, int], root_profile_shift) -> GearTrain:
    gears = {g: replace(spec, teeth=int(teeth[g])) for g, spec in train.gears.items()}
    return GearTrain(gears=gears, meshes=dict(train.meshes), rack=train.rack, helix_angle_deg=train.helix_angle_deg,
                     root_mesh=train.root_mesh, root_gear=train.root_gear, root_profile_shift=root_profile_shift,
                     root_shift_split=train.root_shift_split, root_hand=train.root_hand, name=train.name)


# ----------------------------------------------------------------------------------------------------------------
# the candidate model: constraints, contact ratios and tip thicknesses as a function of the root shift
# ----------------------------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class _Limits:
    min_contact_ratio: float
    min_tip_thickness_ratio: float
    iso_tr_4467_limits: bool
    min_backlash_mm: float | None


@dataclass(frozen=True)
class CandidateModel:
    """One tooth-count candidate as a CasADi function of the root gear's profile shift x_root:
    ``function(x_root) -> (margins, worst_case_contact_ratios, tip_thicknesses_mm)``; the names of the margins
    (``gear:undercut_margin``, ``mesh:contact_ratio_margin`` ..., units in the names, ``g >= 0``), the meshes and
    the gears in output order."""

    function: Any = field(repr=False)
    margin_names: tuple[str, ...]
    meshes: tuple[str, ...]
    gears: tuple[str, ...]

    def evaluate(self, root_profile_shift) -> dict[str, np.ndarray]:
        """Numeric outputs at one or more root shifts (columns = samples)."""
        xs = np.atleast_1d(np.asarray(root_profile_shift, dtype=float))
        f = self.function if xs.size == 1 else self.function.map(int(xs.size))
        g, eps, s = f(xs.reshape(1, -1))
        return {"margins": np.asarray(g).reshape(len(self.margin_names), -1),
                "worst_case_contact_ratio": np.asarray(eps).reshape(len(self.meshes), -1),
                "tip_thickness_mm": np.asarray(s).reshape(len(self.gears), -1)}


def candidate_model(train: GearTrain, teeth: Mapping[str, int], *, min_contact_ratio: float = 1.2,
                    min_tip_thickness_ratio: float = 0.2, iso_tr_4467_limits: bool = True,
                    min_backlash_mm: float | None = 0.0) -> CandidateModel:
    """Build the :class:`CandidateModel` of ``train`` with ``teeth`` (gear -> z): the train is propagated from a
    symbolic root shift (:class:`GearTrain`), every mesh's :meth:`GearPair.constraints` become named margins
    (per-gear limits once per gear, from the first mesh that holds the gear)."""
    x = nm.symbol("root_profile_shift")
    tr = _train_with_teeth(train, teeth, x)
    names, exprs, eps, seen = [], [], [], set()
    tips: dict[str, Any] = {}
    for mesh_name, pair in tr.pairs.items():
        cons = pair.constraints(min_tip_thickness_ratio=min_tip_thickness_ratio, min_contact_ratio=min_contact_ratio,
                                worst_case=True, iso_tr_4467_limits=iso_tr_4467_limits,
                                min_backlash_mm=min_backlash_mm)
        geo = pair.geometry()
        for i, gear in enumerate(pair.names):
            tips.setdefault(gear, geo["tip_thickness_mm"][i])
        for key, expr in cons.items():
            base, unit = (key[:-3], "_mm") if key.endswith("_mm") else (key, "")
            if base[-2:] in ("_1", "_2"):
                gear = pair.names[int(base[-1]) - 1]
                stem = base[:-2]
                if stem in _PER_GEAR_CONSTRAINTS:
                    name = f"{gear}:{stem}{unit}"
                    if name in seen:
                        continue
                else:
                    name = f"{mesh_name}:{stem}_{gear}{unit}"
            else:
                name = f"{mesh_name}:{key}"
            seen.add(name)
            names.append(name)
            exprs.append(expr)
        eps.append(geo["worst_case_transverse_contact_ratio"])
    gears = tuple(train.gears)
    f = nm.function("tooth_count_candidate", [x],
                    [nm.vertcat(*exprs), nm.vertcat(*eps), nm.vertcat(*[tips[g] for g in gears])],
                    ["root_profile_shift"], ["margins", "worst_case_contact_ratio", "tip_thickness_mm"])
    return CandidateModel(function=f, margin_names=tuple(names), meshes=tuple(tr.pairs), gears=gears)
