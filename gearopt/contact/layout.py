"""The discretised mesh of an LTCA: mesh positions over one base pitch, face slices, tooth pairs, their contact
positions on the path, single-pair springs and initial gaps.

Shared by the exact numeric solver (:mod:`gearopt.contact.ltca`) and the smooth CasADi form
(:mod:`gearopt.contact.ltca_smooth`) so both see exactly the same discretisation.

Geometry (transverse plane; lengths mm): the reference tooth pair (index k = 0) enters at the first position; pair k
is k base pitches ahead. At position p, pair k and slice j the contact lies at roll length rho1 on gear 1 (rho1 +
rho2 = T1T2). A helical pair's contact line crosses the slices with the base-helix phase (y + b/2) tan(beta_b).
A spring exists where the contact lies on the active path A..E; elsewhere its stiffness is zero.

Partial engagement (helical pairs): within one slice a contact line covers the path lengths rho_c +- h with
h = (b / J) tan(beta_b) / 2 around the slice centre's rho_c. Only the part of that segment on A..E carries load, so
each spring represents the trimmed segment: its stiffness is c times the segment's engaged face length
(``engaged_length_mm``, b / J times the fraction on the path) and its contact point (rho, y, hence the gap) is the
trimmed segment's midpoint. A slice therefore enters and leaves the path gradually, as the continuous face does,
instead of switching on and off at its centre: the stiffness integral over the face is exact for a linear profile
and the TE's slice-crossing ripple falls like 1/J^2 instead of 1/J. A spur pair (h = 0) is unchanged.

The numeric macro geometry is required (tooth counts, shifts, diameters fixed); the microgeometry (the gaps) may be
symbolic.
"""

from __future__ import annotations

import math
import threading
from collections import OrderedDict
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from .. import numerics as nm
from ..errors import GearoptInputError
from ..validation import check_int, check_range
from ..geometry.pair import GearPair
from .microgeometry import Microgeometry, lead_deviation_um, misalignment_gap_um, profile_deviation_um

RAD2DEG = 180.0 / math.pi


def single_pair_stiffness_profile(kind, pair: GearPair, *, E_MPa: float = 206000.0,
                                  poisson: float = 0.3) -> Callable[[np.ndarray], np.ndarray]:
    """Single-pair stiffness per unit face width c(s) [N/(mm*um)] as a function of the normalised path position
    s in [0, 1] (A -> E).

    - a number: constant c' (for analytic checks);
    - ``"iso6336"``: a parabola c'(1 - kappa (2s - 1)^2), peak c' (ISO 6336-1's single stiffness) at the middle of the
      path and kappa = 0.75 (1 - 1/eps_alpha) so that the mean mesh stiffness eps_alpha * mean(c) equals ISO's
      c_gamma_alpha = c'(0.75 eps_alpha + 0.25). An approximation consistent with both ISO values, not a
      position-resolved tooth model.
    - ``"potential_energy"``: the position-resolved potential-energy tooth model
      (:mod:`gearopt.contact.potential_energy`: Hertz, bending, shear, axial compression and fillet foundation).
    """
    if isinstance(kind, (int, float)) and not isinstance(kind, bool):
        check_range("stiffness", kind, 0.0, None, low_inclusive=False, unit="N/(mm*um)")
        c = float(kind)
        return lambda s: np.full(np.shape(s), c)
    if kind == "iso6336":
        from ..rating.stiffness import iso6336_stiffness

        iso = iso6336_stiffness(pair)
        c_single = float(iso["single_stiffness"])
        eps = float(pair.geometry()["transverse_contact_ratio"])
        kappa = 0.75 * (1.0 - 1.0 / eps)
        return lambda s: c_single * (1.0 - kappa * (2.0 * np.asarray(s) - 1.0) ** 2)
    if kind == "potential_energy":
        from .potential_energy import potential_energy_stiffness_profile

        return potential_energy_stiffness_profile(pair, E_MPa=E_MPa, poisson=poisson)
    raise GearoptInputError(f"stiffness={kind!r} must be a number [N/(mm*um)], 'iso6336' or 'potential_energy'")


