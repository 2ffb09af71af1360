"""Sample points of tool-centre elements and paths, and their boxes, for the cut-deviation measurement.

* :func:`element_samples` — points and tangents of a line or arc every ``step`` mm;
* :func:`elements_samples` — the same for many elements in one pass;
* :func:`fans` — the directions of disc fans at joints;
* :func:`path_samples` — points of a path of lines, arcs and curves every ``step`` mm;
* :func:`boxes`, :func:`meet` — plane bounding boxes and the ones that meet a box.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from itertools import chain
from typing import Any

import numpy as np

from trcopt.geometry import Arc, Line, Poly
from trcopt.geometry.poly import hermite_pieces
from trcopt.path import Segment

__all__ = ["FAN", "boxes", "curve_samples", "element_samples", "elements_samples", "fans", "meet", "path_samples"]


def element_samples(
    el: Line | Arc, step: float, s0: float = 0.0, s1: float | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Points and unit tangents of ``el`` from plane arc length ``s0`` to ``s1`` (default: the
    end) every ``step`` at most, mm."""
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


FAN = 33  # directions of a disc fan at a joint


def fans(pairs: Sequence[tuple[np.ndarray, np.ndarray]]) -> np.ndarray:
    """FAN directions from the angle of the first to that of the second of every pair of unit
    vectors (the shorter way round), one fan after the other (FAN·n × 2)."""
    a1 = np.array([math.atan2(n1[1], n1[0]) for n1, _ in pairs])
    d = np.array(
        [
            (math.atan2(n2[1], n2[0]) - x + math.pi) % (2 * math.pi) - math.pi
            for x, (_, n2) in zip(a1.tolist(), pairs, strict=True)
        ]
    )
    ang = (a1[:, None] + np.linspace(0.0, 1.0, FAN)[None, :] * d[:, None]).ravel()
    return np.stack((np.cos(ang), np.sin(ang)), axis=1)


def elements_samples(elements: Sequence[Line | Arc], step: float) -> tuple[np.ndarray, np.ndarray]:
    """:func:`element_samples` of every element (whole), one after the other, in one pass."""
    L = np.array([el.plane_length for el in elements])
    n = np.maximum(2, np.ceil(L / step).astype(int) + 1)
    member = np.repeat(np.arange(len(elements)), n)
    last = np.cumsum(n) - 1
    j = np.arange(int(n.sum())) - np.repeat(last - n + 1, n)
    # np.linspace(0, L, n) / L: j·(L/(n − 1)), the last one L
    y = j * (L / (n - 1))[member]
    y[last] = L
    lam = y / L[member]
    arc = np.array([isinstance(el, Arc) for el in elements])
    pts = np.empty((len(lam), 2))
    tan = np.empty((len(lam), 2))
    on_line = ~arc[member]
    if on_line.any():
        lines = [el for el in elements if isinstance(el, Line)]
        a = np.array([el.start2 for el in lines]).reshape(-1, 2)
        b = np.array([el.end2 for el in lines]).reshape(-1, 2)
        which = (np.cumsum(~arc) - 1)[member[on_line]]
        pts[on_line] = a[which] + lam[on_line][:, None] * (b - a)[which]
        tan[on_line] = np.array([el.direction2() for el in lines]).reshape(-1, 2)[which]
    if arc.any():
        arcs = [el for el in elements if isinstance(el, Arc)]
        which = (np.cumsum(arc) - 1)[member[~on_line]]
        a0 = np.array([el.a0 for el in arcs])[which]
        sweep = np.array([el.sweep for el in arcs])[which]
        centre = np.array([el.center[:2] for el in arcs]).reshape(-1, 2)[which]
        r = np.array([el.radius for el in arcs])[which]
        ang = a0 + lam[~on_line] * sweep
        pts[~on_line] = np.stack((centre[:, 0] + r * np.cos(ang), centre[:, 1] + r * np.sin(ang)), axis=1)
        k = np.where(sweep > 0, 1.0, -1.0)
        tan[~on_line] = np.stack((-np.sin(ang) * k, np.cos(ang) * k), axis=1)
    return pts, tan


def path_samples(segments: Sequence[Segment], step: float, arrays: dict[int, Any] | None = None) -> np.ndarray:
    """Points of ``segments`` every ``step`` mm at most (in no particular order), n×2; ``arrays``
    keeps the curves' :meth:`~trcopt.geometry.Poly.arrays` by ``id`` from one call to the next
    (those of this call's curves only)."""
    pts = []
    curves: dict[bool, list[Poly]] = {True: [], False: []}
    for s in segments:
        g = s.geometry
        if isinstance(g, Line | Arc):
            if g.plane_length > 0:
                pts.append(element_samples(g, step)[0])
            else:
                pts.append(np.array([g.point2(0.0)]))
        else:
            curves[g.curvatures is not None].append(g)
    pts += [curve_samples(group, step, arrays) for group in curves.values() if group]
    if arrays:
        mine = {id(g) for group in curves.values() for g in group}
        for k in [k for k in arrays if k not in mine]:
            del arrays[k]
    return np.vstack(pts) if pts else np.zeros((0, 2))


