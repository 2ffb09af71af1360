"""What a circular (or G2) blend at one joint may be: the tolerance and how it is measured
(:class:`FilletSpec`), the blend distances in closed form, and the limits shared by
:mod:`~trcopt.optimize.corners.fillet` and :mod:`~trcopt.optimize.corners.fillet_elements`."""

from __future__ import annotations

import math
from dataclasses import dataclass

from trcopt.geometry import Arc, Poly
from trcopt.modes import ToleranceKind
from trcopt.path import Segment

__all__ = [
    "LINE_SHARE", "MAX_TURN_RAD", "MIN_LINE_MM", "MIN_TANGENT_MM", "TANGENT_TOL_RAD", "APPLICATE_TOL_MM",
    "Cut", "FilletSpec", "blend_distances", "inside_turn",
]  # fmt: skip

LINE_SHARE = 0.98  # the largest share of a line a blend may take when the line's other end is not blended
MAX_TURN_RAD = math.radians(170.0)  # sharper turns (near reversals) keep the exact path
TANGENT_TOL_RAD = 1e-6  # smaller turns are tangent-continuous joints, not corners
MIN_TANGENT_MM = 1e-7  # a blend shorter than this on each line is no blend
MIN_LINE_MM = 0.01  # the shortest piece of a line left between two blends (unless they meet exactly)
APPLICATE_TOL_MM = 1e-12  # a line lies in its plane when its applicate changes by less, mm


@dataclass(frozen=True, slots=True)
class FilletSpec:
    """How large the blend at one joint may be.

    Attributes
    ----------
    tolerance_mm:
        Bound of the blend measured as ``kind`` says, mm; None for no bound (as large as the lines
        allow).
    kind:
        How ``tolerance_mm`` is measured.
    max_radius_mm:
        Largest blend radius, mm (the tool radius at an outside corner of a compensated path).
    length_share:
        The tolerance is at most this share of the shorter of the two lines (LinuxCNC's quarter);
        None for no such bound.
    """

    tolerance_mm: float | None
    kind: ToleranceKind = ToleranceKind.CONTOUR
    max_radius_mm: float = math.inf
    length_share: float | None = None

    def bounded(self, length_a: float, length_b: float) -> FilletSpec:
        """This spec with its tolerance bounded by ``length_share`` of the shorter line, mm."""
        if self.length_share is None:
            return self
        cap = self.length_share * min(length_a, length_b)
        tol = cap if self.tolerance_mm is None else min(self.tolerance_mm, cap)
        return FilletSpec(tol, self.kind, self.max_radius_mm)

    def radius(self, phi: float) -> float:
        """The largest radius within the tolerance at a turn of ``phi`` rad (before the line lengths)."""
        r = self.max_radius_mm
        tol = self.tolerance_mm
        if tol is None:
            return r
        half = 0.5 * phi
        one_minus_cos = 2.0 * math.sin(0.5 * half) ** 2  # 1 − cos(φ/2), without cancellation
        if one_minus_cos <= 0.0:
            return r
        if self.kind is ToleranceKind.VERTEX:
            return min(r, tol * math.cos(half) / one_minus_cos)
        if self.kind is ToleranceKind.CONTOUR:
            return min(r, tol / one_minus_cos)
        return min(r, tol / math.tan(half))  # DISTANCE: the tangent length


def blend_distances(radius: float, phi: float) -> tuple[float, float]:
    """(vertex distance, contour distance) of a circular blend of ``radius`` at a turn of ``phi``, mm."""
    c = math.cos(0.5 * phi)
    return radius * (1.0 - c) / c, radius * (1.0 - c)


def inside_turn(seg: Segment, turn: float) -> bool:
    from trcopt.optimize.corners.boundary import material_sign

    return turn * material_sign(seg) < 0


Cut = tuple[float, float, "Arc | Poly", float, float]  # (cut from a's end, from b's start, blend, vertex, contour)


