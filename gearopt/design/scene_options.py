"""The LTCA options of a scene as typed records, one per concern, held by one :class:`LTCAOptions`:

- :class:`ContactModelOptions` (``model``): the smooth LTCA of the NLP -- its initial uniform positions, contact
  smoothing and stiffness (:class:`~gearopt.contact.ltca_smooth.LTCAModel`), the relief-start blend and the room of
  a free tip-relief start, the face slices of a helical mesh and the engagement width of free macro geometry
  (:class:`~gearopt.contact.ltca_macro.MacroLTCAModel`), the nested or lifted approach;
- :class:`ContactTemperatureOptions` (``temperature``): the oil temperature and friction of the flash temperature;
- :class:`ExactCheckOptions` (``check``): the positions of the exact-LTCA check of an optimum
  (benchmarks/results/ltca.json);
- :class:`RefinementOptions` (``refinement``): the semi-infinite PPTE refinement (:mod:`gearopt.design.scene_refine`);
- :class:`SearchOptions` (``search``): the exact screen that picks the NLP's starts and the exact polish of its
  optimum (:mod:`gearopt.design.scene_search`);
- :class:`ReliefToleranceOptions` (``tolerance``): the tip-relief tolerances of a ``ppte_um_toleranced`` quantity;
- ``root_rotation`` on :class:`LTCAOptions` itself: the crank's sense of rotation seen from the front (walk-off).

Users give the options flat, as before: ``Scene(ltca_options={"positions": 24, "max_refinements": 0})`` and the
``ltca_options`` table of a scene file name fields of any record by their (unique) field names;
:meth:`LTCAOptions.from_mapping` turns such a mapping into the record (an unknown key raises naming the nearest
option), :meth:`LTCAOptions.flat` turns it back, and :meth:`LTCAOptions.replace` takes flat overrides (a build's
overrides, e.g. the refinement's halved smoothing or raised face slices). Every value is checked when a record is
made: an error names the option, its value and the limit. :data:`DEFAULT_LTCA_OPTIONS` is the flat read-only view of
the defaults.
"""

from __future__ import annotations

import dataclasses
import difflib
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any, Mapping

from ..contact.ltca_macro import DEFAULT_ENGAGEMENT_WIDTH_MM
from ..contact.ltca_smooth import DEFAULT_COUNT_WIDTH_UM, DEFAULT_SMOOTHING_UM
from ..contact.relief_tolerances import ReliefTolerances
from ..errors import GearoptInputError
from ..validation import as_number, check_choice, check_int, check_range

APPROACHES = ("nested", "lifted")
"""``approach`` values: Newton's method inside the model, or each position's approach an NLP variable."""
STIFFNESS_KINDS = ("iso6336", "potential_energy")
"""Named single-pair stiffness profiles (``stiffness`` may also be a number > 0 [N/(mm*um)])."""
ROOT_ROTATIONS = ("cw", "ccw")
"""Senses of rotation of the train's root gear seen from the front (+z)."""


def _set(record, name: str, value) -> None:
    object.__setattr__(record, name, value)


def _real(record, name: str, low: float | None = None, high: float | None = None, *, unit: str = "",
          low_inclusive: bool = True, high_inclusive: bool = True) -> None:
    """Check the float field ``name`` of ``record`` in [low, high] and store it as a float."""
    value = getattr(record, name)
    check_range(name, value, low, high, unit=unit, low_inclusive=low_inclusive, high_inclusive=high_inclusive)
    _set(record, name, as_number(name, value))


def _count(record, name: str, low: int, high: int | None = None) -> None:
    """Check the integer field ``name`` of ``record`` in [low, high] and store it as an int."""
    _set(record, name, check_int(name, getattr(record, name), low, high))


