"""Smooth LTCA over symbolic macro geometry: the LTCA of :mod:`gearopt.contact.ltca` as one CasADi ``Function`` of
the macro geometry (profile shifts, helix angle, tip diameters, face width) and the microgeometry, for NLPs that
design both at once.

Why a second discretisation: :func:`gearopt.contact.layout.mesh_layout` keeps only the tooth pairs and springs that
lie on the path of contact of one *numeric* geometry, so its graph changes shape with the macro values. Here the
graph is fixed whatever the values (inside the declared bounds):

- mesh positions are fractions ``s`` of one base pitch (the reference pair at roll length
  ``A - b tan(beta_b)/2 + s p_bt`` for a driving gear 1; any fixed set, e.g. the refined set of a semi-infinite
  solve), slices are fractions of the face (``y = (j + 1/2)/J - 1/2`` times ``b``);
- the tooth pairs are a fixed range ``k_lo..k_hi`` covering the largest transverse and overlap ratios the bounds
  admit (``max_contact_ratio``, ``max_overlap_ratio``); a pair beyond the path simply carries no load;
- engagement is smooth: each spring's stiffness is multiplied by
  ``sigmoid(rho1 - A, w_e) sigmoid(E - rho1, w_e)`` (``numerics.sigmoid``, width ``engagement_width_mm`` along the
  path) instead of the exact solver's on/off test, so moving the path ends A, E with the macro variables moves the
  load smoothly. For a helical model the weight is the mean of that smooth step over the slice's contact-line segment
  ``rho1 +- h`` (``h = (b/J) tan(beta_b)/2 + w_e``; differences of ``numerics.softplus``), and the spring sits at
  the middle of the segment's part on the path (``smooth_max``/``smooth_min``), as in the exact layout's partial
  engagement (:mod:`gearopt.contact.layout`); the load intensity stays the slice mean (``c`` times the closure times
  the engaged fraction), lower than the exact model's intensity on the engaged part only in a slice that straddles a
  path end. Where a pair still carries load when it reaches a path end (an under-relieved tip), the exact TE
  jumps there and its peak-to-peak is a one-sided limit at the jump; the smooth model reproduces it at a position
  more than a few widths from the path end. The default width, 0.5 um along the path, is well below the 7 um spacing
  of the exact check's 1280 positions (a base pitch of ~9 mm), so the exact model's worst positions, added by the
  semi-infinite refinement, are reproduced;
- the contact law is the smooth LTCA's softplus of width ``smoothing_um`` and the approach solves
  ``sum c db w_on softplus(delta - e, w) = F_bt`` with a CasADi ``rootfinder`` (implicit-function derivatives).

Everything else is the exact model's physics with symbolic geometry: path of contact A..E and base pitch from
:class:`~gearopt.geometry.pair.GearPair` (ISO 21771), single-pair stiffness ``c'(1 - kappa (2u - 1)^2)`` with ISO
6336-1 method B's c' (:func:`gearopt.contact.layout.single_pair_stiffness_profile`), gaps from
:mod:`gearopt.contact.microgeometry` at the symbolic roll angles, Hertz stress with normal-plane radii, root stress
at the load point (ISO 6336-3 method B generalised), Blok flash temperature.

Approximation and convergence: at a fixed geometry the model differs from the exact solver only by the two widths;
as both shrink it converges to the exact LTCA at the same positions (tested), except at a position where a contact
lies exactly on a path end (there the smooth weight is 1/2). The stiffness profile is clipped to the path (its kink
sits where the engagement weight is 1/2). Only a constant stiffness or ``"iso6336"`` (the potential-energy tooth
model is numeric only).

Units: lengths mm, angles deg, deflections and modifications um, forces N, stresses MPa, temperatures C.
"""

from __future__ import annotations

import math
import os
import threading
from dataclasses import dataclass
from typing import Any, Sequence

import casadi as ca
import numpy as np

from .. import numerics as nm
from ..errors import GearoptInputError
from ..geometry.pair import GearPair
from ..validation import check_int, check_range
from .layout import position_fractions
from .ltca_smooth import DEFAULT_COUNT_WIDTH_UM, DEFAULT_SMOOTHING_UM
from .microgeometry import Microgeometry, lead_deviation_um, misalignment_gap_um, profile_deviation_um

RAD2DEG = 180.0 / math.pi
DEFAULT_ENGAGEMENT_WIDTH_MM = 0.0005

MACRO_INPUTS = ("profile_shift_1", "profile_shift_2", "helix_angle_deg", "tip_diameter_1_mm", "tip_diameter_2_mm",
                "face_width_mm")
"""Entries of the macro input vector (face width: the common, i.e. smaller, face width)."""

MICRO_FIELDS = ("tip_relief_um", "tip_relief_start_roll_deg", "tip_relief_2_um", "tip_relief_2_start_roll_deg",
                "root_relief_um", "root_relief_start_roll_deg", "profile_crown_um", "lead_crown_um", "lead_slope_um")
