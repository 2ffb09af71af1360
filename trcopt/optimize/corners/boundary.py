"""The cut boundary of the exact tool path and the material a new path leaves beyond it.

The cut-part deviation is measured on the physics, not on the tool-centre path: the exact path's
cut boundary is probed along its normals (:func:`boundary_probes`) and the new path's swept discs
must reach every probe (:func:`material_left`); :func:`cut_deviation` is the largest thickness left
over a whole path.

* :func:`blendable` — a segment whose corners may be replaced (compensated plane feed motion);
* :func:`material_sign` — on which side of a compensated segment the material lies;
* :func:`element_samples` — points and tangents of a line or arc (:mod:`.samples`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from functools import partial
from typing import Any

import numpy as np

from trcopt.geometry import Arc, Line
from trcopt.optimize.corners.chain_geometry import Elements
from trcopt.optimize.corners.samples import FAN, boxes, element_samples, elements_samples, fans, meet, path_samples
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

    Candidates (:func:`_candidates`) kept where they lie on the boundary of the exact swept region
    (:func:`_on_boundary`; the path is ``exact`` and ``others``, every element that comes within
    ``radius`` of the candidates) and, with ``near``, within ``reach`` mm of it.
    """
    P, D = _candidates(exact, programmed, radius, sign, step)
    if near is not None:
        keep = np.hypot(*(P - near[None, :]).T) <= reach
        P, D = P[keep], D[keep]
    keep = _on_boundary(Elements([*exact, *(others or ())]), P, radius)
    return P[keep], D[keep]


def _candidates(
    exact: Sequence[Line | Arc], programmed: Sequence[Line | Arc], radius: float, sign: float, step: float
) -> tuple[np.ndarray, np.ndarray]:
    """Candidate points of the exact cut boundary and their directions away from the material: the
    envelope points of the exact centre elements every ``step`` mm, disc fans at their joints, the
    programmed vertices with their normal fans."""
    pts, dirs = [np.zeros((0, 2))], [np.zeros((0, 2))]
    if exact:
        p, t = elements_samples(exact, step)
        n = _normal(t, sign)
        pts.append(p + radius * n)
        dirs.append(-n)
    ends = [(e1, e2) for e1, e2 in zip(exact[:-1], exact[1:], strict=False) if math.dist(e1.end, e2.start) <= 1e-9]
    if ends:
        fan = fans([(_normal(np.array(e1.end_tangent()), sign), _normal(np.array(e2.start_tangent()), sign))
                    for e1, e2 in ends])  # fmt: skip
        pts.append(np.repeat(np.array([e1.point2(1.0) for e1, _ in ends]), FAN, axis=0) + radius * fan)
        dirs.append(-fan)
    ends = [
        (e1, e2) for e1, e2 in zip(programmed[:-1], programmed[1:], strict=False)
        if math.dist(e1.end[:2], e2.start[:2]) <= 1e-9
    ]  # fmt: skip
    if ends:
        fan = fans([(-_normal(np.array(e1.end_tangent()), sign), -_normal(np.array(e2.start_tangent()), sign))
                    for e1, e2 in ends])  # fmt: skip
        pts.append(np.repeat(np.array([e1.point2(1.0) for e1, _ in ends]), FAN, axis=0))
        dirs.append(fan)
    return np.vstack(pts), np.vstack(dirs)


def _on_boundary(path: Elements, P: np.ndarray, radius: float) -> np.ndarray:
    """Which of the points ``P`` lie on the boundary of the region swept by discs of ``radius``
    along ``path``: their distance to it is ``radius`` (to a relative 1e-7); only elements within
    that distance of a point matter."""
    tol = 1e-7 * max(radius, 1.0)
    m, _, d = path.near_distances(P, radius + tol, ordered=False)
    dmin = np.full(len(P), np.inf)
    np.minimum.at(dmin, m, d)
    return np.abs(dmin - radius) <= tol


def material_left(probes: np.ndarray, dirs: np.ndarray, centres: np.ndarray, radius: float) -> np.ndarray:
    """Thickness of material left along each probe ray (mm, ≥ 0).

    A probe is a point of the exact cut boundary with the unit direction pointing away from the
    material; the new tool sweeps discs of ``radius`` around ``centres``. The result is the
    distance along the ray to the first disc (0 when the probe itself is swept). Sampled centres
    sweep a subset of the true region, so the value is an upper bound. ``centres`` is m×2 (the
    same for every probe) or n×m×2 (its own centres per probe).
    """
    rel = (centres if centres.ndim == 3 else centres[None, :, :]) - probes[:, None, :]  # n×m×2
    return _left_along(rel, dirs, radius)[0]


def _left_along(rel: np.ndarray, dirs: np.ndarray, radius: float) -> tuple[np.ndarray, np.ndarray]:
    """:func:`material_left` from the centres relative to the probes (n×m×2), and the squared
    distances of the centres from the probes (n×m)."""
    along = np.einsum("nmk,nk->nm", rel, dirs)
    dist2 = np.einsum("nmk,nmk->nm", rel, rel)
    perp2 = dist2 - along * along
    inside = perp2 <= radius * radius
    root = np.sqrt(np.maximum(radius * radius - perp2, 0.0))
    entry = np.where(inside, along - root, np.inf)
    exit_ = np.where(inside, along + root, -np.inf)
    # a disc that contains the probe (entry ≤ 0 ≤ exit) sweeps it: thickness 0
    covered = np.any((entry <= 0.0) & (exit_ >= 0.0), axis=1)
    ahead = np.where(entry > 0.0, entry, np.inf).min(axis=1)
    out = np.where(covered, 0.0, ahead)
    return np.minimum(out, 10.0 * radius + 1.0), dist2


