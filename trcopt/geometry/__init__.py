"""Exact plane geometry: lines, arcs/helices, polynomial curves, offsets and intersections."""

from .intersect import Hit, bounded_intersections, intersections
from .plane import Plane
from .poly import Poly, conic_curve, hermite_curve, spiral_curve
from .primitives import Arc, Element, Line

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