@dataclass(frozen=True)
class MeshLayout:
    """Discretised mesh of a numeric pair (arrays shaped (positions, pairs, slices) unless stated)."""

    pair: GearPair
    driving_gear: int
    positions: int
    slices: int
    stiffness: Any
    position_roll_deg: np.ndarray      # (P,) roll angle of gear 1 at the reference pair's first slice
    pair_index: np.ndarray             # (K,) tooth-pair indices kept (those on the path somewhere)
    slice_y_mm: np.ndarray             # (J,) slice centres, -b/2..b/2
    slice_width_mm: float
    spring_y_mm: np.ndarray            # face position of each spring's contact point (the engaged part's middle)
    engaged_length_mm: np.ndarray      # face length each spring carries: the slice width times its part on A..E
    face_width_mm: float
    rho1_mm: np.ndarray
    rho2_mm: np.ndarray
    roll1_deg: np.ndarray
    roll2_deg: np.ndarray
    on_path: np.ndarray                # bool
    spring_N_per_um: np.ndarray        # c(rho) * db on the path, 0 elsewhere
    base_pitch_mm: float
    base_helix_angle_rad: float
    base_diameter_mm: tuple
    sap_roll_deg: tuple
    eap_roll_deg: tuple
    force_per_torque_N_per_Nm: float   # transverse base-circle force per unit torque on the driving gear

    @property
    def shape(self) -> tuple:
        return self.rho1_mm.shape

    @property
    def springs_per_position(self) -> int:
        return int(np.prod(self.shape[1:]))

    def root_stress_per_load(self, gear: int) -> np.ndarray:
        """Root stress of ``gear`` (1 or 2) per unit load intensity at every spring [MPa per N/mm], (positions,
        pairs, slices), 0 off the path: ISO 6336-3 method B's Y_F Y_S at each spring's load point
        (:func:`~gearopt.rating.root_stress.root_stress_at_load_point`, linear in the load), computed once per layout
        (read-only)."""
        cache = self.__dict__.setdefault("_root_stress_per_load", {})
        if gear not in cache:
            from ..rating.root_stress import root_stress_at_load_point, virtual_roll_length_mm

            m = self.on_path
            factor = np.zeros(self.shape)
            rho = (self.rho1_mm if gear == 1 else self.rho2_mm)[m]
            factor[m] = root_stress_at_load_point(self.pair, gear, np.ones(rho.shape),
                                                  load_roll_length_mm=virtual_roll_length_mm(self.pair, gear, rho))
            factor.flags.writeable = False
            cache[gear] = factor
        return cache[gear]

    def gaps_um(self, mods: Microgeometry):
        """Initial gap of every spring [um] from the microgeometry: (P, K, J) array for a numeric microgeometry,
        a CasADi column of length P*K*J (row-major: position, pair, slice) when any amount is symbolic."""
        sym = _is_symbolic_mods(mods)
        like = nm.symbol("like") if sym else None
        roll1 = nm.column(self.roll1_deg, like) if sym else self.roll1_deg
        roll2 = nm.column(self.roll2_deg, like) if sym else self.roll2_deg
        y = nm.column(self.spring_y_mm, like) if sym else self.spring_y_mm
        b, d_b = self.face_width_mm, self.base_diameter_mm
        gap = (profile_deviation_um(mods, 0, roll1, sap_roll_deg=self.sap_roll_deg[0],
                                    eap_roll_deg=self.eap_roll_deg[0], base_diameter_mm=d_b[0])
               + profile_deviation_um(mods, 1, roll2, sap_roll_deg=self.sap_roll_deg[1],
                                      eap_roll_deg=self.eap_roll_deg[1], base_diameter_mm=d_b[1])
               + lead_deviation_um(mods, 0, y, b) + lead_deviation_um(mods, 1, y, b) + misalignment_gap_um(mods, y, b))
        if sym:
            return gap if not isinstance(gap, (int, float)) else nm.column(np.full(self.rho1_mm.size, gap), like)
        return np.broadcast_to(np.asarray(gap, dtype=float), self.shape)