@dataclass(frozen=True)
class ContactModelOptions:
    """The smooth LTCA of the NLP (:class:`~gearopt.contact.ltca_smooth.LTCAModel`, with free macro geometry
    :class:`~gearopt.contact.ltca_macro.MacroLTCAModel`).

    Attributes:
        positions: initial uniform mesh positions per base pitch of each mesh's smooth LTCA (2..100000).
        smoothing_um: contact smoothing width [um] (> 0).
        count_width_um: sigmoid width of the smooth loaded-contact count [um] (> 0): a pair counts as half-loaded
            where its gap is exactly closed; narrow it at light load, where the mesh deflection is comparable with it.
        stiffness: single-pair stiffness profile: ``"iso6336"``, ``"potential_energy"`` or a number > 0
            [N/(mm*um)].
        relief_smoothing_deg: roll-angle blend of a relief start in the design's microgeometry [deg] (0..5).
        start_margin_deg: the room of a free tip-relief start ends this far below the tip [deg] (>= 0).
        helical_slices: face slices of a helical mesh, or of any mesh with a free helix angle (>= 1).
        engagement_width_mm: engagement width of the macro-symbolic LTCA [mm] (> 0).
        approach: ``"nested"`` (Newton's method inside the model, as the macro-symbolic LTCA does) or ``"lifted"``
            (a mesh at fixed macro geometry: each position's approach an NLP variable held by an equality
            constraint; cheaper iterations, same optima, but from the same start it may reach another local
            optimum, so it is opt-in).
        macro_derivative_order: derivatives of the macro-symbolic LTCA's approach that are exact: 2 (first and
            second: for Ipopt's exact Hessian) or 1 (first only, one Newton step cheaper per evaluation and
            direction: for a solve with a quasi-Newton Hessian, ``hessian_approximation="limited-memory"``; with the
            exact Hessian Ipopt would get an approximate one) (:class:`~gearopt.contact.ltca_macro.MacroLTCAModel`
            ``derivative_steps``).
        spring_limit_screen: rows by exchange for a limit on a per-spring quantity (contact and root stress,
            contact temperature at every spring of an LTCA; :meth:`gearopt.nlp.problem.Problem.subject_to`
            ``screen``): a spring whose value lies more than this fraction of the limit below it at the start of a
            solve is held back from Ipopt until a solve breaks it or comes within the fraction (a squared contact
            stress: the fraction of the squared limit). ``None``: every spring a row (0 < fraction <= 1).
    """

    positions: int = 40
    smoothing_um: float = DEFAULT_SMOOTHING_UM
    count_width_um: float = DEFAULT_COUNT_WIDTH_UM
    stiffness: str | float = "iso6336"
    relief_smoothing_deg: float = 0.1
    start_margin_deg: float = 0.25
    helical_slices: int = 11
    engagement_width_mm: float = DEFAULT_ENGAGEMENT_WIDTH_MM
    approach: str = "nested"
    macro_derivative_order: int = 2
    spring_limit_screen: float | None = 0.2

    def __post_init__(self) -> None:
        _count(self, "positions", 2, 100000)
        if self.spring_limit_screen is not None:
            _real(self, "spring_limit_screen", 0.0, 1.0, low_inclusive=False)
        _real(self, "smoothing_um", 0.0, None, unit="um", low_inclusive=False)
        _real(self, "count_width_um", 0.0, None, unit="um", low_inclusive=False)
        if isinstance(self.stiffness, str):
            check_choice("stiffness", self.stiffness, STIFFNESS_KINDS)
        else:
            try:
                _real(self, "stiffness", 0.0, None, unit="N/(mm*um)", low_inclusive=False)
            except GearoptInputError as exc:
                raise GearoptInputError(f"{exc} (stiffness is a number > 0 [N/(mm*um)] or one of "
                                        f"{STIFFNESS_KINDS!r})") from None
        _real(self, "relief_smoothing_deg", 0.0, 5.0, unit="deg")
        _real(self, "start_margin_deg", 0.0, None, unit="deg")
        _count(self, "helical_slices", 1, 10000)
        _real(self, "engagement_width_mm", 0.0, None, unit="mm", low_inclusive=False)
        check_choice("approach", self.approach, APPROACHES)
        _count(self, "macro_derivative_order", 1, 2)


@dataclass(frozen=True)
class ContactTemperatureOptions:
    """The contact (flash) temperature of the smooth and the exact LTCA; a scene's data ``[lubrication]`` sets both
    unless the scene's ``ltca_options`` give them.

    Attributes:
        bulk_temperature_C: oil (bulk) temperature [degC] (-273.15..1000).
        friction_coefficient: mean friction coefficient of the flash temperature (0 <= mu < 1).
    """

    bulk_temperature_C: float = 100.0
    friction_coefficient: float = 0.06

    def __post_init__(self) -> None:
        _real(self, "bulk_temperature_C", -273.15, 1000.0, unit="degC")
        _real(self, "friction_coefficient", 0.0, 1.0, high_inclusive=False)


@dataclass(frozen=True)
class ExactCheckOptions:
    """The exact-LTCA check of an optimum (:meth:`~gearopt.design.scene_contact.ContactModels.exact_check`).

    Attributes:
        check_positions: uniform positions per base pitch of the exact LTCA of a spur mesh (at least the smooth
            model's; a helical mesh takes its slices' default) (2..100000).
    """

    check_positions: int = 1280

    def __post_init__(self) -> None:
        _count(self, "check_positions", 2, 100000)


