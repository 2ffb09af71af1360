"""Exact arc-length evaluation of tool-centre segments, and toppra's geometric-path protocol.

Lines and arcs/helices are evaluated in closed form (vectorised over many arc-length values);
:class:`~trcopt.geometry.Poly` curves through their own cubic-Hermite ``derivatives``. Positions and
derivatives are returned in workpiece coordinates (x, y, z), mm, with respect to 3D arc length s
in mm, so ``|dp/ds| = 1`` on every element.

:class:`SectionPath` strings the segments of one section together and implements the protocol
toppra's algorithms call (``__call__(s, order)``, ``dof``, ``path_interval``, ``waypoints``)
without importing toppra. At a knot the path is evaluated right-continuously (the next element),
like every toppra path; the grid therefore carries a point just before each knot (see
:mod:`trcopt.timing.grid`).

:class:`PathArrays` holds a whole tool path as flat arrays for evaluating many (segment, s) pairs
at once; :func:`path_derivatives` adds the third derivative the jerk-limited feed needs.
"""

from __future__ import annotations

import math
import operator
from collections.abc import Sequence
from typing import Literal, overload

import numpy as np

from trcopt.geometry.poly import Poly, hermite_at, hermite_pieces
from trcopt.geometry.primitives import Arc, Line
from trcopt.path import Segment

__all__ = ["SegmentEval", "SectionPath", "PathArrays", "path_derivatives"]


class SegmentEval:
    """Closed-form vectorised evaluation of one segment in (x, y, z).

    Parameters
    ----------
    segment:
        The tool-path segment; its geometry is in plane coordinates (u, v, w).
    """

    __slots__ = ("segment", "length", "kind", "_perm", "_line", "_arc", "_poly")

    def __init__(self, segment: Segment) -> None:
        self.segment = segment
        g = segment.geometry
        self.length = float(g.length)
        # column k of the (u, v, w) result goes to xyz column perm[k]
        self._perm = segment.plane.axes
        self._line: tuple[np.ndarray, np.ndarray] | None = None
        self._arc: tuple[float, ...] | None = None
        self._poly: tuple[np.ndarray, ...] | None = None
        if isinstance(g, Line):
            self.kind = "line"
            p0 = np.array(g.start, dtype=float)
            p1 = np.array(g.end, dtype=float)
            d = (p1 - p0) / self.length if self.length > 0 else np.zeros(3)
            self._line = (p0, d)
        elif isinstance(g, Arc):
            self.kind = "arc"
            self._arc = (g.center[0], g.center[1], g.radius, g.a0, g.sweep, g.w0, g.w1)
        elif isinstance(g, Poly):
            self.kind = "poly"
            self._poly = g.arrays()  # evaluated many times: the samples as arrays once
        else:  # pragma: no cover - the Geometry union is closed
            raise TypeError(f"unsupported geometry {type(g).__name__}")

    # -- plane (u, v, w) evaluation -------------------------------------------------------------
    def _uvw(self, s: np.ndarray, order: int) -> np.ndarray:
        n = s.shape[0]
        if self.kind == "line":
            assert self._line is not None
            p0, d = self._line
            if order == 0:
                return p0[None, :] + s[:, None] * d[None, :]
            if order == 1:
                return np.broadcast_to(d, (n, 3)).copy()
            return np.zeros((n, 3))
        if self.kind == "arc":
            assert self._arc is not None
            cu, cv, r, a0, sweep, w0, w1 = self._arc
            length = self.length
            da = sweep / length
            a = a0 + s * da
            ca, sa = np.cos(a), np.sin(a)
            out = np.empty((n, 3))
            if order == 0:
                out[:, 0] = cu + r * ca
                out[:, 1] = cv + r * sa
                out[:, 2] = w0 + (w1 - w0) * (s / length)
            elif order == 1:
                out[:, 0] = -r * da * sa
                out[:, 1] = r * da * ca
                out[:, 2] = (w1 - w0) / length
            else:
                k = r * da * da
                out[:, 0] = -k * ca
                out[:, 1] = -k * sa
                out[:, 2] = 0.0
            return out
        assert self._poly is not None
        return hermite_at(self._poly, s, order).reshape(n, 3)  # type: ignore[arg-type]

    def eval(self, s: np.ndarray | float, order: int = 0) -> np.ndarray:
        """Position (order 0), dp/ds (1) or d²p/ds² (2) at local arc lengths ``s`` (mm), in xyz."""
        s_arr = np.atleast_1d(np.asarray(s, dtype=float))
        uvw = self._uvw(s_arr, order)
        out = np.empty_like(uvw)
        out[:, self._perm] = uvw
        return out

    def start_dir(self) -> np.ndarray:
        """Unit tangent at the start, xyz."""
        return _unit(self.eval(0.0, 1)[0])

    def end_dir(self) -> np.ndarray:
        """Unit tangent at the end, xyz."""
        return _unit(self.eval(self.length, 1)[0])