def _is_symbolic_mods(mods: Microgeometry) -> bool:
    vals = []
    for v in vars(mods).values():
        vals.extend(v if isinstance(v, tuple) else (v,))
    return nm.is_symbolic(*[v for v in vals if v is not None and not isinstance(v, str)])


def default_slices(pair: GearPair, mods: Microgeometry) -> int:
    """Face slices of the exact LTCA keeping PPTE within 1 % of the converged value (benchmarks/results/ltca.json):
    1 for a spur pair without lead modification or misalignment (exact: the load is uniform over the face), 11 for
    a spur pair with lead modifications (0.06 %). A helical pair: at least 11, and enough that one slice's piece of
    contact line spans at most :data:`HELICAL_SLICE_SPAN` base pitches along the path (``overlap ratio / slices``):
    the partially engaged slices make the stiffness exact, and what remains is the midpoint sampling of the
    profile modifications along each piece. Measured on the packaged timing train's 38/76 spur mesh with tip relief against 641
    slices: 0.7 % at 8 deg with 7 slices (span 0.053), 0.66 % at 15 deg with 21 (span 0.033), 3 % at 15 deg with 11
    (span 0.062); 13 and 23 slices by this rule."""
    spur = float(pair.geometry()["helix_angle_deg"]) == 0.0
    if spur:
        return 1 if not mods.has_lead_modification else 11
    overlap = float(pair.geometry()["overlap_contact_ratio"])
    return max(11, int(math.ceil(overlap / HELICAL_SLICE_SPAN)))


HELICAL_SLICE_SPAN = 0.03
"""Largest piece of contact line per face slice of a helical pair's exact LTCA, in base pitches along the path."""


def default_positions(slices: int) -> int:
    """Mesh positions of the exact LTCA keeping PPTE within 1 % of the converged value even for an optimised,
    sub-micron PPTE (benchmarks/results/ltca.json): the TE jumps where a pair leaves the path and a uniform grid
    converges like 1/positions there. 1280 for one slice (~1 ms), 160 when the face is sliced (a helical pair's
    slices smear the jump; ~10-20 ms)."""
    return 1280 if slices == 1 else 160


def position_fractions(positions) -> np.ndarray:
    """Mesh positions as fractions of one base pitch in [0, 1): ``positions`` is a count (a uniform grid p/P) or a
    sequence of fractions (any order: a refined set of a semi-infinite solve). Raises on an empty set or a fraction
    outside [0, 1)."""
    if isinstance(positions, (int, np.integer)) and not isinstance(positions, bool):
        positions = check_int("positions", positions, 2, 100000)
        return np.arange(positions) / positions
    s = np.asarray(positions, dtype=float).reshape(-1)
    if s.size < 2 or not np.all(np.isfinite(s)) or np.any(s < 0.0) or np.any(s >= 1.0):
        raise GearoptInputError(f"positions={positions!r} must be a count >= 2 or at least two fractions of a base "
                                f"pitch in [0, 1)")
    return s


LAYOUT_CACHE_SIZE = 64
"""Layouts kept by :func:`mesh_layout` (least recently used dropped first). The exact screen and polish of a scene
evaluate the exact LTCA of the same pair hundreds of times at one resolution; building its layout was about 30 % of
each call (measured on the packaged spur train's first mesh, a tip-relief scene at 3 torques: 0.21 of 0.69 s per 100
evaluations)."""
_LAYOUTS: "OrderedDict[tuple, MeshLayout]" = OrderedDict()
_LAYOUTS_LOCK = threading.Lock()


