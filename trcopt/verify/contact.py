"""The contact (``radius``) and ``tangency`` residuals of the common elements as whole arrays.

A compensated contour line or arc with one programmed line or arc in its block lies on that
element's offset carrier and runs in its sense (:func:`contour_residuals`); the joints of the
tool-centre path that must be tangent are found and measured all at once
(:func:`tangent_joints`, :func:`at_offset_points`). Every value is the one of the per-segment
formulas of :mod:`trcopt.verify.plan` and :mod:`trcopt.verify.model`, by the same float
operations (:mod:`trcopt.verify.table`).
"""

from __future__ import annotations

import math

import numpy as np

from trcopt.verify.table import LINE, SegmentTable, fmap, hypot, py_max

__all__ = ["LineIndex", "contour_residuals", "tangency", "at_offset_points", "programmed_turns"]

OFFSET_POINT_TOL_MM = 1e-6  # a joint this close to the offset point is the tangent joint, mm


def tangency(t1u: np.ndarray, t1v: np.ndarray, t2u: np.ndarray, t2v: np.ndarray) -> np.ndarray:
    """:func:`trcopt.verify.model.tangency_residual` elementwise."""
    c = t1u * t2u + t1v * t2v
    s = np.abs(t1u * t2v - t1v * t2u)
    return np.where(c > 0.0, s, 1.0 + np.abs(c))


class LineIndex:
    """The first and last element of every source line of a table (in table order), looked up
    for many lines at once."""

    def __init__(self, lines: np.ndarray, rows: np.ndarray | None = None) -> None:
        rows = np.arange(len(lines)) if rows is None else rows
        sel = lines[rows]
        self.lines, first, self.count = np.unique(sel, return_index=True, return_counts=True)
        self.first = rows[first]
        self.last = rows[len(sel) - 1 - np.unique(sel[::-1], return_index=True)[1]]

    def find(self, lines: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(found, position) of each line."""
        if len(self.lines) == 0:
            return np.zeros(len(lines), bool), np.zeros(len(lines), np.intp)
        pos = np.minimum(np.searchsorted(self.lines, lines), len(self.lines) - 1)
        return self.lines[pos] == lines, pos


def contour_residuals(tool: SegmentTable, prog: SegmentTable, k: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, ...]:
    """(radius, tangency) of the contour lines and arcs ``k`` against their programmed line or arc
    ``q`` (row of ``prog``): the larger of the carrier residual (start, middle, end) and the side
    error at the start; the tangent against the programmed tangent at the start point."""
    m = len(k)
    R, side = tool.radius[k], tool.side[k]
    pts = [tool.point2(k, lam) for lam in (0.0, 0.5, 1.0)]
    p0u, p0v = pts[0]
    carrier, signed, t2u, t2v = np.empty(m), np.empty(m), np.empty(m), np.empty(m)
    li = np.nonzero(prog.kind[q] == LINE)[0]
    if li.size:
        qq = q[li]
        au, av = prog.sx[qq], prog.sy[qq]
        du, dv = prog.ex[qq] - au, prog.ey[qq] - av
        n = hypot(du, dv)
        vals = [np.abs(np.abs((pu[li] - au) * dv - (pv[li] - av) * du) / n - R[li]) for pu, pv in pts]
        carrier[li] = np.maximum(np.maximum(vals[0], vals[1]), vals[2])
        signed[li] = ((p0v[li] - av) * du - (p0u[li] - au) * dv) / n
        t2u[li], t2v[li] = du / n, dv / n
    ai = np.nonzero(prog.kind[q] != LINE)[0]
    if ai.size:
        qq = q[ai]
        cx, cy, r = prog.cx[qq], prog.cy[qq], prog.r[qq]
        sense = np.where(prog.sweep[qq] > 0.0, 1.0, -1.0)
        vals = [np.abs(np.abs(np.hypot(pu[ai] - cx, pv[ai] - cy) - r) - R[ai]) for pu, pv in pts]
        carrier[ai] = np.maximum(np.maximum(vals[0], vals[1]), vals[2])
        ru, rv = p0u[ai] - cx, p0v[ai] - cy
        n = hypot(ru, rv)
        signed[ai] = sense * (r - n)
        t2u[ai], t2v[ai] = -rv / n * sense, ru / n * sense
    radius = py_max(carrier, np.abs(signed - side * R))
    su, sv, _, _ = tool.tangents()
    return radius, tangency(su[k], sv[k], t2u, t2v)


def at_offset_points(
    tool: SegmentTable, comp: SegmentTable, index: LineIndex, s: np.ndarray, *, start: bool
) -> np.ndarray:
    """Whether each contour segment ``s`` starts (ends) at the offset of its block's first (last)
    programmed element's start (end) point, at R on its side (``plan._at_offset_point``; true for
    a block without programmed elements)."""
    out = np.ones(len(s), bool)
    found, pos = index.find(tool.line[s])
    f = np.nonzero(found)[0]
    if f.size == 0:
        return out
    s = s[f]
    su, sv, eu, ev = comp.tangents()
    if start:
        pe = index.first[pos[f]]
        pu, pv, tu, tv, ju, jv = comp.sx[pe], comp.sy[pe], su[pe], sv[pe], tool.sx[s], tool.sy[s]
    else:
        pe = index.last[pos[f]]
        pu, pv, tu, tv, ju, jv = comp.ex[pe], comp.ey[pe], eu[pe], ev[pe], tool.ex[s], tool.ey[s]
    k = tool.side[s] * tool.radius[s]
    out[f] = hypot((pu - k * tv) - ju, (pv + k * tu) - jv) <= OFFSET_POINT_TOL_MM
    return out


def programmed_turns(tool: SegmentTable, comp: SegmentTable, index: LineIndex, a: np.ndarray) -> tuple[np.ndarray, ...]:
    """(has, turn) of the joints a → a + 1 between two source lines: whether both lines have
    programmed elements, and |turn| (rad) from the last element of the first to the first of
    the second."""
    fa, pa = index.find(tool.line[a])
    fb, pb = index.find(tool.line[a + 1])
    has = fa & fb
    turn = np.full(len(a), np.nan)
    h = np.nonzero(has)[0]
    if h.size:
        su, sv, eu, ev = comp.tangents()
        x, y = index.last[pa[h]], index.first[pb[h]]
        tau, tav, tbu, tbv = eu[x], ev[x], su[y], sv[y]
        turn[h] = np.abs(fmap(math.atan2, tau * tbv - tav * tbu, tau * tbu + tav * tbv))
    return has, turn
