"""Plane lines and arcs as arrays: feet, tangents and distances of many (point, element) pairs at once.

The smoothing splines across runs of CAM chords (:mod:`.chain`) measure thousands of sample
points against hundreds of exact and programmed elements in every step; :class:`Elements` keeps a
sequence of lines and arcs as parameter arrays so that every pair is one row of a NumPy
computation (closed forms: the foot on a bounded line, the radial foot or the nearer end on an
arc), and :meth:`Elements.near` finds the pairs within a distance through a k-d tree of the points.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from itertools import chain

import numpy as np

from trcopt.geometry import Arc, Line

__all__ = ["Elements", "Feet", "free_directions", "nearest"]

TWO_PI = 2.0 * math.pi


@dataclass
class Feet:
    """Per pair: the foot point (k×2), its parameter λ on the element, the unit tangent there, the
    distance from the point, and whether the foot is an end of the element."""

    foot: np.ndarray
    lam: np.ndarray
    tangent: np.ndarray
    dist: np.ndarray
    at_end: np.ndarray


class Elements:
    """A sequence of plane lines and arcs (their x, y) as arrays."""

    def __init__(self, elements: Sequence[Line | Arc]) -> None:
        n = len(elements)
        self.n = n
        self.is_arc = np.array([isinstance(e, Arc) for e in elements], bool)
        self.p0 = np.array([e.point2(0.0) for e in elements], float).reshape(n, 2)
        self.p1 = np.array([e.point2(1.0) for e in elements], float).reshape(n, 2)
        self.center = np.array([e.center if isinstance(e, Arc) else (0.0, 0.0) for e in elements], float).reshape(n, 2)
        self.radius = np.array([e.radius if isinstance(e, Arc) else 0.0 for e in elements], float)
        self.a0 = np.array([e.a0 if isinstance(e, Arc) else 0.0 for e in elements], float)
        self.sweep = np.array([e.sweep if isinstance(e, Arc) else 0.0 for e in elements], float)
        self.length = np.array([e.plane_length for e in elements], float)
        mid = np.array([e.point2(0.5) for e in elements], float).reshape(n, 2)
        # a circle around each element: its points lie within `reach` of `mid`
        self.mid = mid
        self.reach = np.maximum(np.hypot(*(self.p0 - mid).T), np.hypot(*(self.p1 - mid).T))
        self.reach = np.where(
            self.is_arc, np.maximum(self.reach, np.minimum(self.radius, 0.5 * self.length)), self.reach
        )

    def points(self, idx: np.ndarray, lam: np.ndarray) -> np.ndarray:
        """The points at parameters ``lam`` of the elements ``idx`` (k×2)."""
        idx = np.asarray(idx, int)
        lam = np.asarray(lam, float)
        line = self.p0[idx] + lam[:, None] * (self.p1[idx] - self.p0[idx])
        ang = self.a0[idx] + lam * self.sweep[idx]
        arc = self.center[idx] + self.radius[idx][:, None] * np.stack((np.cos(ang), np.sin(ang)), axis=1)
        return np.where(self.is_arc[idx][:, None], arc, line)

    def feet(self, idx: np.ndarray, pts: np.ndarray) -> Feet:
        """Nearest points of the elements ``idx`` to the points ``pts`` (pairwise, k each)."""
        idx = np.asarray(idx, int)
        pts = np.asarray(pts, float).reshape(-1, 2)
        a, b = self.p0[idx], self.p1[idx]
        d = b - a
        dd = np.einsum("ij,ij->i", d, d)
        t = np.clip(np.einsum("ij,ij->i", pts - a, d) / np.where(dd > 0.0, dd, 1.0), 0.0, 1.0)
        foot = a + t[:, None] * d
        lam = t
        tan = d / np.maximum(np.sqrt(dd), 1e-300)[:, None]
        arcs = np.nonzero(self.is_arc[idx])[0]
        if len(arcs):
            j = idx[arcs]
            rel = pts[arcs] - self.center[j]
            ang = np.arctan2(rel[:, 1], rel[:, 0])
            sw = self.sweep[j]
            frac = np.mod((ang - self.a0[j]) * np.sign(sw), TWO_PI) / np.maximum(np.abs(sw), 1e-300)
            inside = frac <= 1.0
            near_start = np.hypot(*(pts[arcs] - a[arcs]).T) <= np.hypot(*(pts[arcs] - b[arcs]).T)
            lam_a = np.where(inside, frac, np.where(near_start, 0.0, 1.0))
            th = self.a0[j] + lam_a * sw
            lam[arcs] = lam_a
            foot[arcs] = self.center[j] + self.radius[j][:, None] * np.stack((np.cos(th), np.sin(th)), axis=1)
            tan[arcs] = np.sign(sw)[:, None] * np.stack((-np.sin(th), np.cos(th)), axis=1)
        off = pts - foot
        dist = np.hypot(off[:, 0], off[:, 1])
        return Feet(foot, lam, tan, dist, (lam <= 1e-12) | (lam >= 1.0 - 1e-12))

    def near(self, pts: np.ndarray, within: float, tree: object | None = None) -> tuple[np.ndarray, np.ndarray]:
        """All (point index, element index) pairs at most ``within`` apart, as two arrays
        (candidates from a k-d tree of the points, then measured exactly)."""
        m, e, _ = self.near_distances(pts, within, tree)
        return m, e

    def near_distances(
        self, pts: np.ndarray, within: float, tree: object | None = None, ordered: bool = True
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`near` and the distances of its pairs (those of :meth:`distances`); the pairs by
        element and, with ``ordered``, by point (else the points of an element in any order)."""
        from scipy.spatial import cKDTree

        none = np.zeros(0, int)
        if self.n == 0 or len(pts) == 0:
            return none, none, np.zeros(0)
        kd = tree if tree is not None else cKDTree(pts)
        lists = kd.query_ball_point(self.mid, self.reach + within, return_sorted=ordered)  # type: ignore[attr-defined]
        counts = np.fromiter(map(len, lists), int, self.n)
        if not counts.sum():
            return none, none, np.zeros(0)
        m = np.fromiter(chain.from_iterable(lists), int, int(counts.sum()))
        e = np.repeat(np.arange(self.n), counts)
        d = self.distances(e, pts[m])
        ok = d <= within
        return m[ok], e[ok], d[ok]

    def distances(self, idx: np.ndarray, pts: np.ndarray) -> np.ndarray:
        """Distances from the points ``pts`` to the elements ``idx`` (pairwise, k each): the
        ``dist`` of :meth:`feet` without the feet (an arc's sweep is tested with cross products)."""
        a, b = self.p0[idx], self.p1[idx]
        d = b - a
        rel = pts - a
        dd = np.einsum("ij,ij->i", d, d)
        t = np.clip(np.einsum("ij,ij->i", rel, d) / np.where(dd > 0.0, dd, 1.0), 0.0, 1.0)
        off = rel - t[:, None] * d
        dist = np.hypot(off[:, 0], off[:, 1])
        arcs = np.nonzero(self.is_arc[idx])[0]
        if len(arcs):
            j = idx[arcs]
            q = pts[arcs]
            c = self.center[j]
            rc = q - c
            sw = self.sweep[j]
            sg = np.sign(sw)
            u0, u1 = a[arcs] - c, b[arcs] - c
            # inside the sweep: counter-clockwise (for sg > 0) from the start and before the end
            c0 = sg * (u0[:, 0] * rc[:, 1] - u0[:, 1] * rc[:, 0])
            c1 = sg * (rc[:, 0] * u1[:, 1] - rc[:, 1] * u1[:, 0])
            small = np.abs(sw) <= math.pi
            inside = np.where(small, (c0 >= 0.0) & (c1 >= 0.0), (c0 >= 0.0) | (c1 >= 0.0))
            inside |= np.abs(sw) >= TWO_PI - 1e-12
            radial = np.abs(np.hypot(rc[:, 0], rc[:, 1]) - self.radius[j])
            ends = np.minimum(np.hypot(*(q - a[arcs]).T), np.hypot(*(q - b[arcs]).T))
            dist[arcs] = np.where(inside, radial, ends)
        return dist