EARLY_PROBES = 16  # probes measured exactly before the finer bounds of the others
WINDOW = 1  # centre samples on either side of the nearest one in the first bound of a probe
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
    ebox, cbox = boxes(elements), boxes(contour)
    nbox = boxes([s.geometry for s in centres_of])
    best, where = 0.0, None
    arrays: dict[int, Any] = {}  # the curves' sample arrays, shared by the chunks
    runs = np.split(np.array(touched), np.nonzero(np.diff(touched) > 1)[0] + 1)
    for run in runs:
        for lo in range(0, len(run), CHUNK_ELEMENTS):
            part = run[lo : lo + CHUNK_ELEMENTS]
            a, b = max(int(part[0]) - 1, 0), min(int(part[-1]) + 2, len(elements))  # with the joints
            box = np.concatenate((ebox[a:b, :2].min(axis=0), ebox[a:b, 2:].max(axis=0)))
            near = [elements[i] for i in meet(ebox, box, 2.0 * R + 1e-6) if not a <= i < b]
            cand, dirs = _candidates(elements[a:b], [contour[i] for i in meet(cbox, box, R + 1e-6)], R, sign, step)
            if not len(cand):
                continue
            path = Elements([*elements[a:b], *near])
            centres = path_samples([centres_of[i] for i in meet(nbox, box, 2.0 * R + 1.0 + step)], step, arrays)
            # the probes are the candidates on the boundary (boundary_probes), tested only where
            # they might hold the largest value
            val, at = _left_over(cand, dirs, centres, R, step, best, partial(_on_boundary, path, radius=R))
            if val > best:
                best, where = val, at
    return best, (where if locate else None)


def _left_over(
    cand: np.ndarray,
    dirs: np.ndarray,
    centres: np.ndarray,
    R: float,
    step: float,
    best: float,
    probe: Callable[[np.ndarray], np.ndarray],
) -> tuple[float, np.ndarray | None]:
    """The largest material left by discs around ``centres`` at the candidates ``cand`` that are
    probes (``probe``: which of some candidate points are), if it exceeds ``best``.

    A probe's value can only be the largest if an upper bound of it exceeds the largest exact
    value found: every candidate is first bounded by the few discs around the centre sample nearest
    its ideal centre (the candidate moved by R along its direction, a point next to the new path,
    so the search is short, :func:`_window_bound`); the probes among the candidates of the largest
    such bounds are measured exactly, which prunes nearly all others before the probes among the
    rest go to :func:`_left_over_bounded`.
    """
    from scipy.spatial import cKDTree

    if not len(centres):
        first = np.nonzero(probe(cand))[0][:1]
        return (1.0, cand[first[0]]) if len(first) else (best, None)
    # centres are dense samples along a path: an unbalanced tree of larger leaves answers the
    # nearest-neighbour queries of probes a radius away 2–3× faster than the default one
    tree = cKDTree(centres, leafsize=32, balanced_tree=False, compact_nodes=False)
    screen = _window_bound(tree, cand, dirs, centres, R)
    where = None
    done = np.zeros(len(cand), bool)
    top = np.argsort(-screen)[: 4 * EARLY_PROBES]
    is_probe = probe(cand[top])
    d0 = np.asarray(tree.query(cand[top], k=1)[0]).reshape(len(top))
    evaluated = 0
    for j, ok, d in zip(top.tolist(), is_probe.tolist(), d0.tolist(), strict=True):
        if screen[j] <= best or evaluated >= EARLY_PROBES:
            break
        done[j] = True
        if not ok or d <= R + step * step / (4.0 * R) + 1e-9:
            continue  # not on the boundary, or swept (see _left_over_bounded)
        evaluated += 1
        val = _exact_left(tree, cand, dirs, centres, R, j)
        if val > best:
            best, where = val, cand[j]
    # (a bound within rounding of the largest value stays: it might tie)
    rest = np.nonzero((screen > best - 1e-12) & ~done)[0]
    rest = rest[probe(cand[rest])]
    if not len(rest):
        return best, where
    val, at = _left_over_bounded(tree, cand[rest], dirs[rest], centres, R, step, best)
    return (val, at) if at is not None else (best, where)


def _window_bound(tree: Any, probes: np.ndarray, dirs: np.ndarray, centres: np.ndarray, R: float) -> np.ndarray:
    """An upper bound of the material left at each probe (mm; ``inf`` where none is known): what
    the discs of the WINDOW centre samples on either side of the one nearest the probe's ideal
    centre (``probe + R·dir``) leave. Fewer discs leave at least as much, and only discs within
    R + 1 mm of a probe count in its exact value (:func:`_exact_left`): a window reaching farther
    gives no bound."""
    _, j = tree.query(probes + R * dirs, k=1)
    idx = np.clip(np.asarray(j).reshape(len(probes), 1) + np.arange(-WINDOW, WINDOW + 1), 0, len(centres) - 1)
    bound, dist2 = _left_along(centres[idx] - probes[:, None, :], dirs, R)
    return np.where((dist2 > (R + 1.0 - 1e-9) ** 2).any(axis=1), np.inf, bound)


def _left_over_bounded(
    tree: Any, probes: np.ndarray, dirs: np.ndarray, centres: np.ndarray, R: float, step: float, best: float
) -> tuple[float, np.ndarray | None]:
    """The largest material left at ``probes`` by discs around ``centres`` (in ``tree``) if it
    exceeds ``best``, through bounds of increasing cost."""
    where = None
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
    keep = rough >= floor  # (the probe of the floor itself may have its bound equal to it)
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
