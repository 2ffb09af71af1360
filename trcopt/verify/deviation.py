"""How far a path with corner transitions lies from the exact path, measured by sampling.

An independent check of the transitions' own (closed-form or optimised) deviation figures: every
transition segment is sampled densely in space and measured against the exact elements it
replaced, the two at its joint:

* **contour distance** — the largest distance of a sample from the union of the two exact
  elements, lines or (plane) arcs (the Hausdorff distance from the new path to the exact one near
  the corner);
* **vertex distance** — the smallest distance from the exact corner point to the samples.

The straight and circular pieces that a transition leaves in place lie on the exact elements and
are not measured.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from trcopt.geometry import Arc, Line, Poly
from trcopt.path import Role, Segment

__all__ = ["CornerDeviation", "SAMPLES_PER_TRANSITION", "measure_transitions"]

SAMPLES_PER_TRANSITION = 257  # samples of each transition (plus its end points)


@dataclass(frozen=True, slots=True)
class CornerDeviation:
    """Measured distances of the transition at one joint of the exact path, mm."""

    joint: int
    contour_mm: float
    vertex_mm: float


def _samples(seg: Segment, count: int) -> np.ndarray:
    """``count`` points evenly spaced in arc length along ``seg`` (plane coordinates, n×3)."""
    g = seg.geometry
    s = np.linspace(0.0, g.length, count)
    if isinstance(g, Line):
        p0, p1 = np.array(g.start), np.array(g.end)
        return p0 + np.outer(s / max(g.length, 1e-300), p1 - p0)
    if isinstance(g, Arc):
        ang = g.a0 + np.sign(g.sweep) * s / max(g.length, 1e-300) * abs(g.sweep)
        w = g.w0 + (g.w1 - g.w0) * s / max(g.length, 1e-300)
        return np.column_stack((g.center[0] + g.radius * np.cos(ang), g.center[1] + g.radius * np.sin(ang), w))
    assert isinstance(g, Poly)
    return np.array([g.point(float(x)) for x in s])


def _line_distance(line: Line, pts: np.ndarray) -> np.ndarray:
    """Distance of points (n×3) from a line segment in space."""
    a, b = np.array(line.start), np.array(line.end)
    d = b - a
    dd = float(d @ d)
    t = np.zeros(len(pts)) if dd <= 0 else np.clip((pts - a) @ d / dd, 0.0, 1.0)
    return np.linalg.norm(pts - (a + t[:, None] * d), axis=1)


def _arc_distance(arc: Arc, pts: np.ndarray) -> np.ndarray:
    """Plane distance of points (n×3, applicate ignored) from a flat arc."""
    d = np.array([arc.distance2((float(p[0]), float(p[1]))) for p in pts])
    return d


def _distance(g: Line | Arc, pts: np.ndarray) -> np.ndarray:
    return _line_distance(g, pts) if isinstance(g, Line) else _arc_distance(g, pts)


def measure_transitions(
    exact: Sequence[Segment], blended: Sequence[Segment], origin: Sequence[int]
) -> list[CornerDeviation]:
    """The measured deviation of every transition of ``blended`` between two exact lines.

    Parameters
    ----------
    exact:
        The exact path.
    blended:
        The path with transitions (role ``corner`` where a transition replaced a joint).
    origin:
        For every segment of ``blended``, the index of the exact segment it comes from; a
        transition's is the segment before its joint.
    """
    out = []
    for seg, k in zip(blended, origin, strict=True):
        if seg.role is not Role.CORNER or k + 1 >= len(exact):
            continue
        a, b = exact[k].geometry, exact[k + 1].geometry
        if not (isinstance(a, Line | Arc) and isinstance(b, Line | Arc)) or isinstance(seg.geometry, Line):
            continue
        if (isinstance(a, Arc) or isinstance(b, Arc)) and not isinstance(seg.geometry, Arc | Poly):
            continue
        pts = _samples(seg, SAMPLES_PER_TRANSITION)
        contour = float(np.max(np.minimum(_distance(a, pts), _distance(b, pts))))
        vertex = float(np.min(np.linalg.norm(pts - np.array(a.end), axis=1)))
        out.append(CornerDeviation(k, contour, vertex))
    return out
