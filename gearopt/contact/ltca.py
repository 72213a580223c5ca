"""Loaded tooth contact analysis (LTCA) of a cylindrical gear pair over one mesh cycle: exact numeric solver.

Model (the classic compliance/"slicing" model, as in Harris-type and LDP-type analyses):

- The face is cut into ``slices`` of width db; a tooth pair in contact at a slice is a linear spring of stiffness
  c(rho) db [N/um] along the transverse line of action, where c is the single-pair stiffness per unit face width
  [N/(mm*um)] at the contact's position on the path (constant, or an ISO 6336-1-consistent profile).
- The initial gap of a pair at a slice is the sum of both gears' profile and lead modifications and the
  misalignment (:mod:`gearopt.contact.microgeometry`), zero for unmodified perfect gears.
- At each mesh position the rigid-body approach delta [um] (the static transmission error, positive when the
  driven gear lags) solves sum_{pairs, slices} c db max(delta - gap, 0) = F_bt, the transverse base-circle force
  T / r_b of the driving gear: separated slices carry nothing, no tensile loads. The left side is piecewise linear
  and increasing in delta, so it is solved exactly by sorting the gaps.

Approximations (stated, not hidden): slices are independent (no coupling of neighbouring slices through the tooth
body), contact outside the geometric path A..E (corner contact) is ignored, friction is neglected, and a helical
pair is treated in the transverse plane (contact lines cross the slices with the base-helix phase
y tan(beta_b)).

Lengths mm, deflections and modifications um, forces N, stresses MPa.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from ..errors import GearoptInputError, check_range
from ..geometry.pair import GearPair
from .microgeometry import Microgeometry, lead_deviation_um, misalignment_gap_um, profile_deviation_um

RAD2DEG = 180.0 / math.pi


@dataclass
class LTCAResult:
    """Outputs of one LTCA run (numpy arrays; ``positions`` rows in time order of the mesh cycle).

    ``transmission_error_um`` (positions,): loaded static TE along the line of action, + = driven gear lags.
    ``load_sharing`` (positions, pairs): fraction of the transmitted load carried by each tooth pair, pair 0 being
    the reference pair that enters at the first position.
    ``load_intensity_N_per_mm`` (positions, pairs, slices): load per unit face width (the thesis' LID).
    ``contact_stress_MPa`` (positions, pairs, slices): Hertzian line-contact stress (the thesis' CSD).
    ``roll_length_1_mm`` (positions, pairs): contact position on the path, as roll length on gear 1.
    """

    position_roll_deg: np.ndarray
    transmission_error_um: np.ndarray
    load_sharing: np.ndarray
    load_intensity_N_per_mm: np.ndarray
    contact_stress_MPa: np.ndarray
    roll_length_1_mm: np.ndarray
    slice_y_mm: np.ndarray
    transverse_force_N: float
    settings: dict = field(default_factory=dict)

    @property
    def ppte_um(self) -> float:
        """Peak-to-peak transmission error over the mesh cycle [um]."""
        return float(np.max(self.transmission_error_um) - np.min(self.transmission_error_um))

    @property
    def max_contact_stress_MPa(self) -> float:
        return float(np.max(self.contact_stress_MPa))

    @property
    def max_load_intensity_N_per_mm(self) -> float:
        return float(np.max(self.load_intensity_N_per_mm))

    @property
    def loaded_contact_ratio(self) -> float:
        """Mean number of tooth pairs carrying load over the cycle (a loaded contact ratio)."""
        return float(np.mean(np.sum(self.load_sharing > 1e-9, axis=1)))


def single_pair_stiffness_profile(kind, pair: GearPair) -> Callable[[np.ndarray], np.ndarray]:
    """Single-pair stiffness per unit face width c(s) [N/(mm*um)] as a function of the normalised path position
    s in [0, 1] (A -> E).

    - a number: constant c' (for analytic checks);
    - ``"iso6336"``: a parabola c'(1 - kappa (2s - 1)^2), peak c' (ISO 6336-1's single stiffness) at the middle of the
      path and kappa = 0.75 (1 - 1/eps_alpha) so that the mean mesh stiffness eps_alpha * mean(c) equals ISO's
      c_gamma_alpha = c'(0.75 eps_alpha + 0.25). An approximation consistent with both ISO values, not a
      position-resolved tooth model.
    """
    if isinstance(kind, (int, float)):
        check_range("stiffness", kind, 0.0, None, low_inclusive=False, unit="N/(mm*um)")
        c = float(kind)
        return lambda s: np.full(np.shape(s), c)
    if kind == "iso6336":
        from .stiffness import iso6336_stiffness

        iso = iso6336_stiffness(pair)
        c_single = float(iso["single_stiffness"])
        eps = float(pair.geometry()["transverse_contact_ratio"])
        kappa = 0.75 * (1.0 - 1.0 / eps)
        return lambda s: c_single * (1.0 - kappa * (2.0 * np.asarray(s) - 1.0) ** 2)
    raise GearoptInputError(f"stiffness={kind!r} must be a number [N/(mm*um)] or 'iso6336'")


def ltca(pair: GearPair, torque_Nm: float, *, driving_gear: int = 1, microgeometry: Microgeometry | None = None,
         stiffness: Any = "iso6336", positions: int = 40, slices: int | None = None, E_MPa: float = 206000.0,
         poisson: float = 0.3) -> LTCAResult:
    """Exact numeric LTCA of ``pair`` at ``torque_Nm`` on the driving gear over one base pitch.

    ``slices=None`` uses 1 slice for a spur pair without lead modification or misalignment (the load is uniform over
    the face) and 11 otherwise. ``E_MPa``/``poisson`` are those of both gears (Hertzian stress).
    """
    if pair.is_symbolic:
        raise GearoptInputError("ltca() is the numeric solver: give a numeric pair (the smooth CasADi form is "
                                "ltca_symbolic)")
    check_range("torque_Nm", torque_Nm, 0.0, None, unit="N*m")
    if driving_gear not in (1, 2):
        raise GearoptInputError(f"driving_gear={driving_gear!r} must be 1 or 2")
    check_range("positions", positions, 2, 100000)
    mods = microgeometry or Microgeometry()
    g = pair.geometry()
    spur = float(g["helix_angle_deg"]) == 0.0
    if slices is None:
        slices = 1 if spur and not mods.has_lead_modification else 11
    check_range("slices", slices, 1, 10000)
    b = min(g["face_width_mm"])
    d_b = g["base_diameter_mm"]
    p_bt = g["base_pitch_mm"]
    A, E = g["sap_roll_length_mm"][0], g["eap_roll_length_mm"][0]
    t1t2 = A + g["eap_roll_length_mm"][1]  # rho1 + rho2 = T1T2 at every contact point
    tan_beta_b = math.tan(math.radians(g["base_helix_angle_deg"]))
    y = (np.arange(slices) + 0.5) / slices * b - 0.5 * b
    db = b / slices
    eps_total = (E - A) / p_bt + b * abs(tan_beta_b) / p_bt
    k = np.arange(-int(math.ceil(eps_total)) - 1, int(math.ceil(eps_total)) + 2)

    # positions over one base pitch in time order; rho1 of the reference pair (k = 0) at slice y = -b/2
    s = np.arange(positions) / positions
    if driving_gear == 1:
        rho_ref = A - 0.5 * b * abs(tan_beta_b) + s * p_bt
        direction = 1.0
    else:
        rho_ref = E + 0.5 * b * abs(tan_beta_b) - s * p_bt
        direction = -1.0
    rho1 = (rho_ref[:, None, None] + direction * k[None, :, None] * p_bt
            + direction * (y[None, None, :] + 0.5 * b) * abs(tan_beta_b))  # (P, K, J)
    on_path = (rho1 >= A - 1e-12) & (rho1 <= E + 1e-12)
    rho2 = t1t2 - rho1
    roll1, roll2 = rho1 / (0.5 * d_b[0]) * RAD2DEG, rho2 / (0.5 * d_b[1]) * RAD2DEG
    sap = g["sap_roll_deg"]
    eap = g["eap_roll_deg"]
    gap = (profile_deviation_um(mods, 0, roll1, sap_roll_deg=sap[0], eap_roll_deg=eap[0], base_diameter_mm=d_b[0])
           + profile_deviation_um(mods, 1, roll2, sap_roll_deg=sap[1], eap_roll_deg=eap[1], base_diameter_mm=d_b[1])
           + lead_deviation_um(mods, 0, y, b) + lead_deviation_um(mods, 1, y, b) + misalignment_gap_um(mods, y, b))
    gap = np.broadcast_to(np.asarray(gap, dtype=float), rho1.shape)
    c = single_pair_stiffness_profile(stiffness, pair)(np.clip((rho1 - A) / (E - A), 0.0, 1.0))
    spring = np.where(on_path, c * db, 0.0)  # N/um per slice
    force = torque_Nm * 1000.0 / (0.5 * d_b[driving_gear - 1])  # transverse force on the base circle [N]
    delta = _solve_approach(np.where(on_path, gap, np.inf).reshape(positions, -1),
                            spring.reshape(positions, -1), force)
    w = spring * np.maximum(delta[:, None, None] - gap, 0.0) / db  # N/mm per slice
    w = np.where(on_path, w, 0.0)
    pair_load = w.sum(axis=2) * db
    sharing = pair_load / force if force > 0 else np.zeros_like(pair_load)
    sigma = _hertz_stress(w, rho1, rho2, math.radians(g["base_helix_angle_deg"]), E_MPa, poisson)
    return LTCAResult(position_roll_deg=rho_ref / (0.5 * d_b[0]) * RAD2DEG, transmission_error_um=delta,
                      load_sharing=sharing, load_intensity_N_per_mm=w, contact_stress_MPa=sigma,
                      roll_length_1_mm=rho1[:, :, 0], slice_y_mm=y, transverse_force_N=force,
                      settings={"positions": positions, "slices": slices, "stiffness": stiffness,
                                "driving_gear": driving_gear, "pair_index": k.tolist()})


def _solve_approach(gaps: np.ndarray, springs: np.ndarray, force: float) -> np.ndarray:
    """Solve sum_i s_i max(delta - e_i, 0) = force for delta, row by row, exactly.

    With the gaps sorted, the left side is S_m delta - Q_m on [e_m, e_m+1] (S, Q cumulative sums of s and s e);
    the first segment whose right end carries at least ``force`` holds the root.
    """
    order = np.argsort(gaps, axis=1)
    e = np.take_along_axis(gaps, order, axis=1)
    s = np.take_along_axis(springs, order, axis=1)
    finite = np.isfinite(e)
    e_f = np.where(finite, e, 0.0)
    S = np.cumsum(s, axis=1)
    Q = np.cumsum(s * e_f, axis=1)
    e_next = np.concatenate([e[:, 1:], np.full((e.shape[0], 1), np.inf)], axis=1)
    with np.errstate(invalid="ignore"):
        carried = np.where(np.isinf(e_next), np.inf, S * e_next - Q)
    if np.any(S[:, -1] <= 0):
        raise GearoptInputError("LTCA: no tooth pair is in contact at some mesh position (contact ratio < 1?)")
    m = np.argmax(carried >= force, axis=1)
    rows = np.arange(e.shape[0])
    S_m, Q_m = S[rows, m], Q[rows, m]
    return (force + Q_m) / S_m


def _hertz_stress(w, rho1, rho2, beta_b, E_MPa, poisson):
    """Hertzian line-contact stress sqrt(w / (pi rho_red) * E_r/2) with w the load per unit contact length [N/mm]
    (for a helical pair w_t per face width equals the normal load per unit contact-line length), radii of curvature
    in the normal plane rho_i / cos(beta_b), E_r/2 = 1/((1-nu^2)/E * 2) for equal materials."""
    r1 = np.maximum(rho1, 1e-9) / math.cos(beta_b)
    r2 = np.maximum(rho2, 1e-9) / math.cos(beta_b)
    rho_red = r1 * r2 / (r1 + r2)
    e_term = 1.0 / (2.0 * (1.0 - poisson ** 2) / E_MPa)
    return np.sqrt(np.maximum(w, 0.0) * e_term / (math.pi * rho_red))


__all__ = ["ltca", "LTCAResult", "single_pair_stiffness_profile"]