@dataclass(frozen=True)
class RefinementOptions:
    """The semi-infinite PPTE refinement (:mod:`gearopt.design.scene_refine`).

    Attributes:
        refine_tolerance: relative agreement of the smooth and the exact PPTE that ends it (> 0).
        refine_abs_tolerance_um: absolute floor of that agreement [um] (>= 0).
        refine_stress_tolerance: relative agreement of the smooth and exact stress and temperature maxima (>= 0).
        max_refinements: most re-solves (>= 0).
        max_helical_slices: most face slices it may raise a helical mesh to (>= 1).
        min_smoothing_um: smallest contact smoothing it may halve down to [um] (> 0).
        refine_neighbours: grid neighbours added on either side of each exact worst position (>= 0).
        stop_without_progress: end the re-solves as soon as one neither lowers the best exact objective (by more
            than ``refine_tolerance``) nor gives the first design that meets every limit (the design returned is
            then the best so far, :mod:`gearopt.design.scene_refine` step 5). Off by default: on it cost the
            crown scene of ``benchmarks/bench_optimum_quality.py`` 15 % and the co-design benchmark's refinements
            9-11 % of exact PPTE (the re-solves that repair a broken limit go lower later).
        stop_on_divergence: end the re-solves as soon as one lowers neither the best exact objective (by more than
            ``refine_tolerance``) nor the smooth model's largest PPTE error below the smallest of the solves before
            it, gives no first admissible design and breaks no exact limit (a backed-off re-solve would repair it):
            the loop is then moving away from both the design and the agreement it refines toward. On by default: on the five scenes of
            ``benchmarks/bench_optimum_quality.py`` it never fires (each converges) and the main job's results are
            unchanged; on the root-shift co-design of ``docs/examples.md`` it ends after 5 of 7 solves with the
            same design (9.5 against 15.4 CPU-s); on the tip-relief refinements of
            ``benchmarks/bench_codesign.py`` (sequential, warm from it, from 80 positions) it returns designs
            0.05-0.7 % higher in exact PPTE, within ``refine_tolerance``, in 0.3-0.4x the CPU time.
    """

    refine_tolerance: float = 0.02
    refine_abs_tolerance_um: float = 0.01
    refine_stress_tolerance: float = 0.01
    max_refinements: int = 6
    max_helical_slices: int = 41
    min_smoothing_um: float = 0.005
    refine_neighbours: int = 3
    stop_without_progress: bool = False
    stop_on_divergence: bool = True

    def __post_init__(self) -> None:
        for name in ("stop_without_progress", "stop_on_divergence"):
            if not isinstance(getattr(self, name), bool):
                raise GearoptInputError(f"{name}={getattr(self, name)!r} must be True or False")
        _real(self, "refine_tolerance", 0.0, None, low_inclusive=False)
        _real(self, "refine_abs_tolerance_um", 0.0, None, unit="um")
        _real(self, "refine_stress_tolerance", 0.0, None)
        _count(self, "max_refinements", 0, 1000)
        _count(self, "max_helical_slices", 1, 10000)
        _real(self, "min_smoothing_um", 0.0, None, unit="um", low_inclusive=False)
        _count(self, "refine_neighbours", 0, 1000)


@dataclass(frozen=True)
class SearchOptions:
    """The exact model's global phase and polish around the NLP (:mod:`gearopt.design.scene_search`).

    Attributes:
        screen_samples: scrambled-Sobol designs of the exact screen that picks the Ipopt starts (0: no screen; else a
            power of two, 2..65536).
        screen_positions: mesh positions of a one-slice mesh's exact LTCA in the screen (>= 16; a sliced mesh uses
            its default): the screen only ranks designs to pick the starts, every design the search returns is
            judged at ``check_positions``.
        screen_max_variables: most design variables a scene may have for the screen and the polish (>= 1).
        polish_evaluations_per_variable: exact evaluations per design variable of the Nelder-Mead polish of the
            optimum (0: no polish).
        macro_starts: Ipopt starts (the screen's best designs) of ``solve()`` without ``starts`` on a screened scene
            with free macro variables other than the root shift alone (>= 1; :meth:`BuiltScene.default_starts`). The exact PPTE of a co-design has local optima across the helix angle
            and the shift: on the packaged spur train's first mesh (root shift, helix angle and two relief amounts
            at 300 N m), one start reaches 0.235 um and the best of four 0.124 um, where a global search on the
            exact LTCA finds 0.124 um.
    """

    screen_samples: int = 64
    screen_positions: int = 320
    screen_max_variables: int = 8
    polish_evaluations_per_variable: int = 25
    macro_starts: int = 4

    def __post_init__(self) -> None:
        _count(self, "screen_samples", 0, 65536)
        n = self.screen_samples
        if n and (n < 2 or n & (n - 1)):
            raise GearoptInputError(f"screen_samples={n} is not a power of two (a Sobol sample is balanced at 2^m "
                                    f"points): use 0 (no screen) or 2, 4, ..., 65536")
        _count(self, "screen_positions", 16, 100000)
        _count(self, "screen_max_variables", 1, 1000)
        _count(self, "polish_evaluations_per_variable", 0, 100000)
        _count(self, "macro_starts", 1, 1000)


