"""Gear blanks of a data set of the default schema (``[gears.*]``, ``[joints.*]``) on the geometry of a train.

Bore and hub come from the gear's joint: press fits -- bore = shaft diameter, hub = the joint's hub outer diameter
over the fit length; taper joints -- bore = large taper diameter, hub over the taper length. Webbed/recessed gears
(``blank = "webbed"|"recessed"``) use ``web_thickness_mm``, ``rim_thickness_mm`` and ``web_pocket_area_fraction``
when the data give them; a missing web thickness defaults to 12 mm and a missing rim thickness to 3.5 m_n (the
values the default data's [C] inertia notes use for the AC gear), reported in ``assumed``.
"""

from __future__ import annotations

from ..data import System, system_of
from ..errors import GearoptInputError
from ..geometry.train import GearTrain
from .blank import GearBlank

DEFAULT_WEB_THICKNESS_MM = 12.0
DEFAULT_RIM_THICKNESS_MODULES = 3.5


def blank_from_data(system: System, train: GearTrain, gear: str) -> tuple[GearBlank, list[str]]:
    """The :class:`GearBlank` of one gear of ``system`` (``system.gear(gear).entries``, bore and hub from
    ``system.joint_of(gear)``, density from its ``system.materials`` entry; tip/root diameters from ``train``) and
    the list of assumed inputs. ``system``: the :class:`~gearopt.data.System` of the data file."""
    system = system_of(system, "blank_from_data")
    if gear not in system.gears:
        raise GearoptInputError(f"gear={gear!r} is not in [gears] ({sorted(system.gears)})")
    if gear not in train.gears:
        raise GearoptInputError(f"gear={gear!r} is not a gear of the train ({list(train.gears)})")
    g = system.gear(gear).entries
    table = train.gear_table()
    d_a, d_f = float(table.loc[gear, "tip_diameter_mm"]), float(table.loc[gear, "root_diameter_mm"])
    rho = system.materials[g["material"]]["density_kg_m3"] if g.get("material") in system.materials else 7850.0
    joint = system.joint_of(gear)
    j = joint.entries if joint is not None else None
    assumed = []
    if j is None:
        raise GearoptInputError(f"gear {gear!r} has no [joints.*] entry: its bore and hub are unknown")
    if j["joint_type"] == "press_fit":
        bore, hub_d, hub_l = j["shaft_diameter_mm"], j["hub_outer_diameter_mm"], j["fit_length_mm"]
    else:
        bore, hub_d, hub_l = j["taper_large_diameter_mm"], j["hub_outer_diameter_mm"], j["taper_length_mm"]
    b = g["face_width_mm"]
    kind = g.get("blank", "solid")
    if kind == "solid":  # the hub is known from the joint: a design that frees the web makes the blank webbed
        return GearBlank(d_a, d_f, b, bore, density_kg_m3=rho, hub_outer_diameter_mm=hub_d,
                         hub_length_mm=hub_l), assumed
    if kind not in ("webbed", "recessed"):
        raise GearoptInputError(f"[gears.{gear}] blank={kind!r} must be 'solid', 'webbed' or 'recessed'")
    t = g.get("web_thickness_mm")
    if t is None:
        t = DEFAULT_WEB_THICKNESS_MM
        assumed.append(f"web_thickness_mm={t:g}")
    t_r = g.get("rim_thickness_mm")
    if t_r is None:
        t_r = DEFAULT_RIM_THICKNESS_MODULES * system.rack.module_mm
        assumed.append(f"rim_thickness_mm={t_r:g} (3.5 m_n)")
    blank = GearBlank(d_a, d_f, b, bore, hub_outer_diameter_mm=hub_d, hub_length_mm=max(hub_l, t),
                      web_thickness_mm=t, rim_thickness_mm=t_r,
                      pocket_area_fraction=g.get("web_pocket_area_fraction", 0.0), density_kg_m3=rho)
    return blank, assumed


__all__ = ["blank_from_data", "DEFAULT_WEB_THICKNESS_MM", "DEFAULT_RIM_THICKNESS_MODULES"]
