"""Internal units: mm, s, rad, mm/s. Conversions happen at the I/O boundary only."""

from __future__ import annotations

import math

MM_PER_INCH = 25.4
SECONDS_PER_MINUTE = 60.0


def mm_min_to_mm_s(feed_mm_min: float) -> float:
    """Feed in mm/min → mm/s."""
    return feed_mm_min / SECONDS_PER_MINUTE


def mm_s_to_mm_min(feed_mm_s: float) -> float:
    """Feed in mm/s → mm/min."""
    return feed_mm_s * SECONDS_PER_MINUTE


def deg(angle_rad: float) -> float:
    return math.degrees(angle_rad)


def rad(angle_deg: float) -> float:
    return math.radians(angle_deg)
