"""Entry points, valid baselines and bad values of the robustness contract (shared by ``tests/robustness`` and
``benchmarks/bench_robustness.py``; not a test module).

The contract every public entry point must keep (issue 18): for any input, either a :class:`GearoptInputError`
whose message names the spoiled parameter (or a typed :class:`GearoptError` such as a failed solve or a budget
hit), or a result whose numbers are all finite and plausible (``+inf`` only where documented). Never NaN, never an
untyped exception, never a hang.

Each :class:`EntryPoint` has a ``baseline`` of valid keyword arguments and a ``call(**kwargs)``; a case spoils one
or two of the arguments with a value from :data:`BAD_VALUES` (or a random float) and :func:`classify` sorts the
outcome into ``rejected`` / ``typed_failure`` / ``finite`` / ``untyped`` / ``nan`` / ``implausible``.
"""

from __future__ import annotations

import dataclasses
import math
import os
import re
import tempfile
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

import gearopt as go
from gearopt.errors import GearoptError, GearoptInputError, GeometryError

NAN, INF = float("nan"), float("inf")

#: Bad scalars mixed into the campaign: NaN, +-inf, zero, negatives, tiny and huge magnitudes, numeric and
#: non-numeric strings, None, bools, wrong-length tuples and non-integral counts.
BAD_VALUES: tuple = (NAN, INF, -INF, 0.0, -1.0, -1e-12, 1e-12, 1e12, -1e12, 1e300, -1e300, "3", "abc", None, True,
                     (1.0, 2.0, 3.0), (), 2.5, 0.5, 1.5, 4.0, 100.0)

OUTCOMES = ("rejected", "typed_failure", "finite", "untyped", "nan", "implausible", "hang")


# ----------------------------------------------------------------------------------------------------------------
# result inspection
# ----------------------------------------------------------------------------------------------------------------

def numbers_in(result, depth: int = 0):
    """Yield (path, float array) of every number in a result: dicts, tuples, dataclasses, DataFrames, objects with
    array attributes; public properties of result objects are evaluated too (a lazy NaN is still a NaN)."""
    if depth > 4 or result is None or isinstance(result, (str, bytes, bool, np.bool_)):
        return
    if isinstance(result, dict):
        for k, v in result.items():
            for p, a in numbers_in(v, depth + 1):
                yield f"{k}.{p}" if p else str(k), a
        return
    if isinstance(result, (tuple, list)):
        for i, v in enumerate(result):
            for p, a in numbers_in(v, depth + 1):
                yield f"[{i}]{p}", a
        return
    if isinstance(result, (int, float, np.integer, np.floating)):
        yield "", np.asarray(float(result))
        return
    if isinstance(result, np.ndarray):
        if result.dtype.kind in "iuf":
            yield "", result.astype(float)
        return
    try:
        import pandas as pd
        if isinstance(result, pd.DataFrame):
            num = result.select_dtypes("number")
            yield "", num.to_numpy(dtype=float)
            return
    except ImportError:  # pragma: no cover
        pass
    if dataclasses.is_dataclass(result):
        for f in dataclasses.fields(result):
            if f.name in ("layout", "pair", "network"):
                continue
            for p, a in numbers_in(getattr(result, f.name), depth + 1):
                yield f"{f.name}.{p}" if p else f.name, a
    for name in dir(type(result)):
        if name.startswith("_") or not isinstance(getattr(type(result), name, None), property):
            continue
        for p, a in numbers_in(getattr(result, name), depth + 1):
            yield f"{name}.{p}" if p else name, a