def nearest(E: Elements, pts: np.ndarray, within: float, tree: object) -> tuple[np.ndarray, np.ndarray]:
    """For every point with an element of ``E`` within ``within``: the point's index and the nearest
    element's index."""
    m, e, d = E.near_distances(pts, within, tree, ordered=False)  # (sorted below)
    if not len(m):
        return m, e
    order = np.lexsort((d, m))
    m, e = m[order], e[order]
    first = np.ones(len(m), bool)
    first[1:] = m[1:] != m[:-1]
    return m[first], e[first]


def free_directions(
    E: Elements, e: np.ndarray, P: np.ndarray, material_sign: float, two_sided: bool = False
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Foot points on the elements ``e`` of ``E`` and unit directions of the distance beyond them
    on the side away from the material (the element normal; radial beyond an end, in the outer
    wedge of a vertex), pairwise with the points ``P``, and which of them are radial. With
    ``two_sided`` (no material: a path without compensation) the direction is radial beyond an end
    on either side, and the element normal's sign does not matter."""
    ft = E.feet(e, P)
    free = -material_sign * np.stack((-ft.tangent[:, 1], ft.tangent[:, 0]), axis=1)
    off = P - ft.foot
    radial = ft.at_end & (ft.dist > 1e-9)
    if not two_sided:
        radial &= np.sum(off * free, axis=1) > 0.0
    return ft.foot, np.where(radial[:, None], off / np.maximum(ft.dist, 1e-300)[:, None], free), radial
