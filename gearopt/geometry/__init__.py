"""Involute gear geometry: single-gear relations, pair macro geometry (ISO 21771), profile shift, trains."""

from .pair import GearPair
from .shift import iso_tr_4467_shift_limits, shift_split_iso_tr_4467
from .tolerances import PairTolerances
from .train import GearSpec, GearTrain, MeshSpec, RackSpec

# GearPair and GearTrain are imported from gearopt itself (gearopt.__all__)
__all__ = ["PairTolerances", "GearSpec", "MeshSpec", "RackSpec", "iso_tr_4467_shift_limits", "shift_split_iso_tr_4467"]