def _unit(v: np.ndarray) -> np.ndarray:
    n = float(np.linalg.norm(v))
    return v / n if n > 0 else v


class SectionPath:
    """A tangent-continuous run of segments as one path of arc length ``[0, L]`` mm.

    Implements toppra's geometric-path protocol (duck-typed: toppra is not imported here).
    At a knot the following element is used (right-continuous), except at the very end.
    """

    def __init__(self, segments: Sequence[Segment]) -> None:
        self.evals = [SegmentEval(s) for s in segments]
        lengths = np.array([e.length for e in self.evals])
        self.knots = np.concatenate(([0.0], np.cumsum(lengths)))
        self.length = float(self.knots[-1])

    @property
    def dof(self) -> int:
        return 3

    @property
    def path_interval(self) -> np.ndarray:
        return np.array([0.0, self.length])

    @property
    def waypoints(self) -> tuple[np.ndarray, np.ndarray]:
        pts = np.array([e.eval(0.0)[0] for e in self.evals] + [self.evals[-1].eval(self.length_last)[0]])
        return self.knots.copy(), pts

    @property
    def length_last(self) -> float:
        return self.evals[-1].length

    def segment_index(self, s: np.ndarray, left: bool = False) -> np.ndarray:
        """Index of the segment holding each s (right-continuous unless ``left``)."""
        side: Literal["left", "right"] = "left" if left else "right"
        idx = np.searchsorted(self.knots, s, side=side) - 1
        return np.clip(idx, 0, len(self.evals) - 1)

    def eval(self, s: np.ndarray, order: int = 0, seg_idx: np.ndarray | None = None) -> np.ndarray:
        """Evaluate at section arc lengths ``s`` (mm); ``seg_idx`` forces the element per point."""
        s = np.atleast_1d(np.asarray(s, dtype=float))
        idx = self.segment_index(s) if seg_idx is None else seg_idx
        out = np.empty((s.shape[0], 3))
        for k in np.unique(idx):
            m = idx == k
            out[m] = self.evals[k].eval(s[m] - self.knots[k], order)
        return out

    def __call__(self, path_positions: np.ndarray | float, order: int = 0) -> np.ndarray:
        scalar = np.isscalar(path_positions)
        out = self.eval(np.asarray(path_positions, dtype=float), order)
        return out[0] if scalar else out

    def eval_many(self, s: np.ndarray, order: int = 0) -> np.ndarray:  # toppra <0.4 name
        return self(s, order)


def total_turn(a: np.ndarray, b: np.ndarray) -> float:
    """Angle between two unit vectors, rad."""
    c = float(np.clip(np.dot(a, b), -1.0, 1.0))
    return math.acos(c)