def joined_curves(curves: Sequence[Poly], step: float, known: dict[int, Any]) -> tuple[Any, ...]:
    """Poly curves' sample arrays joined end to end (``known``: the arrays by curve id, filled in as
    they are made): the joined arrays, each curve's offset along them, length, first sample, the
    number of points every ``step`` mm at most, and its sample count."""
    parts = [known[id(g)] if id(g) in known else known.setdefault(id(g), g.arrays()) for g in curves]
    lengths = np.array([p[0][-1] for p in parts])
    sizes = np.array([len(p[0]) for p in parts])
    offset = np.concatenate(([0.0], np.cumsum(lengths)))[:-1]
    first = np.concatenate(([0], np.cumsum(sizes)))[:-1]
    cum = np.concatenate([p[0] for p in parts]) + np.repeat(offset, sizes)
    K = None if parts[0][3] is None else np.concatenate([p[3] for p in parts])
    joined = (cum, np.concatenate([p[1] for p in parts]), np.concatenate([p[2] for p in parts]), K)
    counts = np.maximum(2, np.ceil(lengths / step).astype(int) + 1)
    return joined, offset, lengths, first, counts, sizes


def curve_samples(curves: Sequence[Poly], step: float, arrays: dict[int, Any] | None = None) -> np.ndarray:
    """Points of Poly curves (all with or all without curvatures) every ``step`` mm at most, n×2:
    their samples in one set of arrays, evaluated in one pass (``arrays``: see :func:`path_samples`)."""
    joined, offset, lengths, first, counts, sizes = joined_curves(curves, step, {} if arrays is None else arrays)
    cum = joined[0]
    member = np.repeat(np.arange(len(curves)), counts)
    j = np.arange(int(counts.sum())) - np.repeat(np.concatenate(([0], np.cumsum(counts)[:-1])), counts)
    s = offset[member] + lengths[member] * (j / (counts - 1)[member])
    i = np.searchsorted(cum, s, side="right") - 1
    i = np.clip(i, first[member], (first + sizes - 2)[member])
    return hermite_pieces(joined, i, s, 0)[:, :2]


def boxes(geoms: Sequence[Line | Arc | object]) -> np.ndarray:
    """Plane bounding boxes (n×4: xmin, ymin, xmax, ymax) of lines, arcs and curves, mm (a curve's
    from its sample points, all curves' in one pass)."""
    out = np.empty((len(geoms), 4))
    curves = []
    for i, g in enumerate(geoms):
        if isinstance(g, Arc):
            lo, hi = _arc_box(g)
        elif isinstance(g, Line):
            lo = (min(g.start[0], g.end[0]), min(g.start[1], g.end[1]))
            hi = (max(g.start[0], g.end[0]), max(g.start[1], g.end[1]))
        else:
            curves.append(i)
            continue
        out[i] = (lo[0], lo[1], hi[0], hi[1])
    for at in range(0, len(curves), BOX_CURVES):
        # (a few thousand curves at a time: a path of 10⁵ spline pieces has millions of samples)
        part = curves[at : at + BOX_CURVES]
        pts = [geoms[i].sample_points() for i in part]  # type: ignore[union-attr]
        P = np.array([p[:2] for p in chain.from_iterable(pts)], float)
        first = np.concatenate(([0], np.cumsum([len(p) for p in pts])[:-1]))
        out[part, :2] = np.minimum.reduceat(P, first, axis=0)
        out[part, 2:] = np.maximum.reduceat(P, first, axis=0)
    return out


BOX_CURVES = 4096  # curves whose boxes are found in one pass


def _arc_box(a: Arc) -> tuple[tuple[float, float], tuple[float, float]]:
    """The arc's box: its ends and the points of its sweep at the axis directions (grown by the
    rounding of its samples' cosines: a blend between nearly collinear chords has a radius of
    metres, and its circle's box would meet every part of a path)."""
    cx, cy, r = a.center[0], a.center[1], a.radius
    (x0, y0), (x1, y1) = a.point2(0.0), a.point2(1.0)
    xs, ys = [x0, x1], [y0, y1]
    turn, sign = abs(a.sweep), 1.0 if a.sweep >= 0 else -1.0
    for k in range(4):
        ang = 0.5 * math.pi * k
        if turn >= 2.0 * math.pi - 1e-12 or ((ang - a.a0) * sign) % (2.0 * math.pi) <= turn:
            xs.append(cx + r * math.cos(ang))
            ys.append(cy + r * math.sin(ang))
    pad = 1e-9 * (1.0 + r + abs(cx) + abs(cy))
    return (min(xs) - pad, min(ys) - pad), (max(xs) + pad, max(ys) + pad)


def meet(table: np.ndarray, box: np.ndarray, pad: float) -> np.ndarray:
    """Indices of the boxes of ``table`` (n×4) that meet ``box`` grown by ``pad`` mm."""
    return np.nonzero(
        (table[:, 0] <= box[2] + pad)
        & (table[:, 2] >= box[0] - pad)
        & (table[:, 1] <= box[3] + pad)
        & (table[:, 3] >= box[1] - pad)
    )[0]
