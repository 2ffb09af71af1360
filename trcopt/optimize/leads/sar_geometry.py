"""The SAR geometry the constrained problem decodes: programmed points, circle and tool-centre
points of one SINUMERIK smooth approach or retraction (:class:`SarGeometry`, plane coordinates, mm),
and the tool-centre elements it makes."""

from __future__ import annotations

import math
from dataclasses import dataclass

from trcopt.geometry import Arc, Line
from trcopt.geometry.vec import Vec2, Vec3
from trcopt.modes import SarContour

__all__ = ["SarGeometry"]


@dataclass(frozen=True, slots=True)
class SarGeometry:
    """Decoded SAR geometry (plane coordinates, mm).

    ``p0``…``p4`` are the programmed points (``p0`` start on approach / end on retraction),
    ``center`` the circle centre (None for lines), ``rho_p`` the programmed circle radius (line
    length L for G147/G148), ``rho_c`` the tool-centre radius, ``p3c``/``p4c`` the tool-centre
    points at P3/P4 (applicates w3/w4).
    """

    contour: SarContour
    p0: Vec3
    p1: Vec3
    p2: Vec3
    p3: Vec3
    p4: Vec3
    center: Vec2 | None
    rho_p: float
    rho_c: float
    p3c: Vec3
    p4c: Vec3
    sense: int  # σ: +1 CCW, −1 CW (circles)

    @property
    def helix(self) -> bool:
        return self.center is not None and abs(self.p3[2] - self.p4[2]) > 1e-12

    def lead_element(self) -> Line | Arc:
        """The tool-centre approach (P3c → P4c) or retraction (P4c → P3c) contour element."""
        approach = self.contour.is_approach
        a, b = (self.p3c, self.p4c) if approach else (self.p4c, self.p3c)
        if self.center is None:
            return Line(a, b)
        return Arc.from_points(a, b, self.center, ccw=self.sense > 0, full_if_closed=False)

    def tool_centre_elements(self) -> list[Line | Arc]:
        """Tool-centre elements P0 → P1 → P2 → P3 → P4 (approach order; reversed on retraction),
        zero-length ones dropped. With TRC the centre at P1, P2, P3 is P3c (R46)."""
        c1 = (self.p3c[0], self.p3c[1], self.p1[2])
        c2 = (self.p3c[0], self.p3c[1], self.p2[2])
        pts = [self.p0, c1, c2, self.p3c]
        els: list[Line | Arc] = [Line(a, b) for a, b in zip(pts, pts[1:], strict=False) if math.dist(a, b) > 1e-12]
        if not self.contour.is_approach:
            els = [e.reversed() for e in reversed(els)]
            return [self.lead_element(), *els]
        return [*els, self.lead_element()]
