"""The per-segment constraint families of a tool-centre path as arrays, shared by
:func:`trcopt.verify.plan.verify_plan` (the whole path) and
:class:`trcopt.verify.stream.StreamVerifier` (one window of it at a time).

:func:`contact_arrays` gives the ``radius`` and ``tangency`` residual of every compensated
element, :func:`joint_arrays` the ``continuity`` of every joint and the ``tangency`` of the joints
that must be tangent; the SAR helpers read the approach/retraction words of the moves.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from trcopt.geometry import Arc, Line
from trcopt.path import Role, Segment
from trcopt.verify.batch import ContinuationTable, continuation_residual_arrays
from trcopt.verify.contact import LineIndex, at_offset_points, contour_residuals, programmed_turns, tangency
from trcopt.verify.joints import NEAR_TANGENT
from trcopt.verify.model import carrier_residual, tangency_residual
from trcopt.verify.table import ARC, LINE, OTHER, ROLE, SegmentTable, fmap

__all__ = ["COMPENSATED_ROLES", "LEADS", "arc_radius", "contact_arrays", "joint_arrays", "sar_for", "sar_specs"]

COMPENSATED_ROLES = _COMPENSATED_ROLES = (Role.CONTOUR, Role.CORNER, Role.APPROACH, Role.RETRACT)
_TANGENT_PROGRAMMED_RAD = 1e-7  # programmed joints tangent within this are verified as tangent
LEADS = _LEADS = (Role.APPROACH, Role.RETRACT)


def _sar_specs(moves: Sequence[Any] | None) -> dict[int, Any]:
    out: dict[int, Any] = {}
    for m in moves or ():
        sar = getattr(m, "sar", None)
        if sar is not None:
            out[m.span.line] = sar
    return out


def _sar_for(line: int, specs: dict[int, Any], role: Role | None = None) -> Any:
    """The SAR words behind a lead segment: retraction in the SAR block itself; the approach
    contour in the SAR block or (P4 in a later block, R45) in one of the next few blocks."""
    if line in specs:
        return specs[line]
    if role is Role.APPROACH:
        for back in range(1, 8):
            sar = specs.get(line - back)
            if sar is not None:
                return sar if sar.contour.is_approach else None
    return None


def _signed_offset(tool: Segment, prog: Line | Arc) -> float:
    """Signed offset (left positive) of the tool element's start point from ``prog``'s carrier."""
    p = tool.geometry.point2(0.0)
    if isinstance(prog, Line):
        d = (prog.end[0] - prog.start[0], prog.end[1] - prog.start[1])
        n = math.hypot(*d)
        return ((p[1] - prog.start[1]) * d[0] - (p[0] - prog.start[0]) * d[1]) / n
    return prog.sense * (prog.radius - math.hypot(p[0] - prog.center[0], p[1] - prog.center[1]))


def _programmed_tangent_at(prog: Line | Arc, p: tuple[float, float]) -> tuple[float, float]:
    if isinstance(prog, Line):
        return prog.direction2()
    ru, rv = p[0] - prog.center[0], p[1] - prog.center[1]
    n = math.hypot(ru, rv)
    if n == 0.0:  # at the centre every direction is as far from the arc: its start tangent
        return prog.start_tangent()
    return (-rv / n * prog.sense, ru / n * prog.sense)


def _allowed_note(kind: str, amount: float, seg: Segment, near_tangent_rad: float) -> str:
    where = seg.span.block or f"line {seg.span.line}"
    if kind == NEAR_TANGENT:
        return (
            f"near-tangent joints (turn ≤ {near_tangent_rad:g} rad) are left as they are by the compensation: "
            f"the tool comes up to {amount:.6g} mm closer than R to the contour there (largest at {where}), "
            "R·(1 − cos turn) at most — not counted as a gouge"
        )
    return (
        f"the closed contour is entered and left at its closing point: the first and last block's tool "
        f"paths come up to {amount:.6g} mm closer than R to the block across it (at {where}), as close as "
        "the entry or exit point itself (lead clearance) — not counted as a gouge"
    )


def _radius_one(
    seg: Segment, prog_by_line: dict[int, list[Segment]], specs: dict[int, Any], toolpath: Sequence[Segment], k: int,
    dv: float,
) -> tuple[float | None, float | None]:
    """(radius, tangency) residual of one compensated segment that is not a continuation, one by
    one (None: not measured); ``dv``: an arc's centre's distance to the nearest programmed vertex."""
    g, R = seg.geometry, seg.radius
    if seg.role is Role.CONTOUR and isinstance(g, (Line, Arc)):
        cands = [p.geometry for p in prog_by_line.get(seg.span.line, []) if isinstance(p.geometry, (Line, Arc))]
        if not cands:
            return None, None
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
        radius = max(carrier_residual(g, best, R), abs(_signed_offset(seg, best) - side * R))
        return radius, tangency_residual(g.start_tangent(), _programmed_tangent_at(best, g.point2(0.0)))
    if isinstance(g, Line) and seg.role in _LEADS:
        # SAR G147/G148: the lead line touching the contour has plane length L = DISR + R
        sar = _sar_for(seg.span.line, specs, seg.role)
        nb = toolpath[k + 1] if seg.role is Role.APPROACH and k + 1 < len(toolpath) else None
        if seg.role is Role.RETRACT and k > 0:
            nb = toolpath[k - 1]
        if sar is not None and sar.disr is not None and sar.contour.value in ("G147", "G148"):
            if nb is not None and nb.role is Role.CONTOUR:
                return abs(g.plane_length - (sar.disr + R)), None
    elif isinstance(g, Arc):
        sar = _sar_for(seg.span.line, specs) if seg.role in _LEADS else None
        if seg.role is Role.CORNER or dv <= 1e-6:
            return dv + abs(g.radius - R), None
        if sar is not None and sar.disr is not None and not sar.contour.value.startswith("G14"):
            return abs(g.radius - sar.disr), None
    return None, None


def contact_arrays(tool: SegmentTable, prog: SegmentTable, comp: SegmentTable, conts: ContinuationTable,
                   nearest: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]], toolpath: Sequence[Segment],
                   compensated: Sequence[Segment], specs: dict[int, Any]) -> tuple[np.ndarray, ...]:
    """The ``radius`` and ``tangency`` residual of every compensated element of ``tool`` (see
    :mod:`trcopt.verify.plan`): (radius, tangency, has radius, has tangency, held) arrays in path
    order. ``nearest(centres)``: the distance of each arc centre (m×2) to the nearest programmed
    vertex and which of them are not known yet (those arcs are ``held``: measured later by
    :func:`arc_radius`)."""
    n = len(tool)
    radius, tangent = np.full(n, np.nan), np.full(n, np.nan)
    has_r, has_t = np.zeros(n, bool), np.zeros(n, bool)
    base = ~(tool.radius <= 0.0) & ~(tool.plen <= 0.0) & tool.roles(*_COMPENSATED_ROLES)
    rest = base.copy()
    rest[conts.k] = False
    rows = np.nonzero(base[conts.k])[0]
    if rows.size:  # a near-tangent joint left as it is: the line starts where the tool is
        k = conts.k[rows]
        radius[k], tangent[k] = continuation_residual_arrays(tool, prog, conts, rows)
        has_r[k] = has_t[k] = True
    one_by_one: list[int] = []
    contour = rest & (tool.role == ROLE[Role.CONTOUR]) & (tool.kind != OTHER)
    ks = np.nonzero(contour)[0]
    cands = LineIndex(comp.line, np.nonzero(comp.kind != OTHER)[0])
    found, pos = cands.find(tool.line[ks])
    count = np.where(found, cands.count[pos], 0) if found.any() else np.zeros(len(ks), np.intp)
    one = count == 1
    if one.any():
        k = ks[one]
        r, t = contour_residuals(tool, comp, k, cands.first[pos[one]])
        ok = ~(np.isnan(r) | np.isnan(t))
        radius[k[ok]], tangent[k[ok]] = r[ok], t[ok]
        has_r[k[ok]] = has_t[k[ok]] = True
        one_by_one += k[~ok].tolist()
    one_by_one += ks[count > 1].tolist()
    leads = rest & ~contour & (tool.kind == LINE) & tool.roles(*_LEADS)
    one_by_one += np.nonzero(leads)[0].tolist()
    arcs = np.nonzero(rest & ~contour & (tool.kind == ARC))[0]
    dv = np.full(n, np.nan)
    held = np.zeros(n, bool)
    dv[arcs], held[arcs] = nearest(np.column_stack((tool.cx[arcs], tool.cy[arcs])))
    arcs = arcs[~held[arcs]]
    corner = (tool.role[arcs] == ROLE[Role.CORNER]) | (dv[arcs] <= 1e-6)
    k = arcs[corner]
    radius[k] = dv[k] + np.abs(tool.r[k] - tool.radius[k])
    has_r[k] = True
    one_by_one += arcs[~corner & tool.roles(*_LEADS)[arcs]].tolist()
    prog_by_line: dict[int, list[Segment]] = {}  # the compensated elements of the lines measured one by one
    need = {toolpath[k].span.line for k in one_by_one}
    of_lines = getattr(compensated, "of_lines", None)  # a lazy sequence: only the lines asked for
    for p in (of_lines(need) if of_lines else compensated) if need else ():
        if p.span.line in need:
            prog_by_line.setdefault(p.span.line, []).append(p)
    for j in one_by_one:
        rj, tj = _radius_one(toolpath[j], prog_by_line, specs, toolpath, j, float(dv[j]))
        if rj is not None:
            radius[j], has_r[j] = rj, True
        if tj is not None:
            tangent[j], has_t[j] = tj, True
    return radius, tangent, has_r, has_t, held


def arc_radius(seg: Segment, dv: float, specs: dict[int, Any]) -> float | None:
    """The ``radius`` residual of a corner or lead arc whose centre is ``dv`` from the nearest
    programmed vertex (None: not measured), as :func:`contact_arrays` gives it."""
    if seg.role is Role.CORNER or dv <= 1e-6:
        return dv + abs(seg.geometry.radius - seg.radius)
    return _radius_one(seg, {}, specs, [seg], 0, dv)[0] if seg.role in _LEADS else None


def joint_arrays(tool: SegmentTable, prog: SegmentTable, comp: SegmentTable, conts: ContinuationTable,
                 toolpath: Sequence[Segment], specs: dict[int, Any]) -> tuple[np.ndarray, ...]:
    """``continuity`` of every joint and ``tangency`` of those that must be tangent: a transition
    circle (corner, KONT arc) with the offset contour element it joins at the offset end (start)
    point of its programmed element — where the circle was cut by the neighbouring offset (the
    end point behind the contour, R35) the joint is an intersection by construction, and two
    circles meeting at an intersection (CDON omitted blocks) are not tangent —, the lead contour
    at P4, offsets of tangent programmed joints."""
    n = len(tool)
    if n < 2:
        empty = np.zeros(0, np.intp)
        return np.zeros(0), empty, np.zeros(0)
    a = np.arange(n - 1)
    b = a + 1
    gap = fmap(math.hypot, tool.ex[a] - tool.sx[b], tool.ey[a] - tool.sy[b], tool.ez[a] - tool.sz[b])
    ok = ~(tool.radius[a] <= 0.0) & ~(tool.radius[b] <= 0.0) & ~(tool.plen[a] <= 0.0) & ~(tool.plen[b] <= 0.0)
    ra, rb = tool.role[a], tool.role[b]
    contour, approach, retract = ROLE[Role.CONTOUR], ROLE[Role.APPROACH], ROLE[Role.RETRACT]
    circles = [ROLE[Role.CORNER], approach, retract]
    transition = np.isin(ra, circles), np.isin(rb, circles)
    required = np.zeros(n - 1, bool)
    index = LineIndex(comp.line)
    into = np.nonzero(ok & (tool.kind[a] == ARC) & transition[0] & (rb == contour))[0]
    required[into] = at_offset_points(tool, comp, index, b[into], start=True)
    out_of = np.nonzero(ok & ~required & (tool.kind[b] == ARC) & transition[1] & (ra == contour))[0]
    required[out_of] = at_offset_points(tool, comp, index, a[out_of], start=False)
    for j in np.nonzero(ok & ~required & (ra == approach) & (rb == contour))[0].tolist():
        sar = _sar_for(toolpath[j].span.line, specs, Role.APPROACH)
        required[j] = sar is not None and sar.contour.is_approach  # tangent entry at P4
    for j in np.nonzero(ok & ~required & (rb == retract) & (ra == contour))[0].tolist():
        sar = _sar_for(toolpath[j + 1].span.line, specs, Role.RETRACT)
        required[j] = sar is not None and not sar.contour.is_approach
    both = np.nonzero(ok & ~required & (ra == contour) & (rb == contour))[0]
    has, turn = programmed_turns(tool, comp, index, a[both])
    required[both] = has & (turn <= _TANGENT_PROGRAMMED_RAD)
    rows = np.nonzero(required)[0]
    su, sv, eu, ev = tool.tangents()
    tu, tv = eu[a[rows]], ev[a[rows]]
    # a near-tangent line left as it is ends on its offset carrier, not parallel to it: the
    # transition circle after it is tangent to the carrier
    row = np.full(n, -1)
    row[conts.k] = np.arange(len(conts))
    c = row[a[rows]]
    on = np.nonzero(c >= 0)[0]
    if on.size:
        _, _, peu, pev = prog.tangents()
        tu[on], tv[on] = peu[conts.programmed[c[on]]], pev[conts.programmed[c[on]]]
    return gap, b[rows], tangency(tu, tv, su[b[rows]], sv[b[rows]])


sar_specs, sar_for = _sar_specs, _sar_for