def mesh_layout(pair: GearPair, *, driving_gear: int = 1, positions: Any = 40, slices: int = 1,
                stiffness: Any = "iso6336", E_MPa: float = 206000.0, poisson: float = 0.3) -> MeshLayout:
    """Discretise ``pair``'s mesh: ``positions`` over one base pitch (a count: uniform in time order; or fractions
    of the base pitch, :func:`position_fractions`), ``slices`` over the face. A numeric layout is kept for reuse
    (:data:`LAYOUT_CACHE_SIZE`, keyed by every input to full precision); its arrays are read-only."""
    if pair.is_symbolic:
        raise GearoptInputError("the LTCA needs a numeric pair (fixed macro geometry); the microgeometry and the "
                                "torque may be symbolic")
    key = (repr(pair), driving_gear, np.asarray(positions, dtype=float).tobytes(), np.ndim(positions), slices,
           repr(stiffness), E_MPa, poisson)
    with _LAYOUTS_LOCK:
        layout = _LAYOUTS.get(key)
        if layout is not None:
            _LAYOUTS.move_to_end(key)
            return layout
    layout = _build_layout(pair, driving_gear=driving_gear, positions=positions, slices=slices,
                           stiffness=stiffness, E_MPa=E_MPa, poisson=poisson)
    for value in vars(layout).values():
        if isinstance(value, np.ndarray):
            value.flags.writeable = False
    with _LAYOUTS_LOCK:
        _LAYOUTS[key] = layout
        while len(_LAYOUTS) > LAYOUT_CACHE_SIZE:
            _LAYOUTS.popitem(last=False)
    return layout


def _build_layout(pair: GearPair, *, driving_gear: int, positions: Any, slices: int, stiffness: Any,
                  E_MPa: float, poisson: float) -> MeshLayout:
    if pair.is_symbolic:
        raise GearoptInputError("the LTCA needs a numeric pair (fixed macro geometry); the microgeometry and the "
                                "torque may be symbolic")
    if driving_gear not in (1, 2):
        raise GearoptInputError(f"driving_gear={driving_gear!r} must be 1 or 2")
    s = position_fractions(positions)
    positions = int(s.size)
    slices = check_int("slices", slices, 1, 10000)
    check_range("E_MPa", E_MPa, 0.0, None, low_inclusive=False, unit="MPa")
    check_range("poisson", poisson, 0.0, 0.5, low_inclusive=False, high_inclusive=False)
    g = pair.geometry()
    b = float(min(g["face_width_mm"]))
    d_b = tuple(float(v) for v in g["base_diameter_mm"])
    p_bt = float(g["base_pitch_mm"])
    A, E = float(g["sap_roll_length_mm"][0]), float(g["eap_roll_length_mm"][0])
    t1t2 = A + float(g["eap_roll_length_mm"][1])  # rho1 + rho2 = T1T2 at every contact point
    beta_b = math.radians(float(g["base_helix_angle_deg"]))
    tan_bb = abs(math.tan(beta_b))
    y = (np.arange(slices) + 0.5) / slices * b - 0.5 * b
    eps_total = (E - A) / p_bt + b * tan_bb / p_bt
    k = np.arange(-int(math.ceil(eps_total)) - 1, int(math.ceil(eps_total)) + 2)

    if driving_gear == 1:
        rho_ref, direction = A - 0.5 * b * tan_bb + s * p_bt, 1.0
    else:
        rho_ref, direction = E + 0.5 * b * tan_bb - s * p_bt, -1.0
    db = b / slices
    rho_c = (rho_ref[:, None, None] + direction * k[None, :, None] * p_bt
             + direction * (y[None, None, :] + 0.5 * b) * tan_bb)
    y_c = np.broadcast_to(y[None, None, :], rho_c.shape)
    rho1, y_spring, engaged = _engaged_part(rho_c, y_c, 0.5 * db * tan_bb, A, E, direction * tan_bb, db)
    on_path = engaged > 0.0
    keep = on_path.any(axis=(0, 2))
    rho1, on_path, k = rho1[:, keep, :], on_path[:, keep, :], k[keep]
    y_spring, engaged = y_spring[:, keep, :], engaged[:, keep, :]
    rho2 = t1t2 - rho1
    c = single_pair_stiffness_profile(stiffness, pair, E_MPa=E_MPa, poisson=poisson)(
        np.clip((rho1 - A) / (E - A), 0.0, 1.0))
    return MeshLayout(
        pair=pair, driving_gear=driving_gear, positions=positions, slices=slices, stiffness=stiffness,
        position_roll_deg=rho_ref / (0.5 * d_b[0]) * RAD2DEG, pair_index=k, slice_y_mm=y, slice_width_mm=db,
        spring_y_mm=y_spring, engaged_length_mm=engaged, face_width_mm=b, rho1_mm=rho1, rho2_mm=rho2, roll1_deg=rho1 / (0.5 * d_b[0]) * RAD2DEG,
        roll2_deg=rho2 / (0.5 * d_b[1]) * RAD2DEG, on_path=on_path, spring_N_per_um=np.where(on_path, c * engaged, 0.0),
        base_pitch_mm=p_bt, base_helix_angle_rad=beta_b, base_diameter_mm=d_b,
        sap_roll_deg=tuple(float(v) for v in g["sap_roll_deg"]), eap_roll_deg=tuple(float(v) for v in g["eap_roll_deg"]),
        force_per_torque_N_per_Nm=1000.0 / (0.5 * d_b[driving_gear - 1]))


