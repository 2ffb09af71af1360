"""Verify a planned tool-centre path against the constraint model (design.md §4).

``verify_plan(programmed, toolpath)`` evaluates every constraint family with the exact float
functions of :mod:`trcopt.verify.model` and reports, per family, the largest residual and where
it occurs:

``radius``
    a compensated contour element lies on the offset carrier of its programmed element, on the
    compensation side, at distance R (mm); a transition circle (corner, KONT arc) is centred on its
    programmed vertex with radius R; a SAR approach/retraction circle has tool-centre radius DISR.
``tangency``
    tangent joints stay tangent: transition circles with their neighbours, the lead contour at P4,
    offsets of tangent programmed joints; each contour offset runs parallel to and in the sense of
    its programmed element (a reversed CDOF offset is a violation). Dimensionless (|sin angle|,
    ≥ 1 for reversals).
``continuity``
    consecutive segments meet (mm).
``no_reversal``
    the applicate is monotonic over each run of approach (retraction) sub-movements (mm; spec R42).
``clearance``
    every compensated tool-centre contour, corner and SAR lead element keeps at least R from the
    whole part contour (:func:`trcopt.verify.contour.part_contour`): ``max(0, R − distance)`` (mm;
    a positive value is a gouge) — less than R only where the controller's own rule puts it
    (:mod:`trcopt.verify.joints`: a near-tangent joint left as it is, the closing joint of a closed
    contour), noted in ``notes``.
``lead_clearance`` (informational, not part of ``ok``)
    the same for NORM/KONT activation and deselection moves, which the controller builds towards
    the programmed start/end point and which overlap the contour when that point is close to it,
    the transitions around the contour's start (end) point between them and the contour (LinuxCNC's
    entry arc), and for the lead-in and lead-out blocks CAM posts write around a closed contour.

A line that starts where the tool is at a near-tangent joint (``near_tangent_rad``, the profile's
limit) is measured against that construction in ``radius`` and ``tangency``
(:func:`trcopt.verify.joints.continuation_residuals`).

A family over tolerance is a diagnostic (:meth:`VerificationReport.diagnostics`: ``VERIFY-…``, a
warning, an error under ``--strict``) at the block of its worst segment.

Closed forms and NumPy only. The path is read once into arrays (:mod:`trcopt.verify.table`) and
the residuals of the common elements — contour lines and arcs with one programmed element, the
near-tangent continuations, transition circles, the joints, the clearance distances of lines and
arcs — are computed as whole arrays by the same float operations as the per-segment formulas
(:mod:`.contact`, :mod:`.batch`, :mod:`.pairs`), so they are the same values, bit for bit; the rare
cases (SAR approach and retraction moves, blocks run more than once, polynomial curves, NaN) take
the per-segment code. The clearance candidates come from a uniform grid over the part contour's
bounding boxes (:class:`trcopt.verify.index.BoxGrid`), so a plan verifies in O(n): the same
candidates, hence the same residuals, as filtering every box for every segment.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from trcopt.geometry import Arc, Line
from trcopt.path import Role, Segment
from trcopt.verify.batch import KINDS, ContinuationTable, continuation_residual_arrays, continuation_table, pair_limits
from trcopt.verify.clearance import clearance_distances
from trcopt.verify.contact import LineIndex, at_offset_points, contour_residuals, programmed_turns, tangency
from trcopt.verify.contour import contour_rows
from trcopt.verify.index import BoxGrid
from trcopt.verify.index import BoxGrid as _Grid
from trcopt.verify.joints import NEAR_TANGENT
from trcopt.verify.model import carrier_residual, reversal_residual, tangency_residual
from trcopt.verify.report import FAMILIES, FAMILY_CODES, INFORMATIONAL, FamilyResidual, VerificationReport
from trcopt.verify.table import ARC, LINE, OTHER, ROLE, SegmentTable, fmap, py_max

__all__ = ["FamilyResidual", "VerificationReport", "verify_plan", "FAMILIES", "FAMILY_CODES", "INFORMATIONAL"]

_COMPENSATED_ROLES = (Role.CONTOUR, Role.CORNER, Role.APPROACH, Role.RETRACT)
_TANGENT_PROGRAMMED_RAD = 1e-7  # programmed joints tangent within this are verified as tangent
_LEADS = (Role.APPROACH, Role.RETRACT)


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


def _contact(tool: SegmentTable, prog: SegmentTable, comp: SegmentTable, conts: ContinuationTable, vertices: Any,
             toolpath: Sequence[Segment], compensated: Sequence[Segment], specs: dict[int, Any],
             fam: dict[str, FamilyResidual]) -> None:
    """The ``radius`` and ``tangency`` residual of every compensated element (see the module
    docstring), in path order."""
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
    near = getattr(vertices, "nearest_many", None)
    centres = np.column_stack((tool.cx[arcs], tool.cy[arcs]))
    dv = np.full(n, np.nan)
    if near is not None:
        dv[arcs] = near(centres)
    else:  # a filter without the batch query (a reference filter in the tests)
        dv[arcs] = [vertices.nearest_distance((float(u), float(v))) for u, v in centres]
    corner = (tool.role[arcs] == ROLE[Role.CORNER]) | (dv[arcs] <= 1e-6)
    k = arcs[corner]
    radius[k] = dv[k] + np.abs(tool.r[k] - tool.radius[k])
    has_r[k] = True
    one_by_one += arcs[~corner & tool.roles(*_LEADS)[arcs]].tolist()
    prog_by_line: dict[int, list[Segment]] = {}  # the compensated elements of the lines measured one by one
    need = {toolpath[k].span.line for k in one_by_one}
    for p in compensated if need else ():
        if p.span.line in need:
            prog_by_line.setdefault(p.span.line, []).append(p)
    for j in one_by_one:
        rj, tj = _radius_one(toolpath[j], prog_by_line, specs, toolpath, j, float(dv[j]))
        if rj is not None:
            radius[j], has_r[j] = rj, True
        if tj is not None:
            tangent[j], has_t[j] = tj, True
    fam["radius"].add_many(radius[has_r], np.nonzero(has_r)[0], toolpath)
    fam["tangency"].add_many(tangent[has_t], np.nonzero(has_t)[0], toolpath)


def _joints(tool: SegmentTable, prog: SegmentTable, comp: SegmentTable, conts: ContinuationTable,
            toolpath: Sequence[Segment], specs: dict[int, Any], fam: dict[str, FamilyResidual]) -> None:
    """``continuity`` of every joint and ``tangency`` of those that must be tangent: a transition
    circle (corner, KONT arc) with the offset contour element it joins at the offset end (start)
    point of its programmed element — where the circle was cut by the neighbouring offset (the
    end point behind the contour, R35) the joint is an intersection by construction, and two
    circles meeting at an intersection (CDON omitted blocks) are not tangent —, the lead contour
    at P4, offsets of tangent programmed joints."""
    n = len(tool)
    if n < 2:
        return
    a = np.arange(n - 1)
    b = a + 1
    gap = fmap(math.hypot, tool.ex[a] - tool.sx[b], tool.ey[a] - tool.sy[b], tool.ez[a] - tool.sz[b])
    fam["continuity"].add_many(gap, b, toolpath)
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
    fam["tangency"].add_many(tangency(tu, tv, su[b[rows]], sv[b[rows]]), b[rows], toolpath)


def _no_reversal(
    tool: SegmentTable, toolpath: Sequence[Segment], specs: dict[int, Any], fam: dict[str, FamilyResidual]
) -> None:
    """SAR blocks: w1 → w2 → w3 → w4 over the block's sub-movements (and, on approach, the lead
    contour executed in the following block), P0 excluded (R42); other leads: each run of
    approach (retraction) segments."""
    used: set[int] = set()
    n = len(toolpath)
    if specs:
        order = np.argsort(tool.line, kind="stable")
        lines = tool.line[order]
    for line, sar in specs.items():
        idx = sorted(order[np.searchsorted(lines, line) : np.searchsorted(lines, line, "right")].tolist())
        if not idx:
            continue
        if sar.contour.is_approach:
            j = idx[-1]
            while j + 1 < n and toolpath[j + 1].role is Role.APPROACH:
                j += 1
                idx.append(j)
            ws = [toolpath[i].geometry.end[2] for i in idx]  # from P1 on
        else:
            ws = [toolpath[idx[0]].geometry.start[2]] + [toolpath[i].geometry.end[2] for i in idx[:-1]]
        used.update(idx)
        fam["no_reversal"].add(reversal_residual(ws), idx[0], toolpath[idx[0]])
    after = 0
    for k in np.nonzero(tool.roles(*_LEADS))[0].tolist():
        if k < after or k in used:
            continue
        role = tool.role[k]
        j = k
        while j + 1 < n and tool.role[j + 1] == role and j + 1 not in used:
            j += 1
        ws = [float(tool.sz[k]), *tool.ez[k : j + 1].tolist()]
        fam["no_reversal"].add(reversal_residual(ws), k, toolpath[k])
        after = j + 1


def _lead_segments(tool: SegmentTable, toolpath: Sequence[Segment], lead_lines: frozenset[int],
                   specs: dict[int, Any]) -> np.ndarray:
    """Which segments are lead moves (measured as ``lead_clearance``): approach and retraction
    (not SAR), the transitions around the contour's start and end point
    (:func:`~trcopt.verify.joints.activation_corners`), lead blocks."""
    n = len(tool)
    out = np.isin(tool.line, np.fromiter(lead_lines, np.int64, len(lead_lines)))
    corner = tool.role == ROLE[Role.CORNER]
    for k in np.nonzero(tool.roles(*_LEADS))[0].tolist():
        step = 1 if tool.role[k] == ROLE[Role.APPROACH] else -1
        j = k + step
        while 0 <= j < n and corner[j]:
            out[j] = True
            j += step
        seg = toolpath[k]
        if _sar_for(seg.span.line, specs, seg.role) is None:
            out[k] = True
    return out


def _clearance(tool: SegmentTable, part_table: SegmentTable, toolpath: Sequence[Segment], blocks: Any, grid: Any,
               part_of: np.ndarray, conts: ContinuationTable, leads: np.ndarray, fam: dict[str, FamilyResidual],
               tolerance: float, near_tangent_rad: float) -> list[str]:
    """``clearance`` and ``lead_clearance``: each part element is measured against R, or against
    the limit of a near-tangent joint or of the closing joint (:mod:`trcopt.verify.joints`);
    the notes of the limits used."""
    measured, pk, pi, dist = clearance_distances(toolpath, blocks.part, grid, _COMPENSATED_ROLES, tool, part_table)
    ks = np.asarray(measured, dtype=np.intp)
    if ks.size == 0:
        return []
    slot = np.searchsorted(ks, pk)
    limited, lim, lim_kind = pair_limits(toolpath, tool, blocks, part_table.line, part_of, conts, leads, pk, pi)
    # R − distance, or the pair's own limit − distance; the largest per tool segment (NaN-free)
    worst = np.zeros(len(ks))
    np.fmax.at(worst, slot, np.where(limited, lim, tool.radius[pk]) - dist)
    worst = py_max(np.zeros(len(ks)), worst)
    lead = leads[ks]
    fam["lead_clearance"].add_many(worst[lead], ks[lead], toolpath)
    fam["clearance"].add_many(worst[~lead], ks[~lead], toolpath)
    # how much closer than R the limits let the tool come: per kind, the largest (first) one
    n = np.nonzero(limited)[0]
    excused = tool.radius[pk[n]] - py_max(dist[n], lim[n])
    kind = lim_kind[n]
    firsts = []
    for code in np.unique(kind).tolist():
        e = np.where(kind == code, excused, np.nan)
        pos = np.nonzero(e > 0.0)[0]
        if pos.size:
            best = int(np.argmax(e == np.nanmax(e)))
            firsts.append((int(pos[0]), KINDS[code], float(e[best]), int(pk[n[best]])))
    return [_allowed_note(kind, amount, toolpath[k], near_tangent_rad)
            for _, kind, amount, k in sorted(firsts) if amount > tolerance]  # fmt: skip


def verify_plan(
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
    specs = _sar_specs(moves)

    tool, prog = SegmentTable(toolpath), SegmentTable(programmed)
    blocks, comp_rows, part_rows = contour_rows(programmed, tool, prog)
    part = blocks.part
    comp, part_table = prog.take(comp_rows, blocks.compensated), prog.take(part_rows, part)
    part_of = np.full(len(programmed), -1, np.intp)
    part_of[part_rows] = np.arange(len(part))
    # programmed vertices (the centres of transition circles) and the part's boxes, indexed
    vertices = BoxGrid(np.column_stack((comp.sx, comp.sy, comp.sx, comp.sy)))
    boxes = part_table.bboxes(np.arange(len(part))) if part else np.zeros((0, 4))
    # cells fitted to the queries (an element and R around it); a reference filter put in the
    # grid's place (tests, benchmarks) takes the boxes alone
    positive = tool.radius[tool.radius > 0.0]
    margin = float(positive.max()) if positive.size else 0.0
    grid = BoxGrid(boxes, margin=margin) if BoxGrid is _Grid else BoxGrid(boxes)
    conts = continuation_table(tool, prog, near_tangent_rad, blocks.closings)

    _contact(tool, prog, comp, conts, vertices, toolpath, blocks.compensated, specs, fam)
    _joints(tool, prog, comp, conts, toolpath, specs, fam)
    _no_reversal(tool, toolpath, specs, fam)
    leads = _lead_segments(tool, toolpath, blocks.lead_lines, specs)
    notes = _clearance(
        tool, part_table, toolpath, blocks, grid, part_of, conts, leads, fam, tolerance, near_tangent_rad
    )

    if settings is not None and getattr(settings, "wab_clearance_tolerance_mm", None) is not None:
        if fam["no_reversal"].max_residual > 0.0:
            notes.append(
                f"no_reversal {fam['no_reversal'].max_residual:.6g} mm "
                f"(controller snap tolerance MD20204 = {settings.wab_clearance_tolerance_mm} mm)"
            )
    return VerificationReport(fam, tolerance, time.perf_counter() - t0, notes)
