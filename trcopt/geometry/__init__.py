"""Exact plane geometry: lines, arcs/helices, polynomial curves, offsets and intersections."""

from trcopt.geometry.intersect import Hit, bounded_intersections, intersections
from trcopt.geometry.plane import Plane
from trcopt.geometry.poly import Poly, conic_curve, hermite_curve, spiral_curve
from trcopt.geometry.primitives import Arc, Element, Line

__all__ = [
    "Arc",
    "Element",
    "Hit",
    "Line",
    "Plane",
    "Poly",
    "bounded_intersections",
    "conic_curve",
    "hermite_curve",
    "intersections",
    "spiral_curve",
]
