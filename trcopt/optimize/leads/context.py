"""The constraint model of one lead problem, shared by the lead families.

:class:`LeadContext` holds the plane data of a lead-in problem — start point P0, contour, its start
P4 and the tool-centre target P4c, tool radius, side, ρmin, safety, the allowed region — adds the
clearance and region constraints to a ``casadi.Opti`` problem at sample points, and checks a
solved lead exactly (closed-form distances of :mod:`trcopt.verify.model`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from trcopt.errors import GeometryError
from trcopt.geometry import Arc
from trcopt.geometry.vec import Vec2, Vec3
from trcopt.modes import Side
from trcopt.optimize.leads.records import Element
from trcopt.verify.model import ca_point_element_distance, element_distance, points_distance

__all__ = ["RHO_SCAN", "LeadContext", "inside_margin"]

RHO_SCAN = (1.0, 2.0, 4.0)  # the line + arc lead's radius bound is scanned over ρmin × these


def _unit(v: Sequence[float]) -> Vec2:
    n = math.hypot(v[0], v[1])
    return (v[0] / n, v[1] / n)


def _convex_halfplanes(region: Sequence[Vec2]) -> list[tuple[Vec2, Vec2]]:
    pts = [(float(p[0]), float(p[1])) for p in region]
    if len(pts) >= 2 and pts[0] == pts[-1]:
        pts = pts[:-1]
    if len(pts) < 3:
        raise GeometryError("the allowed region needs at least 3 vertices")
    area = sum(a[0] * b[1] - b[0] * a[1] for a, b in zip(pts, pts[1:] + pts[:1], strict=True))
    if area < 0:
        pts = pts[::-1]
    edges = list(zip(pts, pts[1:] + pts[:1], strict=True))
    for (a, b), (c, d) in zip(edges, edges[1:] + edges[:1], strict=True):
        if (b[0] - a[0]) * (d[1] - c[1]) - (b[1] - a[1]) * (d[0] - c[0]) < -1e-12:
            raise GeometryError("the allowed region must be a convex polygon")
    return edges


def inside_margin(p: Vec2, edges: list[tuple[Vec2, Vec2]]) -> float:
    """Signed distance of ``p`` inside the convex polygon of counter-clockwise ``edges`` (mm,
    negative outside)."""
    return min(((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])) / math.dist(a, b) for a, b in edges)


def _symbolic(g: Any) -> bool:
    import casadi as ca

    return isinstance(g, (ca.MX, ca.SX)) and not g.is_constant()


class LeadContext:
    """Shared data of one lead problem (plane coordinates, mm): P0, the contour and P4, the
    tool-centre target P4c with the contour's unit tangent ``t`` and normal ``n`` there, R, the side
    sign ``s``, ρmin, safety, the allowed region's edges; which contour elements meet P4 (they need
    clearance R only) and which are near enough to constrain the lead."""

    def __init__(
        self,
        p0: Vec3,
        contour: Sequence[Element],
        radius: float,
        side: Side,
        rho_min: float,
        safety: float,
        region: Sequence[Vec2] | None,
    ) -> None:
        self.p0 = p0
        self.contour = list(contour)
        first = self.contour[0]
        self.p4 = first.start
        self.t = _unit(first.start_tangent())
        self.n = (-self.t[1], self.t[0])
        self.s = side.sign
        self.R = radius
        self.p4c2 = (self.p4[0] + self.s * radius * self.n[0], self.p4[1] + self.s * radius * self.n[1])
        self.p4c = (self.p4c2[0], self.p4c2[1], self.p4[2])
        self.rho_min = rho_min
        self.safety = safety
        self.edges = _convex_halfplanes(region) if region is not None else []
        # elements that meet at P4 need only R (contact), the others R + safety
        self.contact = [
            i
            for i, e in enumerate(self.contour)
            if math.dist(e.start[:2], self.p4[:2]) <= 1e-9 or math.dist(e.end[:2], self.p4[:2]) <= 1e-9
        ]
        # first-element curvature of the tool-centre offset at P4c (signed, left positive)
        if isinstance(first, Arc):
            off = first.offset(self.s * radius)
            self.kappa0 = first.sense / off.radius if off.radius > 0 else 0.0
        else:
            self.kappa0 = 0.0
        reach = math.dist(p0[:2], self.p4c2) + 8.0 * rho_min * max(RHO_SCAN) + radius + safety
        self.near = [
            i
            for i, e in enumerate(self.contour)
            if i in self.contact or float(points_distance(e, np.array([self.p4c2]))[0]) <= reach
        ]

    def required(self, i: int) -> float:
        return self.R if i in self.contact else self.R + self.safety

    def add_constraints(self, opti: Any, pts: list[Any], skip_last_contact: int = 0) -> dict[str, list[Any]]:
        """Clearance and region constraints at sample points; returns the expressions by group."""
        groups: dict[str, list[Any]] = {"clearance": [], "region": []}
        for k, p in enumerate(pts):
            for i in self.near:
                if i in self.contact and k >= len(pts) - skip_last_contact:
                    continue  # the last samples touch the contour at P4c
                g = ca_point_element_distance(p, self.contour[i]) - self.required(i)
                if not _symbolic(g):
                    continue  # the fixed start point is checked before solving
                opti.subject_to(g >= 0)
                groups["clearance"].append(g)
            for a, b in self.edges:
                ln = math.dist(a, b)
                g = ((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])) / ln
                if not _symbolic(g):
                    continue
                opti.subject_to(g >= 0)
                groups["region"].append(g)
        return groups

    def exact_check(self, elements: Sequence[Element]) -> dict[str, float]:
        """Exact violations (mm) of clearance, contact, region, curvature and tangency."""
        out = {"clearance": 0.0, "region": 0.0, "curvature": 0.0, "tangency": 0.0}
        self.last_min_clear = math.inf
        self.last_contact = math.inf
        for i, e in enumerate(self.contour):
            d = min(element_distance(el, e)[0] for el in elements)
            if i in self.contact:
                self.last_contact = min(self.last_contact, d)
                out["clearance"] = max(out["clearance"], self.R - d - 1e-9)
            else:
                self.last_min_clear = min(self.last_min_clear, d)
                out["clearance"] = max(out["clearance"], self.R + self.safety - d - 1e-7)
        for el in elements:
            pts = [el.point2(u) for u in np.linspace(0.0, 1.0, 64)]
            if self.edges:
                out["region"] = max(out["region"], max(-inside_margin(p, self.edges) for p in pts) - 1e-7)
            if isinstance(el, Arc):
                out["curvature"] = max(out["curvature"], self.rho_min - el.radius - 1e-9)
        last = elements[-1]
        te = _unit(last.end_tangent())
        out["tangency"] = abs(te[0] * self.t[1] - te[1] * self.t[0]) + max(
            0.0, -(te[0] * self.t[0] + te[1] * self.t[1])
        )
        out["tangency"] += math.dist(last.end[:2], self.p4c2)
        return {k: max(0.0, v) for k, v in out.items()}
