"""Mesh stiffness over the mesh cycle from the exact loaded tooth contact analysis (LTCA), for the dynamic model.

Definition (static, along the transverse line of action): at each mesh position the LTCA
(:func:`gearopt.contact.ltca.ltca`) gives the loaded static transmission error ``TE`` [um] under the transverse
base-circle force ``F = T / r_b1`` [N]. Its elastic part is ``TE - TE_kin``, with ``TE_kin`` the unloaded
kinematic TE of the microgeometry (the smallest initial gap of a spring on the path at that position: the approach
at which the first tooth pair touches; 0 for unmodified flanks). The mesh stiffness is the secant
``k(psi) = F / (TE - TE_kin)`` [N/um -> N/m]: the load per elastic approach of the gear pair at that mesh position,
which is what the dynamic mesh force ``k(psi) delta`` uses. With tip relief or crowning the secant depends on the
load (more pairs come into contact as the load rises), so the stiffness belongs to the torque it was computed at.

Tooth compliance: ``stiffness="potential_energy"`` (default) is the position-resolved tooth model
(:mod:`gearopt.contact.potential_energy`: Hertz, bending, shear, axial compression, fillet foundation -- Sainsot
et al. 2004, Chen & Shao 2011), independent of ISO 6336-1, so its mean can be compared with ISO's
``c_gamma_alpha b``; ``"iso6336"`` reproduces ISO's mean by construction (a parabola over the path scaled to it).
The mesh angle ``psi`` is ``2 pi`` per base pitch with 0 where the LTCA's reference pair enters contact (the same
origin as :meth:`~gearopt.dynamics.mesh.MeshStiffnessShape.from_contact_ratios`). Units: mm, um, N, N m at the
surface of the LTCA; N/m for the stiffness.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import GearoptInputError
from ..validation import check_range
from .mesh import DEFAULT_HARMONICS, MeshStiffnessShape


def ltca_mesh_stiffness(pair, torque_Nm: float, *, microgeometry=None, stiffness: str = "potential_energy",
                        positions: int | None = None, slices: int | None = None,
                        harmonics: int = DEFAULT_HARMONICS) -> dict:
    """Mesh stiffness of ``pair`` over one mesh cycle from the exact LTCA at ``torque_Nm`` [N m] on gear 1
    (module docstring: definition ``k = F / (TE - TE_kin)``).

    ``microgeometry`` (:class:`gearopt.contact.microgeometry.Microgeometry`, default none), ``stiffness`` the
    LTCA's tooth model, ``positions``/``slices`` its resolution (defaults of :func:`gearopt.contact.ltca.ltca`),
    ``harmonics`` of the fitted :class:`~gearopt.dynamics.mesh.MeshStiffnessShape` (Lanczos-smoothed).

    Returns a dict: ``mesh_angle_rad`` (positions,), ``stiffness_N_per_m`` (positions,), ``mean_stiffness_N_per_m``,
    ``shape`` (the fitted shape, mean 1), ``transmission_error_um`` (loaded), ``kinematic_te_um``,
    ``transverse_force_N``, ``torque_Nm``, ``settings`` (of the LTCA). Valid for a loaded mesh (torque > 0, the
    drive flanks in contact at every position).
    """
    from ..contact.ltca import ltca
    from ..contact.microgeometry import Microgeometry

    check_range("torque_Nm", torque_Nm, 0.0, None, low_inclusive=False, unit="N m")
    mods = microgeometry or Microgeometry()
    res = ltca(pair, float(torque_Nm), microgeometry=mods, stiffness=stiffness, positions=positions, slices=slices)
    lay = res.layout
    gaps = np.where(lay.on_path, np.asarray(lay.gaps_um(mods), dtype=float), np.inf)
    kinematic = gaps.reshape(gaps.shape[0], -1).min(axis=1)
    elastic = np.asarray(res.transmission_error_um, dtype=float) - kinematic
    if not np.all(np.isfinite(elastic)) or np.any(elastic <= 0.0):
        raise GearoptInputError(f"LTCA of {getattr(pair, 'names', pair)!r} at {torque_Nm} N m: a position without "
                                f"elastic approach (min {np.min(elastic):.3g} um); the mesh must stay loaded")
    k = res.transverse_force_N / elastic * 1e6  # N/um -> N/m
    n = k.size
    psi = 2.0 * math.pi * np.arange(n) / n
    shape = MeshStiffnessShape.from_samples(psi, k, harmonics, "lanczos",
                                            f"LTCA ({stiffness}) secant stiffness at {torque_Nm:g} N m, "
                                            f"{harmonics} harmonics")
    return {"mesh_angle_rad": psi, "stiffness_N_per_m": k, "mean_stiffness_N_per_m": float(np.mean(k)),
            "shape": shape, "transmission_error_um": np.asarray(res.transmission_error_um, dtype=float),
            "kinematic_te_um": kinematic, "transverse_force_N": float(res.transverse_force_N),
            "torque_Nm": float(torque_Nm), "settings": dict(res.settings)}


__all__ = ["ltca_mesh_stiffness"]