def classify(entry: "EntryPoint", kwargs: dict) -> tuple[str, str]:
    """(outcome, detail) of one call. ``detail`` is the error message or the offending quantity."""
    try:
        result = entry.call(**kwargs)
    except GearoptInputError as err:
        return "rejected", str(err)
    except GearoptError as err:
        return "typed_failure", str(err)
    except Exception as err:  # noqa: BLE001 - the campaign counts exactly these
        return "untyped", f"{type(err).__name__}: {err}"
    try:
        for path, arr in numbers_in(result):
            if np.isnan(arr).any():
                return "nan", path
            if np.isinf(arr).any() and not any(path.startswith(ok) for ok in entry.infinite_ok):
                return "nan", f"{path} (infinite)"
    except GearoptInputError as err:  # a lazy output that raises a named error is a rejection too
        return "rejected", str(err)
    except GearoptError as err:
        return "typed_failure", str(err)
    except Exception as err:  # noqa: BLE001
        return "untyped", f"{type(err).__name__} in a result property: {err}"
    problem = entry.implausible(result) if entry.implausible else None
    if problem:
        return "implausible", problem
    return "finite", ""


def names_parameter(message: str, spoiled: list[str]) -> bool:
    """True if a rejection message names one of the spoiled parameters (or its data path)."""
    low = message.lower()
    forms = set()
    for p in spoiled:
        name = p.lower().split(".")[-1].split("[")[0]
        forms |= {name, re.sub(r"_[12](?=_|$)", "", name), re.sub(r"^(mesh|shaft)_", "", name),
                  name.replace("_torque_nm", "").replace("_", "-")}  # walk_off: mesh_torques_Nm['crank-cam']
    return any(f in low for f in forms)


# ----------------------------------------------------------------------------------------------------------------
# entry points
# ----------------------------------------------------------------------------------------------------------------

@dataclass
class EntryPoint:
    name: str
    call: Callable[..., Any]
    baseline: dict
    spoilable: tuple[str, ...]
    infinite_ok: tuple[str, ...] = ()
    implausible: Callable[[Any], str | None] | None = None
    bad_values: tuple = BAD_VALUES
    array_ok: tuple[str, ...] = ()  # arguments for which a tuple is a valid value (vector variables ...)
    extra_cases: Callable[[np.random.Generator], dict] | None = field(default=None, repr=False)


PAIR_BASE = dict(teeth=(38, 76), module_mm=3.0, profile_shifts=(0.3124, 0.1118), pressure_angle_deg=20.0,
                 helix_angle_deg=0.0, face_width_mm=20.0)
PAIR_KEYS = ("teeth", "module_mm", "profile_shifts", "pressure_angle_deg", "helix_angle_deg", "face_width_mm")


def _pair(teeth, module_mm, profile_shifts, pressure_angle_deg, helix_angle_deg, face_width_mm, **options):
    return go.GearPair.from_profile_shifts(teeth=teeth, profile_shifts=profile_shifts, module_mm=module_mm,
                                           pressure_angle_deg=pressure_angle_deg, helix_angle_deg=helix_angle_deg,
                                           face_width_mm=face_width_mm, **options)


def _split(kwargs):
    pair_kw = {k: kwargs.pop(k) for k in PAIR_KEYS}
    return _pair(**pair_kw), kwargs


def call_pair_geometry(**kw):
    names = kw.pop("names")
    tips = kw.pop("tip_diameters_mm")
    return _pair(**kw, names=names, tip_diameters_mm=tips).geometry()


def call_centre_distance(**kw):
    return go.GearPair.from_centre_distance(**kw).geometry()


def call_check(**kw):
    pair, limits = _split(kw)
    pair.check(**limits)
    return pair.constraints(**limits)


def call_ltca(**kw):
    pair, rest = _split(kw)
    res = go.ltca(pair, **rest)
    return {"ppte_um": res.ppte_um, "max_contact_stress_MPa": res.max_contact_stress_MPa,
            "max_root_stress_MPa": res.max_root_stress_MPa, "loaded_contact_ratio": res.loaded_contact_ratio,
            "max_flash_temperature_C": res.max_flash_temperature_C, "te": res.transmission_error_um}


def call_contact_rating(**kw):
    from gearopt.rating import contact_stress_iso6336
    pair, rest = _split(kw)
    return contact_stress_iso6336(pair, **rest)


def call_root_rating(**kw):
    from gearopt.rating import root_stress_iso6336
    pair, rest = _split(kw)
    return root_stress_iso6336(pair, **rest)