class PathArrays:
    """All segments of a tool path as flat arrays, for evaluation of many (segment, s) pairs.

    Lines and arcs/helices are evaluated in closed form with one numpy expression for every
    element at once; Poly elements fall back to :class:`SegmentEval`.
    """

    def __init__(self, segments: Sequence[Segment]) -> None:
        segments = list(segments)
        n = len(segments)
        self.n = n
        lengths: list[float] = []
        axes: list[tuple[int, int, int]] = []
        kinds: list[int] = []
        line_ends: list[tuple[float, ...]] = []  # start and end of every line, in path order
        arc_rows: list[tuple[float, ...]] = []  # cu, cv, r, a0, dangle/ds, w0, dw/ds, sweep of every arc
        curves: dict[int, SegmentEval] = {}
        # the same values SegmentEval holds, read in one pass over the segments
        for i, seg in enumerate(segments):
            g = seg.geometry
            length = float(g.length)
            lengths.append(length)
            axes.append(seg.plane.axes)
            if isinstance(g, Line):
                kinds.append(0)
                line_ends.append((*g.start, *g.end))
            elif isinstance(g, Arc):
                kinds.append(1)
                arc_rows.append((
                    g.center[0], g.center[1], g.radius, g.a0, g.sweep / length, g.w0, (g.w1 - g.w0) / length, g.sweep
                ))
            else:
                kinds.append(2)
                curves[i] = SegmentEval(seg)
        self.evals = _Evaluators(segments, curves)
        self.length = np.array(lengths, dtype=float)
        self.start = np.concatenate(([0.0], np.cumsum(self.length)))[:-1]
        self.kind = np.array(kinds, dtype=np.int8)  # 0 line, 1 arc, 2 poly
        self.perm = np.array(axes, dtype=np.int64).reshape(n, 3)
        # the perm of every segment is the identity (every segment in G17): no scatter of the columns
        self.identity = bool((self.perm == np.arange(3)).all())
        self.p0 = np.zeros((n, 3))
        self.d = np.zeros((n, 3))
        self.arc = np.zeros((n, 7))  # cu, cv, r, a0, dangle/ds, w0, dw/ds
        is_line = self.kind == 0
        if line_ends:
            ends = np.array(line_ends, dtype=float)
            p0, p1 = ends[:, :3], ends[:, 3:]
            ll = self.length[is_line][:, None]
            self.p0[is_line] = p0
            with np.errstate(divide="ignore", invalid="ignore"):
                self.d[is_line] = np.where(ll > 0, (p1 - p0) / ll, 0.0)
        self.sweep = np.zeros(n)  # of every arc/helix, rad (0 elsewhere)
        if arc_rows:
            rows = np.array(arc_rows, dtype=float)
            self.arc[self.kind == 1] = rows[:, :7]
            self.sweep[self.kind == 1] = rows[:, 7]
        self.has_poly = bool(curves)
        self.lines_only = not (arc_rows or curves)
        # the curves' samples concatenated (quintic and cubic ones apart): every (segment, s) pair
        # on a curve is evaluated in one call
        quintic = {i: e._poly[3] is not None for i, e in curves.items()}  # type: ignore[index]
        self._curves = [
            _Concatenated([(i, e) for i, e in curves.items() if quintic[i] == q], n) for q in (True, False)
        ]

    def eval(self, iseg: np.ndarray, s_local: np.ndarray, order: int) -> np.ndarray:
        """Position/derivative of order 0..2 in xyz at local arc length ``s_local`` of ``iseg``."""
        return self.eval_orders(iseg, s_local, (order,))[0]

    def eval012(self, iseg: np.ndarray, s_local: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(eval(…, 0), eval(…, 1), eval(…, 2))`` in one pass (the masks, angles and their sines
        and cosines computed once)."""
        p, d1, d2 = self.eval_orders(iseg, s_local, (0, 1, 2))
        return p, d1, d2

    def eval_orders(self, iseg: np.ndarray, s_local: np.ndarray, orders: Sequence[int]) -> list[np.ndarray]:
        """The derivatives of the given ``orders`` (0..2) in xyz at local arc lengths ``s_local`` of
        the segments ``iseg``, one n×3 array per order."""
        n = s_local.shape[0]
        if self.lines_only and self.identity:
            # the same values as below without the masks and the scatter of the columns
            return [
                self.p0[iseg] + s_local[:, None] * self.d[iseg] if o == 0 else self.d[iseg] if o == 1
                else np.zeros((n, 3))
                for o in orders
            ]
        uvw = {o: np.zeros((n, 3)) for o in orders}
        kind = self.kind[iseg]
        m = kind == 0
        if np.any(m):
            ii = iseg[m]
            if 0 in uvw:
                uvw[0][m] = self.p0[ii] + s_local[m, None] * self.d[ii]
            if 1 in uvw:
                uvw[1][m] = self.d[ii]
        m = kind == 1
        if np.any(m):
            ii = iseg[m]
            cu, cv, r, a0, da, w0, dw = self.arc[ii].T
            sl = s_local[m]
            a = a0 + sl * da
            ca, sa = np.cos(a), np.sin(a)
            if 0 in uvw:
                uvw[0][m] = np.stack((cu + r * ca, cv + r * sa, w0 + dw * sl), axis=1)
            if 1 in uvw:
                uvw[1][m] = np.stack((-r * da * sa, r * da * ca, dw), axis=1)
            if 2 in uvw:
                k = r * da * da
                uvw[2][m] = np.stack((-k * ca, -k * sa, np.zeros_like(k)), axis=1)
        out = []
        curves = np.nonzero(kind == 2)[0]
        for o in orders:
            if self.identity:
                res = uvw[o]
            else:
                res = np.empty_like(uvw[o])
                res[np.arange(n)[:, None], self.perm[iseg]] = uvw[o]
            for group in self._curves if len(curves) else ():
                group.eval_into(res, curves, iseg[curves], s_local[curves], o)
            out.append(res)
        return out


class _Evaluators(Sequence[SegmentEval]):
    """The :class:`SegmentEval` of every segment of a :class:`PathArrays`, made when first asked
    for (the arrays hold what the lines and arcs need; the curves' evaluators are made at once)."""

    def __init__(self, segments: list[Segment], made: dict[int, SegmentEval]) -> None:
        self._segments = segments
        self._made = made

    def __len__(self) -> int:
        return len(self._segments)

    @overload
    def __getitem__(self, k: int) -> SegmentEval: ...

    @overload
    def __getitem__(self, k: slice) -> list[SegmentEval]: ...

    def __getitem__(self, k: int | slice) -> SegmentEval | list[SegmentEval]:
        if isinstance(k, slice):
            return [self[i] for i in range(*k.indices(len(self)))]
        k = operator.index(k)
        if k < 0:
            k += len(self._segments)
        ev = self._made.get(k)
        if ev is None:
            ev = self._made[k] = SegmentEval(self._segments[k])
        return ev


class _Concatenated:
    """The samples of several Poly segments in one set of arrays (each segment's arc length
    shifted by the lengths before it), evaluated for many (segment, s) pairs in one call."""

    def __init__(self, members: Sequence[tuple[int, SegmentEval]], n_segments: int) -> None:
        self.member = np.full(n_segments, -1, dtype=np.int64)
        if not members:
            return
        evals = [e for _, e in members]
        parts = [e._poly for e in evals]
        lengths = np.array([p[0][-1] for p in parts])  # type: ignore[index]
        self.offset = np.concatenate(([0.0], np.cumsum(lengths)))[:-1]
        sizes = np.array([len(p[0]) for p in parts])  # type: ignore[index]
        first = np.concatenate(([0], np.cumsum(sizes)))[:-1]
        self.first, self.last = first, first + sizes - 2  # the first and last sample interval of each
        cat = [np.concatenate([p[j] for p in parts]) for j in range(3)]  # type: ignore[index]
        cat[0] = cat[0] + np.repeat(self.offset, sizes)
        quintic = parts[0][3] is not None  # type: ignore[index]
        K = np.concatenate([p[3] for p in parts]) if quintic else None  # type: ignore[index,misc]
        self.arrays = (cat[0], cat[1], cat[2], K)
        self.perm = np.array([e._perm for e in evals], dtype=np.int64)
        self.member[[i for i, _ in members]] = np.arange(len(members))

    def eval_into(self, out: np.ndarray, rows: np.ndarray, iseg: np.ndarray, s_local: np.ndarray, order: int) -> None:
        """Write the derivative of ``order`` (xyz) at ``s_local`` of the segments ``iseg`` into ``out[rows]``
        for the pairs whose segment is one of these curves."""
        j = self.member[iseg]
        mine = j >= 0
        if not np.any(mine):
            return
        j, rows, s_local = j[mine], rows[mine], s_local[mine]
        cum = self.arrays[0]
        s = self.offset[j] + np.clip(s_local, 0.0, cum[self.last[j] + 1] - self.offset[j])
        i = np.clip(np.searchsorted(cum, s, side="right") - 1, self.first[j], self.last[j])
        uvw = hermite_pieces(self.arrays, i, s, order)
        res = np.empty_like(uvw)
        res[np.arange(len(j))[:, None], self.perm[j]] = uvw
        out[rows] = res


def path_derivatives(arrays: PathArrays, iseg: np.ndarray, s_local: np.ndarray) -> tuple[np.ndarray, ...]:
    """q′, q″, q‴ (xyz, per mm, mm⁻¹, mm⁻²) of segments ``iseg`` at local arc lengths ``s_local``.

    Lines and arcs/helices in closed form; Poly curves from their Hermite pieces (``q‴`` is
    constant on a cubic piece, quadratic in s on a quintic one).
    """
    iseg = np.asarray(iseg, dtype=np.int64)
    s_local = np.asarray(s_local, dtype=float)
    d1 = arrays.eval(iseg, s_local, 1)
    d2 = arrays.eval(iseg, s_local, 2)
    n = s_local.shape[0]
    uvw = np.zeros((n, 3))
    m = arrays.kind[iseg] == 1
    if np.any(m):
        ii = iseg[m]
        _, _, r, a0, da, _, _ = arrays.arc[ii].T
        ang = a0 + s_local[m] * da
        k = r * da * da * da
        uvw[m] = np.stack((k * np.sin(ang), -k * np.cos(ang), np.zeros_like(k)), axis=1)
    d3 = np.empty_like(uvw)
    d3[np.arange(n)[:, None], arrays.perm[iseg]] = uvw
    for j in np.nonzero(arrays.kind[iseg] == 2)[0]:
        seg = arrays.evals[int(iseg[j])].segment
        assert isinstance(seg.geometry, Poly)  # kind 2 is a Poly
        d3[j] = np.asarray(seg.plane.to_xyz(seg.geometry.third(float(s_local[j]))))
    return d1, d2, d3
