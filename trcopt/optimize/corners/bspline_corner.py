"""A curvature-continuous (G2) transition between two lines in closed form: the symmetric cubic
B-spline of five control points on the lines.

With the corner point J, the unit directions ``ta`` (into J) and ``tb`` (out of J), turning by φ,
and a spacing d, the control points are ``J − 2d·ta, J − d·ta, J, J + d·tb, J + 2d·tb`` (knots
0, 0, 0, 0, ½, 1, 1, 1, 1). The first three and the last three are collinear, so the curve leaves
and joins the lines with zero curvature (G2); it replaces 2d of each line. Its middle point is
``J + (d/4)·(tb − ta)``, so exactly

* vertex distance (corner point to the curve) ``(d/2)·sin(φ/2)``,
* contour distance (largest distance from the two lines, at the middle) ``(d/4)·sin φ``,

and its peak curvature, at the middle, ``4·sin(φ/2) / (3·d·cos²(φ/2))``. This is the corner
transition of Zhao, Zhu & Ding (Int. J. Mach. Tools Manuf. 65, 2013); trcopt sizes it from the
tolerance and the line lengths and times the path with its own time-optimal feed.
"""

from __future__ import annotations

import math

import numpy as np

from trcopt.geometry import Line, Poly
from trcopt.geometry.poly import parametric_curve

__all__ = ["bspline_corner", "bspline_distances", "spacing_for"]


def bspline_distances(d: float, phi: float) -> tuple[float, float]:
    """(vertex distance, contour distance) of the transition of spacing ``d`` at a turn ``phi``, mm."""
    return 0.5 * d * math.sin(0.5 * phi), 0.25 * d * math.sin(phi)


def spacing_for(tolerance_mm: float, phi: float, vertex: bool) -> float:
    """The spacing d whose vertex (``vertex``) or contour distance is ``tolerance_mm``."""
    if vertex:
        return 2.0 * tolerance_mm / math.sin(0.5 * phi)
    return 4.0 * tolerance_mm / max(math.sin(phi), 1e-300)


def bspline_corner(a: Line, b: Line, d: float) -> Poly:
    """The transition of spacing ``d`` between line ``a`` (ending at the corner) and line ``b``."""
    ta = (np.array(a.end) - np.array(a.start)) / a.length
    tb = (np.array(b.end) - np.array(b.start)) / b.length
    J = np.array(a.end)
    first = (J - 2 * d * ta, J - d * ta, J - 0.5 * d * ta, J + 0.25 * d * (tb - ta))
    second = (first[3], J + 0.5 * d * tb, J + d * tb, J + 2 * d * tb)

    def piece(u: float) -> tuple[tuple[np.ndarray, ...], float]:
        return (first, 2.0 * u) if u <= 0.5 else (second, 2.0 * u - 1.0)

    def f(u: float) -> tuple[float, float, float]:
        (q0, q1, q2, q3), v = piece(u)
        w = 1.0 - v
        p = w**3 * q0 + 3 * w * w * v * q1 + 3 * w * v * v * q2 + v**3 * q3
        return float(p[0]), float(p[1]), float(p[2])

    def df(u: float) -> tuple[float, float, float]:
        (q0, q1, q2, q3), v = piece(u)
        w = 1.0 - v
        p = 2.0 * 3.0 * (w * w * (q1 - q0) + 2 * w * v * (q2 - q1) + v * v * (q3 - q2))
        return float(p[0]), float(p[1]), float(p[2])

    def d2f(u: float) -> tuple[float, float, float]:
        (q0, q1, q2, q3), v = piece(u)
        p = 4.0 * 6.0 * ((1.0 - v) * (q2 - 2 * q1 + q0) + v * (q3 - 2 * q2 + q1))
        return float(p[0]), float(p[1]), float(p[2])

    return parametric_curve(f, df, d2f, label="bspline corner")
