"""The segments of a path as arrays, for the verification's whole-path evaluations.

:class:`SegmentTable` reads every segment once (kind, end points, arc parameters, role, tool
radius, side, source line) and gives the derived quantities — points, tangents, bounding boxes —
as arrays. Every value is computed by the same IEEE operations as the scalar geometry code
(:mod:`trcopt.geometry.primitives`, :func:`trcopt.verify.model.bbox`): additions, products and
quotients elementwise in NumPy (correctly rounded, as in Python), and the library functions the
scalar code calls (``math.hypot``, ``math.cos``, ``math.sin``, ``math.atan2``) mapped over the
elements, since NumPy's own versions may differ in the last bit. So a residual computed from the
table equals the one computed segment by segment, bit for bit.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from itertools import chain
from operator import attrgetter

import numpy as np

from trcopt.geometry import Arc, Line
from trcopt.modes import Side
from trcopt.path import Role, Segment
from trcopt.verify.model import bbox

__all__ = ["LINE", "ARC", "OTHER", "ROLE", "SegmentTable", "fmap", "hypot", "py_max", "unique"]

LINE, ARC, OTHER = 0, 1, 2  # element kinds (OTHER: polynomial curves, measured one by one)
ROLE = {r: i for i, r in enumerate(Role)}  # role → code
_ROLE_ID = {id(r): i for r, i in ROLE.items()}
_SIGN_ID = {id(s): float(s.sign) for s in Side}
_role, _radius, _side = attrgetter("role"), attrgetter("radius"), attrgetter("side")
_start, _end = attrgetter("start"), attrgetter("end")
_ARRAYS: tuple[str, ...] = ("kind", "role", "radius", "side", "line", "sx", "sy", "sz", "ex", "ey", "ez", "cx", "cy")
_ARRAYS += ("r", "a0", "sweep", "plen")
_AXIS = [(k * math.pi / 2.0, math.cos(k * math.pi / 2.0), math.sin(k * math.pi / 2.0)) for k in range(-8, 9)]


def fmap(fn: Callable[..., float], *arrays: np.ndarray) -> np.ndarray:
    """``fn`` (a scalar float function of the standard library) applied elementwise."""
    return np.fromiter(map(fn, *(np.asarray(a, float).tolist() for a in arrays)), float, len(arrays[0]))


def hypot(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``math.hypot`` (and ``math.dist`` of the differences) elementwise."""
    return fmap(math.hypot, u, v)


def unique(a: np.ndarray) -> np.ndarray:
    """``np.unique`` of an integer array, by a sort (NumPy's hashing is slower for these)."""
    s = np.sort(a)
    return s[np.append(True, s[1:] != s[:-1])] if s.size else s


