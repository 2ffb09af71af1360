"""Whole-path forms of :mod:`trcopt.verify.joints`: the near-tangent continuations, their
residuals and the clearance limits as arrays, with the same values as the per-segment functions.

:func:`continuation_table` is :func:`~trcopt.verify.joints.continuations` over
:class:`~trcopt.verify.table.SegmentTable` arrays (one row per continuation line, in path order);
:func:`continuation_residual_arrays` is
:func:`~trcopt.verify.joints.continuation_residuals` of every row at once; :func:`pair_limits`
is :func:`~trcopt.verify.joints.clearance_limits` looked up for the measured pairs.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from trcopt.path import Role, Segment
from trcopt.verify.contour import Closing, ContourBlocks
from trcopt.verify.joints import CLOSING, NEAR_TANGENT, NEAR_TANGENT_SLACK_RAD, SAME_POINT_MM
from trcopt.verify.model import points_distance
from trcopt.verify.table import LINE, OTHER, ROLE, SegmentTable, fmap, hypot, py_max

__all__ = ["ContinuationTable", "continuation_table", "continuation_residual_arrays", "pair_limits"]

KINDS = (NEAR_TANGENT, CLOSING)  # limit kind codes


@dataclass(frozen=True, slots=True)
class ContinuationTable:
    """The continuation lines: toolpath index ``k`` (ascending), the start point they must have
    (``su``, ``sv``), the joint's |turn| (rad), and the programmed elements (indices into the
    programmed table): their block's first element, the one before the joint, the one after the
    block (−1: none)."""

    k: np.ndarray
    su: np.ndarray
    sv: np.ndarray
    turn: np.ndarray
    programmed: np.ndarray
    previous: np.ndarray
    following: np.ndarray

    def __len__(self) -> int:
        return len(self.k)


def _empty_continuations() -> ContinuationTable:
    i, f = np.zeros(0, np.intp), np.zeros(0)
    return ContinuationTable(i, f, f, f, i, i, i)


def continuation_table(
    tool: SegmentTable, prog: SegmentTable, near_tangent_rad: float, closings: Sequence[Closing] = ()
) -> ContinuationTable:
    """:func:`~trcopt.verify.joints.continuations` as arrays (the same lines, points and turns)."""
    n = len(tool)
    if near_tangent_rad <= 0.0 or n < 2:
        return _empty_continuations()
    sel = np.nonzero((prog.plen > 0.0) & (prog.kind != OTHER))[0]  # by_line of continuations()
    if sel.size == 0:
        return _empty_continuations()
    sel_lines = prog.line[sel]
    lines, first_pos = np.unique(sel_lines, return_index=True)
    last_pos = len(sel) - 1 - np.unique(sel_lines[::-1], return_index=True)[1]
    first, last = sel[first_pos], sel[last_pos]
    k = np.arange(1, n)
    r, side, ln = tool.radius, tool.side, tool.line
    ok = (tool.role[k] == ROLE[Role.CONTOUR]) & (tool.kind[k] == LINE) & ~(r[k] <= 0.0) & ~(r[k - 1] <= 0.0)
    ok &= (side[k - 1] == side[k]) & (ln[k - 1] != ln[k])
    k = k[ok]
    pa = np.minimum(np.searchsorted(lines, ln[k - 1]), len(lines) - 1)
    pb = np.minimum(np.searchsorted(lines, ln[k]), len(lines) - 1)
    ok = (lines[pa] == ln[k - 1]) & (lines[pb] == ln[k])
    k, pa, pb = k[ok], pa[ok], pb[ok]
    a, b = last[pa], first[pb]
    ok = prog.kind[b] == LINE
    k, pa, pb, a, b = k[ok], pa[ok], pb[ok], a[ok], b[ok]
    ok = ~(hypot(prog.ex[a] - prog.sx[b], prog.ey[a] - prog.sy[b]) > SAME_POINT_MM)
    k, pb, a, b = k[ok], pb[ok], a[ok], b[ok]
    su, sv, eu, ev = prog.tangents()
    tau, tav, tbu, tbv = eu[a], ev[a], su[b], sv[b]
    turn = np.abs(fmap(math.atan2, tau * tbv - tav * tbu, tau * tbu + tav * tbv))
    ok = ~(turn > near_tangent_rad + NEAR_TANGENT_SLACK_RAD)
    k, pb, a, b, turn, tau, tav = k[ok], pb[ok], a[ok], b[ok], turn[ok], tau[ok], tav[ok]
    nxt = np.where(pb + 1 < len(lines), first[np.minimum(pb + 1, len(lines) - 1)], -1)
    if closings:
        loop_start = {c.last_line: c.first_line for c in closings}
        where = {int(v): j for j, v in enumerate(lines.tolist())}
        for j in np.nonzero(np.isin(ln[k], list(loop_start)))[0].tolist():
            pos = where.get(loop_start[int(ln[k[j]])])
            if pos is not None:
                nxt[j] = first[pos]
    has = nxt >= 0
    near = np.zeros(len(k), bool)
    m = nxt[has]
    near[has] = hypot(prog.sx[m] - prog.ex[b[has]], prog.sy[m] - prog.ey[b[has]]) <= SAME_POINT_MM
    off = side[k] * r[k]
    start_u, start_v = prog.sx[b] - off * tav, prog.sy[b] + off * tau
    return ContinuationTable(k, start_u, start_v, turn, b, a, np.where(near, nxt, -1))


def continuation_residual_arrays(
    tool: SegmentTable, prog: SegmentTable, c: ContinuationTable, rows: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """(radius, tangency) of the continuation rows ``rows``, as
    :func:`~trcopt.verify.joints.continuation_residuals` gives them one by one."""
    k, b = c.k[rows], c.programmed[rows]
    eu, ev = tool.point2(k, 1.0)
    pu, pv = tool.point2(k, 0.0)
    du, dv = prog.ex[b] - prog.sx[b], prog.ey[b] - prog.sy[b]
    norm = hypot(du, dv)
    du, dv = du / norm, dv / norm
    offset = (ev - prog.sy[b]) * du - (eu - prog.sx[b]) * dv
    radius = py_max(hypot(pu - c.su[rows], pv - c.sv[rows]), np.abs(offset - tool.side[k] * tool.radius[k]))
    tu, tv, _, _ = tool.tangents()
    cos = tu[k] * du + tv[k] * dv
    return radius, np.where(cos > 0.0, 0.0, 1.0 + np.abs(cos))


def pair_limits(
    toolpath: Sequence[Segment],
    tool: SegmentTable,
    blocks: ContourBlocks,
    part_line: np.ndarray,
    part_of: np.ndarray,
    conts: ContinuationTable,
    leads: np.ndarray,
    pk: np.ndarray,
    pi: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`~trcopt.verify.joints.clearance_limits` of the measured pairs (tool segment ``pk``,
    part element ``pi``): whether the pair has a limit of its own, its distance and its kind
    (index into :data:`KINDS`; of two equal limits the near-tangent one, as the first put).
    ``part_line``: the source line of every part element; ``part_of``: for every programmed
    element its index in ``blocks.part`` (−1: none); ``leads``: which segments are measured as
    lead clearance."""
    n = len(tool)
    near = np.full(len(pk), np.inf)
    if len(conts):
        # a continuation at k limits (k, its previous / programmed / following element) and
        # (k − 1, its previous / programmed element) to R·cos(turn), where that is below R
        row = np.full(n + 1, -1)
        row[conts.k] = np.arange(len(conts))
        limit = tool.radius[conts.k] * fmap(math.cos, conts.turn)
        prev, prog = part_of[conts.previous], part_of[conts.programmed]
        fol = np.where(conts.following >= 0, part_of[np.maximum(conts.following, 0)], -1)
        for r, ends in ((row[pk], True), (row[pk + 1], False)):
            c = np.maximum(r, 0)
            hit = (pi == prev[c]) | (pi == prog[c])
            if ends:
                hit |= pi == fol[c]
            ok = (r >= 0) & hit & ~(limit[c] >= tool.radius[pk]) & (limit[c] < near)
            near = np.where(ok, limit[c], near)
    closing = np.full(len(pk), np.inf)
    entries = _closing_limits(toolpath, tool, blocks, part_line, leads)
    if entries:
        width = max(len(blocks.part), 1)
        keys = np.array(sorted(entries), np.int64)
        dist = np.array([entries[k] for k in keys.tolist()])
        key = pk.astype(np.int64) * width + pi
        at = np.minimum(np.searchsorted(keys, key), len(keys) - 1)
        closing = np.where(keys[at] == key, dist[at], np.inf)
    first = ~(closing < near)
    return (near < np.inf) | (closing < np.inf), np.where(first, near, closing), np.where(first, 0, 1)


