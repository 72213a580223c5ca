"""gearopt: exact, differentiable gear-train design models on CasADi, optimised with Ipopt.

The public surface has one documented import path per object:

- the names in :data:`__all__` below, the ones most studies need, are imported from the package itself
  (``import gearopt as go; go.GearPair``);
- every other public name is imported from its subpackage and is listed in that subpackage's ``__all__``
  (``from gearopt.rating import contact_stress_iso6336``, ``from gearopt.nlp import Problem``); the top-level
  modules ``gearopt.errors``, ``gearopt.executor``, ``gearopt.numerics``, ``gearopt.units``,
  ``gearopt.validation`` and ``gearopt.compile_cache`` are public in the same way;
- a name of :data:`__all__` is not listed again in its subpackage's ``__all__``, and no subpackage lists another's
  names; the modules inside a subpackage (``gearopt.contact.ltca_smooth``, ...) are its implementation.

``tests/test_public_surface.py`` holds the package to these rules; ``docs/architecture.md`` has the package map.
"""

from .errors import GearoptError, GearoptInputError, SolveError
from .geometry import GearPair, GearTrain
from .data import System, load_default_data, load_default_train, load_system
from .contact import LTCAModel, Microgeometry, harris_map, ltca
from .rating import rate_iso6336
from .joints import press_fit, taper_fit, walk_off
from .design import (DesignVariable, Limit, LoadCase, Objective, Scene, TrainDesign, evaluate_requirements,
                     optimise_microgeometry, recommend)

__version__ = "0.1.0"

__all__ = [
    # data: your system (gears, meshes with their design loads, joints, ...) parsed and validated once, or the
    # packaged timing train; the raw validated file and its spur/helical train
    "load_system", "System", "load_default_data", "load_default_train",
    # geometry: one gear pair (numeric or symbolic) and a train of meshes at fixed centre distances
    "GearPair", "GearTrain",
    # tooth contact: microgeometry, the exact LTCA, its CasADi form, PPTE against torque
    "Microgeometry", "ltca", "LTCAModel", "harris_map",
    # strength rating
    "rate_iso6336",
    # shaft-hub joints
    "press_fit", "taper_fit", "walk_off",
    # design: declarative scenes and their spec records, the microgeometry NLP
    "Scene", "LoadCase", "DesignVariable", "Objective", "Limit", "optimise_microgeometry",
    # the verdict: a design judged on every requirement of the data's [requirements] by the exact models, and the
    # one recommended among candidates (with its design sheet)
    "TrainDesign", "evaluate_requirements", "recommend",
    # errors: the base classes (the specific ones are in gearopt.errors)
    "GearoptError", "GearoptInputError", "SolveError",
]