@dataclass(frozen=True)
class ReliefToleranceOptions:
    """The tip-relief tolerances of a ``ppte_um_toleranced`` quantity (the largest PPTE over the variants of
    :func:`~gearopt.contact.relief_tolerances.relief_variants`). Defaults: those of the data's PPTE requirement
    (:class:`~gearopt.data.requirements.Requirements`).

    Attributes:
        relief_tolerance_um: half-width of each relief amount's tolerance [um] (0..50).
        relief_start_tolerance_deg: half-width of each relief start's tolerance [deg roll] (0..10).
        relief_sharp_start: the exact check judges the start sharp as well as blended (the smooth NLP carries the
            blended variants: its relief starts are blended by ``relief_smoothing_deg``).
        toleranced_ppte_width_um: width of the log-sum-exp maximum and minimum of the NLP's TE at each variant
            [um] (> 0): its PPTE is an upper bound of the sampled one, above it by at most ``2 w ln(positions)``.
        toleranced_ppte_screen: a variant's PPTE further than this fraction of its limit below the limit at the
            start of a solve is held back from Ipopt (rows by exchange, :meth:`gearopt.nlp.problem.Problem.subject_to`
            ``screen``; 0 < fraction <= 1): only the variants that can bind cost Jacobians.
        toleranced_ppte_lazy: the limit enters the NLP only once the exact check of a solve breaks it (by more
            than ``refine_stress_tolerance``): the refinement's re-solve then carries it as stated, and tightens it
            by 1.25 times the excess if the exact check breaks it again. A limit that never binds costs no smooth
            variant models, only their exact checks.
    """

    relief_tolerance_um: float = 2.0
    relief_start_tolerance_deg: float = 0.5
    relief_sharp_start: bool = True
    toleranced_ppte_width_um: float = 0.01
    toleranced_ppte_screen: float = 0.05
    toleranced_ppte_lazy: bool = False

    def __post_init__(self) -> None:
        _real(self, "relief_tolerance_um", 0.0, 50.0, unit="um")
        _real(self, "relief_start_tolerance_deg", 0.0, 10.0, unit="deg")
        if not isinstance(self.relief_sharp_start, bool):
            raise GearoptInputError(f"relief_sharp_start={self.relief_sharp_start!r} must be true or false")
        _real(self, "toleranced_ppte_width_um", 0.0, None, unit="um", low_inclusive=False)
        _real(self, "toleranced_ppte_screen", 0.0, 1.0, low_inclusive=False)
        if not isinstance(self.toleranced_ppte_lazy, bool):
            raise GearoptInputError(f"toleranced_ppte_lazy={self.toleranced_ppte_lazy!r} must be true or false")

    @property
    def tolerances(self) -> ReliefTolerances:
        return ReliefTolerances(self.relief_tolerance_um, self.relief_start_tolerance_deg, self.relief_sharp_start)


_GROUPS = {"model": ContactModelOptions, "temperature": ContactTemperatureOptions, "check": ExactCheckOptions,
           "refinement": RefinementOptions, "search": SearchOptions, "tolerance": ReliefToleranceOptions}
_TOP_LEVEL = ("root_rotation",)
OPTION_GROUP: Mapping[str, str | None] = MappingProxyType({
    **{f.name: group for group, cls in _GROUPS.items() for f in dataclasses.fields(cls)},
    **{name: None for name in _TOP_LEVEL}})
"""Flat option name -> the :class:`LTCAOptions` field holding its record (``None``: a field of ``LTCAOptions``)."""


