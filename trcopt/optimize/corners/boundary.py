"""The cut boundary of the exact tool path and the material a new path leaves beyond it.

The cut-part deviation is measured on the physics, not on the tool-centre path: the exact path's
cut boundary is probed along its normals (:func:`boundary_probes`) and the new path's swept discs
must reach every probe (:func:`material_left`); :func:`cut_deviation` is the largest thickness left
over a whole path.

* :func:`blendable` — a segment whose corners may be replaced (compensated plane feed motion);
* :func:`material_sign` — on which side of a compensated segment the material lies;
* :func:`element_samples` — points and tangents of a line or arc.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from trcopt.geometry import Arc, Line, Poly
from trcopt.geometry.poly import hermite_pieces
from trcopt.optimize.corners.chain_geometry import Elements
from trcopt.path import Role, Segment

__all__ = [
    "NEAREST_CENTRES",
    "blendable",
    "boundary_probes",
    "cut_deviation",
    "element_samples",
    "material_left",
    "material_sign",
]

NEAREST_CENTRES = 128  # centres per probe for the bound of the deviation measurement


def blendable(seg: Segment) -> bool:
    """True for a compensated plane feed line or arc of the contour (or a corner element)."""
    g = seg.geometry
    return (
        not seg.is_rapid
        and seg.role in (Role.CONTOUR, Role.CORNER)
        and seg.radius > 0
        and isinstance(g, Line | Arc)
        and g.plane_length > 1e-9
        and abs(g.start[2] - g.end[2]) <= 1e-12
    )


def material_sign(seg: Segment) -> float:
    """+1 when the material lies left of the tool's travel (G42), −1 when right (G41)."""
    # G41 (LEFT): tool left of the contour, so the material is right of travel (−1)
    return -1.0 if seg.side.value == "left" else 1.0


def _normal(t: np.ndarray, sign: float) -> np.ndarray:
    return sign * np.array([-t[..., 1], t[..., 0]]).T if t.ndim > 1 else sign * np.array([-t[1], t[0]])


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


def _fan(n1: np.ndarray, n2: np.ndarray, count: int) -> np.ndarray:
    a1, a2 = math.atan2(n1[1], n1[0]), math.atan2(n2[1], n2[0])
    d = (a2 - a1 + math.pi) % (2 * math.pi) - math.pi
    ang = a1 + np.linspace(0.0, 1.0, count) * d
    return np.stack((np.cos(ang), np.sin(ang)), axis=1)


