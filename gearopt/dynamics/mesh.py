"""Gear mesh force of the torsional model: time-varying stiffness, viscous damping and backlash, dual-typed.

Coordinates. A mesh joins gear 1 (driving) and gear 2. Its deflection along the transverse line of action is
``delta = s1 (r_b1 phi_1 + r_b2 phi_2)`` [m], where ``phi_i`` are the gears' angular deviations from the nominal
(rigid, constant-speed) rotation in the network's common sign convention and ``s1 = +-1`` is the sense of gear 1's
nominal rotation. For an external mesh the rigid rotation gives ``r_b1 phi_1 = -r_b2 phi_2``, i.e. ``delta = 0``;
``delta > 0`` compresses the *drive* flanks (gear 1 ahead of gear 2 in its sense of rotation, the flanks that carry
the load when gear 1 drives), ``delta < -j`` closes the backlash ``j`` [m, along the line of action] and loads the
*back* (coast) flanks. ``delta`` is the dynamic transmission error along the line of action.

Force (Kahraman & Singh 1990, J. Sound Vib. 142(1):49, dead-zone model; damping active only in contact):

* no lash (linear option): ``F = k(psi) delta + c delta_dot``;
* lash: ``F_drive = k(psi) sp(delta) + c delta_dot sig_d(delta)``,
  ``F_back = k(psi) sp(-(delta + j)) - c delta_dot sig_d(-(delta + j))``, ``F = F_drive - F_back``,

with ``sp`` = :func:`gearopt.numerics.softplus` of a stated physical width ``w`` [m] (the smooth dead zone; force
error at the contact point ``k w ln 2``, converges to the exact dead zone as ``w -> 0``, tested) and ``sig_d`` =
:func:`gearopt.numerics.sigmoid` of the damping width ``w_d`` (the dashpot engages over about the lubricant film
thickness, see :func:`mesh_force`). Because ``sp(x) - sp(-x) = x`` and ``sig(x) + sig(-x) = 1`` exactly, the lash
model with ``j = 0`` *is* the linear model, for every width. Flank forces can become slightly tensile while a
contact opens fast (the dashpot acts until ``delta`` returns to 0, as in the Kelvin-Voigt contact); the outputs
report them as computed.

Stiffness over the mesh phase: ``k(psi) = k_mean (1 + a v(psi))`` with ``k_mean`` the ISO 6336-1 mean mesh
stiffness ``c_gamma_alpha b`` (:func:`gearopt.rating.stiffness.iso6336_stiffness`), ``a`` the variation amplitude
(1 = full shape, 0 = constant) and ``v`` a zero-mean, ``2 pi``-periodic shape of the mesh angle ``psi = z1 theta_1``
(one period per tooth). Default shape (:meth:`MeshStiffnessShape.from_contact_ratios`): proportional to the total
length of the contact lines in the plane of action -- the thesis' approach (sec. 3.6, Eqs. 3.22-3.23: stiffness =
constant x contact-line length) -- as a Lanczos-smoothed truncated Fourier series (smooth for the integrator).
Any periodic shape (e.g. the LTCA's stiffness over the mesh cycle) enters through
:meth:`MeshStiffnessShape.from_samples`. Units: SI inside (m, N/m, N s/m, N, rad).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import numerics as nm
from ..errors import GearoptInputError
from ..geometry.forces import axial_force_N  # noqa: F401 -- the thrust F_bt tan(beta_b) of a mesh force; re-exported
from ..validation import check_range

#: Default width of the smooth dead zone [m] (0.05 um; force error at first touch k w ln 2 ~ 20 N at 5.5e8 N/m).
DEFAULT_CONTACT_WIDTH_M = 0.05e-6
#: Default width over which the mesh dashpot engages [m] ([E] 0.5 um, about an EHL film thickness of gear teeth).
DEFAULT_DAMPING_WIDTH_M = 0.5e-6
#: Default number of harmonics of the stiffness shape (mesh orders 1..5).
DEFAULT_HARMONICS = 5
_SHAPE_SAMPLES = 4096


# ----------------------------------------------------------------------------------------------------------------
# stiffness shape over the mesh phase
# ----------------------------------------------------------------------------------------------------------------

def contact_line_length_ratio(mesh_phase, transverse_contact_ratio: float, overlap_contact_ratio: float = 0.0):
    """Total contact-line length over the mesh cycle divided by its mean (dimensionless, mean 1), numeric.

    ``mesh_phase`` in base pitches (period 1; array), ``transverse_contact_ratio`` eps_alpha > 1,
    ``overlap_contact_ratio`` eps_beta >= 0. In the plane of action the field of contact is eps_alpha base pitches
    long and one face width wide; each contact line spans eps_beta base pitches along the path across the face (its
    inclination at the base helix angle) and the lines follow one base pitch apart. The length inside the field is
    summed over all lines; its mean over the cycle is eps_alpha (times b / cos beta_b), so the ratio has mean 1.
    Spur gears (eps_beta = 0) give the rectangular single/double-pair wave (ratios floor/eps and ceil/eps); an
    integer eps_beta gives a constant length (classical result, e.g. ISO 21771 plane of action).
    """
    check_range("transverse_contact_ratio", transverse_contact_ratio, 1.0, None, low_inclusive=False)
    check_range("overlap_contact_ratio", overlap_contact_ratio, 0.0, None)
    u = np.mod(np.atleast_1d(np.asarray(mesh_phase, dtype=float)), 1.0)
    ea, eb = float(transverse_contact_ratio), float(overlap_contact_ratio)
    k = np.arange(-1, int(math.ceil(ea + eb)) + 2)
    s = u[:, None] + k[None, :]  # leading end of each line (at face position 0), base pitches along the path
    if eb == 0.0:
        inside = ((s >= 0.0) & (s < ea)).astype(float)
    else:  # face fraction y in [0, 1] with 0 <= s - eb y <= ea
        y_lo = np.clip((s - ea) / eb, 0.0, 1.0)
        y_hi = np.clip(s / eb, 0.0, 1.0)
        inside = np.clip(y_hi - y_lo, 0.0, None)
    return inside.sum(axis=1) / ea


@dataclass(frozen=True)
class MeshStiffnessShape:
    """Zero-mean periodic stiffness shape ``v(psi) = sum_k a_k cos(k psi) + b_k sin(k psi)`` of the mesh angle.

    ``cos_coefficients``/``sin_coefficients`` (orders 1..n) are dimensionless (fractions of the mean stiffness);
    ``description`` says where they come from. :meth:`factor` gives ``1 + amplitude v(psi)``, dual-typed.
    """

    cos_coefficients: tuple = ()
    sin_coefficients: tuple = ()
    description: str = "constant mean stiffness"

    def __post_init__(self):
        if len(self.cos_coefficients) != len(self.sin_coefficients):
            raise GearoptInputError("cos_coefficients and sin_coefficients must have the same length (orders 1..n)")

    @property
    def harmonics(self) -> int:
        return len(self.cos_coefficients)

    @classmethod
    def constant(cls) -> MeshStiffnessShape:
        """No variation: the mean stiffness throughout the cycle."""
        return cls()

    @classmethod
    def from_samples(cls, mesh_angle_rad, stiffness, harmonics: int = DEFAULT_HARMONICS, smoothing: str = "lanczos",
                     description: str = "fitted to samples") -> MeshStiffnessShape:
        """Fit the shape to samples of stiffness over one mesh cycle (any units; normalised by their mean).

        ``mesh_angle_rad``: equally spaced angles covering one period ``[0, 2 pi)`` (endpoint excluded);
        ``stiffness``: values there (e.g. the LTCA's mesh stiffness over the mesh cycle). The first ``harmonics``
        Fourier coefficients of ``stiffness/mean - 1`` are kept, multiplied by Lanczos sigma factors
        ``sinc(k/(n+1))`` (``smoothing="lanczos"``, damps the Gibbs ripple of a truncated square wave) or not
        (``"none"``).
        """
        psi = np.asarray(mesh_angle_rad, dtype=float).reshape(-1)
        k_s = np.asarray(stiffness, dtype=float).reshape(-1)
        if psi.size != k_s.size or psi.size < 2 * harmonics + 2:
            raise GearoptInputError(f"need matching samples, at least 2*harmonics+2 = {2 * harmonics + 2}; got "
                                    f"{psi.size} angles and {k_s.size} stiffness values")
        step = np.diff(psi)
        if np.any(step <= 0) or not np.allclose(step, 2 * np.pi / psi.size, rtol=1e-6, atol=1e-12):
            raise GearoptInputError("mesh_angle_rad must be equally spaced over one period [0, 2 pi), endpoint "
                                    "excluded")
        if smoothing not in ("lanczos", "none"):
            raise GearoptInputError(f"smoothing={smoothing!r} must be 'lanczos' or 'none'")
        check_range("harmonics", harmonics, 0, None)
        mean = float(np.mean(k_s))
        if not mean > 0:
            raise GearoptInputError(f"mean stiffness of the samples is {mean!r}; must be > 0")
        v = k_s / mean - 1.0
        a, b = [], []
        for order in range(1, int(harmonics) + 1):
            sigma = float(np.sinc(order / (harmonics + 1.0))) if smoothing == "lanczos" else 1.0
            a.append(sigma * 2.0 * float(np.mean(v * np.cos(order * psi))))
            b.append(sigma * 2.0 * float(np.mean(v * np.sin(order * psi))))
        return cls(tuple(a), tuple(b), description)

    @classmethod
    def from_contact_ratios(cls, transverse_contact_ratio: float, overlap_contact_ratio: float = 0.0,
                            harmonics: int = DEFAULT_HARMONICS) -> MeshStiffnessShape:
        """Stiffness proportional to the total contact-line length (:func:`contact_line_length_ratio`), i.e. the
        thesis' line-of-contact stiffness (sec. 3.6, Eqs. 3.22-3.23) over the mesh cycle, normalised to mean 1 and
        smoothed to ``harmonics`` Lanczos-weighted Fourier orders. Mesh angle 0: a new pair enters contact."""
        psi = 2.0 * np.pi * np.arange(_SHAPE_SAMPLES) / _SHAPE_SAMPLES
        ratio = contact_line_length_ratio(psi / (2.0 * np.pi), transverse_contact_ratio, overlap_contact_ratio)
        return cls.from_samples(psi, ratio, harmonics, "lanczos", f"contact-line length, eps_alpha="
                                f"{transverse_contact_ratio:.4f}, eps_beta={overlap_contact_ratio:.4f}, "
                                f"{harmonics} harmonics")

    def variation(self, mesh_angle_rad):
        """Zero-mean shape ``v(psi)`` (dimensionless), dual-typed."""
        total = 0.0 * mesh_angle_rad
        for order, (a, b) in enumerate(zip(self.cos_coefficients, self.sin_coefficients), start=1):
            total = total + a * nm.cos(order * mesh_angle_rad) + b * nm.sin(order * mesh_angle_rad)
        return total

    def factor(self, mesh_angle_rad, amplitude=1.0):
        """Stiffness factor ``1 + amplitude v(psi)`` (k(psi) / k_mean), dual-typed."""
        return 1.0 + amplitude * self.variation(mesh_angle_rad)


# ----------------------------------------------------------------------------------------------------------------
# mesh force
# ----------------------------------------------------------------------------------------------------------------

def mesh_force(deflection_m, deflection_rate_m_s, stiffness_N_per_m, damping_N_s_per_m, backlash_m=None,
               contact_width_m=DEFAULT_CONTACT_WIDTH_M, damping_width_m=None) -> dict:
    """Force of a gear mesh along the line of action [N] (module docstring: coordinates and sources), dual-typed.

    ``deflection_m`` delta [m] (> 0 loads the drive flanks), ``deflection_rate_m_s`` d(delta)/dt [m/s],
    ``stiffness_N_per_m`` k (may already include the variation over the mesh phase), ``damping_N_s_per_m`` c,
    ``backlash_m`` j >= 0 along the line of action, or ``None`` for the linear no-lash model,
    ``contact_width_m`` w > 0 of the smooth dead zone, ``damping_width_m`` w_d > 0 over which the dashpot engages
    (default ``w``; see below).

    Returns a dict: ``force_N`` (signed, drive flanks positive), ``drive_force_N`` and ``back_force_N`` (flank
    forces, positive when pressed), ``drive_contact`` and ``back_contact`` (smooth contact indicators in [0, 1]; for
    the linear model the indicators are 1 and 0 and the flank forces are the positive and negative parts of F).
    Validity: small deflections (linear tooth compliance), external spur/helical meshes, one flank pair at a time
    per side.

    The gate ``sig(delta, w_d)`` of the dashpot adds ``c delta_dot / (4 w_d)`` to the force slope at the contact
    edge -- a negative stiffness while a contact opens. With ``w_d`` of a few nanometres it exceeds the tooth
    stiffness by orders of magnitude and stalls implicit integrators; a ramp of the order of the lubricant film
    thickness (0.1-1 um) keeps it below the mesh stiffness. ``w_d -> 0`` gives the Kelvin-Voigt contact.
    """
    check_range("stiffness_N_per_m", stiffness_N_per_m, 0.0, None, unit="N/m")
    check_range("damping_N_s_per_m", damping_N_s_per_m, 0.0, None, unit="N s/m")
    k, c, d, dd = stiffness_N_per_m, damping_N_s_per_m, deflection_m, deflection_rate_m_s
    if backlash_m is None:
        f = k * d + c * dd
        return {"force_N": f, "drive_force_N": nm.fmax(f, 0.0), "back_force_N": nm.fmax(-f, 0.0),
                "drive_contact": 1.0 + 0.0 * f, "back_contact": 0.0 * f}
    check_range("backlash_m", backlash_m, 0.0, None, unit="m")
    check_range("contact_width_m", contact_width_m, 0.0, None, low_inclusive=False, unit="m")
    w = contact_width_m
    wd = w if damping_width_m is None else damping_width_m
    check_range("damping_width_m", wd, 0.0, None, low_inclusive=False, unit="m")
    back_gap = -(d + backlash_m)
    s_drive, s_back = nm.sigmoid(d, w), nm.sigmoid(back_gap, w)
    g_drive, g_back = (s_drive, s_back) if damping_width_m is None else (nm.sigmoid(d, wd), nm.sigmoid(back_gap, wd))
    drive = k * nm.softplus(d, w) + c * dd * g_drive
    back = k * nm.softplus(back_gap, w) - c * dd * g_back
    return {"force_N": drive - back, "drive_force_N": drive, "back_force_N": back,
            "drive_contact": s_drive, "back_contact": s_back}


def restitution_coefficient(damping_ratio):
    """Coefficient of restitution of a linear spring-dashpot (Kelvin-Voigt) contact that ends when the deflection
    returns to zero: ``e = exp(-pi zeta / sqrt(1 - zeta^2))``, ``zeta = c / (2 sqrt(k m))`` < 1 (dimensionless).
    It is the velocity ratio over half a period of the damped oscillator: the classical linear spring-dashpot result
    with the contact ending when the overlap returns to zero (Schwager & Poeschel 2007, Granular Matter 9:465, who
    note that ending the contact when the *force* vanishes gives a different value; Feng 2026, arXiv:2603.27764,
    case p = 1). The lash model gates its dashpot by the overlap, so this is its limit for ``w -> 0``."""
    check_range("damping_ratio", damping_ratio, 0.0, 1.0, high_inclusive=False)
    return math.exp(-math.pi * damping_ratio / math.sqrt(1.0 - damping_ratio ** 2))


__all__ = ["DEFAULT_CONTACT_WIDTH_M", "DEFAULT_DAMPING_WIDTH_M", "DEFAULT_HARMONICS", "contact_line_length_ratio", "MeshStiffnessShape",
           "mesh_force", "axial_force_N", "restitution_coefficient"]
