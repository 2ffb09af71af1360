"""Tolerance-bounded corner transitions of the tool-centre path (issue 6, part 1).

With exact geometry the tool stops at every tangent discontinuity of the tool-centre path. Given a
contour tolerance ε (mm), :func:`optimize_corners` replaces each such corner by a G2-continuous
quintic (``Poly`` segment, role ``corner``, span of the following block) chosen by
:class:`~trcopt.optimize.corners.qp.CornerBlendProblem` (SQP of OSQP QPs: least peak curvature,
material left ≤ ε, no gouge). ``mode="arc"`` builds the baseline instead: the largest circular
blend (G1) meeting the same cut-part constraints, the usual controller smoothing. A run of ≥ 3
consecutive corners of ≤ 20° joined by short lines (CAM polylines) is replaced as a whole by one G2
smoothing spline (:mod:`~trcopt.optimize.corners.chain`), which may leave ε between the vertices and
so follows the curve the chords approximate instead of turning at every vertex.

The cut-part deviation is measured on the physics, not on the tool-centre path: the exact path's
cut boundary is probed along its normals and the new path's swept discs must reach every probe
within ε (:func:`cut_deviation`), while every tool-centre point keeps distance ≥ R from the
programmed contour (no gouge).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from trcopt.config import DEFAULT_MACHINE, Machine
from trcopt.errors import ConfigError
from trcopt.geometry import Arc, Line, Poly, hermite_curve
from trcopt.modes import CornerTransition, parse_enum
from trcopt.optimize.corners.chain import (
    KNOT_MIN_JUMP_PER_MM,
    ChainSite,
    ChainSolution,
    find_chains,
    knot_site,
    solve_chain,
)
from trcopt.optimize.corners.qp import (
    CornerBlendProblem,
    CornerGeometry,
    CornerSite,
    CornerSolution,
    joint_turn,
    material_left,
    quintic_basis,
    signed_curvature,
)
from trcopt.path import Role, Segment
from trcopt.verify.model import points_distance
from trcopt.verify.plan import part_contour

__all__ = [
    "CornerRecord",
    "CornerResult",
    "blend_corners",
    "optimize_corners",
    "cut_deviation",
    "find_corner_sites",
]

MAX_TURN_RAD = math.radians(170.0)
ARC_BLEND_TOL_MM = 1e-7  # the largest same-ε circular blend is found to this tangent length
JUMP_SMOOTHED = "curvature jump smoothed"  # reason of a record whose curvature jump got a G2 spline
TANGENT_TOL_RAD = 1e-6
TARGET_MARGIN = 2e-3
NEAREST_CENTRES = 128  # centres per probe for the bound of the deviation measurement
PARALLEL_MIN_CORNERS = 8  # fewer corner problems are solved in-process (a pool costs ~1 s to start)


@dataclass(frozen=True)
class CornerRecord:
    """What happened at one tangent discontinuity (joint between toolpath[index] and [index+1])."""

    index: int
    turn_deg: float
    inside: bool
    blended: bool
    tolerance_mm: float
    max_curvature: float | None = None  # 1/mm
    span_mm: float | None = None  # sa + sb
    solution: CornerSolution | None = None
    reason: str = ""
    transition: str = ""  # "quintic" (G2), "spline" (G2 across a run of corners) or "arc" (G1); "" when not blended


@dataclass
class CornerResult:
    """New tool-centre path and per-corner records."""

    segments: list[Segment]
    corners: list[CornerRecord] = field(default_factory=list)
    max_deviation_mm: float = 0.0
    mode: CornerTransition = CornerTransition.OPTIMAL

    @property
    def blended(self) -> int:
        return sum(c.blended for c in self.corners)

    def count(self, transition: str) -> int:
        """Corners blended with ``transition`` (``"quintic"``, ``"spline"`` or ``"arc"``)."""
        return sum(c.blended and c.transition == transition for c in self.corners)

    @property
    def curvature_jumps(self) -> int:
        """Curvature jumps (tangent-continuous joints) replaced by G2 splines."""
        return sum(c.blended and c.reason == JUMP_SMOOTHED for c in self.corners)


# ------------------------------------------------------------------------------------- sites
def _eligible(seg: Segment) -> bool:
    g = seg.geometry
    return (
        not seg.is_rapid
        and seg.role in (Role.CONTOUR, Role.CORNER)
        and seg.radius > 0
        and isinstance(g, Line | Arc)
        and g.plane_length > 1e-9
        and abs(g.start[2] - g.end[2]) <= 1e-12
    )


def _joint_indices(toolpath: Sequence[Segment]) -> list[int]:
    out = []
    for k in range(len(toolpath) - 1):
        s1, s2 = toolpath[k], toolpath[k + 1]
        if not (_eligible(s1) and _eligible(s2)):
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


def _material_sign(seg: Segment) -> float:
    # G41 (LEFT): tool left of the contour, so the material is right of travel (−1)
    return -1.0 if seg.side.value == "left" else 1.0


def _normal(t: np.ndarray, sign: float) -> np.ndarray:
    return sign * np.array([-t[..., 1], t[..., 0]]).T if t.ndim > 1 else sign * np.array([-t[1], t[0]])


def _element_samples(
    el: Line | Arc, step: float, s0: float = 0.0, s1: float | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Points and unit tangents of ``el`` from plane arc length s0 to s1 (default: end) at ``step``."""
    L = el.plane_length
    s1 = L if s1 is None else min(s1, L)
    n = max(2, int(math.ceil((s1 - s0) / step)) + 1)
    lam = np.linspace(s0, s1, n) / L
    if isinstance(el, Line):
        a, b = np.array(el.start2), np.array(el.end2)
        pts = a[None, :] + lam[:, None] * (b - a)[None, :]
        tan = np.repeat(np.array([el.direction2()]), n, axis=0)
        return pts, tan
    ang = el.a0 + lam * el.sweep
    pts = np.stack((el.center[0] + el.radius * np.cos(ang), el.center[1] + el.radius * np.sin(ang)), axis=1)
    k = 1.0 if el.sweep > 0 else -1.0
    tan = np.stack((-np.sin(ang) * k, np.cos(ang) * k), axis=1)
    return pts, tan


