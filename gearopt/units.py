"""Unit conversions used at the public surface (names say from and to)."""

from __future__ import annotations

import math

DEG_PER_RAD = 180.0 / math.pi
RAD_PER_DEG = math.pi / 180.0
UM_PER_MM = 1000.0
MM_PER_UM = 1e-3


def deg2rad(angle_deg):
    """Degrees -> radians (dual-typed: floats, arrays and CasADi expressions)."""
    return angle_deg * RAD_PER_DEG


def rad2deg(angle_rad):
    """Radians -> degrees (dual-typed)."""
    return angle_rad * DEG_PER_RAD


def rpm2rad_per_s(speed_rpm):
    """Shaft speed rpm -> rad/s."""
    return speed_rpm * (2.0 * math.pi / 60.0)


def rad_per_s2rpm(speed_rad_per_s):
    """Shaft speed rad/s -> rpm."""
    return speed_rad_per_s * (60.0 / (2.0 * math.pi))
