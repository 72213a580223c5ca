"""Smooth, differentiable LTCA: the physics of :mod:`gearopt.contact.ltca` as a CasADi model for Ipopt.

Same discretisation (:func:`gearopt.contact.layout.mesh_layout`) and the same compliance model as the exact solver;
the one change is the contact law. Where the exact solver loads a spring by ``c db max(delta - e, 0)`` (no tensile
loads), the smooth form uses ``c db softplus(delta - e, w)`` with a width ``w`` in um (``numerics.softplus``:
overflow-free, an upper bound of ``max`` with error at most ``w ln 2``). At each position the approach ``delta``
solves ``sum c db softplus(delta - e, w) = F_bt``; the left side is convex and increasing in ``delta``, so Newton's
method started right of the root (``max e + F/sum(c db)``) converges monotonically. The root is a CasADi
``rootfinder`` (derivatives by the implicit function theorem), built once per model as a ``casadi.Function`` and
mapped over the positions (and load cases for a Harris map). The *lifted* form (:meth:`LTCAModel.evaluate` with
``approach_um``) leaves the root to the NLP instead: the approaches are its variables and the force balance its
equality constraints.

Convergence to the exact solver as ``w -> 0``: the smooth approach lies below the exact one by at most ``w ln 2``
(every softplus over-estimates its spring's load by at most ``c db w ln 2``), so TE and PPTE converge linearly in
``w`` (tested).

Loaded contact ratio: the exact solver counts the loaded contact length over the face width
(``sum (l_j / b) [delta - e_j > 0]`` with ``l_j`` each spring's engaged face length); the smooth form replaces the step by ``numerics.sigmoid`` with its own width
``count_width_um`` (a pair counts as half-loaded where its gap is exactly closed).

Inputs: a numeric pair; microgeometry amounts/starts and the torque numeric or CasADi ``MX``. Outputs are numpy
arrays for numeric inputs and CasADi ``MX`` expressions otherwise. Units as in the exact solver (um, N, N/mm, MPa).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import numerics as nm
from ..errors import GearoptInputError, NumericalSolveError
from ..validation import check_int, check_range
from .validity import check_ltca_inputs, check_ltca_size
from ..geometry.pair import GearPair
from .layout import MeshLayout, hertz_stress_factor, mesh_layout, position_fractions
from .microgeometry import Microgeometry

DEFAULT_SMOOTHING_UM = 0.05
LIFTED_OFF_PATH_GAP_UM = 1e4
"""Gap given to springs off the path of contact in the lifted form's smooth minimum (they never close)."""
DEFAULT_COUNT_WIDTH_UM = 0.25


