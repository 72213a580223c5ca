"""Minimum-inertia webbed gear blank: an Ipopt NLP (through :class:`~gearopt.design.Problem`) over web thickness,
rim thickness and web pocket fraction.

Models: :class:`gearopt.blank.GearBlank` (closed-form mass and inertia: teeth, rim, web less pockets, hub) and
:mod:`gearopt.blank.web` (web shear from torque and in-plane tooth force, annular-plate bending from the axial force,
von Mises, modified Goodman / equivalent fully reversed stress). Thesis sec. 3.10 / 4.6: webs and pockets cut the
"dead" inertia of the large cam and fuel-pump gears while the web must keep a fatigue margin.

Variables: ``web_thickness_mm`` t_w, ``rim_thickness_mm`` t_R (below the root), ``pocket_area_fraction`` f (of the
web annulus), each within bounds. Objective: ``GearBlank(...).inertia_kgm2()``. Constraints:

* rim backup ratio t_R / h_t >= ``min_backup_ratio`` (1.2: the AGMA rim-thickness-factor threshold; Bibel et al.
  1994 quote 1.3 for solid-gear-like root stress, see :mod:`gearopt.blank.blank`);
* web fatigue: for every demand, the equivalent fully reversed stress (Goodman) of the forward, reverse and
  forward-reverse cases <= endurance limit / ``min_fatigue_margin`` -- at the hub junction and at the pocket pitch
  circle *separately* (the model's ``max`` of the two shear stresses is split into two constraints, an exact
  epigraph; the two are equivalent because forward and reverse loads are proportional, ``reverse_factor``);
* optional: peak von Mises <= yield / ``min_yield_margin``; inertia >= ``min_inertia_kgm2``;
* web radial length ``(d_f - 2 t_R - D_hub)/2 >= min_web_length_mm`` (a web must exist).

The web thickness upper bound is the smaller of face width and hub length (GearBlank's ordering).

Units: mm, N, N m, MPa, kg m^2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Sequence

import pandas as pd

from .. import numerics as nm
from ..blank.blank import GearBlank
from ..blank.catalogue import blank_from_data
from ..blank.web import web_fatigue, web_stress
from ..data import System, material_record, system_of
from ..errors import GearoptInputError
from ..validation import check_range
from ..geometry.train import GearTrain
from ..joints.walk_off import walk_off
from ..nlp.problem import Problem
from ..nlp.result import ProblemResult

CASES = ("forward", "reverse", "forward_reverse")
LOCATIONS = ("hub", "pocket")


@dataclass(frozen=True)
class BlankSpec:
    """Fixed part of a webbed blank (units in the names) with its material strengths and the present web design
    (``web_thickness_mm``, ``rim_thickness_mm``, ``pocket_area_fraction``; optional, for comparison and start)."""

    tip_diameter_mm: float
    root_diameter_mm: float
    face_width_mm: float
    bore_diameter_mm: float
    hub_outer_diameter_mm: float
    hub_length_mm: float
    endurance_limit_MPa: float
    ultimate_strength_MPa: float
    yield_strength_MPa: float
    density_kg_m3: float = 7850.0
    tooth_fill_factor: float = 0.5
    poisson_ratio: float = 0.3
    web_thickness_mm: float | None = None
    rim_thickness_mm: float | None = None
    pocket_area_fraction: float = 0.0
    name: str = "gear"

    def __post_init__(self):
        check_range("root_diameter_mm", self.root_diameter_mm, self.hub_outer_diameter_mm, self.tip_diameter_mm,
                    low_inclusive=False, high_inclusive=False, unit="mm")
        check_range("hub_outer_diameter_mm", self.hub_outer_diameter_mm, self.bore_diameter_mm, None,
                    low_inclusive=False, unit="mm")
        check_range("face_width_mm", self.face_width_mm, 0.0, None, low_inclusive=False, unit="mm")
        check_range("hub_length_mm", self.hub_length_mm, 0.0, None, low_inclusive=False, unit="mm")
        for key in ("endurance_limit_MPa", "ultimate_strength_MPa", "yield_strength_MPa"):
            check_range(key, getattr(self, key), 0.0, None, low_inclusive=False, unit="MPa")

    @property
    def whole_depth_mm(self) -> float:
        return 0.5 * (self.tip_diameter_mm - self.root_diameter_mm)

    def blank(self, web_thickness_mm, rim_thickness_mm, pocket_area_fraction) -> GearBlank:
        """The :class:`GearBlank` of a web design (arguments may be CasADi symbols)."""
        return GearBlank(self.tip_diameter_mm, self.root_diameter_mm, self.face_width_mm, self.bore_diameter_mm,
                         hub_outer_diameter_mm=self.hub_outer_diameter_mm, hub_length_mm=self.hub_length_mm,
                         web_thickness_mm=web_thickness_mm, rim_thickness_mm=rim_thickness_mm,
                         pocket_area_fraction=pocket_area_fraction, density_kg_m3=self.density_kg_m3,
                         tooth_fill_factor=self.tooth_fill_factor)

    @classmethod
    def from_data(cls, system: System, train: GearTrain, gear: str) -> "BlankSpec":
        """The webbed blank of ``gear`` (:func:`gearopt.blank.blank_from_data`) with its material
        (``system.materials`` of ``system.gear(gear).material``). ``system``: the :class:`~gearopt.data.System` of
        the data file."""
        system = system_of(system, "BlankSpec.from_data")
        blank, _ = blank_from_data(system, train, gear)
        if blank.web_thickness_mm is None:
            raise GearoptInputError(f"gear {gear!r} has a solid blank: nothing to size (limit: a webbed or recessed "
                                    f"blank)")
        mat = material_record(system, system.gear(gear).material, "BlankSpec.from_data", f"gears.{gear}.material")
        return cls(tip_diameter_mm=float(blank.tip_diameter_mm), root_diameter_mm=float(blank.root_diameter_mm),
                   face_width_mm=float(blank.face_width_mm), bore_diameter_mm=float(blank.bore_diameter_mm),
                   hub_outer_diameter_mm=float(blank.hub_outer_diameter_mm), hub_length_mm=float(blank.hub_length_mm),
                   endurance_limit_MPa=mat["endurance_limit_MPa"], ultimate_strength_MPa=mat["tensile_strength_MPa"],
                   yield_strength_MPa=mat["yield_strength_MPa"], density_kg_m3=float(blank.density_kg_m3),
                   tooth_fill_factor=float(blank.tooth_fill_factor), poisson_ratio=mat.get("poisson_ratio", 0.3),
                   web_thickness_mm=float(blank.web_thickness_mm), rim_thickness_mm=float(blank.rim_thickness_mm),
                   pocket_area_fraction=float(blank.pocket_area_fraction), name=gear)


@dataclass(frozen=True)
class WebDemand:
    """Web loads at the forward peak: torque through the web [N m], in-plane tooth-force resultant [N], net axial
    tooth force [N]; ``reverse_factor`` = reverse peak / forward peak (1: fully reversed, 0: forward only)."""

    torque_Nm: float
    in_plane_force_N: float = 0.0
    axial_force_N: float = 0.0
    reverse_factor: float = 1.0
    name: str = "demand"

    def __post_init__(self):
        for key in ("torque_Nm", "in_plane_force_N", "axial_force_N"):
            if not math.isfinite(float(getattr(self, key))):
                raise GearoptInputError(f"{key}={getattr(self, key)!r} of web demand {self.name!r} must be finite")
        check_range("reverse_factor", self.reverse_factor, 0.0, 10.0)
        if self.torque_Nm == 0.0 and self.in_plane_force_N == 0.0 and self.axial_force_N == 0.0:
            raise GearoptInputError(f"web demand {self.name!r} has no load (limit: at least one nonzero load)")


def web_demand_from_loads(system: System, train: GearTrain, gear: str, torques_Nm: dict | None = None, *,
                          reverse_factor: float = 1.0, root_rotation: str = "cw", name: str = "design") -> WebDemand:
    """Web loads of ``gear`` under per-mesh torques (default the data's design torques, ``[meshes.<name>]
    design_torque_Nm``: torque on each mesh's driving gear), as the main job's web table takes them: joint torque (:func:`gearopt.joints.walk_off`), the
    in-plane force bounded by the sum of the transverse mesh-force magnitudes F_t / cos(alpha_wt), the net axial
    force. ``system``: the :class:`~gearopt.data.System` of the data file (read only for its design torques when
    ``torques_Nm`` is None)."""
    system = system_of(system, "web_demand_from_loads")
    if torques_Nm is None:
        torques_Nm = system.design_torques_Nm()
        if not torques_Nm:
            raise GearoptInputError("the data state no design torque ([meshes.<name>] design_torque_Nm); pass "
                                    "torques_Nm")
    res = walk_off(train, torques_Nm, root_rotation=root_rotation)
    if gear not in res.joint_torque_Nm:
        raise GearoptInputError(f"gear={gear!r} is not a gear of the train ({list(train.gears)})")
    force = 0.0
    for row in res.contributions:
        if row["gear"] == gear:
            alpha = float(train.pairs[row["mesh"]].geometry()["working_pressure_angle_deg"])
            force += abs(float(row["tangential_force_N"])) / math.cos(math.radians(alpha))
    return WebDemand(torque_Nm=abs(float(res.joint_torque_Nm[gear])), in_plane_force_N=force,
                     axial_force_N=abs(float(res.axial_force_N[gear])), reverse_factor=reverse_factor, name=name)


def blank_sizing_expressions(spec: BlankSpec, web_thickness_mm, rim_thickness_mm, pocket_area_fraction,
                             demand: WebDemand, *, stress_concentration: float = 1.0) -> dict:
    """Inertia, backup ratio and web fatigue of a web design at one demand (dual-typed).

    Returns ``inertia_kgm2``, ``mass_kg``, ``backup_ratio``, ``web_length_mm`` (radial), per location
    (``hub``, ``pocket``) ``von_mises_<loc>_MPa`` at the forward peak and per case ``efr_<case>_<loc>_MPa`` and
    ``peak_<case>_<loc>_MPa``; numeric input adds ``fatigue_margin`` (endurance / largest EFR) and
    ``yield_margin`` (yield / largest peak).
    """
    blank = spec.blank(web_thickness_mm, rim_thickness_mm, pocket_area_fraction)
    d_r = blank.rim_inner_diameter_mm
    s = web_stress(demand.torque_Nm, hub_outer_diameter_mm=spec.hub_outer_diameter_mm, rim_inner_diameter_mm=d_r,
                   web_thickness_mm=web_thickness_mm, in_plane_force_N=demand.in_plane_force_N,
                   axial_force_N=demand.axial_force_N, nu=spec.poisson_ratio,
                   pocket_area_fraction=pocket_area_fraction, stress_concentration=stress_concentration)
    tau = {"hub": s["shear_torsion_hub_MPa"] + s["shear_force_hub_MPa"], "pocket": s["shear_pocket_MPa"]}
    out = {"inertia_kgm2": blank.inertia_kgm2(), "mass_kg": blank.mass_kg(), "backup_ratio": blank.backup_ratio,
           "web_length_mm": 0.5 * (d_r - spec.hub_outer_diameter_mm)}
    efrs, peaks = [], []
    for loc in LOCATIONS:
        vm = nm.sqrt(s["bending_MPa"] ** 2 + 3.0 * tau[loc] ** 2)
        out[f"von_mises_{loc}_MPa"] = vm
        fat = web_fatigue(vm, demand.reverse_factor * vm, endurance_limit_MPa=spec.endurance_limit_MPa,
                          ultimate_strength_MPa=spec.ultimate_strength_MPa)
        for case in CASES:
            out[f"efr_{case}_{loc}_MPa"] = fat[case]["efr_MPa"]
            out[f"peak_{case}_{loc}_MPa"] = fat[case]["max_MPa"]
            efrs.append(fat[case]["efr_MPa"])
            peaks.append(fat[case]["max_MPa"])
    if nm.is_numeric(*efrs):
        out["fatigue_margin"] = spec.endurance_limit_MPa / max(float(nm.value(e)) for e in efrs)
        out["yield_margin"] = spec.yield_strength_MPa / max(float(nm.value(p)) for p in peaks)
    return out


@dataclass
class BlankSizing:
    """Result of :func:`size_blank`: ``values`` (web_thickness_mm, rim_thickness_mm, pocket_area_fraction,
    inertia_kgm2, solid/present inertia for comparison), ``margins`` (one row per demand, re-evaluated
    numerically with :func:`blank_sizing_expressions`), ``blank`` (the optimal :class:`GearBlank`), ``solve``."""

    gear: str
    values: dict
    margins: pd.DataFrame
    blank: GearBlank
    solve: ProblemResult

    @property
    def active_constraints(self) -> list[str]:
        c = self.solve.constraints
        return [str(n) for n in c.loc[c["active"], "name"]]

    @property
    def at_bound(self) -> dict[str, str]:
        """{variable: "lower"|"upper"} for the variables at one of their bounds."""
        v = self.solve.variables
        out = {}
        for _, row in v[v["at_bound"]].iterrows():
            lo, hi, x = float(row["lower"]), float(row["upper"]), float(row["value"])
            out[str(row["name"])] = "lower" if abs(x - lo) <= abs(hi - x) else "upper"
        return out


def size_blank(spec: BlankSpec, demands: WebDemand | Sequence[WebDemand] = (), *, min_fatigue_margin: float | None
               = 1.5, min_backup_ratio: float = 1.2, min_yield_margin: float | None = None,
               min_inertia_kgm2: float | None = None, stress_concentration: float = 1.0,
               web_thickness_bounds_mm: tuple[float, float] | None = None,
               rim_thickness_bounds_mm: tuple[float, float] | None = None,
               pocket_fraction_bounds: tuple[float, float] = (0.0, 0.6), min_web_length_mm: float = 5.0,
               verbose: bool = False, **ipopt: Any) -> BlankSizing:
    """Minimum-inertia web design (module docstring).

    Args:
        spec: the fixed blank and material (:meth:`BlankSpec.from_data`).
        demands: web loads (:class:`WebDemand`, :func:`web_demand_from_loads`); empty: no fatigue constraint.
        min_fatigue_margin: endurance / EFR lower limit at every demand, case and location (None: no fatigue
            constraint).
        min_backup_ratio: rim backup ratio lower limit.
        min_yield_margin: yield / peak von Mises lower limit (None: not imposed).
        min_inertia_kgm2: optional inertia floor (e.g. to keep a flywheel effect).
        stress_concentration: K_t at the pockets.
        web_thickness_bounds_mm: default (0.2 x face width, min(face width, hub length)); the lower default is a
            stiffness/manufacturing rule of thumb [E] -- the web model has no bending stiffness or buckling check.
        rim_thickness_bounds_mm: default (0.5 h_t, room for ``min_web_length_mm`` of web).
        pocket_fraction_bounds: pocket area fraction bounds (GearBlank allows up to 0.8).
    """
    if isinstance(demands, WebDemand):
        demands = (demands,)
    demands = tuple(demands)
    if not all(isinstance(x, WebDemand) for x in demands):
        raise GearoptInputError("demands must be WebDemand instances")
    if min_fatigue_margin is not None:
        check_range("min_fatigue_margin", min_fatigue_margin, 0.5, 100.0)
        if not demands:
            raise GearoptInputError("min_fatigue_margin needs at least one WebDemand (or pass min_fatigue_margin=None)")
    check_range("min_backup_ratio", min_backup_ratio, 0.0, 10.0)
    check_range("min_web_length_mm", min_web_length_mm, 0.0, None, unit="mm")
    h_t = spec.whole_depth_mm
    t_hi_max = min(spec.face_width_mm, spec.hub_length_mm)
    t_lo, t_hi = web_thickness_bounds_mm or (0.2 * spec.face_width_mm, t_hi_max)
    check_range("web_thickness upper bound", t_hi, t_lo, t_hi_max, low_inclusive=False, unit="mm")
    room = 0.5 * (spec.root_diameter_mm - spec.hub_outer_diameter_mm) - min_web_length_mm
    r_lo, r_hi = rim_thickness_bounds_mm or (0.5 * h_t, room)
    check_range("rim_thickness upper bound", r_hi, r_lo, None, low_inclusive=False, unit="mm")
    check_range("rim_thickness lower bound", r_lo, 0.0, None, low_inclusive=False, unit="mm")
    f_lo, f_hi = pocket_fraction_bounds
    check_range("pocket_fraction upper bound", f_hi, f_lo, 0.8, unit="")
    check_range("pocket_fraction lower bound", f_lo, 0.0, None, unit="")

    def clip(v, lo, hi):
        return min(max(v, lo), hi)

    p = Problem(name=f"blank sizing {spec.name}")
    t0 = clip(spec.web_thickness_mm or 0.5 * (t_lo + t_hi), t_lo, t_hi)
    r0 = clip(spec.rim_thickness_mm or max(min_backup_ratio * h_t, r_lo), r_lo, r_hi)
    f0 = clip(spec.pocket_area_fraction, f_lo, f_hi)
    t = p.variable("web_thickness_mm", init=t0, lower=t_lo, upper=t_hi, scale=t0, unit="mm")
    r = p.variable("rim_thickness_mm", init=r0, lower=r_lo, upper=r_hi, scale=r0, unit="mm")
    f = p.variable("pocket_area_fraction", init=f0, lower=f_lo, upper=f_hi, scale=0.5)
    solid_j = float(spec.blank(t0, r0, 0.0).solid_equivalent().inertia_kgm2())
    geo = blank_sizing_expressions(spec, t, r, f, demands[0] if demands else WebDemand(1.0),
                                   stress_concentration=stress_concentration)
    p.subject_to("backup_ratio", geo["backup_ratio"], lower=min_backup_ratio)
    p.subject_to("web_length_mm", geo["web_length_mm"], lower=min_web_length_mm, scale=10.0, unit="mm")
    if min_inertia_kgm2 is not None:
        p.subject_to("inertia_floor_kgm2", geo["inertia_kgm2"], lower=min_inertia_kgm2, scale=solid_j, unit="kg m^2")
    for x in demands:
        e = blank_sizing_expressions(spec, t, r, f, x, stress_concentration=stress_concentration)
        for loc in LOCATIONS:
            for case in CASES:
                if min_fatigue_margin is not None:
                    lim = spec.endurance_limit_MPa / min_fatigue_margin
                    p.subject_to(f"{x.name}:efr_{case}_{loc}_MPa", e[f"efr_{case}_{loc}_MPa"], upper=lim, scale=lim,
                                 unit="MPa")
            if min_yield_margin is not None:
                lim = spec.yield_strength_MPa / min_yield_margin
                peak = e[f"peak_forward_reverse_{loc}_MPa"]
                p.subject_to(f"{x.name}:peak_{loc}_MPa", peak, upper=lim, scale=lim, unit="MPa")
    p.minimize(geo["inertia_kgm2"], scale=solid_j)
    res = p.solve(verbose=verbose, **ipopt)

    tv, rv, fv = (float(res.values[k]) for k in ("web_thickness_mm", "rim_thickness_mm", "pocket_area_fraction"))
    best = spec.blank(tv, rv, fv)
    vals = {"web_thickness_mm": tv, "rim_thickness_mm": rv, "pocket_area_fraction": fv,
            "inertia_kgm2": float(best.inertia_kgm2()), "mass_kg": float(best.mass_kg()),
            "backup_ratio": float(best.backup_ratio), "solid_inertia_kgm2": solid_j}
    if spec.web_thickness_mm is not None and spec.rim_thickness_mm is not None:
        present = spec.blank(spec.web_thickness_mm, spec.rim_thickness_mm, spec.pocket_area_fraction)
        vals["present_inertia_kgm2"] = float(present.inertia_kgm2())
    rows = []
    for x in demands:
        e = blank_sizing_expressions(spec, tv, rv, fv, x, stress_concentration=stress_concentration)
        rows.append({"demand": x.name, "torque_Nm": x.torque_Nm, "in_plane_force_N": x.in_plane_force_N,
                     "axial_force_N": x.axial_force_N, "reverse_factor": x.reverse_factor,
                     **{k: float(nm.value(v)) for k, v in e.items()}})
    margins = pd.DataFrame(rows).set_index("demand") if rows else pd.DataFrame()
    return BlankSizing(gear=spec.name, values=vals, margins=margins, blank=best, solve=res)


__all__ = ["BlankSpec", "WebDemand", "BlankSizing", "web_demand_from_loads", "blank_sizing_expressions", "size_blank",
           "CASES", "LOCATIONS"]
