"""Tool-path segments as two NumPy matrices and a small side table: :func:`encode`, :func:`decode`.

A plan computed window by window keeps each window's segments in a temporary file until a later
stage reads them back (:class:`~trcopt.io.spill.SpilledSegments`). Pickling the objects costs
about 10 µs a segment both ways; these columns cost a fraction of that. ``decode(encode(s))``
equals ``s`` field by field, with the same types: the floats of a chunk go into a ``float64``
matrix (exact), the enums, source lines, columns and flags into an ``int64`` one, and what is
rare or not a plain number — polynomial curves and other geometry, machine-coordinate spans, block
names, file names — into the side table. A chunk with a number that is not a Python float (an
``int`` coordinate) is not encoded (:func:`encode` returns None; the caller pickles it).
"""

from __future__ import annotations

from itertools import chain, repeat
from operator import attrgetter, is_
from typing import Any

import numpy as np

from trcopt.errors import SourceSpan, _SpanSlots
from trcopt.geometry.plane import Plane
from trcopt.geometry.primitives import Arc, Line, _LineSlots
from trcopt.modes import Side
from trcopt.path import Role, Segment, _SegmentSlots

__all__ = ["encode", "decode"]

_PLANES, _ROLES, _SIDES = list(Plane), list(Role), list(Side)
_PLANE_ID = {id(p): i for i, p in enumerate(_PLANES)}
_ROLE_ID = {id(r): i for i, r in enumerate(_ROLES)}
_SIDE_ID = {id(s): i for i, s in enumerate(_SIDES)}
_LINE, _ARC, _OTHER = 0, 1, 2
# flags (the int64 column F): the booleans and which optional fields are None
_STOP, _SMOOTH, _FEED_NONE, _T0_NONE, _T1_NONE, _ENDCOL_NONE, _BLOCK_NONE = (1 << k for k in range(7))
# columns of the int64 matrix
_K, _P, _R, _S, _LN, _COL, _ENDCOL, _RUN, _BLOCK, _FILE, _F = range(11)


_FIELDS = attrgetter("geometry", "plane", "role", "span", "feed_mm_s", "side", "radius", "t_start_s", "t_end_s",
                     "stop", "smooth_end")  # fmt: skip
_SPAN = attrgetter("file", "line", "column", "block", "end_column", "machine", "run")


def encode(segments: list[Segment]) -> tuple[np.ndarray, np.ndarray, dict[str, Any]] | None:
    """``(floats, ints, side)`` of ``segments``; None when a number is not a float (see above)."""
    n = len(segments)
    if n == 0:
        return np.zeros((0, 11)), np.zeros((0, 11), np.int64), {"other": {}, "machine": {}, "files": [], "blocks": []}
    geoms, planes, roles, spans, feed, sides, radius, t0, t1, stop, smooth = zip(*map(_FIELDS, segments), strict=True)
    files, lines, columns, blocks, ends, machines, runs = zip(*map(_SPAN, spans), strict=True)
    kind = np.fromiter(map(_KIND.get, map(type, geoms), repeat(_OTHER)), np.int64, n)
    floats = np.zeros((n, 11))
    ints = np.zeros((n, 11), np.int64)
    side: dict[str, Any] = {"other": {}, "machine": {}, "files": [], "blocks": []}
    values: list[Any] = [radius]
    if kind.any():
        at_line = np.nonzero(kind == _LINE)[0].tolist()
        at_arc = np.nonzero(kind == _ARC)[0].tolist()
        for j in np.nonzero(kind == _OTHER)[0].tolist():
            side["other"][j] = geoms[j]
    else:
        at_line, at_arc = None, []
    line_geoms = geoms if at_line is None else [geoms[j] for j in at_line]
    if line_geoms:
        points = [*chain.from_iterable(map(_ENDS, line_geoms))]
        if set(map(type, points)) - {tuple}:
            return None  # a point given as a list or another sequence: kept as it is
        flat = [*chain.from_iterable(points)]
        if len(flat) != 6 * len(line_geoms):
            return None  # a point without three coordinates
        values.append(flat)
        cols = np.array(flat, float).reshape(-1, 6)
        if at_line is None:
            floats[:, :6] = cols
        else:
            floats[at_line, :6] = cols
    if at_arc:
        arcs = [geoms[j] for j in at_arc]
        if {type(g.center) for g in arcs} - {tuple}:
            return None
        flat = [*chain.from_iterable((*g.center, g.radius, g.a0, g.sweep, g.w0, g.w1) for g in arcs)]
        if len(flat) != 7 * len(at_arc):
            return None
        values.append(flat)
        floats[at_arc, :7] = np.array(flat, float).reshape(-1, 7)
    flags = np.zeros(n, np.int64)
    for col, vals, bit in ((8, feed, _FEED_NONE), (9, t0, _T0_NONE), (10, t1, _T1_NONE)):
        none = np.fromiter(_is_none(vals), bool, n)
        if none.all():
            flags |= bit
            continue
        given = vals if not none.any() else [v for v in vals if v is not None]
        values.append(given)
        flags[none] |= bit
        floats[~none, col] = given
    if set(map(type, chain.from_iterable(values))) - {float}:
        return None
    floats[:, 7] = radius
    if set(map(type, chain(lines, columns, runs))) - {int} or set(map(type, chain(stop, smooth))) - {bool}:
        return None
    ints[:, _K] = kind
    ints[:, _P] = np.fromiter(map(_PLANE_ID.__getitem__, map(id, planes)), np.int64, n)
    ints[:, _R] = np.fromiter(map(_ROLE_ID.__getitem__, map(id, roles)), np.int64, n)
    ints[:, _S] = np.fromiter(map(_SIDE_ID.__getitem__, map(id, sides)), np.int64, n)
    flags[np.array(stop, bool)] |= _STOP
    flags[np.array(smooth, bool)] |= _SMOOTH
    ints[:, _LN] = lines
    ints[:, _COL] = columns
    ints[:, _RUN] = runs
    none = np.fromiter(_is_none(ends), bool, n)
    flags[none] |= _ENDCOL_NONE
    if not none.all():
        given = [v for v in ends if v is not None]
        if set(map(type, given)) - {int}:
            return None
        ints[~none, _ENDCOL] = given
    for col, key, vals in ((_FILE, "files", files), (_BLOCK, "blocks", blocks)):
        table = {v: k for k, v in enumerate(dict.fromkeys(vals))}
        ints[:, col] = np.fromiter(map(table.__getitem__, vals), np.int64, n)
        side[key] = list(table)
    if any(m is not None for m in machines):
        side["machine"] = {j: m for j, m in enumerate(machines) if m is not None}
    ints[:, _F] = flags
    return floats, ints, side


