"""The verification one segment at a time, as it was before the whole-array evaluation: the
reference :func:`reference_verify_plan` that ``trcopt.verify.verify_plan`` must equal exactly
(the same report, the same floats), on any path.

It uses the per-segment functions of the package (``carrier_residual``, ``element_distance``,
``continuations``, ``clearance_limits``, …) and none of its tables.
"""

from __future__ import annotations

import math
from collections.abc import Collection, Sequence
from itertools import chain
from typing import Any

import numpy as np

from trcopt.geometry import Arc, Line
from trcopt.path import Role, Segment
from trcopt.verify.contour import contour_blocks
from trcopt.verify.index import BoxGrid
from trcopt.verify.joints import activation_corners, clearance_limits, continuation_residuals, continuations
from trcopt.verify.model import (
    bbox,
    carrier_residual,
    element_distance,
    reversal_residual,
    tangency_residual,
)
from trcopt.verify.plan import _allowed_note, _programmed_tangent_at, _sar_for, _sar_specs, _signed_offset
from trcopt.verify.report import FAMILIES, FamilyResidual, VerificationReport

__all__ = ["reference_line_pair_distances", "reference_verify_plan"]

_Grid = BoxGrid
_COMPENSATED_ROLES = (Role.CONTOUR, Role.CORNER, Role.APPROACH, Role.RETRACT)
_TANGENT_PROGRAMMED_RAD = 1e-7
_OFFSET_POINT_TOL_MM = 1e-6
QUERY_CHUNK = 1 << 13
PAIR_CHUNK = 1 << 16