def boundary_probes(
    exact: Sequence[Line | Arc],
    programmed: Sequence[Line | Arc],
    radius: float,
    sign: float,
    step: float,
    near: np.ndarray | None = None,
    reach: float = math.inf,
    others: Sequence[Line | Arc] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Points of the exact cut boundary (n×2, mm) and unit directions away from the material (n×2).

    Candidates: envelope points of the exact centre elements every ``step`` mm, disc fans at their
    joints, the programmed vertices with their normal fans; kept where they lie on the boundary of
    the exact swept region (distance to the exact centre path = ``radius``; the path is ``exact``
    and ``others``, every element that comes within ``radius`` of the candidates) and, with
    ``near``, within ``reach`` mm of it.
    """
    pts, dirs = [], []
    for el in exact:
        p, t = element_samples(el, step)
        n = _normal(t, sign)
        pts.append(p + radius * n)
        dirs.append(-n)
    for e1, e2 in zip(exact[:-1], exact[1:], strict=False):
        if math.dist(e1.end, e2.start) > 1e-9:
            continue
        j = np.array(e1.point2(1.0))
        fan = _fan(_normal(np.array(e1.end_tangent()), sign), _normal(np.array(e2.start_tangent()), sign), 33)
        pts.append(j[None, :] + radius * fan)
        dirs.append(-fan)
    for e1, e2 in zip(programmed[:-1], programmed[1:], strict=False):
        if math.dist(e1.end[:2], e2.start[:2]) > 1e-9:
            continue
        v = np.array(e1.point2(1.0))
        fan = _fan(-_normal(np.array(e1.end_tangent()), sign), -_normal(np.array(e2.start_tangent()), sign), 33)
        pts.append(np.repeat(v[None, :], len(fan), axis=0))
        dirs.append(fan)
    P, D = np.vstack(pts), np.vstack(dirs)
    if near is not None:
        keep = np.hypot(*(P - near[None, :]).T) <= reach
        P, D = P[keep], D[keep]
    # the distance to the exact path: only elements within R (+ the tolerance) of a candidate matter
    tol = 1e-7 * max(radius, 1.0)
    path = Elements([*exact, *(others or ())])
    m, e = path.near(P, radius + tol)
    dmin = np.full(len(P), np.inf)
    np.minimum.at(dmin, m, path.distances(e, P[m]))
    keep = np.abs(dmin - radius) <= tol
    return P[keep], D[keep]


def material_left(probes: np.ndarray, dirs: np.ndarray, centres: np.ndarray, radius: float) -> np.ndarray:
    """Thickness of material left along each probe ray (mm, ≥ 0).

    A probe is a point of the exact cut boundary with the unit direction pointing away from the
    material; the new tool sweeps discs of ``radius`` around ``centres``. The result is the
    distance along the ray to the first disc (0 when the probe itself is swept). Sampled centres
    sweep a subset of the true region, so the value is an upper bound. ``centres`` is m×2 (the
    same for every probe) or n×m×2 (its own centres per probe).
    """
    rel = (centres if centres.ndim == 3 else centres[None, :, :]) - probes[:, None, :]  # n×m×2
    along = np.einsum("nmk,nk->nm", rel, dirs)
    perp2 = np.einsum("nmk,nmk->nm", rel, rel) - along * along
    inside = perp2 <= radius * radius
    root = np.sqrt(np.maximum(radius * radius - perp2, 0.0))
    entry = np.where(inside, along - root, np.inf)
    exit_ = np.where(inside, along + root, -np.inf)
    # a disc that contains the probe (entry ≤ 0 ≤ exit) sweeps it: thickness 0
    covered = np.any((entry <= 0.0) & (exit_ >= 0.0), axis=1)
    ahead = np.where(entry > 0.0, entry, np.inf).min(axis=1)
    out = np.where(covered, 0.0, ahead)
    return np.minimum(out, 10.0 * radius + 1.0)


def _path_samples(segments: Sequence[Segment], step: float) -> np.ndarray:
    """Points of ``segments`` every ``step`` mm at most (in no particular order), n×2."""
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
    pts += [_curve_samples(group, step) for group in curves.values() if group]
    return np.vstack(pts) if pts else np.zeros((0, 2))


def _curve_samples(curves: Sequence[Poly], step: float) -> np.ndarray:
    """Points of Poly curves (all with or all without curvatures) every ``step`` mm at most, n×2:
    their samples in one set of arrays, evaluated in one pass."""
    parts = [g.arrays() for g in curves]
    lengths = np.array([p[0][-1] for p in parts])
    sizes = np.array([len(p[0]) for p in parts])
    offset = np.concatenate(([0.0], np.cumsum(lengths)))[:-1]
    first = np.concatenate(([0], np.cumsum(sizes)))[:-1]
    cum = np.concatenate([p[0] for p in parts]) + np.repeat(offset, sizes)
    K = None if parts[0][3] is None else np.concatenate([p[3] for p in parts])
    arrays = (cum, np.concatenate([p[1] for p in parts]), np.concatenate([p[2] for p in parts]), K)
    counts = np.maximum(2, np.ceil(lengths / step).astype(int) + 1)
    member = np.repeat(np.arange(len(curves)), counts)
    j = np.arange(int(counts.sum())) - np.repeat(np.concatenate(([0], np.cumsum(counts)[:-1])), counts)
    s = offset[member] + lengths[member] * (j / (counts - 1)[member])
    i = np.searchsorted(cum, s, side="right") - 1
    i = np.clip(i, first[member], (first + sizes - 2)[member])
    return hermite_pieces(arrays, i, s, 0)[:, :2]


def _boxes(geoms: Sequence[Line | Arc | object]) -> np.ndarray:
    """Plane bounding boxes (n×4: xmin, ymin, xmax, ymax) of lines, arcs and curves, mm."""
    out = np.empty((len(geoms), 4))
    for i, g in enumerate(geoms):
        if isinstance(g, Arc):
            lo, hi = _arc_box(g)
        elif isinstance(g, Line):
            lo = (min(g.start[0], g.end[0]), min(g.start[1], g.end[1]))
            hi = (max(g.start[0], g.end[0]), max(g.start[1], g.end[1]))
        else:
            pts = np.array([p[:2] for p in g.sample_points()])  # type: ignore[attr-defined]
            lo, hi = pts.min(axis=0), pts.max(axis=0)
        out[i] = (lo[0], lo[1], hi[0], hi[1])
    return out


def _arc_box(a: Arc) -> tuple[tuple[float, float], tuple[float, float]]:
    # the circle's box: a superset of the arc's, enough for a proximity filter
    cx, cy, r = a.center[0], a.center[1], a.radius
    return (cx - r, cy - r), (cx + r, cy + r)


def _meet(boxes: np.ndarray, box: np.ndarray, pad: float) -> np.ndarray:
    """Indices of ``boxes`` that meet ``box`` grown by ``pad`` mm."""
    return np.nonzero(
        (boxes[:, 0] <= box[2] + pad) & (boxes[:, 2] >= box[0] - pad)
        & (boxes[:, 1] <= box[3] + pad) & (boxes[:, 3] >= box[1] - pad)
    )[0]


EARLY_PROBES = 16  # probes measured exactly before the finer bounds of the others
CHUNK_ELEMENTS = 48  # exact elements measured together (bounds the probes and centres held at once)


def cut_deviation(
    programmed: Sequence[Segment],
    exact: Sequence[Segment],
    new: Sequence[Segment],
    *,
    step: float = 0.002,
    locate: bool = False,
) -> tuple[float, np.ndarray | None]:
    """Largest thickness of material the new path leaves beyond the exact path's cut (mm).

    The exact cut boundary (envelope points, disc fans at corners, programmed vertices on the
    boundary) is probed every ``step`` mm along its normals; for each probe the distance along
    the normal to the first disc of radius R swept by the new path (sampled every ``step`` mm)
    is the material left. Returns (max, location of the worst probe when ``locate``, else None).

    Only the boundary of the exact elements the new path does not keep whole can be left uncut
    (a kept element sweeps its own envelope), so only those are probed, in chunks of
    :data:`CHUNK_ELEMENTS` consecutive elements, each against the exact and new elements within
    reach of it: the cost grows with the path's length, not with its square.
    """
    comp = [s for s in exact if blendable(s)]
    if not comp:
        return 0.0, None
    kept = {id(s) for s in new}
    touched = [i for i, s in enumerate(comp) if id(s) not in kept]
    if not touched:
        return 0.0, None
    # group by compensation radius/side (one group in practice)
    R, sign = comp[0].radius, material_sign(comp[0])
    contour = [
        p.geometry
        for p in programmed
        if p.role is Role.CONTOUR
        and isinstance(p.geometry, Line | Arc)
        and p.geometry.plane_length > 0
        and not p.is_rapid
    ]
    # blendable() admits lines and arcs only: the filter drops nothing, it states the type
    elements = [s.geometry for s in comp if isinstance(s.geometry, Line | Arc)]
    centres_of = [s for s in new if not s.is_rapid and s.radius > 0]
    ebox, cbox = _boxes(elements), _boxes(contour)
    nbox = _boxes([s.geometry for s in centres_of])
    best, where = 0.0, None
    runs = np.split(np.array(touched), np.nonzero(np.diff(touched) > 1)[0] + 1)
    for run in runs:
        for lo in range(0, len(run), CHUNK_ELEMENTS):
            part = run[lo : lo + CHUNK_ELEMENTS]
            a, b = max(int(part[0]) - 1, 0), min(int(part[-1]) + 2, len(elements))  # with the joints
            box = np.concatenate((ebox[a:b, :2].min(axis=0), ebox[a:b, 2:].max(axis=0)))
            near = [i for i in _meet(ebox, box, 2.0 * R + 1e-6) if not a <= i < b]
            probes, dirs = boundary_probes(
                elements[a:b], [contour[i] for i in _meet(cbox, box, R + 1e-6)], R, sign, step,
                others=[elements[i] for i in near],
            )
            if not len(probes):
                continue
            centres = _path_samples([centres_of[i] for i in _meet(nbox, box, 2.0 * R + 1.0 + step)], step)
            val, at = _left_over(probes, dirs, centres, R, step, best)
            if val > best:
                best, where = val, at
    return best, (where if locate else None)


def _left_over(
    probes: np.ndarray, dirs: np.ndarray, centres: np.ndarray, R: float, step: float, best: float
) -> tuple[float, np.ndarray | None]:
    """The largest material left at ``probes`` by discs around ``centres`` if it exceeds ``best``."""
    from scipy.spatial import cKDTree

    if not len(centres):
        return 1.0, probes[0]
    where = None
    # centres are dense samples along a path: an unbalanced tree of larger leaves answers the
    # nearest-neighbour queries of probes a radius away 2–3× faster than the default one
    tree = cKDTree(centres, leafsize=32, balanced_tree=False, compact_nodes=False)
    k0 = min(4, len(centres))
    d0, i0 = tree.query(probes, k=k0)
    d0, i0 = np.asarray(d0).reshape(len(probes), k0), np.asarray(i0).reshape(len(probes), k0)
    # a probe within R (+ half a sample spacing of chord sag) of a centre sample is swept
    open_ = np.nonzero(d0[:, 0] > R + step * step / (4.0 * R) + 1e-9)[0]
    if not len(open_):
        return best, None
    # bounds per open probe: at least its distance to the nearest centre less R (no disc is
    # nearer), at most what its nearest 4, then NEAREST_CENTRES, discs leave (fewer discs leave at
    # least as much); then the exact value against every centre within R + 1 mm, in decreasing
    # order of the bound, until no bound exceeds the largest exact value found
    floor = max(best, float((d0[open_, 0] - R).max()))
    rough = material_left(probes[open_], dirs[open_], centres[i0[open_]], R)
    keep = rough > floor
    open_, rough = open_[keep], rough[keep]
    # the exact value at the few probes of the largest bounds first: a good lower bound of the
    # maximum prunes most of the others before their finer bounds are computed
    for j in np.argsort(-rough)[:EARLY_PROBES]:
        if rough[j] <= best:
            break
        val = _exact_left(tree, probes, dirs, centres, R, int(open_[j]))
        if val > best:
            best, where = val, probes[open_[j]]
    open_ = open_[rough > best]
    k = min(NEAREST_CENTRES, len(centres))
    bound = np.empty(len(open_))
    for lo in range(0, len(open_), 2048):
        sel = open_[lo : lo + 2048]
        _, nbr = tree.query(probes[sel], k=k)
        nbr = np.asarray(nbr).reshape(len(sel), k)
        bound[lo : lo + 2048] = material_left(probes[sel], dirs[sel], centres[nbr], R)
    for j in np.argsort(-bound):
        if bound[j] <= best:
            break
        i = open_[j]
        val = _exact_left(tree, probes, dirs, centres, R, int(i))
        if val > best:
            best, where = val, probes[i]
    return best, where


def _exact_left(tree: Any, probes: np.ndarray, dirs: np.ndarray, centres: np.ndarray, R: float, i: int) -> float:
    """The material left at probe ``i`` by every disc around ``centres`` within R + 1 mm of it."""
    idx = tree.query_ball_point(probes[i], R + 1.0)
    if not idx:
        return 1.0
    return float(material_left(probes[i : i + 1], dirs[i : i + 1], centres[idx], R)[0])
