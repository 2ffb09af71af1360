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

from collections.abc import Sequence
from typing import Any

import numpy as np

from trcopt.path import Role, Segment
from trcopt.verify.batch import KINDS, ContinuationTable, continuation_table, pair_limits
from trcopt.verify.clearance import clearance_distances
from trcopt.verify.contour import contour_rows
from trcopt.verify.families import (
    _COMPENSATED_ROLES,
    _LEADS,
    _allowed_note,
    _programmed_tangent_at,
    _radius_one,
    _sar_for,
    _sar_specs,
    _signed_offset,
    contact_arrays,
    joint_arrays,
)
from trcopt.verify.index import BoxGrid
from trcopt.verify.index import BoxGrid as _Grid
from trcopt.verify.model import reversal_residual
from trcopt.verify.report import FAMILIES, FAMILY_CODES, INFORMATIONAL, FamilyResidual, VerificationReport
from trcopt.verify.table import ROLE, SegmentTable, py_max

__all__ = ["FamilyResidual", "VerificationReport", "verify_plan", "FAMILIES", "FAMILY_CODES", "INFORMATIONAL"]

# used by the reference verification of the tests
_REEXPORTED = (_allowed_note, _programmed_tangent_at, _radius_one, _sar_for, _signed_offset)

def _contact(tool: SegmentTable, prog: SegmentTable, comp: SegmentTable, conts: ContinuationTable, vertices: Any,
             toolpath: Sequence[Segment], compensated: Sequence[Segment], specs: dict[int, Any],
             fam: dict[str, FamilyResidual]) -> None:
    """The ``radius`` and ``tangency`` residual of every compensated element, in path order."""

    def nearest(centres: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        near = getattr(vertices, "nearest_many", None)
        if near is not None:
            return near(centres), np.zeros(len(centres), bool)
        # a filter without the batch query (a reference filter in the tests)
        dv = [vertices.nearest_distance((float(u), float(v))) for u, v in centres]
        return np.array(dv, float).reshape(-1), np.zeros(len(centres), bool)

    radius, tangent, has_r, has_t, _ = contact_arrays(tool, prog, comp, conts, nearest, toolpath, compensated, specs)
    fam["radius"].add_many(radius[has_r], np.nonzero(has_r)[0], toolpath)
    fam["tangency"].add_many(tangent[has_t], np.nonzero(has_t)[0], toolpath)


def _joints(tool: SegmentTable, prog: SegmentTable, comp: SegmentTable, conts: ContinuationTable,
            toolpath: Sequence[Segment], specs: dict[int, Any], fam: dict[str, FamilyResidual]) -> None:
    """``continuity`` of every joint and ``tangency`` of those that must be tangent."""
    gap, rows, values = joint_arrays(tool, prog, comp, conts, toolpath, specs)
    fam["continuity"].add_many(gap, np.arange(1, len(gap) + 1), toolpath)
    fam["tangency"].add_many(values, rows, toolpath)


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
    for code in np.flatnonzero(np.bincount(kind, minlength=len(KINDS))).tolist():  # the kinds present
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