def _fan(n1: np.ndarray, n2: np.ndarray, count: int) -> np.ndarray:
    a1, a2 = math.atan2(n1[1], n1[0]), math.atan2(n2[1], n2[0])
    d = (a2 - a1 + math.pi) % (2 * math.pi) - math.pi
    ang = a1 + np.linspace(0.0, 1.0, count) * d
    return np.stack((np.cos(ang), np.sin(ang)), axis=1)


def _boundary_probes(
    exact: Sequence[Line | Arc],
    programmed: Sequence[Line | Arc],
    radius: float,
    sign: float,
    step: float,
    near: np.ndarray | None = None,
    reach: float = math.inf,
) -> tuple[np.ndarray, np.ndarray]:
    """Points of the exact cut boundary and unit directions away from the material.

    Candidates: envelope points of the exact centre elements, disc fans at their joints, the
    programmed vertices with their normal fans; kept where they lie on the boundary of the exact
    swept region (distance to the exact centre path = R).
    """
    pts, dirs = [], []
    for el in exact:
        p, t = _element_samples(el, step)
        n = _normal(t, sign)
        pts.append(p + radius * n)
        dirs.append(-n)
    for e1, e2 in zip(exact[:-1], exact[1:], strict=False):
        if math.dist(e1.end, e2.start) > 1e-9:
            continue
        j = np.array(e1.point2(1.0))
        fan = _fan(_normal(np.array(e1.end_tangent()), sign), _normal(np.array(e2.start_tangent()), sign), 33)
        pts.append(j[None, :] + radius * fan)
        dirs.append(-fan)
    for e1, e2 in zip(programmed[:-1], programmed[1:], strict=False):
        if math.dist(e1.end[:2], e2.start[:2]) > 1e-9:
            continue
        v = np.array(e1.point2(1.0))
        fan = _fan(-_normal(np.array(e1.end_tangent()), sign), -_normal(np.array(e2.start_tangent()), sign), 33)
        pts.append(np.repeat(v[None, :], len(fan), axis=0))
        dirs.append(fan)
    P, D = np.vstack(pts), np.vstack(dirs)
    if near is not None:
        keep = np.hypot(*(P - near[None, :]).T) <= reach
        P, D = P[keep], D[keep]
    dmin = np.min([points_distance(el, P) for el in exact], axis=0)
    keep = np.abs(dmin - radius) <= 1e-7 * max(radius, 1.0)
    return P[keep], D[keep]


