"""The corner sites of a tool-centre path: where a transition may replace the exact path, and
what constrains it there.

* :class:`CornerSite` — one tangent discontinuity (or G450 transition circle) with its
  neighbours, the programmed contour near it and the probes of its cut boundary; measures the
  material a transition leaves (:meth:`CornerSite.material_left`);
* :func:`find_corner_sites` — the sites of a tool path;
* :func:`curvature_jump_joints` — the tangent-continuous joints whose curvature jumps (line↔arc,
  arcs of different curvature), smoothed under jerk limits.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import NamedTuple

import numpy as np

from trcopt.geometry import Arc, Line, Plane
from trcopt.optimize.corners.boundary import blendable, boundary_probes, material_left, material_sign
from trcopt.optimize.corners.chain import KNOT_MIN_JUMP_PER_MM
from trcopt.optimize.corners.chain_geometry import Elements
from trcopt.optimize.corners.curves import Element, frame_back, frame_forward, joint_turn, signed_curvature
from trcopt.path import Role, Segment
from trcopt.verify.contour import part_contour
from trcopt.verify.index import BoxGrid
from trcopt.verify.model import bbox, point_distance, points_distance
from trcopt.verify.nearest import ElementSet

__all__ = [
    "MAX_TURN_RAD",
    "TANGENT_TOL_RAD",
    "CornerSite",
    "curvature_jump_joints",
    "find_corner_sites",
]

MAX_TURN_RAD = math.radians(170.0)  # sharper turns (near reversals) keep the exact path
WITHIN_POINTS = 4096  # corner points whose programmed neighbours are found at once
TANGENT_TOL_RAD = 1e-6  # smaller turns are tangent-continuous joints, not corners


@dataclass(frozen=True)
class CornerSite:
    """A tangent discontinuity of the tool-centre path and what constrains its transition.

    Attributes
    ----------
    a, b:
        Incoming and outgoing tool-centre elements (plane coordinates, mm).
    radius:
        Tool radius in force, mm.
    material_sign:
        +1 when the material (programmed contour) lies left of the tool's travel (G42), −1 when
        right (G41).
    avail_a, avail_b:
        Longest plane arc length the transition may take from ``a`` (before J) and ``b`` (after J), mm.
    programmed:
        Programmed contour elements near the corner (no-gouge and deviation reference).
    probe_source:
        Computes the points of the exact cut boundary near the corner (n×2, mm) and unit directions
        away from the material (n×2), :attr:`probes` and :attr:`probe_dirs`: the deviation is the
        material left along these rays (a picklable callable, evaluated once when first needed).
    w:
        Applicate of the plane the corner lies in, mm.
    context:
        Exact tool-centre elements around the corner that stay in the new path (they cover
        probes the transition need not reach).
    min_cut:
        Smallest ``sa`` and ``sb`` (mm). Non-zero when the corner is a transition circle (G450)
        between two lines: ``a`` and ``b`` are then the lines extended to their intersection, the
        circle is replaced as a whole, and the transition must start and end on the real lines,
        at least ``min_cut`` (the circle's tangent length) from the intersection.
    """

    a: Element
    b: Element
    radius: float
    material_sign: float
    avail_a: float
    avail_b: float
    programmed: tuple[Element, ...]
    probe_source: Callable[[], tuple[np.ndarray, np.ndarray]]
    w: float = 0.0
    context: tuple[Element, ...] = ()
    min_cut: float = 0.0

    @cached_property
    def _probe_pair(self) -> tuple[np.ndarray, np.ndarray]:
        return self.probe_source()

    @property
    def probes(self) -> np.ndarray:
        """Points of the exact cut boundary near the corner (n×2, mm), computed when first needed
        (a corner on a run spline never needs them)."""
        return self._probe_pair[0]

    @property
    def probe_dirs(self) -> np.ndarray:
        """Unit directions away from the material at :attr:`probes` (n×2)."""
        return self._probe_pair[1]

    def release(self) -> None:
        """Forget the probes (computed again when next needed): a plan of many corners keeps
        their sites, and their probes would hold about 100 KB each."""
        self.__dict__.pop("_probe_pair", None)

    def material_left(self, curve: np.ndarray, sa: float, sb: float, eps: float) -> np.ndarray:
        """Material left (mm) at every probe for a transition sampled by ``curve`` (k×2) that
        replaces ``sa`` mm of ``a`` and ``sb`` mm of ``b``.

        Probes within R of the remaining exact elements are swept (exact distances); the rest
        are measured against discs around the transition samples and fine samples of the legs
        near the cut points (spacing ``sqrt(0.08·R·ε)``: the sampled swept region lags the true
        one by ≤ 1 % of ε).
        """
        if not len(self.probes):
            return np.zeros(1)
        R = self.radius
        la, lb = self.a.plane_length, self.b.plane_length
        rest = [self.a.sub(0.0, 1.0 - sa / la), self.b.sub(sb / lb, 1.0), *self.context]
        d = np.min([points_distance(e, self.probes) for e in rest], axis=0)
        out = np.zeros(len(self.probes))
        open_ = d > R * (1.0 + 1e-12) + 1e-12
        if not np.any(open_):
            return out
        fine = max(math.sqrt(0.08 * R * eps), 1e-5)
        legs = []
        for d0, el, back in ((sa, self.a, True), (sb, self.b, False)):
            stop = min(d0 + 2.0 * R, el.plane_length)
            for dd in np.append(np.arange(d0, stop, fine), stop):
                legs.append((frame_back if back else frame_forward)(el, dd)[0])
        centres = np.vstack((curve, np.array(legs)))
        out[open_] = material_left(self.probes[open_], self.probe_dirs[open_], centres, R)
        return out

    @cached_property
    def programmed_set(self) -> ElementSet:
        """:attr:`programmed` as an :class:`~trcopt.verify.nearest.ElementSet` (batched distances)."""
        return ElementSet(self.programmed)

    @property
    def joint(self) -> np.ndarray:
        """The corner point J (plane, mm)."""
        return np.array(self.a.point2(1.0), float)

    @property
    def turn(self) -> float:
        """Signed turning angle at J, rad (positive = left)."""
        return joint_turn(self.a, self.b)

    @property
    def inside(self) -> bool:
        """True when the material lies on the outer side of the turn (pocket-like corner)."""
        return self.turn * self.material_sign < 0


# ------------------------------------------------------------------------------------- finding sites
def _joint_indices(toolpath: Sequence[Segment]) -> list[int]:
    out = []
    for k in range(len(toolpath) - 1):
        s1, s2 = toolpath[k], toolpath[k + 1]
        if not (blendable(s1) and blendable(s2)):
            continue
        if s1.plane != s2.plane or s1.side != s2.side or abs(s1.radius - s2.radius) > 1e-12:
            continue
        g1, g2 = s1.geometry, s2.geometry
        if math.dist(g1.end, g2.start) > 1e-9:
            continue
        turn = abs(joint_turn(g1, g2))  # type: ignore[arg-type]
        if TANGENT_TOL_RAD < turn <= MAX_TURN_RAD:
            out.append(k)
    return out


def _circle_indices(toolpath: Sequence[Segment], joints: set[int]) -> list[int]:
    """Indices k of transition circles (G450, role ``corner``) at ``k + 1`` between two lines
    ``k`` and ``k + 2`` that are tangent to it and not themselves tangent discontinuities."""
    out = []
    for k in range(len(toolpath) - 2):
        s1, arc, s2 = toolpath[k], toolpath[k + 1], toolpath[k + 2]
        if not (blendable(s1) and blendable(arc) and blendable(s2)):
            continue
        if arc.role is not Role.CORNER or not isinstance(arc.geometry, Arc):
            continue
        if not (isinstance(s1.geometry, Line) and isinstance(s2.geometry, Line)):
            continue
        if k in joints or (k + 1) in joints or s1.plane != s2.plane or abs(s1.radius - s2.radius) > 1e-12:
            continue
        if max(math.dist(s1.geometry.end, arc.geometry.start), math.dist(arc.geometry.end, s2.geometry.start)) > 1e-9:
            continue
        if TANGENT_TOL_RAD < abs(joint_turn(s1.geometry, s2.geometry)) <= MAX_TURN_RAD:
            out.append(k)
    return out


def curvature_jump_joints(toolpath: Sequence[Segment], taken: set[int]) -> list[int]:
    """Indices k of tangent-continuous joints between ``toolpath[k]`` and ``[k + 1]`` whose
    curvature jumps by at least KNOT_MIN_JUMP_PER_MM (line↔arc, arcs of different curvature), not
    in ``taken`` (the joints of other sites)."""
    out = []
    for k in range(len(toolpath) - 1):
        s1, s2 = toolpath[k], toolpath[k + 1]
        if k in taken or not (blendable(s1) and blendable(s2)):
            continue
        if s1.plane != s2.plane or s1.side != s2.side or abs(s1.radius - s2.radius) > 1e-12:
            continue
        g1, g2 = s1.geometry, s2.geometry
        assert isinstance(g1, Line | Arc) and isinstance(g2, Line | Arc)
        if math.dist(g1.end, g2.start) > 1e-9 or abs(joint_turn(g1, g2)) > TANGENT_TOL_RAD:
            continue
        if abs(signed_curvature(g2) - signed_curvature(g1)) >= KNOT_MIN_JUMP_PER_MM:
            out.append(k)
    return out


class _Pending(NamedTuple):
    """A corner site before the programmed elements near it are known."""

    k: int
    plane: Plane
    joint: np.ndarray  # J
    within: float  # the programmed elements within this distance of J (mm) constrain the site
    head: tuple[Element, Element, float, float, float, float]  # CornerSite's fields before them
    probes: tuple[list[Line | Arc], float, float]  # exact elements, probe step, reach from J
    tail: tuple[float, tuple[Element, ...], float]  # CornerSite's fields after the probe source


def find_corner_sites(
    toolpath: Sequence[Segment],
    programmed: Sequence[Segment],
    *,
    probe_step: float | None = None,
    tolerance_mm: float = 0.01,
    transition_circles: bool = False,
) -> list[tuple[int, CornerSite]]:
    """The tangent discontinuities that may be blended and their constraint data; with
    ``transition_circles`` also the G450 transition circles between two lines (curvature jumps of
    1/R at both ends, what limits a jerk-limited feed), as sites whose ``a``/``b`` are the lines
    extended to their intersection (:attr:`CornerSite.min_cut`)."""
    joints = _joint_indices(toolpath)
    at = set(joints)
    circles = _circle_indices(toolpath, at) if transition_circles else []
    # the part contour (as the verification sees it): approach/retraction blocks are not part of it
    contour: list[tuple[Plane, Element]] = [
        (p.plane, p.geometry)
        for p in part_contour(programmed, toolpath)
        if isinstance(p.geometry, Line | Arc) and not p.is_rapid
    ]
    grids = _PlaneGrids(contour)
    pending = []
    for k in sorted(joints + circles):
        circle = k in circles and k not in at
        first, last = k, (k + 2 if circle else k + 1)
        ga, gb = toolpath[first].geometry, toolpath[last].geometry
        assert isinstance(ga, Line | Arc) and isinstance(gb, Line | Arc)
        # a segment shared with a neighbouring site gives each site half of its length
        share_a = 0.5 if (first - 1) in at or first in {c + 2 for c in circles} else 0.98
        share_b = 0.5 if last in at or last in circles else 0.98
        min_cut = 0.0
        if circle:
            assert isinstance(ga, Line) and isinstance(gb, Line)
            X = _line_intersection(ga, gb)
            if X is None:
                continue
            min_cut = math.dist(X, ga.end[:2])
            a: Line | Arc = Line(ga.start, (X[0], X[1], ga.end[2]))
            b: Line | Arc = Line((X[0], X[1], gb.start[2]), gb.end)
            # the line leaves the circle by d²/(2R) at d beyond its tangent point: a transition that
            # leaves at most ε starts within a few sqrt(2Rε) of it
            r_c = min_cut / math.tan(0.5 * abs(joint_turn(ga, gb)))
            near = 4.0 * math.sqrt(2.0 * r_c * tolerance_mm)
            avail_a = min_cut + ga.plane_length * share_a
            avail_b = min_cut + gb.plane_length * share_b
        else:
            a, b = ga, gb
            avail_a, avail_b = a.plane_length * share_a, b.plane_length * share_b
        seg0 = toolpath[first]
        R = seg0.radius
        sign = material_sign(seg0)
        J = np.array(a.point2(1.0))
        reach = max(avail_a, avail_b) + 3.0 * R
        # exact neighbourhood: previous, the replaced elements, next (when joined)
        ex: list[Line | Arc] = []
        prev = toolpath[first - 1] if first >= 1 else None
        if prev is not None and blendable(prev) and math.dist(prev.geometry.end, ga.start) < 1e-9:
            ex.append(toolpath[first - 1].geometry)  # type: ignore[arg-type]
        ex += [toolpath[i].geometry for i in range(first, last + 1)]  # type: ignore[misc]
        if (
            last + 1 < len(toolpath)
            and blendable(toolpath[last + 1])
            and math.dist(gb.end, toolpath[last + 1].geometry.start) < 1e-9
        ):
            ex.append(toolpath[last + 1].geometry)  # type: ignore[arg-type]
        step = probe_step or max(min(0.5 * tolerance_mm, (max(avail_a, avail_b) + R) / 300.0), 1e-4)
        # inside corners: the transition cannot be much longer than the same-ε circle's
        c = math.cos(0.5 * abs(joint_turn(a, b)))
        t_arc = tolerance_mm * c / max(1.0 - c, 1e-12) * math.tan(0.5 * abs(joint_turn(a, b)))
        span = max(avail_a, avail_b)
        if joint_turn(a, b) * sign < 0:
            span = min(span, 4.0 * t_arc + 2.0 * R)
        if circle:
            span = min(span, min_cut + near)
        replaced = {id(toolpath[i].geometry) for i in range(first, last + 1)}
        context = tuple(e for e in ex if id(e) not in replaced)
        head = (a, b, R, sign, avail_a, avail_b)
        pending.append(
            _Pending(k, seg0.plane, J, reach + R, head, (ex, step, span + 1.05 * R), (ga.end[2], context, min_cut))
        )
    # the programmed elements within reach + R of each corner point, for all corners at once
    progs: dict[int, tuple[Element, ...]] = {}
    for plane in {x.plane for x in pending}:
        mine = [x for x in pending if x.plane == plane]
        found = grids.within(
            plane, np.array([x.joint for x in mine]).reshape(-1, 2), np.array([x.within for x in mine])
        )
        progs.update((x.k, f) for x, f in zip(mine, found, strict=True))
    sites = []
    for x in pending:
        prog = progs[x.k]
        (ex, step, reach), (_, _, R, sign, _, _) = x.probes, x.head
        probes = _ProbeSource(tuple(ex), prog, R, sign, step, x.joint, reach)
        sites.append((x.k, CornerSite(*x.head, prog, probes, *x.tail)))
    return sites


class _ProbeSource:
    """The probes of a corner's cut boundary (:func:`~.boundary.boundary_probes` of its exact
    elements and programmed contour near ``joint``), computed when called: a plan keeps one per
    corner, so it holds only references and numbers (picklable for the worker processes)."""

    __slots__ = ("exact", "programmed", "radius", "sign", "step", "joint", "reach")

    def __init__(self, exact: tuple[Line | Arc, ...], programmed: tuple[Element, ...], radius: float, sign: float,
                 step: float, joint: np.ndarray, reach: float) -> None:  # fmt: skip
        self.exact, self.programmed, self.radius, self.sign = exact, programmed, radius, sign
        self.step, self.joint, self.reach = step, joint, reach

    def __getstate__(self) -> tuple:
        return tuple(getattr(self, k) for k in self.__slots__)

    def __setstate__(self, state: tuple) -> None:
        for k, v in zip(self.__slots__, state, strict=True):
            setattr(self, k, v)

    def __call__(self) -> tuple[np.ndarray, np.ndarray]:
        return boundary_probes(self.exact, list(self.programmed), self.radius, self.sign, self.step,
                               near=self.joint, reach=self.reach)  # fmt: skip


class _PlaneGrids:
    """The part contour's elements hashed per plane (:class:`~trcopt.verify.index.BoxGrid`): the
    elements within a distance of a point in contour order, without a pass over the whole contour."""

    def __init__(self, contour: Sequence[tuple[Plane, Element]]) -> None:
        self._by_plane: dict[Plane, tuple[list[Element], BoxGrid, Elements]] = {}
        for plane in {p for p, _ in contour}:
            els = [g for p, g in contour if p == plane]
            self._by_plane[plane] = (els, BoxGrid(np.array([bbox(g) for g in els], float)), Elements(els))

    def within(self, plane: Plane, points: np.ndarray, radii: np.ndarray) -> list[tuple[Element, ...]]:
        """For every point (m×2, mm) the elements of ``plane`` at most its radius away
        (:func:`~trcopt.verify.model.point_distance`), in contour order: candidates by their boxes,
        distances of all pairs at once (WITHIN_POINTS points at a time: bounded memory), and the
        scalar distance where the two come within rounding of the radius."""
        if plane not in self._by_plane or not len(points):
            return [()] * len(points)
        out: list[tuple[Element, ...]] = []
        for lo in range(0, len(points), WITHIN_POINTS):
            out += self._within(plane, points[lo : lo + WITHIN_POINTS], radii[lo : lo + WITHIN_POINTS])
        return out

    def _within(self, plane: Plane, points: np.ndarray, radii: np.ndarray) -> list[tuple[Element, ...]]:
        out: list[list[Element]] = [[] for _ in range(len(points))]
        els, grid, arrays = self._by_plane[plane]
        q, i = grid.near_many(np.column_stack((points, points)), radii)
        d = arrays.distances(i, points[q])
        r = radii[q]
        keep = d <= r
        for j in np.nonzero(np.abs(d - r) <= 1e-9 * (1.0 + r))[0].tolist():
            keep[j] = point_distance(els[i[j]], (float(points[q[j], 0]), float(points[q[j], 1]))) <= r[j]
        for qq, ii in zip(q[keep].tolist(), i[keep].tolist(), strict=True):
            out[qq].append(els[ii])
        return [tuple(x) for x in out]


def _line_intersection(a: Line, b: Line) -> tuple[float, float] | None:
    """Intersection of the carriers of two plane lines (None when parallel)."""
    ta, tb = np.array(a.direction2()), np.array(b.direction2())
    den = ta[0] * tb[1] - ta[1] * tb[0]
    if abs(den) < 1e-12:
        return None
    pa, pb = np.array(a.end[:2]), np.array(b.start[:2])
    t = ((pb - pa)[0] * tb[1] - (pb - pa)[1] * tb[0]) / den
    X = pa + t * ta
    return float(X[0]), float(X[1])