@dataclass
class SmoothLTCAResult:
    """Outputs of one smooth LTCA evaluation (numpy arrays, or CasADi MX for symbolic inputs).

    ``transmission_error_um`` (P,) [or (P, L) for L load cases]; ``load_intensity_N_per_mm``,
    ``contact_stress_squared_MPa2`` and ``closure_um`` are (N, P[*L]) with N = pairs x slices springs per position
    (pair-major); ``load_sharing`` (K, P[*L]); ``loaded_pairs`` (P[*L],) loaded contact length / face width.
    """

    transmission_error_um: Any
    closure_um: Any
    load_intensity_N_per_mm: Any
    contact_stress_squared_MPa2: Any
    load_sharing: Any
    loaded_pairs: Any
    layout: MeshLayout
    torque_Nm: Any
    root_stress_MPa: Any = None            # (gear 1, gear 2), each (N, P[*L]), when the model was built for it
    flash_temperature_rise_K: Any = None   # (N, P[*L]) when the model has a speed
    bulk_temperature_C: Any = None
    approach_residual_N: Any = None        # (1, P*L) force balance of the lifted form (evaluate(approach_um=...))
    approach_floor_um: Any = None          # (1, P*L) approach above the smallest gap (smooth), lifted form

    @property
    def max_root_stress_MPa(self) -> tuple[float, float]:
        if self.root_stress_MPa is None:
            raise GearoptInputError("root stress not computed: build the LTCAModel with root_stress=True")
        return tuple(float(np.max(np.asarray(r, dtype=float))) for r in self.root_stress_MPa)

    @property
    def max_flash_temperature_C(self) -> float:
        if self.flash_temperature_rise_K is None:
            raise GearoptInputError("flash temperature not computed: build the LTCAModel with speed_rpm")
        return self.bulk_temperature_C + float(np.max(np.asarray(self.flash_temperature_rise_K, dtype=float)))

    @property
    def contact_stress_MPa(self):
        """Hertzian contact stress of every spring [MPa] (guarded sqrt: finite derivatives at zero load)."""
        return nm.sqrt_safe(self.contact_stress_squared_MPa2, 1e-12)

    @property
    def loaded_contact_ratio(self):
        """Mean of ``loaded_pairs`` over the positions (per load case for a Harris map)."""
        return _mean_over_positions(self.loaded_pairs, self.layout.positions)

    @property
    def ppte_um(self):
        """Exact peak-to-peak TE of numeric results [um] (per load case for several torques). For an NLP use the
        epigraph form instead (``t_hi >= TE_p >= t_lo``, minimise ``t_hi - t_lo``)."""
        te = self.transmission_error_um
        if nm.is_symbolic(te):
            raise GearoptInputError("ppte_um of a symbolic LTCA is not smooth: bound the TE with epigraph variables "
                                    "(see gearopt.design.microgeometry_nlp)")
        te = np.asarray(te, dtype=float)
        return float(np.ptp(te)) if te.ndim == 1 else np.ptp(te, axis=0)

    @property
    def max_contact_stress_MPa(self):
        return float(np.sqrt(np.max(np.asarray(self.contact_stress_squared_MPa2, dtype=float))))