def _circle_indices(toolpath: Sequence[Segment], joints: set[int]) -> list[int]:
    """Indices k of transition circles (G450, role ``corner``) at ``k + 1`` between two lines
    ``k`` and ``k + 2`` that are tangent to it and not themselves tangent discontinuities."""
    out = []
    for k in range(len(toolpath) - 2):
        s1, arc, s2 = toolpath[k], toolpath[k + 1], toolpath[k + 2]
        if not (_eligible(s1) and _eligible(arc) and _eligible(s2)):
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


def _knot_indices(toolpath: Sequence[Segment], taken: set[int]) -> list[int]:
    """Indices k of tangent-continuous joints between ``toolpath[k]`` and ``[k + 1]`` whose
    curvature jumps by at least KNOT_MIN_JUMP_PER_MM (line↔arc, arcs of different curvature), not
    in ``taken`` (the joints of other sites)."""
    out = []
    for k in range(len(toolpath) - 1):
        s1, s2 = toolpath[k], toolpath[k + 1]
        if k in taken or not (_eligible(s1) and _eligible(s2)):
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
    contour = [
        p
        for p in part_contour(programmed, toolpath)
        if isinstance(p.geometry, Line | Arc) and not p.is_rapid
    ]
    sites = []
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
        sign = _material_sign(seg0)
        J = np.array(a.point2(1.0))
        reach = max(avail_a, avail_b) + 3.0 * R
        prog = tuple(
            p.geometry
            for p in contour
            if p.plane == seg0.plane and points_distance(p.geometry, J[None, :])[0] <= reach + R  # type: ignore[arg-type]
        )
        # exact neighbourhood: previous, the replaced elements, next (when joined)
        ex: list[Line | Arc] = []
        prev = toolpath[first - 1] if first >= 1 else None
        if prev is not None and _eligible(prev) and math.dist(prev.geometry.end, ga.start) < 1e-9:
            ex.append(toolpath[first - 1].geometry)  # type: ignore[arg-type]
        ex += [toolpath[i].geometry for i in range(first, last + 1)]  # type: ignore[misc]
        if (
            last + 1 < len(toolpath)
            and _eligible(toolpath[last + 1])
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
        probes, dirs = _boundary_probes(ex, list(prog), R, sign, step, near=J, reach=span + 1.05 * R)
        replaced = {id(toolpath[i].geometry) for i in range(first, last + 1)}
        context = tuple(e for e in ex if id(e) not in replaced)
        site = CornerSite(a, b, R, sign, avail_a, avail_b, prog, probes, dirs, ga.end[2], context, min_cut)
        sites.append((k, site))
    return sites


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


# ------------------------------------------------------------------------------------- blends
def _trim(g: Line | Arc, lam0: float, lam1: float) -> Line | Arc:
    return g.sub(lam0, lam1, g.start[2], g.end[2])


def _arc_blend(site: CornerSite, eps: float) -> tuple[Arc, float, float] | None:
    """Largest circular blend (tangent to both lines) with material left ≤ ε and no gouge."""
    if not (isinstance(site.a, Line) and isinstance(site.b, Line)):
        return None
    phi = abs(site.turn)
    ta, tb = np.array(site.a.direction2()), np.array(site.b.direction2())
    J = site.joint
    sgn = 1.0 if site.turn > 0 else -1.0
    tmax = min(site.avail_a, site.avail_b)

    def build(T: float) -> tuple[Arc, np.ndarray]:
        r = T / math.tan(0.5 * phi)
        A, B = J - T * ta, J + T * tb
        c = A + sgn * r * np.array([-ta[1], ta[0]])
        arc = Arc.from_points((A[0], A[1], site.w), (B[0], B[1], site.w), (c[0], c[1]), sgn > 0, False)
        pts, _ = _element_samples(arc, max(arc.plane_length / 200.0, 1e-6))
        return arc, pts


    def ok(T: float) -> bool:
        _, pts = build(T)
        dev = site.material_left(pts, T, T, eps)
        clear = min((points_distance(e, pts).min() for e in site.programmed), default=math.inf)
        return float(dev.max(initial=0.0)) <= eps and clear >= site.radius - 1e-9

    lo, hi = 0.0, tmax
    if ok(hi):
        lo = hi
    else:
        # the feasible tangent lengths are an interval [0, T*]: bisect T* to ARC_BLEND_TOL_MM
        while hi - lo > ARC_BLEND_TOL_MM:
            mid = 0.5 * (lo + hi)
            if ok(mid):
                lo = mid
            else:
                hi = mid
    if lo <= 1e-9:
        return None
    return build(lo)[0], lo, lo


def blend_corners(
    toolpath: Sequence[Segment],
    programmed: Sequence[Segment],
    *,
    tolerance_mm: float,
    machine: Machine | None = None,
    mode: str | CornerTransition = CornerTransition.OPTIMAL,
    workers: int = 1,
    select: bool = True,
    objective: str = "curvature",
    chains: bool = True,
) -> CornerResult:
    """Replace tangent discontinuities by transitions within the contour tolerance.

    Parameters
    ----------
    toolpath:
        Exact tool-centre path (output of compensation).
    programmed:
        The programmed (uncompensated) path: the no-gouge and deviation reference.
    tolerance_mm:
        Contour tolerance ε, mm: material left beyond the exact cut ≤ ε.
    machine:
        Axis limits for the choice between G2 and circular transitions (``select``).
    mode:
        ``"optimal"`` (G2 quintics by SQP/OSQP), ``"arc"`` (largest same-ε circular blends, G1) or
        ``"exact"`` (unchanged).
    workers:
        Processes for the per-corner problems (independent; ``1`` solves in this process).
    select:
        ``optimal`` only: time the G2 plan, the same-ε circular blends and a per-corner mix of
        both on ``machine`` (the default machine when omitted) and return the fastest, so the
        result is never slower than the circular blends. ``False`` keeps the G2 transitions
        wherever they are feasible (wanted under jerk limits, where curvature continuity pays).
    objective:
        ``optimal`` only: ``"curvature"`` minimises the peak curvature (the speed limit under
        acceleration limits); ``"jerk"`` minimises the larger of the curvature and the curvature
        equivalent of the curvature rate under the machine's X/Y jerk limit
        (:meth:`CornerBlendProblem.objective_samples`), for jerk-limited timing.
    chains:
        ``optimal`` only: replace each run of ≥ 3 consecutive corners of ≤ 20° joined by lines
        ≤ 5 mm (CAM polylines) by one G2 spline (:mod:`trcopt.optimize.corners.chain`) instead of
        per-corner transitions; a run whose spline is infeasible keeps per-corner transitions.
    """
    mode = parse_enum(CornerTransition, mode, "corner mode")
    if objective not in ("curvature", "jerk"):
        raise ValueError(f"unknown corner objective {objective!r}; valid: curvature, jerk")
    limits = None
    if objective == "jerk":
        m = machine or DEFAULT_MACHINE
        jm = [m.axis(k).jmax_mm_s3 for k in "XY"]
        if any(j is None for j in jm):
            raise ConfigError(f"machine {m.name!r}: the jerk objective needs jmax_mm_s3 on X and Y")
        limits = (min(m.axis(k).amax_mm_s2 for k in "XY"), float(min(jm)))  # type: ignore[type-var]
    segs = list(toolpath)
    if mode is CornerTransition.EXACT or tolerance_mm <= 0:
        return CornerResult(segs, [], 0.0, mode)
    # under jerk limits the G450 transition circles and the other curvature jumps (line↔arc, arcs
    # of different curvature) are worth replacing as well
    jumps = mode is CornerTransition.OPTIMAL and objective == "jerk"
    sites = find_corner_sites(segs, programmed, tolerance_mm=tolerance_mm, transition_circles=jumps)
    # a small margin for the difference between the per-corner and the global sampling
    eps_of = {k: (1.0 - TARGET_MARGIN) * tolerance_mm for k, _ in sites}
    # runs of small-deflection corners (CAM polylines): one G2 spline across each run; curvature
    # jumps: one G2 spline across each jump
    runs = chains and mode is CornerTransition.OPTIMAL
    splines, kept = _solve_chains(segs, programmed, sites, tolerance_mm, runs=runs, knots=jumps and chains)
    in_chain = {k for c, _, _ in splines for k in c.joints}
    single = [(k, site) for k, site in sites if k not in in_chain]
    result = CornerResult(segs, [], 0.0, mode)
    solved: dict[tuple[int, float], CornerSolution] = {}
    for _round in range(4):
        if mode is CornerTransition.OPTIMAL:
            jobs = [(k, site, eps_of[k], limits) for k, site in single if (k, eps_of[k]) not in solved]
            _solve_sites(jobs, solved, workers)
        result = _assemble(segs, single, eps_of, mode, solved, chains=splines)
        dev, where = cut_deviation(programmed, segs, result.segments, locate=True)
        result.max_deviation_mm = dev
        if dev <= tolerance_mm or where is None:
            break
        # tighten the corner (or the run of corners, or the curvature jump) closest to the worst
        # probe and try again
        near = [(k, site.joint) for k, site in sites]
        near += [(k, np.array(segs[k].geometry.end[:2])) for c, _, _ in splines for k in c.joints if k not in eps_of]
        k_bad = min(near, key=lambda kp: float(np.hypot(*(kp[1] - where))))[0]
        factor = 0.98 * tolerance_mm / max(dev, tolerance_mm)
        if k_bad in in_chain:
            i = next(i for i, c in enumerate(splines) if k_bad in c[0].joints)
            chain, _, eps_c = splines[i]
            sol = solve_chain(chain, eps_c * factor)
            if sol.ok:
                splines[i] = (chain, sol, eps_c * factor)
            else:
                splines.pop(i)
                in_chain -= set(chain.joints)
                single = [(k, site) for k, site in sites if k not in in_chain]
                if chain.max_turn <= TANGENT_TOL_RAD and len(chain.joints) == 1:
                    why = f"spline infeasible at ε {eps_c * factor:.6g} mm ({sol.message})"
                    kept.append(_kept_jump(segs, chain, why))
        else:
            eps_of[k_bad] *= factor
    if mode is CornerTransition.OPTIMAL and select and (result.count("quintic") or result.count("spline")):
        result = _fastest(segs, programmed, single, eps_of, solved, result, tolerance_mm, machine, splines, sites)
    if kept:
        result.corners = sorted(result.corners + kept, key=lambda r: r.index)
    return result


def _kept_jump(segs: list[Segment], chain: ChainSite, why: str) -> CornerRecord:
    """Record of a curvature jump whose spline was not used (the exact path stays there)."""
    k = chain.joints[0]
    turn = math.degrees(joint_turn(segs[k].geometry, segs[k + 1].geometry))  # type: ignore[arg-type]
    return CornerRecord(k, turn, False, False, 0.0, reason=f"curvature jump kept: {why}")


def _solve_chains(
    segs: list[Segment],
    programmed: Sequence[Segment],
    sites: list[tuple[int, CornerSite]],
    tolerance_mm: float,
    *,
    runs: bool = True,
    knots: bool = False,
) -> tuple[list[tuple[ChainSite, ChainSolution, float]], list[CornerRecord]]:
    """G2 splines across the runs of small-deflection corners (``runs``) and across the curvature
    jumps (``knots``): the feasible ones, and records of the curvature jumps that keep the exact
    path."""
    plain = [k for k, site in sites if site.min_cut == 0.0]
    owned = {k for k, _ in sites} | {k + 1 for k, site in sites if site.min_cut > 0.0}
    jumps = _knot_indices(segs, owned) if knots else []
    owned |= set(jumps)
    contour = [
        p.geometry
        for p in part_contour(programmed, segs)
        if isinstance(p.geometry, Line | Arc) and not p.is_rapid
    ]
    eps = (1.0 - TARGET_MARGIN) * tolerance_mm
    out, kept = [], []
    found = find_chains(segs, plain, owned, contour) if runs else []  # type: ignore[arg-type]
    if knots:
        # curvature jumps: each line↔arc joint, and each G450 transition circle between two lines
        # as a whole (its two joints); a feasible spline takes the place of the circle's site
        runs_k = [[k] for k in jumps] + [[k, k + 1] for k, site in sites if site.min_cut > 0.0]
        found += [knot_site(segs, run, owned, contour, eps) for run in runs_k]  # type: ignore[arg-type]
    for chain in found:
        sol = solve_chain(chain, eps)
        if sol.ok:
            out.append((chain, sol, eps))
        elif chain.max_turn <= TANGENT_TOL_RAD and len(chain.joints) == 1:  # (a circle keeps its site)
            kept.append(_kept_jump(segs, chain, f"spline infeasible ({sol.message})"))
    return out, kept


def _fastest(
    segs: list[Segment],
    programmed: Sequence[Segment],
    sites: list[tuple[int, CornerSite]],
    eps_of: dict[int, float],
    solved: dict[tuple[int, float], CornerSolution],
    optimal: CornerResult,
    tolerance_mm: float,
    machine: Machine | None,
    chains: list[tuple[ChainSite, ChainSolution, float]] | None = None,
    every: list[tuple[int, CornerSite]] | None = None,
) -> CornerResult:
    """The fastest of: G2 transitions everywhere (``chains``: splines across runs of CAM chords),
    same-ε circular blends everywhere (``every`` site), and a per-corner choice by a local time
    estimate — timed by the timing stage, never slower than the circular blends. A per-corner G2
    quintic needs zero curvature where it meets a line, so between short chords a circular blend of
    the same ε can carry more speed under acceleration limits."""
    from trcopt.timing import time_parameterize

    m = machine or DEFAULT_MACHINE
    arc = blend_corners(segs, programmed, tolerance_mm=tolerance_mm, mode=CornerTransition.ARC)
    t_opt = time_parameterize(optimal.segments, m).duration
    t_arc = time_parameterize(arc.segments, m).duration
    best, t_best = (optimal, t_opt) if t_opt <= t_arc else (arc, t_arc)
    a_lat = min(m.axis("X").amax_mm_s2, m.axis("Y").amax_mm_s2)
    choice = {}
    for k, site in sites:
        if site.min_cut > 0.0:  # transition circles: G2 or the circle, nothing to choose here
            continue
        sol = solved.get((k, eps_of[k]))
        built = _arc_blend(site, eps_of[k])
        if sol is None or not sol.ok or built is None:
            continue
        feed = m.rapid_mm_s if segs[k].feed_mm_s is None else float(segs[k].feed_mm_s)
        choice[k] = "quintic" if _local_time(sol.geometry, built, feed, a_lat) <= 0.0 else "arc"
    if set(choice.values()) == {"quintic", "arc"}:
        hybrid = _assemble(segs, sites, eps_of, CornerTransition.OPTIMAL, solved, choice, chains)
        hybrid.max_deviation_mm = cut_deviation(programmed, segs, hybrid.segments)[0]
        if hybrid.max_deviation_mm <= tolerance_mm:
            t_h = time_parameterize(hybrid.segments, m).duration
            if t_h < t_best:
                best, t_best = hybrid, t_h
    if best is arc:
        # keep the G2 solutions in the records: the report says why each corner is circular
        every = every or sites
        best = _assemble(segs, every, eps_of, CornerTransition.OPTIMAL, solved, {k: "arc" for k, _ in every})
        best.max_deviation_mm = arc.max_deviation_mm
    best.mode = CornerTransition.OPTIMAL
    return best


def _local_time(q: CornerGeometry, built: tuple[Arc, float, float], feed: float, a_lat: float) -> float:
    """Estimated time of the quintic minus that of the circular blend over the same stretch
    (from the farther start to the farther end of the two), s: each curve at
    ``min(feed, sqrt(a_lat/|κ|))``, the uncovered line pieces at the feed."""
    arc, ta, tb = built
    C = np.array([q.p0, q.d0, q.a0, q.a1, q.d1, q.p1])
    H0, H1, H2 = quintic_basis(np.linspace(0.0, 1.0, 129))
    d1, d2 = H1 @ C, H2 @ C
    sp = np.hypot(d1[:, 0], d1[:, 1])
    kappa = np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.maximum(sp, 1e-300) ** 3
    inv_v = 1.0 / np.minimum(feed, np.sqrt(a_lat / np.maximum(kappa, 1e-300)))
    f = sp * inv_v
    t_q = float(np.sum(0.5 * (f[1:] + f[:-1])) / 128.0)
    t_a = arc.plane_length / min(feed, math.sqrt(a_lat * arc.radius))
    sa, sb = max(q.sa, ta), max(q.sb, tb)
    t_q += (sa - q.sa + sb - q.sb) / feed
    t_a += (sa - ta + sb - tb) / feed
    return t_q - t_a


def _solve_one(
    job: tuple[int, CornerSite, float, tuple[float, float] | None],
) -> tuple[tuple[int, float], CornerSolution]:
    k, site, eps, limits = job
    return (k, eps), CornerBlendProblem(site, eps, limits=limits).solve()


def _solve_sites(
    jobs: list[tuple[int, CornerSite, float, tuple[float, float] | None]],
    solved: dict[tuple[int, float], CornerSolution],
    workers: int,
) -> None:
    """Solve the corner problems of ``jobs`` into ``solved`` (keyed by corner index and ε)."""
    if workers > 1 and len(jobs) >= PARALLEL_MIN_CORNERS:
        from concurrent.futures import ProcessPoolExecutor

        with ProcessPoolExecutor(max_workers=workers) as pool:
            solved.update(pool.map(_solve_one, jobs, chunksize=max(1, len(jobs) // (4 * workers))))
    else:
        solved.update(map(_solve_one, jobs))


def _assemble(
    segs: list[Segment],
    sites: list[tuple[int, CornerSite]],
    eps_of: dict[int, float],
    mode: CornerTransition,
    solved: dict[tuple[int, float], CornerSolution],
    choice: dict[int, str] | None = None,
    chains: Sequence[tuple[ChainSite, ChainSolution, float]] = (),
) -> CornerResult:
    lam0 = [0.0] * len(segs)
    lam1 = [1.0] * len(segs)
    inserts: dict[int, list[Segment]] = {}
    records = []
    for chain, csol, ceps in chains:
        # the spline replaces the run: the end elements are trimmed, the chords between dropped,
        # and each piece keeps the block of the element it follows
        lam1[chain.first] = min(lam1[chain.first], chain.lam_a)
        lam0[chain.last] = max(lam0[chain.last], chain.lam_b)
        for i in range(chain.first + 1, chain.last):
            lam0[i], lam1[i] = 1.0, 0.0
        for j, piece in enumerate(csol.pieces):
            seg = replace(segs[chain.first + j], geometry=piece, role=Role.CORNER, t_start_s=None, t_end_s=None)
            inserts.setdefault(chain.first + max(j - 1, 0), []).append(seg)
        jump = chain.max_turn <= TANGENT_TOL_RAD
        for k in chain.joints:
            turn = math.degrees(joint_turn(segs[k].geometry, segs[k + 1].geometry))  # type: ignore[arg-type]
            inside = not jump and turn * chain.material_sign < 0
            why = JUMP_SMOOTHED if jump else ""
            records.append(
                CornerRecord(k, turn, inside, True, ceps, csol.max_curvature, None, None, why, "spline")
            )
    for k, site in sites:
        eps = eps_of[k]
        turn = math.degrees(site.turn)
        a, b = segs[k].geometry, segs[k + 1].geometry
        sol = solved.get((k, eps)) if mode is CornerTransition.OPTIMAL else None
        use_quintic = sol is not None and sol.ok and (choice is None or choice.get(k, "quintic") == "quintic")
        if use_quintic:
            assert sol is not None
            gm = sol.geometry
            sa, sb, w = gm.sa, gm.sb, site.w
            geom: Line | Arc | Poly = hermite_curve(
                (gm.p0[0], gm.p0[1], w),
                (gm.d0[0], gm.d0[1], 0.0),
                (gm.p1[0], gm.p1[1], w),
                (gm.d1[0], gm.d1[1], 0.0),
                (gm.a0[0], gm.a0[1], 0.0),
                (gm.a1[0], gm.a1[1], 0.0),
                label="corner-quintic",
            )
            kmax, kind, why = gm.max_curvature, "quintic", ""
        elif site.min_cut > 0.0:  # a transition circle stays unless a G2 transition replaces it
            why = "transition circle kept"
            if sol is not None and not sol.ok:
                why = f"G2 transition infeasible ({sol.message}); transition circle kept"
            records.append(CornerRecord(k, turn, site.inside, False, eps, solution=sol, reason=why))
            continue
        else:
            built = _arc_blend(site, eps)
            if built is None:
                why = "no circular blend (arc neighbours)"
                if sol is not None and not sol.ok:
                    why = f"G2 transition infeasible ({sol.message}); {why}"
                records.append(CornerRecord(k, turn, site.inside, False, eps, solution=sol, reason=why))
                continue
            geom, sa, sb = built
            kmax, kind = 1.0 / geom.radius, "arc"
            why = ""
            if sol is not None and not sol.ok:
                why = f"G2 transition infeasible ({sol.message}): circular blend"
            elif sol is not None:
                why = "circular blend is faster here"
        if site.min_cut > 0.0:
            # the circle at k + 1 is replaced whole; the lines lose what lies beyond the circle
            b = segs[k + 2].geometry
            lam1[k] = min(lam1[k], 1.0 - (sa - site.min_cut) / a.plane_length)
            lam0[k + 1], lam1[k + 1] = 1.0, 0.0
            lam0[k + 2] = max(lam0[k + 2], (sb - site.min_cut) / b.plane_length)
        else:
            lam1[k] = min(lam1[k], 1.0 - sa / a.plane_length)
            lam0[k + 1] = max(lam0[k + 1], sb / b.plane_length)
        inserts[k] = [replace(segs[k + 1], geometry=geom, role=Role.CORNER, t_start_s=None, t_end_s=None)]
        records.append(CornerRecord(k, turn, site.inside, True, eps, kmax, sa + sb, sol, why, kind))
    out: list[Segment] = []
    for i, s in enumerate(segs):
        if lam0[i] != 0.0 or lam1[i] != 1.0:
            g = s.geometry
            if (lam1[i] - lam0[i]) * g.plane_length > 1e-7:
                out.append(s.with_geometry(_trim(g, lam0[i], lam1[i])))  # type: ignore[arg-type]
        else:
            out.append(s)
        out.extend(inserts.get(i, ()))
    records.sort(key=lambda r: r.index)
    return CornerResult(out, records, 0.0, mode)


def optimize_corners(
    toolpath: Sequence[Segment],
    programmed: Sequence[Segment],
    *,
    tolerance_mm: float,
    machine: Machine | None = None,
    mode: str | CornerTransition = "optimal",
    workers: int = 1,
) -> list[Segment]:
    """New tool-centre path with tolerance-bounded corner transitions (see :func:`blend_corners`)."""
    return blend_corners(
        toolpath, programmed, tolerance_mm=tolerance_mm, machine=machine, mode=mode, workers=workers
    ).segments


# ------------------------------------------------------------------------------------- measure
def _path_samples(segments: Sequence[Segment], step: float) -> np.ndarray:
    pts = []
    for s in segments:
        g = s.geometry
        n = max(2, int(math.ceil(g.length / step)) + 1)
        pts.append(np.array([g.point(x)[:2] for x in np.linspace(0.0, g.length, n)]))
    return np.vstack(pts) if pts else np.zeros((0, 2))


def cut_deviation(
    programmed: Sequence[Segment],
    exact: Sequence[Segment],
    new: Sequence[Segment],
    *,
    step: float = 0.002,
    locate: bool = False,
) -> tuple[float, np.ndarray | None]:
    """Largest thickness of material the new path leaves beyond the exact path's cut (mm).

    The exact cut boundary (envelope points, disc fans at corners, programmed vertices on the
    boundary) is probed every ``step`` mm along its normals; for each probe the distance along
    the normal to the first disc of radius R swept by the new path (sampled every ``step`` mm)
    is the material left. Returns (max, location of the worst probe or None).
    """
    from scipy.spatial import cKDTree

    comp = [s for s in exact if _eligible(s)]
    if not comp:
        return 0.0, None
    best, where = 0.0, None
    # group by compensation radius/side (one group in practice)
    R, sign = comp[0].radius, _material_sign(comp[0])
    contour = [
        p.geometry
        for p in programmed
        if p.role is Role.CONTOUR
        and isinstance(p.geometry, Line | Arc)
        and p.geometry.plane_length > 0
        and not p.is_rapid
    ]
    probes, dirs = _boundary_probes([s.geometry for s in comp], contour, R, sign, step)  # type: ignore[misc]
    centres = _path_samples([s for s in new if not s.is_rapid and s.radius > 0], step)
    tree = cKDTree(centres)
    dmin, _ = tree.query(probes)
    # a probe within R (+ half a sample spacing of chord sag) of a centre sample is swept
    open_ = np.nonzero(dmin > R + step * step / (4.0 * R) + 1e-9)[0]
    if not len(open_):
        return best, None
    # an upper bound per probe from its nearest centres (fewer discs leave at least as much), then
    # the exact value against every centre within R + 1 mm, in decreasing order of the bound, until
    # no bound exceeds the largest exact value found
    k = min(NEAREST_CENTRES, len(centres))
    bound = np.empty(len(open_))
    for lo in range(0, len(open_), 2048):
        sel = open_[lo : lo + 2048]
        _, nbr = tree.query(probes[sel], k=k)
        nbr = np.asarray(nbr).reshape(len(sel), k)
        bound[lo : lo + 2048] = material_left(probes[sel], dirs[sel], centres[nbr], R)
    for j in np.argsort(-bound):
        if bound[j] <= best:
            break
        i = open_[j]
        idx = tree.query_ball_point(probes[i], R + 1.0)
        if not idx:
            val = 1.0
        else:
            val = float(material_left(probes[i : i + 1], dirs[i : i + 1], centres[idx], R)[0])
        if val > best:
            best, where = val, probes[i]
    return best, (where if locate else None)