def _closing_limits(
    toolpath: Sequence[Segment], tool: SegmentTable, blocks: ContourBlocks, part_line: np.ndarray, leads: np.ndarray
) -> dict[int, float]:
    """The limits of the closing joints (:func:`~trcopt.verify.joints.clearance_limits`): key
    (segment · width + part element) → the smallest distance, where below R."""
    out: dict[int, float] = {}
    if not blocks.closings:
        return out
    n, width = len(toolpath), max(len(blocks.part), 1)
    part_order = np.argsort(part_line, kind="stable")
    part_lines = part_line[part_order]

    def part_of_line(ln: int) -> list[int]:
        return part_order[np.searchsorted(part_lines, ln) : np.searchsorted(part_lines, ln, "right")].tolist()

    usable = (tool.radius > 0.0) & tool.roles(Role.CONTOUR, Role.CORNER) & ~leads
    order = np.argsort(tool.line, kind="stable")
    lines = tool.line[order]
    for closing in blocks.closings:
        first, last = (
            [k for k in np.sort(order[np.searchsorted(lines, ln) : np.searchsorted(lines, ln, "right")]).tolist()
             if usable[k]]
            for ln in (closing.first_line, closing.last_line)
        )  # fmt: skip
        if not first or not last:
            continue
        # only where a lead move ends (starts) at that point: its own lead clearance shows the overlap
        if first[0] > 0 and not leads[first[0] - 1] or last[-1] + 1 < n and not leads[last[-1] + 1]:
            continue
        entry, exit_ = toolpath[first[0]].geometry.point2(0.0), toolpath[last[-1]].geometry.point2(1.0)
        for group, point, across in ((first, entry, closing.last_line), (last, exit_, closing.first_line)):
            for i in part_of_line(across):
                limit = float(points_distance(blocks.part[i].geometry, np.array([point], float))[0])
                for k in group:
                    key = k * width + i
                    if not limit >= toolpath[k].radius and (key not in out or limit < out[key]):
                        out[key] = limit
    return out