def _negative_safety(result) -> str | None:
    items = result.to_dict().items() if hasattr(result, "to_dict") else result.items()  # typed records, dicts
    for key, v in items:
        if "safety" in key:
            for x in np.atleast_1d(np.asarray(v, dtype=float)):
                if x <= 0:
                    return f"{key}={x:g} is not positive"
    return None


def call_ltca_model(**kw):
    from gearopt.contact.ltca_smooth import LTCAModel
    torque = kw.pop("torque_Nm")
    pair, rest = _split(kw)
    res = LTCAModel(pair, **rest).evaluate(torque_Nm=torque)
    return {"ppte_um": res.ppte_um, "max_contact_stress_MPa": res.max_contact_stress_MPa,
            "loaded_contact_ratio": res.loaded_contact_ratio}


def call_flash(**kw):
    from gearopt.rating import flash_temperature_blok_K
    return flash_temperature_blok_K(**kw)


def call_lewis(**kw):
    from gearopt.rating import lewis_bending_stress_MPa
    return lewis_bending_stress_MPa(**kw)


def call_bolt(**kw):
    from gearopt.joints import bolt_preload_N
    return bolt_preload_N(**kw)


def call_joint_margins(**kw):
    from gearopt.joints.walk_off import joint_margins
    return joint_margins(**kw)


def call_walk_off(*, kind, crank_cam_torque_Nm, cam_ac_torque_Nm, root_rotation):
    train = _default_train(kind)
    res = go.walk_off(train, {"crank-cam": crank_cam_torque_Nm, "cam-ac": cam_ac_torque_Nm},
                      root_rotation=root_rotation)
    return {k: v for k, v in vars(res).items() if not k.startswith("_")}


_TRAINS: dict = {}


def _default_train(kind):
    if kind not in _TRAINS:
        _TRAINS[kind] = go.load_default_train(kind) if kind in ("spur", "helical") else go.load_default_train(kind)
    return _TRAINS[kind]


def call_peak_pressure(**kw):
    from gearopt.engine import peak_pressure_bar
    kw.setdefault("load", 1.0)
    return peak_pressure_bar(system=go.load_system(), **kw)


def call_fit_interference(**kw):
    from gearopt.joints.iso286 import fit_interference_um
    return fit_interference_um(**kw)


def call_min_tip_relief(**kw):
    from gearopt.contact import min_tip_relief_um
    torque = kw.pop("torque_Nm")
    pair, rest = _split(kw)
    return min_tip_relief_um(pair, torque, **rest)


def call_web_stress(**kw):
    from gearopt.blank.web import web_stress
    return web_stress(**kw)


def call_blank(**kw):
    from gearopt.blank import GearBlank
    blank = GearBlank(**kw)
    return {"mass_kg": blank.mass_kg(), "inertia_kgm2": blank.inertia_kgm2(), "backup_ratio": blank.backup_ratio}


def call_lewis_form_factor(**kw):
    from gearopt.rating import lewis_form_factor
    return lewis_form_factor(**kw)


def call_excitation(*, speed_rpm, load, pressure, crank_angle_rad):
    from gearopt.engine import EngineExcitation
    exc = EngineExcitation.from_data(go.load_system(), speed_rpm=speed_rpm, load=load, pressure=pressure)
    return {"total_torque_Nm": exc.total_torque_Nm(crank_angle_rad, exc.speed_rpm * math.pi / 30.0),
            "mean_torque_Nm": exc.mean_torque_Nm()}


def call_stiffness(**kw):
    from gearopt.rating.stiffness import iso6336_stiffness   # module path: the baseline commit has it there too
    rest = {k: kw.pop(k) for k in ("line_load_N_per_mm", "E_MPa")}
    pair, _ = _split(kw)
    return iso6336_stiffness(pair, **rest)


def call_shift_split(**kw):
    from gearopt.design.shift_distribution import optimise_shift_split
    rest = {k: kw.pop(k) for k in ("min_contact_ratio", "min_tip_thickness_ratio", "shift_split")}
    pair, _ = _split(kw)
    out = optimise_shift_split(pair, **rest)
    return {k: v for k, v in out.items() if k not in ("status", "objective")}