def reference_line_pair_distances(p0: np.ndarray, p1: np.ndarray, q0: np.ndarray, q1: np.ndarray) -> np.ndarray:
    """Exact minimum plane distances (mm) between the segments ``p0p1`` and ``q0q1`` (each n×2):
    :func:`element_distance` of many pairs of lines at once — 0 where they cross, else the
    smallest distance of an end point to the other segment."""

    def point_segment(pt: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        d = b - a
        dd = (d * d).sum(axis=1)
        t = np.where(dd > 0.0, ((pt - a) * d).sum(axis=1) / np.where(dd > 0.0, dd, 1.0), 0.0)
        t = np.clip(t, 0.0, 1.0)
        return np.hypot(pt[:, 0] - a[:, 0] - t * d[:, 0], pt[:, 1] - a[:, 1] - t * d[:, 1])

    def orient(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
        return (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])

    ends = np.minimum(
        np.minimum(point_segment(p0, q0, q1), point_segment(p1, q0, q1)),
        np.minimum(point_segment(q0, p0, p1), point_segment(q1, p0, p1)),
    )
    crossing = (orient(p0, p1, q0) * orient(p0, p1, q1) < 0.0) & (orient(q0, q1, p0) * orient(q0, q1, p1) < 0.0)
    return np.where(crossing, 0.0, ends)


def _at_offset_point(seg: Segment, prog_by_line: dict[int, list[Segment]], *, start: bool) -> bool:
    """True if the contour segment starts (ends) at the offset of its programmed element's start
    (end) point, at R on its side — where a transition circle joins it tangentially."""
    progs = prog_by_line.get(seg.span.line, [])
    if not progs:
        return True
    pe = progs[0].geometry if start else progs[-1].geometry
    p = pe.start if start else pe.end
    t = pe.start_tangent() if start else pe.end_tangent()
    k = seg.side.sign * seg.radius
    offset = (p[0] - k * t[1], p[1] + k * t[0])
    joint = seg.geometry.start if start else seg.geometry.end
    return math.dist(offset, joint[:2]) <= _OFFSET_POINT_TOL_MM


def _ends(segments: Sequence[Segment]) -> tuple[np.ndarray, np.ndarray]:
    """Plane start and end point of every line (n×4, NaN for the other elements) and which are lines."""
    is_line = np.fromiter((isinstance(s.geometry, Line) for s in segments), bool, len(segments))
    ends = np.full((len(segments), 4), np.nan)
    count = int(is_line.sum())
    if count:
        flat = chain.from_iterable(
            (s.geometry.start[0], s.geometry.start[1], s.geometry.end[0], s.geometry.end[1])
            for s, li in zip(segments, is_line.tolist(), strict=True)
            if li
        )
        ends[is_line] = np.fromiter(flat, float, 4 * count).reshape(count, 4)
    return ends, is_line


def _clearance_distances(
    toolpath: Sequence[Segment], part: Sequence[Segment], grid: BoxGrid, roles: Collection[Role]
) -> tuple[list[int], np.ndarray, np.ndarray, np.ndarray]:
    """For every compensated tool-centre segment (of ``roles``; their indices, ascending, are the
    first result), the exact distance to each programmed part element within R of its box: the
    pairs (tool segment, part element, distance) as three arrays, by tool segment and then by
    part element. The pairs of two lines all at once
    (:func:`~trcopt.verify.model.line_pair_distances`), the others one by one."""
    empty = np.zeros(0, dtype=np.intp)
    if not part:
        return [], empty, empty, np.zeros(0)
    ks = [
        k for k, seg in enumerate(toolpath)
        if seg.radius > 0.0 and seg.geometry.plane_length > 0.0 and seg.role in roles
    ]  # fmt: skip
    if not ks:
        return ks, empty, empty, np.zeros(0)
    kk = np.array(ks, dtype=np.intp)
    boxes = np.fromiter(chain.from_iterable(bbox(toolpath[k].geometry) for k in ks), float, 4 * len(ks)).reshape(-1, 4)
    radii = np.array([toolpath[k].radius for k in ks], float)
    near_many = getattr(grid, "near_many", None)
    pk_parts, pi_parts = [empty], [empty]
    for a in range(0, len(ks), QUERY_CHUNK):
        if near_many is not None:
            q, i = near_many(boxes[a : a + QUERY_CHUNK], radii[a : a + QUERY_CHUNK])
        else:  # a grid without the batch query (a reference filter in the tests)
            found = [grid.near(tuple(boxes[j]), float(radii[j])) for j in range(a, min(a + QUERY_CHUNK, len(ks)))]
            q = np.repeat(np.arange(len(found)), [len(f) for f in found])
            i = np.concatenate([empty, *[np.asarray(f, dtype=np.intp) for f in found]])
        pk_parts.append(kk[a + q])
        pi_parts.append(i.astype(np.intp))
    pk, pi = np.concatenate(pk_parts), np.concatenate(pi_parts)
    tool_ends, tool_line = _ends(toolpath)
    part_ends, part_line = _ends(part)
    lines = tool_line[pk] & part_line[pi]
    dist = np.empty(len(pk))
    both = np.nonzero(lines)[0]
    for a in range(0, len(both), PAIR_CHUNK):  # in chunks: the temporaries stay small
        n = both[a : a + PAIR_CHUNK]
        t, p = tool_ends[pk[n]], part_ends[pi[n]]
        dist[n] = reference_line_pair_distances(t[:, 0:2], t[:, 2:4], p[:, 0:2], p[:, 2:4])
    for n in np.nonzero(~lines)[0].tolist():
        dist[n] = element_distance(toolpath[int(pk[n])].geometry, part[int(pi[n])].geometry)[0]
    return ks, pk, pi, dist


def reference_verify_plan(
    programmed: Sequence[Segment],
    toolpath: Sequence[Segment],
    moves: Sequence[Any] | None = None,
    settings: Any = None,
    *,
    tolerance: float = 1e-6,
    near_tangent_rad: float = 0.0,
) -> VerificationReport:
    """Evaluate the constraint model on a planned path.

    Parameters
    ----------
    programmed, toolpath:
        ``PlanResult.programmed`` and ``PlanResult.toolpath``.
    moves:
        ``PlanResult.nc.moves`` (optional): gives SAR DISR for the approach-circle radius check
        and DISRP for the no-reversal run.
    settings:
        :class:`~trcopt.config.TrcSettings` (optional): ``wab_clearance_tolerance_mm`` is noted.
    tolerance:
        Largest residual still reported as ok (mm, and dimensionless for tangency).
    near_tangent_rad:
        The compensation's near-tangent limit, rad: joints whose programmed turn is at most this
        are left as they are, the next line starting where the tool is (LinuxCNC 0.05; 0: none;
        :mod:`trcopt.verify.joints`).
    """
    import time

    t0 = time.perf_counter()
    fam = {name: FamilyResidual(name) for name in FAMILIES}
    notes: list[str] = []
    specs = _sar_specs(moves)

    blocks = contour_blocks(programmed, toolpath)
    part, lead_lines = blocks.part, blocks.lead_lines
    prog_by_line: dict[int, list[Segment]] = {}
    for p in blocks.compensated:
        prog_by_line.setdefault(p.span.line, []).append(p)
    # programmed vertices (the centres of transition circles) and the part's boxes, indexed
    vertices = BoxGrid(np.array([[*p.geometry.start[:2], *p.geometry.start[:2]] for p in blocks.compensated]))
    boxes = np.array([bbox(p.geometry) for p in part]) if part else np.zeros((0, 4))
    # cells fitted to the queries (an element and R around it); a reference filter put in the
    # grid's place (tests, benchmarks) takes the boxes alone
    margin = max((seg.radius for seg in toolpath if seg.radius > 0.0), default=0.0)
    grid = BoxGrid(boxes, margin=margin) if BoxGrid is _Grid else BoxGrid(boxes)
    conts = continuations(toolpath, programmed, near_tangent_rad, blocks.closings)

    # ---- radius (contact) and element direction -------------------------------------------
    for k, seg in enumerate(toolpath):
        g = seg.geometry
        if seg.radius <= 0.0 or g.plane_length <= 0.0 or seg.role not in _COMPENSATED_ROLES:
            continue
        R = seg.radius
        if k in conts:  # a near-tangent joint left as it is: the line starts where the tool is
            radius, tangency = continuation_residuals(seg, conts[k])
            fam["radius"].add(radius, k, seg)
            fam["tangency"].add(tangency, k, seg)
        elif seg.role is Role.CONTOUR and isinstance(g, (Line, Arc)):
            cands = [p.geometry for p in prog_by_line.get(seg.span.line, []) if isinstance(p.geometry, (Line, Arc))]
            if not cands:
                continue
            side = seg.side.sign
            # the distance error along the element and the side at its start: the larger of the
            # two (at the start they measure the same error; a sum would count it twice)
            resid = [max(carrier_residual(g, pg, R), abs(_signed_offset(seg, pg) - side * R)) for pg in cands]
            # a block run more than once (subprogram, repeat, transformed frames) has one element
            # per run: among the equally good, the run whose element starts nearest the tool
            least = min(resid)
            best = min(
                (pg for pg, r in zip(cands, resid, strict=True) if r <= least + 1e-9),
                key=lambda pg: math.dist(pg.start[:2], g.point2(0.0)),
            )
            fam["radius"].add(max(carrier_residual(g, best, R), abs(_signed_offset(seg, best) - side * R)), k, seg)
            p0 = g.point2(0.0)
            fam["tangency"].add(tangency_residual(g.start_tangent(), _programmed_tangent_at(best, p0)), k, seg)
        elif isinstance(g, Line) and seg.role in (Role.APPROACH, Role.RETRACT):
            # SAR G147/G148: the lead line touching the contour has plane length L = DISR + R
            sar = _sar_for(seg.span.line, specs, seg.role)
            nb = toolpath[k + 1] if seg.role is Role.APPROACH and k + 1 < len(toolpath) else None
            if seg.role is Role.RETRACT and k > 0:
                nb = toolpath[k - 1]
            if sar is not None and sar.disr is not None and sar.contour.value in ("G147", "G148"):
                if nb is not None and nb.role is Role.CONTOUR:
                    fam["radius"].add(abs(g.plane_length - (sar.disr + R)), k, seg)
        elif isinstance(g, Arc):
            dv = vertices.nearest_distance(g.center)
            sar = _sar_for(seg.span.line, specs) if seg.role in (Role.APPROACH, Role.RETRACT) else None
            if seg.role is Role.CORNER or dv <= 1e-6:
                fam["radius"].add(dv + abs(g.radius - R), k, seg)
            elif sar is not None and sar.disr is not None and not sar.contour.value.startswith("G14"):
                fam["radius"].add(abs(g.radius - sar.disr), k, seg)

    # ---- joints: continuity and tangency ---------------------------------------------------
    # a transition circle (corner, KONT arc) is tangent to the offset contour element it joins;
    # two circles meeting at an intersection (CDON omitted blocks) are not
    transition = (Role.CORNER, Role.APPROACH, Role.RETRACT)
    end_tangents: dict[int, Any] = {}  # line → end tangent of its last programmed element
    start_tangents: dict[int, Any] = {}  # line → start tangent of its first one
    for k in range(len(toolpath) - 1):
        a, b = toolpath[k], toolpath[k + 1]
        fam["continuity"].add(math.dist(a.geometry.end, b.geometry.start), k + 1, b)
        if a.radius <= 0.0 or b.radius <= 0.0:
            continue
        ga, gb = a.geometry, b.geometry
        if ga.plane_length <= 0.0 or gb.plane_length <= 0.0:
            continue
        # ... at the offset end (start) point of its programmed element; where the circle was cut
        # by the neighbouring offset (the end point behind the contour, R35) the joint is an
        # intersection by construction
        required = (
            isinstance(ga, Arc)
            and a.role in transition
            and b.role is Role.CONTOUR
            and _at_offset_point(b, prog_by_line, start=True)
        ) or (
            isinstance(gb, Arc)
            and b.role in transition
            and a.role is Role.CONTOUR
            and _at_offset_point(a, prog_by_line, start=False)
        )
        if not required and a.role is Role.APPROACH and b.role is Role.CONTOUR:
            sar = _sar_for(a.span.line, specs, Role.APPROACH)
            required = sar is not None and sar.contour.is_approach  # tangent entry at P4
        if not required and b.role is Role.RETRACT and a.role is Role.CONTOUR:
            sar = _sar_for(b.span.line, specs, Role.RETRACT)
            required = sar is not None and not sar.contour.is_approach
        if not required and a.role is Role.CONTOUR and b.role is Role.CONTOUR:
            la, lb = a.span.line, b.span.line
            if prog_by_line.get(la) and prog_by_line.get(lb):
                ta = end_tangents.get(la)
                if ta is None:
                    ta = end_tangents[la] = prog_by_line[la][-1].geometry.end_tangent()
                tb = start_tangents.get(lb)
                if tb is None:
                    tb = start_tangents[lb] = prog_by_line[lb][0].geometry.start_tangent()
                required = abs(math.atan2(ta[0] * tb[1] - ta[1] * tb[0], ta[0] * tb[0] + ta[1] * tb[1])) <= (
                    _TANGENT_PROGRAMMED_RAD
                )
        if required:
            # a near-tangent line left as it is ends on its offset carrier, not parallel to it:
            # the transition circle after it is tangent to the carrier
            end_tangent = conts[k].programmed.geometry.end_tangent() if k in conts else ga.end_tangent()
            fam["tangency"].add(tangency_residual(end_tangent, gb.start_tangent()), k + 1, b)

    # ---- no reversal of the infeed axis -----------------------------------------------------
    # SAR blocks: w1 → w2 → w3 → w4 over the block's sub-movements (and, on approach, the lead
    # contour executed in the following block), P0 excluded (R42); other leads: each run of
    # approach (retraction) segments.
    used: set[int] = set()
    for line, sar in specs.items():
        idx = [k for k, sg in enumerate(toolpath) if sg.span.line == line]
        if not idx:
            continue
        if sar.contour.is_approach:
            j = idx[-1]
            while j + 1 < len(toolpath) and toolpath[j + 1].role is Role.APPROACH:
                j += 1
                idx.append(j)
            ws = [toolpath[i].geometry.end[2] for i in idx]  # from P1 on
        else:
            ws = [toolpath[idx[0]].geometry.start[2]] + [toolpath[i].geometry.end[2] for i in idx[:-1]]
        used.update(idx)
        fam["no_reversal"].add(reversal_residual(ws), idx[0], toolpath[idx[0]])
    k = 0
    while k < len(toolpath):
        role = toolpath[k].role
        if role not in (Role.APPROACH, Role.RETRACT) or k in used:
            k += 1
            continue
        j = k
        while j + 1 < len(toolpath) and toolpath[j + 1].role is role and j + 1 not in used:
            j += 1
        ws = [toolpath[k].geometry.start[2]] + [toolpath[i].geometry.end[2] for i in range(k, j + 1)]
        fam["no_reversal"].add(reversal_residual(ws), k, toolpath[k])
        k = j + 1

    # ---- clearance from the whole programmed contour (no gouge) ---------------------------
    # lead moves: approach and retraction (not SAR), the transitions around the contour's start
    # and end point, lead blocks; each part element is measured against R, or against the
    # limit of a near-tangent joint or of the closing joint (verify.joints)
    activation = activation_corners(toolpath)
    leads = {
        k
        for k, seg in enumerate(toolpath)
        if seg.span.line in lead_lines
        or k in activation
        or (seg.role in (Role.APPROACH, Role.RETRACT) and _sar_for(seg.span.line, specs, seg.role) is None)
    }
    limits = clearance_limits(toolpath, blocks, conts, leads)
    allowed: dict[str, tuple[float, int]] = {}  # kind → (largest R − distance within its limit, segment)
    measured, pk, pi, dist = _clearance_distances(toolpath, part, grid, _COMPENSATED_ROLES)
    # the pairs without a limit of their own: R − distance, largest per tool segment, all at once
    radius_of = np.array([toolpath[k].radius for k in measured], float)
    slot = np.searchsorted(np.array(measured, dtype=np.intp), pk)
    width = max(len(part), 1)
    limit_keys = np.fromiter((k * width + i for k, own in limits.items() for i in own), np.int64)
    limited = np.isin(pk.astype(np.int64) * width + pi, limit_keys)  # the pairs with a limit of their own
    worst_of = np.zeros(len(measured))
    free = ~limited
    np.fmax.at(worst_of, slot[free], radius_of[slot[free]] - dist[free])  # NaN-free max, as max() over the pairs
    worst_by = dict(zip(measured, worst_of.tolist(), strict=True))
    for n in np.nonzero(limited)[0].tolist():
        k, i, d = int(pk[n]), int(pi[n]), float(dist[n])
        lim = limits[k][i]
        worst_by[k] = max(worst_by[k], lim.distance - d)
        excused = toolpath[k].radius - max(d, lim.distance)
        if excused > allowed.get(lim.kind, (0.0, -1))[0]:
            allowed[lim.kind] = (excused, k)
    for k in measured:
        fam["lead_clearance" if k in leads else "clearance"].add(max(0.0, worst_by[k]), k, toolpath[k])
    for kind, (amount, k) in allowed.items():
        if amount > tolerance:
            notes.append(_allowed_note(kind, amount, toolpath[k], near_tangent_rad))

    if settings is not None and getattr(settings, "wab_clearance_tolerance_mm", None) is not None:
        if fam["no_reversal"].max_residual > 0.0:
            notes.append(
                f"no_reversal {fam['no_reversal'].max_residual:.6g} mm "
                f"(controller snap tolerance MD20204 = {settings.wab_clearance_tolerance_mm} mm)"
            )
    return VerificationReport(fam, tolerance, time.perf_counter() - t0, notes)