def _engaged_part(rho_c, y_c, half_mm: float, A: float, E: float, drho_dy: float, db: float):
    """The part of each slice's contact-line segment rho_c +- ``half_mm`` that lies on the path A..E: its middle's
    roll length and face position (``drho_dy`` = d rho / d y along the line) and its face length [mm] (0 off the
    path). ``half_mm`` = 0 (a spur pair): the slice is on the path where its centre is (ends inclusive, 1e-12 mm)."""
    if half_mm == 0.0:
        on = (rho_c >= A - 1e-12) & (rho_c <= E + 1e-12)
        return rho_c, y_c, np.where(on, db, 0.0)
    lo, hi = np.maximum(rho_c - half_mm, A), np.minimum(rho_c + half_mm, E)
    on = hi > lo
    mid = np.where(on, 0.5 * (lo + hi), rho_c)
    return mid, y_c + (mid - rho_c) / drho_dy, np.where(on, db * (hi - lo) / (2.0 * half_mm), 0.0)


def hertz_stress_factor(layout: MeshLayout, E_MPa: float, poisson: float) -> np.ndarray:
    """sigma_H^2 / w [MPa^2 mm/N] of every spring: Hertz line contact sigma_H = sqrt(w E_r' / (pi rho_red)) with
    w the load per unit face width [N/mm] (for a helical pair equal to the normal load per unit contact-line length
    in the transverse treatment), normal-plane radii rho_i / cos(beta_b), and 1/E_r' = 2 (1 - nu^2)/E (equal
    materials). Shigley eq. 3-74 / ISO 6336-2 Z_E form."""
    cb = math.cos(layout.base_helix_angle_rad)
    r1 = np.maximum(layout.rho1_mm, 1e-9) / cb
    r2 = np.maximum(layout.rho2_mm, 1e-9) / cb
    rho_red = r1 * r2 / (r1 + r2)
    e_term = 1.0 / (2.0 * (1.0 - poisson ** 2) / E_MPa)
    return np.where(layout.on_path, e_term / (math.pi * rho_red), 0.0)


__all__ = ["MeshLayout", "mesh_layout", "position_fractions", "default_slices", "HELICAL_SLICE_SPAN", "single_pair_stiffness_profile", "hertz_stress_factor"]
