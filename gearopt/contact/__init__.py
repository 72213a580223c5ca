"""Tooth contact: microgeometry, mesh stiffness, tip-relief physics and loaded tooth contact analysis (LTCA)."""

from .ltca import LTCAResult, ltca
from .microgeometry import Microgeometry