MICRO_INPUTS = tuple(f"{f}[{i}]" for i in (0, 1) for f in MICRO_FIELDS) + ("misalignment_um",)
"""Entries of the micro input vector: per gear (gear 1 first) the :class:`Microgeometry` fields, then the pair's
misalignment. Starts are roll angles [deg]; a relief whose amount is zero may have any start inside the profile."""


def macro_vector(pair: GearPair) -> list:
    """The macro inputs of ``pair`` (numbers or CasADi expressions), in :data:`MACRO_INPUTS` order."""
    g = pair.geometry()
    d_a = g["tip_diameter_mm"]
    return [pair.profile_shifts[0], pair.profile_shifts[1], pair.helix_angle_deg, d_a[0], d_a[1],
            nm.fmin(pair.face_width_mm[0], pair.face_width_mm[1]) if nm.is_symbolic(*pair.face_width_mm)
            else min(float(pair.face_width_mm[0]), float(pair.face_width_mm[1]))]


def micro_vector(mods: Microgeometry, geometry: dict) -> list:
    """The micro inputs of ``mods`` in :data:`MICRO_INPUTS` order. Starts given as diameters are converted to roll
    angles with ``geometry``'s base diameters; an unused start (zero amount) becomes the gear's pitch-point roll
    angle, inside the profile so that the relief's ramp stays finite (times a zero amount: no effect)."""
    out = []
    for i in (0, 1):
        d_b = geometry["base_diameter_mm"][i]
        for f in MICRO_FIELDS:
            v = getattr(mods, f)[i]
            if f.endswith("start_roll_deg"):
                diameter_field = f.replace("roll_deg", "diameter_mm")
                d = getattr(mods, diameter_field)[i] if hasattr(mods, diameter_field) else None
                if v is None and d is not None:
                    v = 0.5 * nm.sqrt(d ** 2 - d_b ** 2) / (0.5 * d_b) * RAD2DEG
                if v is None:
                    v = geometry["pitch_point_roll_deg"][i]
            out.append(v)
    out.append(mods.misalignment_um)
    return out


@dataclass
class MacroLTCAResult:
    """One evaluation of :class:`MacroLTCAModel` (numpy arrays, or CasADi MX for symbolic inputs).

    ``transmission_error_um`` (P, L); spring quantities (N, P*L) with N = pairs x slices (pair-major) and the load
    cases side by side (position-major within each); ``engagement`` the smooth on-path weight of every spring;
    ``loaded_pairs`` (1, P*L).
    """

    transmission_error_um: Any
    closure_um: Any
    load_intensity_N_per_mm: Any
    contact_stress_squared_MPa2: Any
    engagement: Any
    loaded_pairs: Any
    root_stress_MPa: Any
    flash_temperature_rise_K: Any
    positions: int
    load_cases: int
    bulk_temperature_C: float | None

    def _np(self, x) -> np.ndarray:
        if nm.is_symbolic(x):
            raise GearoptInputError("this summary needs a numeric evaluation (use the arrays in an NLP)")
        return np.asarray(x, dtype=float)

    @property
    def ppte_um(self) -> np.ndarray:
        """Peak-to-peak TE per load case [um] (numeric evaluations)."""
        return np.ptp(self._np(self.transmission_error_um), axis=0)

    def _per_case_max(self, x) -> np.ndarray:
        a = self._np(x)
        return a.reshape(a.shape[0], self.load_cases, self.positions).max(axis=(0, 2)) if a.ndim == 2 else \
            a.reshape(self.load_cases, self.positions).max(axis=1)

    @property
    def max_contact_stress_MPa(self) -> np.ndarray:
        return np.sqrt(np.maximum(self._per_case_max(self.contact_stress_squared_MPa2), 0.0))

    @property
    def max_root_stress_MPa(self) -> np.ndarray:
        if self.root_stress_MPa is None:
            raise GearoptInputError("root stress not computed: build the MacroLTCAModel with root_stress=True")
        return np.maximum(*[self._per_case_max(r) for r in self.root_stress_MPa])

    @property
    def max_flash_temperature_C(self) -> np.ndarray:
        if self.flash_temperature_rise_K is None:
            raise GearoptInputError("flash temperature not computed: build the MacroLTCAModel with speed_rpm")
        return self.bulk_temperature_C + self._per_case_max(self.flash_temperature_rise_K)

    @property
    def loaded_contact_ratio(self) -> np.ndarray:
        return self._np(self.loaded_pairs).reshape(self.load_cases, self.positions).mean(axis=1)


def default_map_threads() -> int:
    """Threads of a :class:`MacroLTCAModel`'s position map: ``GEAROPT_THREADS`` if set, else the machine's CPU
    count (at most 8)."""
    env = os.environ.get("GEAROPT_THREADS")
    if env:
        return check_int("GEAROPT_THREADS", int(env) if env.strip().isdigit() else env, 1, 256)
    return max(1, min(os.cpu_count() or 1, 8))


