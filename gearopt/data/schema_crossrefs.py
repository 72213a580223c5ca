"""Cross-references between the sections of a data file: mesh gears, the root mesh and gear of each train, gear
materials and joint gears exist; a mesh is named ``<driving>-<driven>``; lower allowances do not exceed upper ones;
the firing order is a permutation of the cylinders; station lists match their counts."""

from __future__ import annotations

import difflib

def cross_checks(data: dict, problems: list[str]) -> None:
    """Append one line per broken cross-reference of ``data`` (a file whose keys passed the schema) to
    ``problems``."""
    gears, meshes = data.get("gears", {}), data.get("meshes", {})
    for name, m in meshes.items():
        pair = m.get("gears", [])
        for g in pair:
            if g not in gears:
                problems.append(f"meshes.{name}.gears: {g!r} is not a key of gears ({', '.join(gears)})")
        if len(pair) == 2 and pair[0] == pair[1]:
            problems.append(f"meshes.{name}.gears: a gear cannot mesh with itself ({pair[0]!r})")
        if len(pair) == 2 and name != f"{pair[0]}-{pair[1]}":
            problems.append(f"meshes.{name}: the table name must be '<driving>-<driven>' = '{pair[0]}-{pair[1]}'")
        _ordered(m, "centre_distance_lower_allowance_mm", "centre_distance_upper_allowance_mm", f"meshes.{name}",
                 problems)
    for kind, t in data.get("trains", {}).items():
        if t.get("root_mesh") not in meshes:
            near = difflib.get_close_matches(str(t.get("root_mesh")), list(meshes), n=1)
            problems.append(f"trains.{kind}.root_mesh: {t.get('root_mesh')!r} is not a key of meshes"
                            + (f"; did you mean {near[0]!r}?" if near else ""))
        elif t.get("root_gear") not in meshes[t["root_mesh"]].get("gears", []):
            problems.append(f"trains.{kind}.root_gear: {t.get('root_gear')!r} is not a gear of the root mesh "
                            f"{t['root_mesh']!r}")
    materials = data.get("materials")
    for name, g in gears.items():
        _ordered(g, "tooth_thickness_lower_allowance_um", "tooth_thickness_upper_allowance_um", f"gears.{name}",
                 problems)
        _ordered(g, "tip_diameter_lower_allowance_mm", "tip_diameter_upper_allowance_mm", f"gears.{name}", problems)
        if materials is not None and "material" in g and g["material"] not in materials:
            problems.append(f"gears.{name}.material: {g['material']!r} is not a key of materials "
                            f"({', '.join(materials)})")
    for name, j in data.get("joints", {}).items():
        if "gear" in j and j["gear"] not in gears:
            problems.append(f"joints.{name}.gear: {j['gear']!r} is not a key of gears")
    exc = data.get("excitation", {})
    if "gear" in exc and exc["gear"] not in gears:
        problems.append(f"excitation.gear: {exc['gear']!r} is not a key of gears ({', '.join(gears)})")
    lengths = {k: len(exc[k]) for k in ("harmonic_orders", "harmonic_amplitudes_Nm", "harmonic_phases_deg")
               if k in exc}
    if len(set(lengths.values())) > 1:
        problems.append(f"excitation: the harmonic lists must have one entry per harmonic (lengths {lengths})")
    engine = data.get("engine", {})
    if "firing_order" in engine and "cylinders" in engine:
        if sorted(engine["firing_order"]) != list(range(1, engine["cylinders"] + 1)):
            problems.append(f"engine.firing_order: {engine['firing_order']} is not a permutation of 1.."
                            f"{engine['cylinders']} (engine.cylinders)")
    cam = engine.get("camshaft", {})
    if "stations" in cam:
        n = cam["stations"]
        for key, want in (("station_inertias_kgm2", n), ("station_stiffnesses_Nm_per_rad", n - 1)):
            if key in cam and len(cam[key]) != want:
                problems.append(f"engine.camshaft.{key}: has {len(cam[key])} entries; engine.camshaft.stations = "
                                f"{n} needs {want}")
    crank = engine.get("crankshaft", {})
    if "node_names" in crank:
        n = len(crank["node_names"])
        for key, want in (("inertias_kgm2", n), ("connection_stiffnesses_Nm_per_rad", n - 1)):
            if key in crank and len(crank[key]) != want:
                problems.append(f"engine.crankshaft.{key}: has {len(crank[key])} entries; "
                                f"engine.crankshaft.node_names has {n} nodes, which need {want}")
    trace = (engine.get("pressure_trace_crank_deg"), engine.get("pressure_trace_MPa"))
    if trace[0] is not None and trace[1] is not None and len(trace[0]) != len(trace[1]):
        problems.append(f"engine.pressure_trace_MPa: has {len(trace[1])} entries; engine.pressure_trace_crank_deg "
                        f"has {len(trace[0])}")


def _ordered(table: dict, low_key: str, high_key: str, path: str, problems: list[str]) -> None:
    if low_key in table and high_key in table and table[low_key] > table[high_key]:
        problems.append(f"{path}.{low_key}: {table[low_key]!r} exceeds {high_key} = {table[high_key]!r}")