def _is_none(values: tuple[Any, ...]) -> Any:
    """Which of ``values`` are None (an iterator of booleans)."""
    return map(is_, values, repeat(None))


_ENDS = attrgetter("start", "end")
_KIND = {Line: _LINE, Arc: _ARC}


def decode(floats: np.ndarray, ints: np.ndarray, side: dict[str, Any]) -> list[Segment]:
    """The segments :func:`encode` was given."""
    out: list[Segment] = []
    append = out.append
    other, machine, files, blocks = side["other"], side["machine"], side["files"], side["blocks"]
    planes, roles, sides = _PLANES, _ROLES, _SIDES
    last: Any = None  # the span of the previous segment, reused when the next one is equal
    for j, (f, i) in enumerate(zip(floats.tolist(), ints.tolist(), strict=True)):
        k, flags = i[_K], i[_F]
        if k == _LINE:
            g: Any = _LineSlots()
            g.start, g.end = (f[0], f[1], f[2]), (f[3], f[4], f[5])
            g.__class__ = Line
        elif k == _ARC:
            g = Arc((f[0], f[1]), f[2], f[3], f[4], f[5], f[6])
        else:
            g = other[j]
        block = blocks[i[_BLOCK]]
        end_column = None if flags & _ENDCOL_NONE else i[_ENDCOL]
        mach = machine.get(j) if machine else None
        file = files[i[_FILE]]
        line, column, run = i[_LN], i[_COL], i[_RUN]
        if (
            last is None or last.line != line or last.column != column or last.block is not block
            or last.file is not file or last.end_column != end_column or last.run != run
            or last.machine is not mach
        ):  # fmt: skip
            sp: Any = _SpanSlots()
            sp.file, sp.line, sp.column, sp.block = file, line, column, block
            sp.end_column, sp.machine, sp.run = end_column, mach, run
            sp.__class__ = SourceSpan
            last = sp
        s: Any = _SegmentSlots()
        s.geometry, s.plane, s.role, s.span = g, planes[i[_P]], roles[i[_R]], last
        s.feed_mm_s = None if flags & _FEED_NONE else f[8]
        s.side, s.radius = sides[i[_S]], f[7]
        s.t_start_s = None if flags & _T0_NONE else f[9]
        s.t_end_s = None if flags & _T1_NONE else f[10]
        s.stop, s.smooth_end = bool(flags & _STOP), bool(flags & _SMOOTH)
        s.__class__ = Segment
        append(s)
    return out