def call_press_fit(**kw):
    return go.press_fit(**kw)


def _press_fit_plausible(r) -> str | None:
    if r.pressure_MPa < 0:
        return f"pressure_MPa={r.pressure_MPa:g} < 0"
    if r.release_speed_rpm < 0:
        return "release_speed_rpm < 0"
    return _negative_safety(r)


def call_taper_fit(**kw):
    return go.taper_fit(**kw)


def call_crank_torque(**kw):
    from gearopt.engine import crank_torque
    return crank_torque(**kw)


def call_simulate(*, inertia_1_kgm2, inertia_2_kgm2, mesh_stiffness_N_per_m, stiffness_variation, backlash_mm,
                  shaft_stiffness_Nm_per_rad, speed_rpm, cycles, teeth, base_radii_mm):
    from gearopt.dynamics import TorsionalNetwork
    from gearopt.dynamics.simulate import simulate
    net = TorsionalNetwork("robustness pair", cycle_deg=360.0)
    net.add_inertia("drive", 1.0).add_inertia("g1", inertia_1_kgm2).add_inertia("g2", inertia_2_kgm2)
    net.add_shaft("drive", "g1", shaft_stiffness_Nm_per_rad, 5.0)
    net.add_mesh("g1", "g2", base_radii_mm=base_radii_mm, teeth=teeth, stiffness_N_per_m=mesh_stiffness_N_per_m,
                 damping_N_s_per_m=2000.0, backlash_mm=backlash_mm, stiffness_variation=stiffness_variation)
    net.set_speed_boundary("drive")
    net.add_torque("g2", lambda t, a, w, T0: -T0, parameters={"T0": 50.0}, name="load")
    sim = simulate(net, speed_rpm, cycles)
    return sim.summary()


def call_problem(*, init, lower, upper, target, max_iter):
    from gearopt.nlp import Problem
    p = Problem("robustness")
    x = p.variable("x", init, lower=lower, upper=upper)
    a = p.parameter("target", target)
    p.subject_to("x_floor", x, lower=-10.0)
    p.minimize((x - a) ** 2)
    res = p.solve(max_iter=max_iter)
    return {"x": res.value("x") if hasattr(res, "value") else res.x["x"], "objective": res.objective}


def call_cli(*, argv):
    from gearopt.cli import main
    import contextlib
    import io
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(list(argv))
        except SystemExit as exc:  # argparse's own rejection (exit 2, usage message)
            code = exc.code
    text = out.getvalue()
    if code == 1 and "check: FAIL:" in text:  # the contract: a pair that fails its check exits 1, naming the limit
        raise GeometryError(text.split("check: FAIL:", 1)[1].strip()[:300])
    if code not in (0, 2):
        raise RuntimeError(f"exit code {code}")
    if code == 2:
        raise GearoptInputError(err.getvalue().strip()[-300:])
    if "nan" in text.split():
        return {"nan_printed": NAN}
    return {"exit": 0}


def call_data_file(*, content: bytes):
    from gearopt.data import load_default_data, train_from_data
    fd, path = tempfile.mkstemp(suffix=".toml")
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(content)
        data = load_default_data(path)
        train = train_from_data(data, "spur")
        return {"backlash": train.mesh_table().select_dtypes("number")}
    finally:
        os.unlink(path)


def call_data_value(*, path: str, value):
    from gearopt.data import load_default_data, train_from_data
    try:
        from gearopt.data import validate_data
    except ImportError:  # a gearopt without the data schema (the campaign's baseline): build the train directly
        def validate_data(data, source):
            return data
    data = load_default_data()
    node = data
    keys = path.split(".")
    for k in keys[:-1]:
        node = node[k]
    node[keys[-1]] = value
    validate_data(data, source="<spoiled>")
    train = train_from_data(data, "spur")
    return {"mesh_table": train.mesh_table().select_dtypes("number")}