def _mean_over_positions(v, P):
    if nm.is_casadi(v):
        n = v.numel()
        return nm.column_sum(nm.reshape(v, P, n // P)) / P
    v = np.asarray(v, dtype=float)
    return float(np.mean(v)) if v.size == P else np.mean(v.reshape(-1, P), axis=1)


class LTCAModel:
    """Smooth LTCA of one numeric pair, discretised and built once, evaluated for any microgeometry and torque.

    ``slices=None``: 1 slice for a spur pair unless ``lead_modification=True`` (lead crown, slope or misalignment
    will be given), else 11. ``smoothing_um`` is the softplus width of the contact law, ``count_width_um`` the
    sigmoid width of the loaded-contact count.
    """

    def __init__(self, pair: GearPair, *, driving_gear: int = 1, stiffness: Any = "iso6336", positions: int = 40,
                 slices: int | None = None, lead_modification: bool = False,
                 smoothing_um: float = DEFAULT_SMOOTHING_UM, count_width_um: float = DEFAULT_COUNT_WIDTH_UM,
                 E_MPa: float = 206000.0, poisson: float = 0.3, root_stress: bool = False,
                 speed_rpm: float | None = None, bulk_temperature_C: float = 100.0,
                 friction_coefficient: float = 0.06, materials: Any = "20MnCr5",
                 sliding_smoothing_m_s: float = 0.01) -> None:
        check_range("smoothing_um", smoothing_um, 0.0, None, low_inclusive=False, unit="um")
        check_range("count_width_um", count_width_um, 0.0, None, low_inclusive=False, unit="um")
        check_ltca_inputs(pair, driving_gear, E_MPa, poisson, bulk_temperature_C, friction_coefficient)
        if slices is None:
            spur = float(pair.geometry()["helix_angle_deg"]) == 0.0
            slices = 1 if spur and not lead_modification else 11
        check_ltca_size(pair, position_fractions(positions).size, check_int("slices", slices, 1, 10000))
        self.layout = mesh_layout(pair, driving_gear=driving_gear, positions=positions, slices=slices,
                                  stiffness=stiffness, E_MPa=E_MPa, poisson=poisson)
        self.smoothing_um = float(smoothing_um)
        self.count_width_um = float(count_width_um)
        self.E_MPa = float(E_MPa)
        lay = self.layout
        P, N = lay.positions, lay.springs_per_position
        self._springs = lay.spring_N_per_um.reshape(P, N).T            # (N, P)
        self._on_path = lay.on_path.reshape(P, N).T.astype(float)        # (N, P)
        self._engaged_length = np.where(lay.on_path, lay.engaged_length_mm, 1.0).reshape(P, N).T   # (N, P) mm
        self._stress_factor = hertz_stress_factor(lay, E_MPa, poisson).reshape(P, N).T
        self._stiffness_sum = self._springs.sum(axis=0)                 # (P,)
        if np.any(self._stiffness_sum <= 0):
            raise GearoptInputError("LTCA: no tooth pair is in contact at some mesh position (contact ratio < 1?)")
        w = self.smoothing_um

        def residual(x, p):
            e, s, force = p[:N], p[N:2 * N], p[2 * N]
            return nm.column_sum(s * nm.softplus(x - e, w)) - force

        self.approach_kernel = nm.implicit_scalar_root("ltca_approach", residual, 2 * N + 1)
        self.root_stress = bool(root_stress)
        self.speed_rpm = speed_rpm
        self._thermal = None
        on = lay.on_path
        if self.root_stress:
            from ..rating.root_stress import virtual_roll_length_mm

            mid = 0.5 * (lay.rho1_mm[on].min() + lay.rho1_mm[on].max())
            rho1 = np.where(on, lay.rho1_mm, mid)
            rho2 = np.where(on, lay.rho2_mm, lay.rho1_mm[on].min() + lay.rho2_mm[on].max() - mid)
            self._virtual_roll = tuple(virtual_roll_length_mm(lay.pair, g, r).reshape(P, N).T
                                       for g, r in ((1, rho1), (2, rho2)))
        if speed_rpm is not None:
            from ..rating.materials import material_pair
            from .tip_relief import plane_strain_compliance_per_MPa

            check_range("speed_rpm", speed_rpm, 0.0, None, unit="rpm")
            drive = driving_gear - 1
            teeth = pair.teeth
            omega = [0.0, 0.0]
            omega[drive] = speed_rpm * 2.0 * np.pi / 60.0
            omega[1 - drive] = omega[drive] * teeth[drive] / teeth[1 - drive]
            cb = np.cos(lay.base_helix_angle_rad)
            v1 = np.where(on, omega[0] * lay.rho1_mm * 1e-3, 0.0).reshape(P, N).T
            v2 = np.where(on, omega[1] * lay.rho2_mm * 1e-3, 0.0).reshape(P, N).T
            curvature = np.where(on, 0.5 * cb / np.maximum(lay.rho1_mm, 1e-9) + 0.5 * cb
                                 / np.maximum(lay.rho2_mm, 1e-9), 1.0).reshape(P, N).T
            m1, m2 = material_pair(materials)
            self._thermal = dict(v1=v1, v2=v2, curvature=curvature, bulk=float(bulk_temperature_C),
                                 friction=float(friction_coefficient), sliding=float(sliding_smoothing_m_s),
                                 compliance=2.0 * plane_strain_compliance_per_MPa(E_MPa, poisson),
                                 B=(m1.thermal_contact_coefficient_N_per_mm_sqrt_s_K,
                                    m2.thermal_contact_coefficient_N_per_mm_sqrt_s_K))
        self._maps: dict[int, Any] = {}
        self.builds = {"approach_kernel": 1, "maps": 0}

    @property
    def thermal_contact_coefficients(self) -> tuple[float, float] | None:
        """B_M of both gears [N/(mm s^0.5 K)] used by the flash temperature (None without ``speed_rpm``)."""
        return None if self._thermal is None else tuple(float(b) for b in self._thermal["B"])

    def _approach_map(self, n: int):
        if n not in self._maps:
            self._maps[n] = self.approach_kernel.map(n)
            self.builds["maps"] += 1
        return self._maps[n]

    def gaps_um(self, microgeometry: Microgeometry):
        """Initial gaps (N, P) [um] of ``microgeometry`` (numpy or MX)."""
        lay = self.layout
        g = lay.gaps_um(microgeometry)
        P, N = lay.positions, lay.springs_per_position
        if nm.is_casadi(g):
            return nm.reshape(g, N, P)
        return np.asarray(g, dtype=float).reshape(P, N).T

    def evaluate(self, microgeometry: Microgeometry | None = None, torque_Nm: Any = 0.0, *,
                 stiffness_factor: Any = 1.0, E_MPa: Any = None, speed_rpm: Any = None,
                 thermal_contact_coefficients: Any = None, face_width_mm: Any = None,
                 approach_um: Any = None) -> SmoothLTCAResult:
        """Smooth LTCA at ``torque_Nm`` (a scalar, or a 1-D sequence of L load cases: the outputs then hold the
        load cases side by side, position-major within each case).

        Data the model was built with may be given again here, numeric or CasADi-symbolic (a parameter of an NLP,
        for parametric sensitivities); each enters exactly as it does at build time, without rebuilding:

        - ``stiffness_factor``: multiplies every spring (the single-pair stiffness c' scaled, shape kept);
        - ``E_MPa``: Young's modulus of the Hertz contact stress (sigma_H^2 proportional to E) and of the Hertz
          half-width of the flash temperature; the springs keep the build's stiffness (with ``stiffness="iso6336"``
          they do not depend on E: ISO 6336-1's c' is the steel value);
        - ``speed_rpm`` of the driving gear (the rolling speeds scale with it); ``thermal_contact_coefficients``
          (B_M1, B_M2) [N/(mm s^0.5 K)]: both need a model built with ``speed_rpm``;
        - ``face_width_mm``: the contact face width of a model with one face slice (a spur pair without lead
          modifications: the springs scale with the width, the load per unit width falls with it); a helical
          pair's contact lines change with the width, so it needs a new model.

        ``approach_um`` (symbolic evaluations only): the approach of every position and load case as given symbols
        (a (P*L) vector, load-case-major) instead of the Newton solve -- the *lifted* form of an NLP, where they are
        variables and ``result.approach_residual_N`` (the force balance ``sum c db softplus(delta - e) - F_bt`` of
        every position [N]) is held at zero by equality constraints. ``result.approach_floor_um`` (the approach
        above a smooth minimum of the position's gaps, never above the smallest gap) is positive at every solution
        (a loaded mesh closes its smallest gap); held >= 0 it keeps the NLP out of the region where no spring is
        loaded and the force balance has no slope (there Ipopt stalls and reports a local infeasibility). The NLP's graph is then a few operations per
        spring (no Newton iterations to differentiate twice); at a feasible point every output equals the nested
        form's.
        """
        for name, value in (("stiffness_factor", stiffness_factor), ("E_MPa", E_MPa), ("speed_rpm", speed_rpm),
                            ("face_width_mm", face_width_mm)):
            if value is not None:
                check_range(name, value, 0.0, None, low_inclusive=False)
        if face_width_mm is not None and (self.layout.slices != 1 or self.layout.base_helix_angle_rad != 0.0):
            raise GearoptInputError(f"face_width_mm given to evaluate: only a spur model with one face slice scales "
                                    f"with its face width (this one: {self.layout.slices} slices, base helix angle "
                                    f"{np.degrees(self.layout.base_helix_angle_rad):.3g} deg); build a new model")
        width = 1.0 if face_width_mm is None else face_width_mm / self.layout.face_width_mm
        stiffness_factor = stiffness_factor * width
        if (speed_rpm is not None or thermal_contact_coefficients is not None) and not self.speed_rpm:
            raise GearoptInputError("speed_rpm/thermal_contact_coefficients given to evaluate: build the LTCAModel "
                                    "with speed_rpm > 0 (the flash temperature)")
        data = {"stiffness_factor": stiffness_factor, "E_MPa": E_MPa, "speed_rpm": speed_rpm,
                "B": thermal_contact_coefficients}
        mods = microgeometry or Microgeometry()
        lay = self.layout
        P = lay.positions
        if isinstance(torque_Nm, (list, tuple, np.ndarray)):  # load cases: each a number >= 0 or a symbol
            for i, t in enumerate(torque_Nm.reshape(-1) if isinstance(torque_Nm, np.ndarray) else torque_Nm):
                check_range(f"torque_Nm[{i}]", t, 0.0, None, unit="N*m")
        torques = _load_cases(torque_Nm)
        L = len(torques)
        e = self.gaps_um(mods)
        symbolic = (nm.is_casadi(e) or nm.is_symbolic(*torques)
                    or nm.is_symbolic(*(v for v in (stiffness_factor, E_MPa, speed_rpm, face_width_mm)
                                        if v is not None))
                    or (thermal_contact_coefficients is not None and nm.is_symbolic(*thermal_contact_coefficients))
                    or (approach_um is not None and nm.is_symbolic(approach_um)))
        if not symbolic:
            for T in torques:
                check_range("torque_Nm", T, 0.0, None, unit="N*m")
        like = True if symbolic else None
        e = nm.matrix(e, like)
        masked = e * self._on_path - 1e6 * (1.0 - self._on_path)
        x0_base = nm.column_max(masked)
        forces = [T * lay.force_per_torque_N_per_Nm for T in torques]
        E_all = nm.hcat([e] * L) if L > 1 else e
        S_all = nm.matrix(np.tile(self._springs, (1, L)), like) * stiffness_factor
        F_all = nm.hcat([f * np.ones((1, P)) for f in forces])
        X0 = nm.hcat([nm.row(x0_base) + nm.row(f / (self._stiffness_sum * stiffness_factor)) + 1e-3 for f in forces])
        params = nm.vcat([E_all, S_all, F_all])
        lifted_residual = lifted_floor = None
        if approach_um is not None:
            if not nm.is_symbolic(approach_um):
                raise GearoptInputError("approach_um is for symbolic (NLP) evaluations; a numeric evaluation solves "
                                        "the approach itself")
            if approach_um.numel() != P * L:
                raise GearoptInputError(f"approach_um has {approach_um.numel()} elements: needs positions x load "
                                        f"cases = {P * L}")
            delta = nm.row(approach_um)
            lifted_residual = nm.column_sum(S_all * nm.softplus(nm.repeat_rows(delta, e.shape[0]) - E_all,
                                                                self.smoothing_um)) - F_all
            on_all = nm.matrix(np.tile(self._on_path, (1, L)), True)
            lifted_floor = delta - nm.row(nm.column_softmin(E_all * on_all + LIFTED_OFF_PATH_GAP_UM * (1.0 - on_all),
                                                            self.smoothing_um))
        else:
            try:
                delta = self._approach_map(P * L)(X0, params)
            except RuntimeError as exc:  # numeric inputs only: the Newton root of the approach failed
                raise NumericalSolveError(f"LTCAModel: the approach (Newton root) did not converge at torque_Nm="
                                          f"{torque_Nm!r}", hint="check the torque and the microgeometry for "
                                          "implausible magnitudes") from exc
        if not symbolic:
            delta = np.asarray(delta, dtype=float).reshape(-1)
        on_path = np.tile(self._on_path, (1, L))
        closure = nm.repeat_rows(nm.row(delta), e.shape[0]) - E_all
        load = (on_path / np.tile(self._engaged_length, (1, L))) * S_all * nm.softplus(closure, self.smoothing_um) \
            / width
        stress_sq = load * np.tile(self._stress_factor, (1, L))
        if E_MPa is not None:
            stress_sq = stress_sq * (E_MPa / self.E_MPa)
        J, K = lay.slices, lay.shape[1]
        pair_sum = np.kron(np.eye(K), np.ones((1, J)))                        # (K, N): spring forces -> pair load
        sharing = nm.matmul(pair_sum, load * np.tile(self._engaged_length, (1, L))) * width \
            / nm.repeat_rows(F_all + 1e-12, K)
        loaded = nm.column_sum(on_path * np.tile(self._engaged_length, (1, L))
                               * nm.sigmoid(closure, self.count_width_um)) / lay.face_width_mm
        te = delta if (L == 1 and not symbolic) else nm.reshape(delta, P, L)
        if not symbolic:
            loaded = np.asarray(loaded, dtype=float).reshape(-1)
        root = flash = None
        if self.root_stress:
            from ..rating.root_stress import root_stress_at_load_point

            root = tuple(root_stress_at_load_point(lay.pair, g, load, load_roll_length_mm=nm.matrix(
                np.tile(self._virtual_roll[g - 1], (1, L)), True if symbolic else None)) for g in (1, 2))
        if self._thermal is not None:
            flash = self._flash_temperature_K(load, L, symbolic, data)
        return SmoothLTCAResult(transmission_error_um=te, closure_um=closure, load_intensity_N_per_mm=load,
                                contact_stress_squared_MPa2=stress_sq, load_sharing=sharing,
                                loaded_pairs=loaded, layout=lay, torque_Nm=torque_Nm, root_stress_MPa=root,
                                flash_temperature_rise_K=flash,
                                bulk_temperature_C=self._thermal["bulk"] if self._thermal else None,
                                approach_residual_N=lifted_residual, approach_floor_um=lifted_floor)

    def approach_start(self, microgeometry: Microgeometry | None, torques) -> np.ndarray:
        """Numeric approaches [um] (a (P*L) vector, load-case-major) of ``microgeometry`` at numeric ``torques``:
        the start of the lifted form's approach variables (see :meth:`evaluate`)."""
        te = np.asarray(self.evaluate(microgeometry, list(np.atleast_1d(np.asarray(torques, dtype=float))))
                        .transmission_error_um, dtype=float)
        return te.reshape(-1, order="F") if te.ndim == 2 else te.ravel()

    def _flash_temperature_K(self, load, L: int, symbolic: bool, data: dict):
        """Blok flash temperature of every spring (:func:`gearopt.rating.flash_temperature.flash_temperature_blok_K`,
        smooth |v1 - v2| of width ``sliding_smoothing_m_s``; Hertz half-width from the smooth load with a floor);
        ``data``: the data given to :meth:`evaluate` (speed, E, B_M) in place of the build's."""
        from ..rating.flash_temperature import flash_temperature_blok_K

        th = self._thermal
        like = True if symbolic else None
        speed = 1.0 if data["speed_rpm"] is None else data["speed_rpm"] / self.speed_rpm
        v1 = nm.matrix(np.tile(th["v1"], (1, L)), like) * speed
        v2 = nm.matrix(np.tile(th["v2"], (1, L)), like) * speed
        curv = np.tile(th["curvature"], (1, L))
        compliance = th["compliance"] if data["E_MPa"] is None else th["compliance"] * (self.E_MPa / data["E_MPa"])
        b_h = nm.sqrt_safe(2.0 * load / np.pi * compliance / curv, 1e-12)
        B1, B2 = th["B"] if data["B"] is None else data["B"]
        return flash_temperature_blok_K(load, b_h, v1, v2, th["friction"], B1, B2,
                                        sliding_smoothing_m_s=th["sliding"])


def _load_cases(torque_Nm):
    if nm.is_casadi(torque_Nm):
        return [torque_Nm[i] for i in range(torque_Nm.numel())]
    if isinstance(torque_Nm, (list, tuple, np.ndarray)):
        return list(np.asarray(torque_Nm, dtype=float).reshape(-1)) if not any(
            nm.is_casadi(t) for t in torque_Nm) else list(torque_Nm)
    return [torque_Nm]


__all__ = ["LTCAModel", "SmoothLTCAResult", "DEFAULT_SMOOTHING_UM", "DEFAULT_COUNT_WIDTH_UM"]