def py_max(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Python's ``max(x, y)`` elementwise: ``x`` unless ``y > x``."""
    return np.where(y > x, y, x)


def _py_min(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    return np.where(y < x, y, x)


def _kinds(geoms: list) -> np.ndarray:
    types = list(map(type, geoms))
    kind = {t: LINE if issubclass(t, Line) else ARC if issubclass(t, Arc) else OTHER for t in set(types)}
    return np.fromiter(map(kind.__getitem__, types), np.int8, len(types))


class SegmentTable:
    """The segments of a path as arrays (one entry per segment, in order).

    Attributes
    ----------
    kind:
        :data:`LINE`, :data:`ARC` or :data:`OTHER`.
    sx, sy, sz, ex, ey, ez:
        Start and end point (u, v, w), exactly ``geometry.start`` and ``geometry.end``.
    cx, cy, r, a0, sweep:
        Arc centre, radius, start angle and sweep (NaN for other kinds).
    plen:
        ``geometry.plane_length``.
    role, radius, side, line:
        Role code (:data:`ROLE`), tool radius, side sign (+1 left, −1 right, 0 off), source line.
    """

    def __init__(self, segments: Sequence[Segment]) -> None:
        self.segments = segments
        n = len(segments)
        geoms = [s.geometry for s in segments]
        self.geoms = geoms
        self.kind = kind = _kinds(geoms)
        # enum members are singletons: looked up by identity (an Enum's hash is Python code)
        self.role = np.fromiter(map(_ROLE_ID.__getitem__, map(id, map(_role, segments))), np.int8, n)
        self.radius = np.fromiter(map(_radius, segments), float, n)
        self.side = np.fromiter(map(_SIGN_ID.__getitem__, map(id, map(_side, segments))), float, n)
        self.line = np.fromiter((s.span.line for s in segments), np.int64, n)
        pts = np.full((n, 6), np.nan)
        arc = np.full((n, 7), np.nan)
        is_arc = kind == ARC
        not_arc = np.nonzero(~is_arc)[0]
        if not_arc.size:
            others = geoms if not_arc.size == n else [geoms[j] for j in not_arc.tolist()]
            for c, end in ((0, _start), (3, _end)):
                flat = chain.from_iterable(map(end, others))
                pts[not_arc, c : c + 3] = np.fromiter(flat, float, 3 * len(others)).reshape(-1, 3)
        arcs = np.nonzero(is_arc)[0]
        if arcs.size:
            arc_geoms: list[Arc] = [geoms[j] for j in arcs.tolist()]  # type: ignore[misc]
            flat = chain.from_iterable((*g.center[:2], g.radius, g.a0, g.sweep, g.w0, g.w1) for g in arc_geoms)
            arc[arcs] = np.fromiter(flat, float, 7 * len(arcs)).reshape(-1, 7)
        self.cx, self.cy, self.r, self.a0, self.sweep = (arc[:, i] for i in range(5))
        if arcs.size:
            a = arc[arcs]
            cx, cy, r, a0, sw = a[:, 0], a[:, 1], a[:, 2], a[:, 3], a[:, 4]
            a1 = a0 + sw
            pts[arcs] = np.column_stack(
                (cx + r * fmap(math.cos, a0), cy + r * fmap(math.sin, a0), a[:, 5],
                 cx + r * fmap(math.cos, a1), cy + r * fmap(math.sin, a1), a[:, 6])
            )  # fmt: skip
        self.sx, self.sy, self.sz, self.ex, self.ey, self.ez = (pts[:, i] for i in range(6))
        plen = np.empty(n)
        lines = np.nonzero(kind == LINE)[0]
        plen[lines] = hypot(self.ex[lines] - self.sx[lines], self.ey[lines] - self.sy[lines])
        plen[arcs] = np.abs(self.sweep[arcs]) * self.r[arcs]
        for j in np.nonzero(kind == OTHER)[0].tolist():
            plen[j] = geoms[j].plane_length
        self.plen = plen
        self._tangents: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None = None
        self._ends2: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None = None

    def __len__(self) -> int:
        return len(self.kind)

    def take(self, idx: np.ndarray, segments: Sequence[Segment]) -> SegmentTable:
        """The table of the segments ``idx`` of this one (``segments``: those segments)."""
        out = object.__new__(SegmentTable)
        out.segments = segments
        out.geoms = [self.geoms[j] for j in idx.tolist()]
        for name in _ARRAYS:
            setattr(out, name, getattr(self, name)[idx])
        t, e = self._tangents, self._ends2
        out._tangents = None if t is None else (t[0][idx], t[1][idx], t[2][idx], t[3][idx])
        out._ends2 = None if e is None else (e[0][idx], e[1][idx], e[2][idx], e[3][idx])
        return out

    def roles(self, *roles: Role) -> np.ndarray:
        """Which segments have one of ``roles``."""
        return np.isin(self.role, [ROLE[r] for r in roles])

    def point2(self, idx: np.ndarray, lam: float) -> tuple[np.ndarray, np.ndarray]:
        """``geometry.point2(lam)`` of the lines and arcs ``idx``."""
        u, v = np.full(len(idx), np.nan), np.full(len(idx), np.nan)
        kind = self.kind[idx]
        li, ai = np.nonzero(kind == LINE)[0], np.nonzero(kind == ARC)[0]
        j = idx[li]
        u[li] = self.sx[j] + (self.ex[j] - self.sx[j]) * lam
        v[li] = self.sy[j] + (self.ey[j] - self.sy[j]) * lam
        j = idx[ai]
        a = self.a0[j] + lam * self.sweep[j]
        u[ai] = self.cx[j] + self.r[j] * fmap(math.cos, a)
        v[ai] = self.cy[j] + self.r[j] * fmap(math.sin, a)
        return u, v

    def ends2(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(u0, v0, u1, v1): ``point2(0.0)`` and ``point2(1.0)`` of every line and arc, computed once."""
        if self._ends2 is None:
            rows = np.arange(len(self))
            self._ends2 = (*self.point2(rows, 0.0), *self.point2(rows, 1.0))
        return self._ends2

    def tangents(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(su, sv, eu, ev): ``start_tangent()`` and ``end_tangent()`` of every line of non-zero
        plane length and every arc (NaN elsewhere), computed once."""
        if self._tangents is None:
            n = len(self)
            out = [np.full(n, np.nan) for _ in range(4)]
            li = np.nonzero((self.kind == LINE) & (self.plen > 0.0))[0]
            du, dv = self.ex[li] - self.sx[li], self.ey[li] - self.sy[li]
            norm = hypot(du, dv)
            for k in (0, 2):
                out[k][li], out[k + 1][li] = du / norm, dv / norm
            ai = np.nonzero(self.kind == ARC)[0]
            sense = np.where(self.sweep[ai] > 0, 1.0, -1.0)
            for k, lam in ((0, 0.0), (2, 1.0)):
                a = self.a0[ai] + lam * self.sweep[ai]
                out[k][ai] = -fmap(math.sin, a) * sense
                out[k + 1][ai] = fmap(math.cos, a) * sense
            for j in np.nonzero((self.kind == OTHER) & (self.plen > 0.0))[0].tolist():
                g = self.geoms[j]
                try:
                    (out[0][j], out[1][j]), (out[2][j], out[3][j]) = g.start_tangent(), g.end_tangent()
                except (ArithmeticError, ValueError):
                    pass
            self._tangents = (out[0], out[1], out[2], out[3])
        return self._tangents

    def bboxes(self, idx: np.ndarray) -> np.ndarray:
        """:func:`trcopt.verify.model.bbox` of the segments ``idx`` (m×4)."""
        out = np.empty((len(idx), 4))
        kind = self.kind[idx]
        li = np.nonzero(kind == LINE)[0]
        j = idx[li]
        out[li, 0], out[li, 1] = _py_min(self.sx[j], self.ex[j]), _py_min(self.sy[j], self.ey[j])
        out[li, 2], out[li, 3] = py_max(self.sx[j], self.ex[j]), py_max(self.sy[j], self.ey[j])
        ai = np.nonzero(kind == ARC)[0]
        j = idx[ai]
        if ai.size:
            (u0, v0), (u1, v1) = self.point2(j, 0.0), self.point2(j, 1.0)
            lo_u, lo_v, hi_u, hi_v = _py_min(u0, u1), _py_min(v0, v1), py_max(u0, u1), py_max(v0, v1)
            cx, cy, r, a0, sw = self.cx[j], self.cy[j], self.r[j], self.a0[j], self.sweep[j]
            safe = np.where(sw != 0.0, sw, 1.0)
            for a, ca, sa in _AXIS:  # axis extremes inside the sweep, in bbox()'s order
                lam = np.where(sw != 0.0, (a - a0) / safe, 2.0)
                inside = (lam >= 0.0) & (lam <= 1.0)
                pu, pv = cx + r * ca, cy + r * sa
                lo_u, lo_v = np.where(inside, _py_min(lo_u, pu), lo_u), np.where(inside, _py_min(lo_v, pv), lo_v)
                hi_u, hi_v = np.where(inside, py_max(hi_u, pu), hi_u), np.where(inside, py_max(hi_v, pv), hi_v)
            out[ai, 0], out[ai, 1], out[ai, 2], out[ai, 3] = lo_u, lo_v, hi_u, hi_v
        for m in np.nonzero(kind == OTHER)[0].tolist():
            out[m] = bbox(self.geoms[int(idx[m])])
        return out