def _default_toml() -> bytes:
    from gearopt.data import default_data_path
    return default_data_path().read_bytes()


def _data_file_bad_contents() -> tuple:
    good = _default_toml()
    return (b"", b"\xff\xfe\x00garbage", good[: len(good) // 2], good.replace(b"teeth = 38", b"teeth = 0"),
            good.replace(b"teeth = 38", b"teeth = 38.5"), good.replace(b"module_mm = 3.0", b"module_mm = nan"),
            good.replace(b"module_mm = 3.0", b'module_mm = "3.0"'), good.replace(b"[rack]", b"[rakc]"),
            good.replace(b"module_mm = 3.0", b"modulus_mm = 3.0"), b"[rack]\nmodule_mm = 3\n",
            good.replace(b"centre_distance_mm = 172", b"centre_distance_mm = inf #"), good + b"\n[rack]\n",
            bytes(range(256)), good.replace(b"tooth_thickness_lower_allowance_um = -",
                                            b"tooth_thickness_lower_allowance_um = nan #"))


DATA_PATHS = ("rack.module_mm", "rack.pressure_angle_deg", "rack.addendum_coefficient", "rack.dedendum_coefficient",
              "rack.root_radius_coefficient", "gears.crank.teeth", "gears.cam.teeth", "gears.crank.face_width_mm",
              "gears.cam.tooth_thickness_lower_allowance_um", "meshes.crank-cam.centre_distance_mm",
              "meshes.cam-ac.centre_distance_upper_allowance_mm", "trains.spur.helix_angle_deg",
              "trains.spur.root_profile_shift", "trains.spur.root_mesh", "trains.spur.root_gear",
              "meshes.crank-cam.gears", "schema_version")


def entry_points() -> dict[str, EntryPoint]:
    """The public entry points of the contract with their valid baselines."""
    pair_opts = dict(PAIR_BASE, names=("crank", "cam"), tip_diameters_mm=None)
    eps = [
        EntryPoint("GearPair.from_profile_shifts", call_pair_geometry, pair_opts, tuple(pair_opts)),
        EntryPoint("GearPair.from_centre_distance", call_centre_distance,
                   dict(teeth=(38, 76), centre_distance_mm=172.2406, module_mm=3.0, pressure_angle_deg=20.0,
                        helix_angle_deg=0.0, face_width_mm=20.0, shift_split=0.5, profile_shift1=0.3124),
                   ("teeth", "centre_distance_mm", "module_mm", "pressure_angle_deg", "helix_angle_deg",
                    "face_width_mm", "shift_split", "profile_shift1")),
        EntryPoint("GearPair.check", call_check,
                   dict(PAIR_BASE, min_contact_ratio=1.0, min_tip_thickness_ratio=0.2, min_backlash_mm=0.0),
                   PAIR_KEYS + ("min_contact_ratio", "min_tip_thickness_ratio", "min_backlash_mm")),
        EntryPoint("ltca", call_ltca,
                   dict(PAIR_BASE, torque_Nm=300.0, positions=64, slices=1, E_MPa=206000.0, poisson=0.3,
                        speed_rpm=2500.0, friction_coefficient=0.06, bulk_temperature_C=100.0, driving_gear=1),
                   PAIR_KEYS + ("torque_Nm", "positions", "slices", "E_MPa", "poisson", "speed_rpm",
                                "friction_coefficient", "bulk_temperature_C", "driving_gear")),
        EntryPoint("contact_stress_iso6336", call_contact_rating,
                   dict(PAIR_BASE, torque_Nm=300.0, K_A=1.25, K_v=1.1, life_factor=1.0, S_Hmin=1.0),
                   PAIR_KEYS + ("torque_Nm", "K_A", "K_v", "life_factor", "S_Hmin"), implausible=_negative_safety),
        EntryPoint("root_stress_iso6336", call_root_rating,
                   dict(PAIR_BASE, torque_Nm=300.0, K_A=1.25, K_v=1.1, life_factor=1.0, S_Fmin=1.0,
                        rim_backup_ratio=None),
                   PAIR_KEYS + ("torque_Nm", "K_A", "K_v", "life_factor", "S_Fmin", "rim_backup_ratio"),
                   implausible=_negative_safety),
        EntryPoint("LTCAModel", call_ltca_model,
                   dict(PAIR_BASE, torque_Nm=300.0, positions=24, slices=1, E_MPa=206000.0, poisson=0.3,
                        smoothing_um=0.05, driving_gear=1),
                   PAIR_KEYS + ("torque_Nm", "positions", "slices", "E_MPa", "poisson", "smoothing_um",
                                "driving_gear")),
        EntryPoint("flash_temperature_blok_K", call_flash,
                   dict(load_N_per_mm=200.0, half_width_mm=0.2, v1_m_s=10.0, v2_m_s=8.0, friction=0.06,
                        B_M1=13.44, B_M2=13.44),
                   ("load_N_per_mm", "half_width_mm", "v1_m_s", "v2_m_s", "friction", "B_M1", "B_M2")),
        EntryPoint("lewis_bending_stress_MPa", call_lewis,
                   dict(tangential_force_N=5000.0, face_width_mm=25.0, module_mm=3.0, form_factor=0.38,
                        dynamic_factor=1.2),
                   ("tangential_force_N", "face_width_mm", "module_mm", "form_factor", "dynamic_factor")),
        EntryPoint("bolt_preload_N", call_bolt, dict(nut_torque_Nm=150.0, nut_factor=0.15, thread_diameter_mm=16.0),
                   ("nut_torque_Nm", "nut_factor", "thread_diameter_mm")),
        EntryPoint("joint_margins", call_joint_margins,
                   dict(joint_type="press_fit", torque_Nm=300.0, axial_force_N=2000.0, torque_capacity_Nm=800.0,
                        axial_capacity_N=40000.0),
                   ("joint_type", "torque_Nm", "axial_force_N", "torque_capacity_Nm", "axial_capacity_N"),
                   infinite_ok=("torque_margin", "axial_margin", "combined_margin", "slip_utilisation")),
        EntryPoint("walk_off", call_walk_off,
                   dict(kind="helical", crank_cam_torque_Nm=300.0, cam_ac_torque_Nm=240.0, root_rotation="cw"),
                   ("kind", "crank_cam_torque_Nm", "cam_ac_torque_Nm", "root_rotation"),
                   infinite_ok=("margins",)),
        EntryPoint("peak_pressure_bar", call_peak_pressure, dict(speed_rpm=2500.0, load=1.0), ("speed_rpm", "load")),
        EntryPoint("fit_interference_um", call_fit_interference, dict(nominal_mm=42.0, fit="H7/u6"),
                   ("nominal_mm", "fit"), bad_values=BAD_VALUES + ("H7", "u6/H7", "H7/zz9", "H99/u6")),
        EntryPoint("min_tip_relief_um", call_min_tip_relief,
                   dict(PAIR_BASE, torque_Nm=300.0, driving_gear=1, E_MPa=206000.0, poisson=0.3),
                   PAIR_KEYS + ("torque_Nm", "driving_gear", "E_MPa", "poisson")),
        EntryPoint("web_stress", call_web_stress,
                   dict(torque_Nm=300.0, hub_outer_diameter_mm=70.0, rim_inner_diameter_mm=200.0,
                        web_thickness_mm=10.0, in_plane_force_N=2000.0, axial_force_N=500.0, nu=0.3,
                        pocket_area_fraction=0.2, pocket_pitch_diameter_mm=135.0, stress_concentration=1.5),
                   ("torque_Nm", "hub_outer_diameter_mm", "rim_inner_diameter_mm", "web_thickness_mm",
                    "in_plane_force_N", "axial_force_N", "nu", "pocket_area_fraction", "pocket_pitch_diameter_mm",
                    "stress_concentration")),
        EntryPoint("GearBlank", call_blank,
                   dict(tip_diameter_mm=234.0, root_diameter_mm=220.0, face_width_mm=25.0, bore_diameter_mm=42.0,
                        hub_outer_diameter_mm=70.0, hub_length_mm=35.0, web_thickness_mm=10.0,
                        rim_thickness_mm=12.0, pocket_area_fraction=0.2),
                   ("tip_diameter_mm", "root_diameter_mm", "face_width_mm", "bore_diameter_mm",
                    "hub_outer_diameter_mm", "hub_length_mm", "web_thickness_mm", "rim_thickness_mm",
                    "pocket_area_fraction")),
        EntryPoint("lewis_form_factor", call_lewis_form_factor, dict(teeth=38), ("teeth",)),
        EntryPoint("EngineExcitation", call_excitation,
                   dict(speed_rpm=2500.0, load=1.0, pressure="table", crank_angle_rad=0.5),
                   ("speed_rpm", "load", "pressure", "crank_angle_rad")),
        EntryPoint("iso6336_stiffness", call_stiffness, dict(PAIR_BASE, line_load_N_per_mm=200.0, E_MPa=206000.0),
                   PAIR_KEYS + ("line_load_N_per_mm", "E_MPa")),
        EntryPoint("optimise_shift_split", call_shift_split,
                   dict(PAIR_BASE, min_contact_ratio=1.2, min_tip_thickness_ratio=0.2, shift_split=0.5),
                   PAIR_KEYS + ("min_contact_ratio", "min_tip_thickness_ratio", "shift_split")),
        EntryPoint("press_fit", call_press_fit,
                   dict(shaft_diameter_mm=42.0, shaft_bore_mm=0.0, hub_outer_diameter_mm=70.0, length_mm=25.0,
                        interference_um=65.5, shaft_E_MPa=210000.0, shaft_nu=0.3, hub_E_MPa=206000.0,
                        hub_nu=0.3, friction=0.12, speed_rpm=3000.0, shaft_temperature_C=90.0,
                        hub_temperature_C=100.0, shaft_yield_MPa=650.0, hub_yield_MPa=700.0),
                   ("shaft_diameter_mm", "shaft_bore_mm", "hub_outer_diameter_mm", "length_mm", "interference_um",
                    "shaft_E_MPa", "shaft_nu", "hub_E_MPa", "hub_nu", "friction", "speed_rpm",
                    "shaft_temperature_C", "hub_temperature_C", "shaft_yield_MPa", "hub_yield_MPa"),
                   infinite_ok=("release_speed_rpm", "hub_yield_safety", "shaft_yield_safety"),
                   implausible=_press_fit_plausible),
        EntryPoint("taper_fit", call_taper_fit,
                   dict(large_diameter_mm=30.0, small_diameter_mm=26.25, half_angle_deg=3.5763, friction=0.15,
                        nut_torque_Nm=150.0, nut_factor=0.15, thread_diameter_mm=16.0, hub_outer_diameter_mm=60.0,
                        hub_yield_MPa=700.0),
                   ("large_diameter_mm", "small_diameter_mm", "half_angle_deg", "friction", "nut_torque_Nm",
                    "nut_factor", "thread_diameter_mm", "hub_outer_diameter_mm", "hub_yield_MPa"),
                   infinite_ok=("hub_yield_safety",), implausible=_negative_safety),
        EntryPoint("crank_torque", call_crank_torque,
                   dict(crank_angle_deg=30.0, speed_rpm=2500.0, bore_mm=107.0, stroke_mm=124.0,
                        rod_length_mm=192.0, reciprocating_mass_kg=2.5, cylinder_pressure_bar=120.0,
                        crank_acceleration_rad_s2=0.0, crankcase_pressure_bar=1.0),
                   ("crank_angle_deg", "speed_rpm", "bore_mm", "stroke_mm", "rod_length_mm",
                    "reciprocating_mass_kg", "cylinder_pressure_bar", "crank_acceleration_rad_s2",
                    "crankcase_pressure_bar")),
        EntryPoint("simulate", call_simulate,
                   dict(inertia_1_kgm2=0.01, inertia_2_kgm2=0.04, mesh_stiffness_N_per_m=4e8,
                        stiffness_variation=0.2, backlash_mm=0.1, shaft_stiffness_Nm_per_rad=2e5,
                        speed_rpm=1500.0, cycles=1, teeth=(30, 60), base_radii_mm=(40.0, 80.0)),
                   ("inertia_1_kgm2", "inertia_2_kgm2", "mesh_stiffness_N_per_m", "stiffness_variation",
                    "backlash_mm", "shaft_stiffness_Nm_per_rad", "speed_rpm", "cycles", "teeth", "base_radii_mm"),
                   bad_values=BAD_VALUES + (1e-12, 1e15, 1e-9)),
        EntryPoint("Problem.solve", call_problem, dict(init=1.0, lower=-5.0, upper=5.0, target=2.0, max_iter=100),
                   ("init", "lower", "upper", "target", "max_iter"), infinite_ok=(),
                   array_ok=("init", "lower", "upper", "target"),
                   bad_values=BAD_VALUES + (1e200, -1e200, 1e19, -1e19)),
        EntryPoint("cli", call_cli, dict(argv=("pair", "--teeth", "38", "76", "--module-mm", "3",
                                               "--profile-shifts", "0.3124", "0.1118")), ("argv",)),
        EntryPoint("data file", call_data_file, dict(content=b""), ("content",)),
        EntryPoint("data value", call_data_value, dict(path="rack.module_mm", value=3.0), ("value",)),
    ]
    return {e.name: e for e in eps}


CLI_ARGS = ("--module-mm", "--pressure-angle-deg", "--helix-angle-deg", "--face-width-mm", "--centre-distance-mm",
            "--profile-shift1", "--shift-split", "--min-contact-ratio")
CLI_VALUES = ("nan", "inf", "-inf", "0", "-1", "1e300", "1e-12", "abc", "", "3")


def spoil(entry: EntryPoint, rng: np.random.Generator) -> tuple[dict, list[str]]:
    """A baseline with one or two arguments replaced by bad values; returns (kwargs, spoiled names)."""
    kw = dict(entry.baseline)
    if entry.name == "cli":
        argv = ["pair", "--teeth", "38", "76", "--profile-shifts", "0.3124", "0.1118"]
        keys = list(rng.choice(CLI_ARGS, size=int(rng.integers(1, 3)), replace=False))
        for k in keys:
            argv += [k, str(rng.choice(CLI_VALUES))]
        if "--module-mm" not in keys:
            argv += ["--module-mm", "3"]
        if "--centre-distance-mm" in keys and rng.random() < 0.5:
            argv = [a for a in argv if a not in ("--profile-shifts", "0.3124", "0.1118")]
        kw["argv"] = tuple(argv)
        return kw, [k.strip("-").replace("-", "_") for k in keys]
    if entry.name == "data file":
        options = _data_file_bad_contents()
        kw["content"] = options[int(rng.integers(len(options)))]
        return kw, ["content"]
    if entry.name == "data value":
        kw["path"] = DATA_PATHS[int(rng.integers(len(DATA_PATHS)))]
        kw["value"] = _random_bad(entry.bad_values, rng)
        return kw, [kw["path"]]
    n = 1 if rng.random() < 0.7 else 2
    names = list(rng.choice(entry.spoilable, size=min(n, len(entry.spoilable)), replace=False))
    for name in names:
        kw[name] = _random_bad(entry.bad_values, rng)
    return kw, names


def _random_bad(pool, rng):
    r = rng.random()
    if r < 0.7:
        return pool[int(rng.integers(len(pool)))]
    if r < 0.9:  # a random float over 30 decades with a random sign
        return float(rng.choice([-1.0, 1.0]) * 10.0 ** rng.uniform(-15, 15))
    v = pool[int(rng.integers(len(pool)))]
    return (v, v) if not isinstance(v, tuple) else v


__all__ = ["BAD_VALUES", "OUTCOMES", "EntryPoint", "entry_points", "classify", "spoil", "numbers_in",
           "names_parameter"]