PIECES: dict[tuple, tuple] = {}
"""The per-position ``SX`` functions of recently built :class:`MacroLTCAModel` s by what they depend on
(:meth:`MacroLTCAModel._pieces_key`): a model built again at other positions reuses them."""
PIECES_CACHE_SIZE = 16
"""Most entries :data:`PIECES` keeps (the least recently used leave first)."""
_PIECES_LOCK = threading.Lock()


class MacroLTCAModel:
    """Smooth LTCA of one mesh as a CasADi ``Function`` ``(macro, micro, torque) -> outputs`` built once.

    Args:
        pair: numeric template: teeth, module, pressure angle, centre distance, rack, names and hands are fixed;
            the macro inputs (:data:`MACRO_INPUTS`) replace its shifts, helix angle, tip diameters and face width.
        positions: a count (uniform fractions p/P of the base pitch) or fractions in [0, 1).
        slices: face slices (default: 1 for a spur mesh without lead modifications, 11 when ``helical`` or
            ``lead_modification``).
        helical: whether the helix angle may be nonzero (default: the template's helix angle is nonzero).
        load_cases: number of torques per evaluation (fixed at build).
        max_contact_ratio, max_overlap_ratio: upper bounds of the transverse and overlap ratios over the design
            space (they fix the tooth pairs kept; default: the template's plus 0.3 and 0.3).
        smoothing_um, engagement_width_mm, count_width_um: widths of the contact law, the engagement and the
            loaded-contact count.
        relief_shape, relief_smoothing_deg: as in :class:`Microgeometry` (fixed at build).
        root_stress, speed_rpm (of the driving gear), bulk_temperature_C, friction_coefficient, materials: switch on
            the root-stress and flash-temperature outputs as in :class:`~gearopt.contact.ltca_smooth.LTCAModel`.
        approach_steps: Newton steps unrolled for the approach (default 8 + springs per position / 4; on the default
            38/76 spur mesh of the packaged train 4 steps reach a relative residual of 1e-13 with one slice, 10 steps 5e-16 with 44 springs).
        derivative_steps: Newton steps from the converged approach that carry the derivatives (see below): 2
            (default) gives the implicit function's first and second derivatives, 1 its first derivatives only --
            for an NLP solved with a quasi-Newton Hessian (Ipopt's ``hessian_approximation="limited-memory"``),
            which never asks for the second. Measured on the packaged train's root mesh at 6 deg (65 positions x 3
            torques, 11 slices, root stress and flash temperature, one thread): the value 19.8 -> 17.1 ms, six
            forward directions 130 -> 97 ms, values and first derivatives the same within 1.5e-9.
        map_threads: threads that evaluate the positions (and the derivatives CasADi builds from them) in parallel
            (CasADi's ``map(..., "thread", n)``; default :func:`default_map_threads`, 1 = serial). The results are
            the same to the last bit; on 2 cores that mesh at 200 positions x 4 load cases x 7 slices
            evaluates with gradient and Hessian in 0.91 s instead of 1.73 s.

    The approach ``delta`` of every position solves ``sum c db w_on softplus(delta - e, w) = F_bt`` by Newton's
    method unrolled in the expression graph (the residual is convex and increasing in ``delta`` and the start,
    ``max e + F / sum(c db)`` over the engaged springs, lies right of the root, so the iterates fall monotonically;
    each step crosses at least one kink of the contact law, then converges quadratically). Those steps run without
    derivatives; two more steps from their result carry them, which at convergence gives the implicit-function first
    and second derivatives exactly (Newton's map is flat at its fixed point; see :meth:`_build`; one step gives the
    first derivatives exactly: ``derivative_steps``). Every piece is an
    ``SX`` function whose derivatives CasADi generates as ``SX`` too (an implicit ``rootfinder`` would put an ``MX``
    node in every Jacobian and Hessian of the NLP; ~10x slower to build and solve here). What depends on the macro
    geometry and the position only (contact points, stiffness, stress and temperature per unit load) is evaluated
    once per position, not per load case, and differentiated in the macro directions only.
    ``approach_residual`` (output, relative to the force) says how well the steps converged; numeric evaluations
    raise if it exceeds 1e-8.
    """

    def __init__(self, pair: GearPair, *, driving_gear: int = 1, stiffness: Any = "iso6336", positions: Any = 40,
                 slices: int | None = None, lead_modification: bool = False, helical: bool | None = None,
                 load_cases: int = 1, max_contact_ratio: float | None = None, max_overlap_ratio: float | None = None,
                 smoothing_um: float = DEFAULT_SMOOTHING_UM,
                 engagement_width_mm: float = DEFAULT_ENGAGEMENT_WIDTH_MM,
                 count_width_um: float = DEFAULT_COUNT_WIDTH_UM, relief_shape: str = "linear",
                 relief_smoothing_deg: float = 0.0, E_MPa: float = 206000.0, poisson: float = 0.3,
                 root_stress: bool = False, speed_rpm: float | None = None, bulk_temperature_C: float = 100.0,
                 friction_coefficient: float = 0.06, materials: Any = "20MnCr5",
                 sliding_smoothing_m_s: float = 0.01, approach_steps: int | None = None,
                 derivative_steps: int = 2, map_threads: int | None = None) -> None:
        if pair.is_symbolic:
            raise GearoptInputError("MacroLTCAModel needs a numeric template pair; the macro values are its inputs")
        if driving_gear not in (1, 2):
            raise GearoptInputError(f"driving_gear={driving_gear!r} must be 1 or 2")
        if not (stiffness == "iso6336" or (isinstance(stiffness, (int, float)) and not isinstance(stiffness, bool)
                                           and stiffness > 0)):
            raise GearoptInputError(f"stiffness={stiffness!r}: the macro-symbolic LTCA takes a number > 0 "
                                    f"[N/(mm*um)] or 'iso6336'")
        for name, v, unit in (("smoothing_um", smoothing_um, "um"), ("engagement_width_mm", engagement_width_mm, "mm"),
                              ("count_width_um", count_width_um, "um")):
            check_range(name, v, 0.0, None, low_inclusive=False, unit=unit)
        check_range("load_cases", load_cases, 1, 1000)
        if speed_rpm is not None:
            check_range("speed_rpm", speed_rpm, 0.0, None, unit="rpm")
        g0 = pair.geometry()
        self.helical = bool(float(g0["helix_angle_deg"]) != 0.0) if helical is None else bool(helical)
        if slices is None:
            slices = 11 if (self.helical or lead_modification) else 1
        check_range("slices", slices, 1, 10000)
        self.template = pair
        self.driving_gear = driving_gear
        self.stiffness = stiffness
        self.fractions = position_fractions(positions)
        self.positions = int(self.fractions.size)
        self.slices = int(slices)
        self.load_cases = int(load_cases)
        self.smoothing_um = float(smoothing_um)
        self.engagement_width_mm = float(engagement_width_mm)
        self.count_width_um = float(count_width_um)
        self.relief_shape = relief_shape
        self.relief_smoothing_deg = float(relief_smoothing_deg)
        self.root_stress = bool(root_stress)
        self.speed_rpm = speed_rpm
        self.bulk_temperature_C = float(bulk_temperature_C)
        self._materials = dict(E_MPa=float(E_MPa), poisson=float(poisson), friction=float(friction_coefficient),
                               materials=materials, sliding=float(sliding_smoothing_m_s))
        eps_a = float(g0["transverse_contact_ratio"]) + 0.3 if max_contact_ratio is None else float(max_contact_ratio)
        eps_b = (float(g0["overlap_contact_ratio"]) + (0.3 if self.helical else 0.0)) if max_overlap_ratio is None \
            else float(max_overlap_ratio)
        check_range("max_contact_ratio", eps_a, 1.0, 10.0)
        check_range("max_overlap_ratio", eps_b, 0.0, 10.0)
        # pair k spans offsets [k p - b tan/2, (k+1) p + b tan/2] from A; it meets [0, E - A] for these k
        self.max_contact_ratio, self.max_overlap_ratio = eps_a, eps_b
        self.pair_index = np.arange(math.floor(-1.0 - 0.5 * eps_b) + 1, math.ceil(eps_a + 0.5 * eps_b))
        self.springs_per_position = len(self.pair_index) * self.slices
        self.approach_steps = int(approach_steps) if approach_steps is not None else \
            8 + math.ceil(self.springs_per_position / 4)
        check_range("approach_steps", self.approach_steps, 1, 1000)
        self.derivative_steps = check_int("derivative_steps", derivative_steps, 1, 2)
        self.map_threads = default_map_threads() if map_threads is None else check_int("map_threads", map_threads,
                                                                                        1, 256)
        self.kernel = self._build()
        self.builds = {"kernel": 1}

    # -- build ---------------------------------------------------------------------------------------------------

    def symbolic_pair(self, macro) -> GearPair:
        """The template pair with the macro inputs (a sequence in :data:`MACRO_INPUTS` order) substituted."""
        t = self.template
        x1, x2, beta, da1, da2, b = (macro[i] for i in range(6))
        hands = t.helix_hands or ("right", "left")
        return GearPair(teeth=t.teeth, module_mm=t.module_mm, pressure_angle_deg=t.pressure_angle_deg,
                        helix_angle_deg=beta, profile_shifts=(x1, x2), centre_distance_mm=t.centre_distance_mm,
                        face_width_mm=(b, b), addendum_coefficient=t.addendum_coefficient,
                        dedendum_coefficient=t.dedendum_coefficient,
                        root_radius_coefficient=t.root_radius_coefficient, tip_diameters_mm=(da1, da2),
                        tip_shortening=t.tip_shortening, tolerances=t.tolerances, names=t.names,
                        helix_hands=hands if self.helical else t.helix_hands)

    def _grid(self):
        """Constant (N, 1) columns of one position: pair index k and normalised slice centre y/b (pair-major)."""
        K, J = len(self.pair_index), self.slices
        ybar = (np.arange(J) + 0.5) / J - 0.5
        return ca.DM(np.repeat(self.pair_index.astype(float), J)), ca.DM(np.tile(ybar, K))

    GEOMETRY = ("A", "E", "t1t2", "p_bt", "tan_bb", "cos_bb", "d_b1", "d_b2", "c_single", "kappa", "sap_roll1",
                "sap_roll2", "eap_roll1", "eap_roll2")

    def _geometry_scalars(self, macro) -> list:
        """SX: the scalars of the mesh geometry every position needs (:attr:`GEOMETRY` order), computed once."""
        pair = self.symbolic_pair(macro)
        g = pair.geometry()
        A, E = g["sap_roll_length_mm"][0], g["eap_roll_length_mm"][0]
        beta_b = g["base_helix_angle_deg"] / RAD2DEG
        if self.stiffness == "iso6336":
            from ..rating.stiffness import iso6336_stiffness

            c_single = iso6336_stiffness(pair, validity="ignore", E_MPa=self._materials["E_MPa"])["single_stiffness"]
            kappa = 0.75 * (1.0 - 1.0 / g["transverse_contact_ratio"])
        else:
            c_single, kappa = float(self.stiffness), 0.0
        return [A, E, A + g["eap_roll_length_mm"][1], g["base_pitch_mm"], nm.tan(beta_b), nm.cos(beta_b),
                g["base_diameter_mm"][0], g["base_diameter_mm"][1], c_single, kappa, g["sap_roll_deg"][0],
                g["sap_roll_deg"][1], g["eap_roll_deg"][0], g["eap_roll_deg"][1]]

    SPRINGS = ("y_mm", "engaged", "spring", "roll1", "roll2", "stress_factor", "root_stress_1_per_load",
               "root_stress_2_per_load", "flash_unit_K", "half_width_sq_per_load")
    """Per-spring columns of :meth:`_springs` (macro geometry and position only; no microgeometry, no load)."""

    def _springs(self, macro, G, S) -> dict:
        """SX: the N springs of position ``S`` from the macro inputs and their geometry scalars ``G`` -- contact
        points, engagement, stiffness, roll angles, and the stress and temperature per unit load (the Hertz stress
        squared, the root stress and the Blok flash temperature are ``w``, ``w`` and ``w / sqrt(b_H)`` times a
        factor of the contact point, ``b_H^2`` is ``w`` times one): nothing here depends on the microgeometry or
        the torque, so it is evaluated once per position and differentiated in the macro directions only."""
        A, E, t1t2, p_bt, tb, cb, d_b1, d_b2, c_single, kappa, sap1, sap2, eap1, eap2 = (
            G[i] for i in range(len(self.GEOMETRY)))
        d_b = (d_b1, d_b2)
        b = macro[5]
        Kg, Y = self._grid()
        if self.driving_gear == 1:
            rho1 = A - 0.5 * b * tb + p_bt * (S + Kg) + (Y + 0.5) * b * tb
        else:
            rho1 = E + 0.5 * b * tb - p_bt * (S + Kg) - (Y + 0.5) * b * tb
        w_e = self.engagement_width_mm
        y_mm = Y * b
        if self.helical:    # the slice's contact-line segment rho +- h, trimmed smoothly to A..E (see the layout)
            direction = 1.0 if self.driving_gear == 1 else -1.0
            h = 0.5 * (b / self.slices) * tb + w_e
            engaged = ((nm.softplus(rho1 + h - A, w_e) - nm.softplus(rho1 - h - A, w_e))
                       * (nm.softplus(E - rho1 + h, w_e) - nm.softplus(E - rho1 - h, w_e)) / (2.0 * h) ** 2)
            mid = 0.5 * (nm.smooth_max(rho1 - h, A, w_e) + nm.smooth_min(rho1 + h, E, w_e))
            y_mm = y_mm + direction * (mid - rho1) * 0.5 * (b / self.slices) / h
            rho1 = mid
        else:
            engaged = nm.sigmoid(rho1 - A, w_e) * nm.sigmoid(E - rho1, w_e)
        rho2 = t1t2 - rho1
        u = nm.clip((rho1 - A) / (E - A), 0.0, 1.0)
        c = c_single * (1.0 - kappa * (2.0 * u - 1.0) ** 2)
        spring = c * (b / self.slices) * engaged
        roll1, roll2 = rho1 / (0.5 * d_b[0]) * RAD2DEG, rho2 / (0.5 * d_b[1]) * RAD2DEG
        on1 = nm.clip(rho1, A, E)                   # contact point held on the path (off it the load is ~0)
        on2 = t1t2 - on1
        r1, r2 = on1 / cb, on2 / cb
        e_term = 1.0 / (2.0 * (1.0 - self._materials["poisson"] ** 2) / self._materials["E_MPa"])
        zero = ca.SX.zeros(rho1.shape)
        out = dict(y_mm=y_mm, engaged=engaged, spring=spring, roll1=roll1, roll2=roll2,
                   stress_factor=e_term * (r1 + r2) / (math.pi * r1 * r2), root_stress_1_per_load=zero,
                   root_stress_2_per_load=zero, flash_unit_K=zero, half_width_sq_per_load=zero)
        if self.root_stress:     # ISO 6336-3 method B's sigma_F is linear in the load at a fixed load point
            from ..rating.root_stress import root_stress_at_load_point, virtual_roll_length_mm

            pair = self.symbolic_pair(macro)
            for gear, rho in ((1, on1), (2, on2)):
                v = virtual_roll_length_mm(pair, gear, rho)
                out[f"root_stress_{gear}_per_load"] = root_stress_at_load_point(pair, gear, 1.0,
                                                                                load_roll_length_mm=v)
        if self.speed_rpm is not None:
            out.update(self._flash_factors(on1, on2, cb))
        return out

    def _microgeometry(self, micro) -> Microgeometry:
        n = len(MICRO_FIELDS)
        kw = {f: (micro[j], micro[n + j]) for j, f in enumerate(MICRO_FIELDS)}
        return Microgeometry(**kw, misalignment_um=micro[2 * n], relief_shape=self.relief_shape,
                             relief_smoothing_deg=self.relief_smoothing_deg)

    def _gap(self, macro, micro, G, sp):
        """SX: the no-load gap of every spring [um] (the flank modifications at its roll angles and face position)."""
        sap1, sap2, eap1, eap2 = (G[self.GEOMETRY.index(k)] for k in ("sap_roll1", "sap_roll2", "eap_roll1",
                                                                      "eap_roll2"))
        d_b1, d_b2 = G[self.GEOMETRY.index("d_b1")], G[self.GEOMETRY.index("d_b2")]
        b = macro[5]
        mods = self._microgeometry(micro)
        y_mm = sp["y_mm"]
        return (profile_deviation_um(mods, 0, sp["roll1"], sap_roll_deg=sap1, eap_roll_deg=eap1, base_diameter_mm=d_b1)
                + profile_deviation_um(mods, 1, sp["roll2"], sap_roll_deg=sap2, eap_roll_deg=eap2,
                                       base_diameter_mm=d_b2)
                + lead_deviation_um(mods, 0, y_mm, b) + lead_deviation_um(mods, 1, y_mm, b)
                + misalignment_gap_um(mods, y_mm, b))

    def _newton(self, x, e, s, force):
        """One Newton step on the force balance ``sum s softplus(x - e, w) = force`` from the approach ``x``."""
        w = self.smoothing_um
        z = x - e
        return x - (ca.sum1(s * nm.softplus(z, w)) - force) / ca.sum1(s * nm.sigmoid(z, w))

    def _build(self) -> ca.Function:
        """Four ``SX`` functions mapped in one ``MX`` kernel ``(macro, micro, torque) -> outputs``:

        - the springs (:meth:`_springs`) of each position, from the macro inputs only (mapped over the positions);
        - the no-load gaps (:meth:`_gap`, the microgeometry) of each position;
        - the approach: ``approach_steps`` Newton steps from the start below, a function without derivatives
          (``is_diff_out``; an expression graph of ``SX`` symbols inlines it and differentiates through it, with the
          same values);
        - the contact of each position and load case: two more Newton steps from that approach, and the outputs.
          At the converged approach these two steps give the implicit-function first and second derivatives
          exactly (Newton's map has zero slope at its fixed point), so the derivatives never pass through the
          unrolled steps. Measured on the packaged train's root mesh at 8 deg (11 slices, 40 positions x
          3 torques): the Jacobian took 197 ms through every step and per load case, 65-89 ms in these pieces.

        The graph is that of one position whatever their number: the ``SX`` pieces do not depend on the positions or
        the load cases, so a model built again with other positions (a refinement's re-solve) takes them from
        :data:`PIECES` when everything else is the same."""
        P, L = self.positions, self.load_cases
        key = self._pieces_key()
        with _PIECES_LOCK:
            pieces = PIECES.pop(key, None) if key is not None else None
        if pieces is None:
            pieces = self._pieces()
        if key is not None:
            with _PIECES_LOCK:                      # a thread of a Dask worker may build beside another
                PIECES.pop(key, None)
                while len(PIECES) >= PIECES_CACHE_SIZE:
                    PIECES.pop(next(iter(PIECES)))
                PIECES[key] = pieces                # most recent last
        geometry, springs, gaps, approach, contact, names = pieces
        macro_n, micro_n = len(MACRO_INPUTS), len(MICRO_INPUTS)

        def mapped(f, n):
            return f.map(n, "thread", self.map_threads) if self.map_threads > 1 else f.map(n)

        m_mx, u_mx, t_mx = ca.MX.sym("macro", macro_n), ca.MX.sym("micro", micro_n), ca.MX.sym("torque", L)
        g_mx = geometry(m_mx)
        per_position = mapped(springs, P)(m_mx, g_mx, ca.DM(self.fractions).T)      # N x (P * columns)
        gap_row = ca.repmat(mapped(gaps, P)(m_mx, u_mx, g_mx, per_position), 1, L)
        cols_row = ca.repmat(per_position, 1, L)                                    # the positions of every case
        t_row = ca.horzcat(*[ca.repmat(t_mx[i], 1, P) for i in range(L)])
        x_row = mapped(approach, P * L)(m_mx, g_mx, cols_row, gap_row, t_row)
        res = list(mapped(contact, P * L)(m_mx, g_mx, cols_row, gap_row, t_row, x_row))
        res[0] = ca.reshape(res[0], P, L)
        self.output_names = tuple(names)
        return ca.Function("macro_ltca", [m_mx, u_mx, t_mx], res, ["macro", "micro", "torque"], list(names))

    def _pieces_key(self) -> tuple | None:
        """What the ``SX`` pieces of :meth:`_pieces` depend on (everything but the positions, the load cases and
        the threads), or None when the template pair's numbers are not hashable."""
        template = self.template.numeric_key()
        if template is None:
            return None
        return (template, self.driving_gear, repr(self.stiffness), self.slices, self.helical, self.smoothing_um,
                self.engagement_width_mm, self.count_width_um, self.relief_shape, self.relief_smoothing_deg,
                self.root_stress, self.speed_rpm, repr(sorted(self._materials.items())),
                tuple(int(k) for k in self.pair_index), self.approach_steps, self.derivative_steps)

    def _pieces(self) -> tuple:
        """The ``SX`` functions of one position (:meth:`_build`): geometry, springs, gaps, approach, contact and the
        contact's output names."""
        macro = ca.SX.sym("macro", len(MACRO_INPUTS))
        micro = ca.SX.sym("micro", len(MICRO_INPUTS))
        torque, frac = ca.SX.sym("torque"), ca.SX.sym("s")
        G = ca.SX.sym("geometry", len(self.GEOMETRY))
        N = self.springs_per_position
        geometry = ca.Function("macro_ltca_geometry", [macro], [ca.vertcat(*self._geometry_scalars(macro))])
        sp = self._springs(macro, G, frac)
        springs = ca.Function("macro_ltca_springs", [macro, G, frac], [ca.horzcat(*[sp[k] for k in self.SPRINGS])],
                              {"cse": True})
        cols = ca.SX.sym("springs", N, len(self.SPRINGS))
        sp_in = {k: cols[:, j] for j, k in enumerate(self.SPRINGS)}
        gaps = ca.Function("macro_ltca_gaps", [macro, micro, G, cols], [self._gap(macro, micro, G, sp_in)],
                           {"cse": True})
        e = ca.SX.sym("gap_um", N)
        s, engaged = sp_in["spring"], sp_in["engaged"]
        force = torque * 1000.0 / (0.5 * G[self.GEOMETRY.index(f"d_b{self.driving_gear}")])
        on = engaged > 0.5
        x = ca.mmax(ca.if_else(on, e, -1e6)) + force / ca.sum1(s * on) + 1e-3   # right of the root
        for _ in range(self.approach_steps):     # monotone from the right on a convex increasing residual
            x = self._newton(x, e, s, force)
        approach = ca.Function("macro_ltca_approach", [macro, G, cols, e, torque], [x],
                               {"cse": True, "is_diff_out": [False]})     # no derivatives: see the docstring
        x0 = ca.SX.sym("approach_start")
        delta = x0
        for _ in range(self.derivative_steps):
            delta = self._newton(delta, e, s, force)
        w = self.smoothing_um
        closure = delta - e
        residual = (ca.sum1(s * nm.softplus(closure, w)) - force) / ca.fmax(force, 1e-9)
        b = macro[5]
        load = s * nm.softplus(closure, w) / (b / self.slices)
        stress_sq = load * sp_in["stress_factor"]
        loaded = ca.sum1(engaged * nm.sigmoid(closure, self.count_width_um)) / self.slices
        outs = [delta, closure, load, stress_sq, engaged, loaded, residual]
        names = ["te_um", "closure_um", "load_N_per_mm", "stress_sq_MPa2", "engagement", "loaded_pairs",
                 "approach_residual"]
        if self.root_stress:
            for gear in (1, 2):
                outs.append(load * sp_in[f"root_stress_{gear}_per_load"])
                names.append(f"root_stress_{gear}_MPa")
        if self.speed_rpm is not None:   # Blok: theta = theta(w = 1, b_H = 1) w / sqrt(b_H), b_H^2 proportional to w
            b_h = nm.sqrt_safe(load * sp_in["half_width_sq_per_load"], 1e-12)
            outs.append(sp_in["flash_unit_K"] * load / nm.sqrt(b_h))
            names.append("flash_rise_K")
        contact = ca.Function("macro_ltca_contact", [macro, G, cols, e, torque, x0], outs, {"cse": True})
        return geometry, springs, gaps, approach, contact, tuple(names)

    def _flash_factors(self, on1, on2, cb) -> dict:
        """Blok's flash temperature per spring at unit load intensity and unit half-width [K], and the Hertzian
        half-width squared per unit load [mm^2 / (N/mm)]: theta = flash_unit * w / sqrt(b_H), b_H = sqrt(w *
        half_width_sq_per_load)."""
        from ..rating.flash_temperature import flash_temperature_blok_K
        from ..rating.materials import material_pair
        from .tip_relief import plane_strain_compliance_per_MPa

        teeth = self.template.teeth
        drive = self.driving_gear - 1
        omega = [0.0, 0.0]
        omega[drive] = self.speed_rpm * 2.0 * math.pi / 60.0
        omega[1 - drive] = omega[drive] * teeth[drive] / teeth[1 - drive]
        m = self._materials
        v1 = omega[0] * on1 * 1e-3
        v2 = omega[1] * on2 * 1e-3
        curvature = 0.5 * cb / on1 + 0.5 * cb / on2
        compliance = 2.0 * plane_strain_compliance_per_MPa(m["E_MPa"], m["poisson"])
        m1, m2 = material_pair(m["materials"])
        unit = flash_temperature_blok_K(1.0, 1.0, v1, v2, m["friction"],
                                        m1.thermal_contact_coefficient_N_per_mm_sqrt_s_K,
                                        m2.thermal_contact_coefficient_N_per_mm_sqrt_s_K,
                                        sliding_smoothing_m_s=m["sliding"])
        return {"flash_unit_K": unit, "half_width_sq_per_load": 2.0 / math.pi * compliance / curvature}

    # -- evaluate ------------------------------------------------------------------------------------------------

    def evaluate(self, macro: Sequence | None = None, micro: Sequence | None = None,
                 torque_Nm: Any = 0.0) -> MacroLTCAResult:
        """Outputs at ``macro`` (default: the template's), ``micro`` (default: no modification) and ``torque_Nm``
        (``load_cases`` torques on the driving gear [N m]); numbers give numpy arrays, CasADi symbols MX."""
        macro = macro_vector(self.template) if macro is None else list(macro)
        micro = micro_vector(Microgeometry(), self.template.geometry()) if micro is None else list(micro)
        torques = list(np.atleast_1d(torque_Nm)) if not nm.is_casadi(torque_Nm) else torque_Nm
        if not nm.is_casadi(torques) and len(torques) != self.load_cases:
            raise GearoptInputError(f"torque_Nm has {len(torques)} load case(s); the model was built for "
                                    f"{self.load_cases}")
        if len(macro) != len(MACRO_INPUTS) or len(micro) != len(MICRO_INPUTS):
            raise GearoptInputError(f"macro needs {len(MACRO_INPUTS)} entries {MACRO_INPUTS}, micro "
                                    f"{len(MICRO_INPUTS)} {MICRO_INPUTS}")
        symbolic = nm.is_symbolic(*macro, *micro) or nm.is_casadi(torques) or nm.is_symbolic(*torques)
        if not symbolic:
            for t in torques:
                check_range("torque_Nm", t, 0.0, None, unit="N*m")
        args = [ca.vertcat(*macro), ca.vertcat(*micro), ca.vertcat(*torques) if not nm.is_casadi(torques) else torques]
        out = dict(zip(self.output_names, self.kernel(*args)))
        if not symbolic:
            out = {k: np.asarray(v, dtype=float) for k, v in out.items()}
            worst = float(np.max(np.abs(out["approach_residual"])))
            if not worst <= 1e-8:
                raise GearoptInputError(f"MacroLTCAModel: the approach did not converge in approach_steps="
                                        f"{self.approach_steps} Newton steps (relative force residual {worst:.3g}, "
                                        f"limit 1e-8): raise approach_steps")
        root = (out["root_stress_1_MPa"], out["root_stress_2_MPa"]) if self.root_stress else None
        return MacroLTCAResult(
            transmission_error_um=out["te_um"], closure_um=out["closure_um"],
            load_intensity_N_per_mm=out["load_N_per_mm"],
            contact_stress_squared_MPa2=out["stress_sq_MPa2"], engagement=out["engagement"],
            loaded_pairs=out["loaded_pairs"], root_stress_MPa=root, flash_temperature_rise_K=out.get("flash_rise_K"),
            positions=self.positions, load_cases=self.load_cases,
            bulk_temperature_C=self.bulk_temperature_C if self.speed_rpm is not None else None)


__all__ = ["MacroLTCAModel", "MacroLTCAResult", "MACRO_INPUTS", "MICRO_INPUTS", "MICRO_FIELDS", "macro_vector",
           "micro_vector", "DEFAULT_ENGAGEMENT_WIDTH_MM"]