@dataclass(frozen=True)
class LTCAOptions:
    """The LTCA options of a scene build (module docstring): one record per concern and the walk-off sense.

    Attributes:
        model: :class:`ContactModelOptions`.
        temperature: :class:`ContactTemperatureOptions`.
        check: :class:`ExactCheckOptions`.
        refinement: :class:`RefinementOptions`.
        search: :class:`SearchOptions`.
        tolerance: :class:`ReliefToleranceOptions`.
        root_rotation: the crank's (the train root's) sense of rotation seen from the front, ``"cw"`` or ``"ccw"``
            (walk-off).
        limit_backoff: set by the refinement, not a user option: ``(limit label, amount)`` pairs by which a re-solve
            tightens lower limits the exact LTCA broke (:meth:`backoff`).
    """

    model: ContactModelOptions = ContactModelOptions()
    temperature: ContactTemperatureOptions = ContactTemperatureOptions()
    check: ExactCheckOptions = ExactCheckOptions()
    refinement: RefinementOptions = RefinementOptions()
    search: SearchOptions = SearchOptions()
    tolerance: ReliefToleranceOptions = ReliefToleranceOptions()
    root_rotation: str = "cw"
    limit_backoff: tuple[tuple[str, float], ...] = ()

    def __post_init__(self) -> None:
        for group, cls in _GROUPS.items():
            if not isinstance(getattr(self, group), cls):
                raise GearoptInputError(f"LTCAOptions {group}={getattr(self, group)!r} must be a {cls.__name__}")
        check_choice("root_rotation", self.root_rotation, ROOT_ROTATIONS)
        backoff = self.limit_backoff.items() if isinstance(self.limit_backoff, Mapping) else self.limit_backoff
        pairs = []
        for label, amount in backoff:
            check_range(f"limit_backoff[{label}]", amount)
            pairs.append((str(label), float(amount)))
        _set(self, "limit_backoff", tuple(pairs))

    @classmethod
    def from_mapping(cls, mapping: Mapping[str, Any] | None = None, *, base: "LTCAOptions | None" = None
                     ) -> "LTCAOptions":
        """The record of flat options (``{"positions": 24, "max_refinements": 0}``, the ``ltca_options`` of a scene
        or scene file) on top of ``base`` (default: the defaults). An unknown key raises naming the nearest option;
        a bad value raises naming the option, its value and its limit."""
        mapping = dict(mapping or {})
        unknown = [k for k in mapping if k not in OPTION_GROUP]
        if unknown:
            raise GearoptInputError("ltca_options: " + "; ".join(_unknown_text(k) for k in unknown)
                                    + f" (options: {', '.join(sorted(OPTION_GROUP))})")
        return (base or cls()).replace(**mapping)

    def replace(self, **options: Any) -> "LTCAOptions":
        """A copy with flat options replaced (``replace(smoothing_um=0.025, helical_slices=21)``), each checked;
        ``limit_backoff`` (a mapping of limit label to amount) is accepted as well."""
        unknown = [k for k in options if k not in OPTION_GROUP and k != "limit_backoff"]
        if unknown:
            raise GearoptInputError("LTCA options: " + "; ".join(_unknown_text(k) for k in unknown))
        changes: dict[str, Any] = {}
        per_group: dict[str, dict[str, Any]] = {}
        for name, value in options.items():
            group = OPTION_GROUP.get(name)
            if group is None:
                changes[name] = value
            else:
                per_group.setdefault(group, {})[name] = value
        for group, values in per_group.items():
            changes[group] = dataclasses.replace(getattr(self, group), **values)
        return dataclasses.replace(self, **changes) if changes else self

    def flat(self) -> dict[str, Any]:
        """The options as one flat dict (the keys of :data:`DEFAULT_LTCA_OPTIONS`; ``limit_backoff`` left out):
        ``LTCAOptions.from_mapping(o.flat()) == o`` for a record without a backoff."""
        return {name: getattr(self if group is None else getattr(self, group), name)
                for name, group in OPTION_GROUP.items()}

    def backoff(self, label: str) -> float:
        """The amount by which the refinement tightens the lower limit ``label`` (0 if none)."""
        return dict(self.limit_backoff).get(label, 0.0)


def _unknown_text(key: str) -> str:
    close = difflib.get_close_matches(str(key), list(OPTION_GROUP), n=1)
    return f"unknown option {key!r}" + (f" (did you mean {close[0]!r}?)" if close else "")


DEFAULT_LTCA_OPTIONS: Mapping[str, Any] = MappingProxyType(LTCAOptions().flat())
"""The default LTCA options of a scene as a flat read-only mapping (``LTCAOptions().flat()``; override per scene
with ``ltca_options``): see :class:`LTCAOptions` and its records for what each sets."""

__all__ = ["LTCAOptions", "ContactModelOptions", "ContactTemperatureOptions", "ExactCheckOptions",
           "RefinementOptions", "SearchOptions", "ReliefToleranceOptions", "DEFAULT_LTCA_OPTIONS", "OPTION_GROUP", "APPROACHES", "STIFFNESS_KINDS",
           "ROOT_ROTATIONS"]
