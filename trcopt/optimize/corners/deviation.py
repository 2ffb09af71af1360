"""The cut-part deviation of a new tool path: the largest material it leaves beyond the exact cut.

:func:`cut_deviation` probes the exact path's cut boundary every ``step`` mm along its normals
(:mod:`.boundary`) and measures, at the probes where that can matter, the material the discs of the
new path leave (:func:`~.boundary.material_left`). It is the maximum over every probe, found with
bounds that settle nearly all of them cheaply:

* the envelope candidates of an exact **line** come in blocks of :data:`BLOCK` consecutive ones
  (a line's are collinear with one direction): one bound per block from its two end candidates
  (:func:`_block_bounds`); the other candidates (on arcs, the disc fans at joints and programmed
  vertices) get one bound each (:func:`_bounds`);
* those bounds come from the discs of every few centre samples near the candidates' ideal
  centres (:meth:`~.centres.CentreSamples.coarse`: fewer discs leave at least as much);
* the candidates of the largest bounds are measured exactly first, then every candidate whose
  bound exceeds the largest value found is bounded on its own, tested for being a probe, and
  measured (:func:`_left_over_bounded`) against every centre sample near it.

A candidate is left out only when an upper bound of its value is below a value measured, so the
result is the maximum over every probe, as if each were measured exactly.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from functools import partial
from typing import Any

import numpy as np

from trcopt.geometry import Arc, Line
from trcopt.optimize.corners.boundary import (
    _normal,
    _on_boundary,
    blendable,
    envelope,
    joint_fans,
    material_left,
    material_sign,
)
from trcopt.optimize.corners.centres import CentreSamples
from trcopt.optimize.corners.chain_geometry import Elements
from trcopt.optimize.corners.samples import boxes, meet
from trcopt.path import Role, Segment

__all__ = ["NEAREST_CENTRES", "cut_deviation"]

NEAREST_CENTRES = 128  # centres per probe for the bound of the deviation measurement
EARLY_PROBES = 16  # probes measured exactly before the finer bounds of the others
WINDOW = 1  # coarse centre samples on either side of the nearest one in a bound
CHUNK_ELEMENTS = 48  # exact elements measured together (bounds the probes and centres held at once)
COARSE_MM = 0.016  # spacing of the centre samples of the bounds (at most, a multiple of step)
BLOCK = 8  # envelope candidates of a line bounded together


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
            prog = [contour[i] for i in meet(cbox, box, R + 1e-6)]
            cands = _Candidates(elements[a:b], prog, R, sign, step)
            if not cands.count:
                continue
            path = Elements([*elements[a:b], *near])
            centres = CentreSamples([centres_of[i] for i in meet(nbox, box, 2.0 * R + 1.0 + step)], step, arrays)
            # the probes are the candidates on the boundary (boundary_probes), tested only where
            # they might hold the largest value
            centres.region = np.concatenate((box[:2] - (2.0 * R + 1.0 + step), box[2:] + (2.0 * R + 1.0 + step)))
            val, at = _left_over(cands, centres, R, step, best, partial(_on_boundary, path, radius=R))
            if val > best:
                best, where = val, at
    return best, (where if locate else None)


class _Candidates:
    """The candidates of the exact cut boundary of some exact elements (those of
    :func:`~.boundary._candidates`, the same points): the envelope points of the lines by number
    (line by line, ``step`` apart), the others as arrays after them."""

    def __init__(self, exact: Sequence[Line | Arc], programmed: Sequence[Line | Arc], R: float, sign: float,
                 step: float) -> None:  # fmt: skip
        lines = [e for e in exact if isinstance(e, Line)]
        arcs = [e for e in exact if isinstance(e, Arc)]
        self.R = R
        L = np.array([e.plane_length for e in lines])
        self.n = np.maximum(2, np.ceil(L / step).astype(int) + 1)  # samples per line (elements_samples)
        self.first = np.concatenate(([0], np.cumsum(self.n)))
        self.L = L
        self.a = np.array([e.start2 for e in lines], float).reshape(-1, 2)
        self.d = np.array([e.end2 for e in lines], float).reshape(-1, 2) - self.a
        t = np.array([e.direction2() for e in lines], float).reshape(-1, 2)
        self.normal = _normal(t, sign).reshape(-1, 2)
        # the arcs' envelope points and the fans at the joints, one by one
        P, D = envelope(arcs, R, sign, step)
        Pf, Df = joint_fans(exact, programmed, R, sign)
        self.other, self.other_dirs = np.vstack((P, Pf)), np.vstack((D, Df))
        self.lines = int(self.first[-1])
        self.count = self.lines + len(self.other)

    def points(self, ids: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The candidates ``ids`` (numbers: lines' envelope points, then the others) and their
        directions away from the material."""
        ids = np.asarray(ids, np.int64)
        P, D = np.empty((len(ids), 2)), np.empty((len(ids), 2))
        on_line = ids < self.lines
        if on_line.any():
            k = ids[on_line]
            e = np.searchsorted(self.first, k, side="right") - 1
            j = k - self.first[e]
            L, n = self.L[e], self.n[e]
            # np.linspace(0, L, n) / L, the point and the envelope point (elements_samples, _candidates)
            y = j * (L / (n - 1))
            last = j == n - 1
            y[last] = L[last]
            lam = y / L
            N = self.normal[e]
            P[on_line] = (self.a[e] + lam[:, None] * self.d[e]) + self.R * N
            D[on_line] = -N
        if (~on_line).any():
            k = ids[~on_line] - self.lines
            P[~on_line], D[~on_line] = self.other[k], self.other_dirs[k]
        return P, D

    def blocks(self) -> tuple[np.ndarray, np.ndarray]:
        """The first and last number of every block of BLOCK consecutive envelope points of a line."""
        per = (self.n + BLOCK - 1) // BLOCK
        line = np.repeat(np.arange(len(self.n)), per)
        k = np.arange(int(per.sum())) - np.repeat(np.cumsum(per) - per, per)
        lo = self.first[line] + k * BLOCK
        hi = np.minimum(lo + BLOCK - 1, self.first[line + 1] - 1)
        return lo, hi


def _left_over(
    cands: _Candidates,
    centres: CentreSamples,
    R: float,
    step: float,
    best: float,
    probe: Callable[[np.ndarray], np.ndarray],
) -> tuple[float, np.ndarray | None]:
    """The largest material left by discs around the samples of ``centres`` at the candidates of
    ``cands`` that are probes (``probe``: which of some candidate points are), if it exceeds
    ``best`` (see the module description)."""
    from scipy.spatial import cKDTree

    if not len(centres):
        for start in range(0, cands.count, 4096):
            P, _ = cands.points(np.arange(start, min(start + 4096, cands.count)))
            first = np.nonzero(probe(P))[0][:1]
            if len(first):
                return 1.0, P[first[0]]
        return best, None
    coarse = centres.coarse(max(1, int(COARSE_MM / step + 1e-9)), centres.region)
    tree = cKDTree(coarse, leafsize=32, balanced_tree=False, compact_nodes=False)
    # units: the blocks of the lines' envelope points, then the other candidates one by one
    lo, hi = cands.blocks()
    # (the other candidates are tested for being probes at once: most that are not lie in the
    # fans at the inside corners of the exact path, and they would come first by their bounds)
    other = np.where(probe(cands.other), _bounds(tree, coarse, cands.other, cands.other_dirs, R, stride=8), -np.inf)
    unit = np.concatenate((_block_bounds(tree, coarse, cands, lo, hi), other))
    first = np.concatenate((lo, cands.lines + np.arange(len(cands.other))))
    last = np.concatenate((hi, cands.lines + np.arange(len(cands.other))))
    reach = R + 1.0 + 1e-6 + 2.0 * step  # (what _exact_left uses, with a margin for a curve's box)
    where = None
    done = np.zeros(cands.count, bool)
    evaluated = 0
    for batch in _by_bound(unit, EARLY_PROBES):
        # the units of the largest bounds, a batch at a time, until EARLY_PROBES probes are
        # measured or no bound exceeds the largest value: their candidates by their own bounds
        batch = batch[unit[batch] > best]
        if not len(batch):
            break
        ids = np.sort(_ids(first[batch], last[batch]))  # (along the elements: see _window)
        ids = ids[~done[ids]]
        P, D = cands.points(ids)
        screen = _bounds(tree, coarse, P, D, R, stride=8)
        order = np.argsort(-screen, kind="stable")
        ids, P, D, screen = ids[order], P[order], D[order], screen[order]
        done[ids[screen <= best]] = True
        keep = screen > best
        ids, P, D, screen = ids[keep], P[keep], D[keep], screen[keep]
        is_probe = probe(P)
        fine = centres.near(P[is_probe], reach)
        ftree = _tree(fine)
        d0 = np.full(len(ids), np.inf)
        d0[is_probe] = _nearest(ftree, P[is_probe])
        for j, ok, d in zip(range(len(ids)), is_probe.tolist(), d0.tolist(), strict=True):
            if screen[j] <= best or evaluated >= EARLY_PROBES:
                break
            done[ids[j]] = True
            if not ok or d <= R + step * step / (4.0 * R) + 1e-9:
                continue  # not on the boundary, or swept (see _left_over_bounded)
            evaluated += 1
            val = _exact_left(ftree, P, D, fine, R, j)
            if val > best:
                best, where = val, P[j]
        if evaluated >= EARLY_PROBES:
            break
    # (a bound within rounding of the largest value stays: it might tie)
    ids = _ids(first[unit > best - 1e-12], last[unit > best - 1e-12])
    ids = ids[~done[ids]]
    if not len(ids):
        return best, where
    P, D = cands.points(ids)
    keep = _bounds(tree, coarse, P, D, R, stride=8) > best - 1e-12
    P, D = P[keep], D[keep]
    keep = probe(P)
    P, D = P[keep], D[keep]
    if not len(P):
        return best, where
    fine = centres.near(P, reach)
    if not len(fine):
        return (1.0, P[0]) if 1.0 > best else (best, where)
    val, at = _left_over_bounded(_tree(fine), P, D, fine, R, step, best)
    return (val, at) if at is not None else (best, where)


def _ids(first: np.ndarray, last: np.ndarray) -> np.ndarray:
    """Every number from ``first[i]`` to ``last[i]`` for every i, in that order."""
    count = last - first + 1
    return np.repeat(first - np.cumsum(count) + count, count) + np.arange(int(count.sum()))


def _by_bound(bound: np.ndarray, size: int) -> Iterator[np.ndarray]:
    """The indices of ``bound`` in decreasing order of its values, ``size`` at first, then four
    times as many each batch (only as much of the order as is asked for is sorted)."""
    order = np.zeros(0, np.int64)
    done = 0
    while done < len(bound):
        k = min(len(bound), done + size)
        if k > len(order):
            part = np.argpartition(-bound, k - 1)[:k] if k < len(bound) else np.arange(len(bound))
            order = part[np.argsort(-bound[part], kind="stable")]
        yield order[done:k]
        done, size = k, 4 * size


def _tree(points: np.ndarray) -> Any:
    """A k-d tree of centre samples (dense samples along a path: an unbalanced tree of larger
    leaves answers the queries of probes a radius away 2–3× faster than the default one)."""
    from scipy.spatial import cKDTree

    return cKDTree(points.reshape(-1, 2), leafsize=32, balanced_tree=False, compact_nodes=False)


def _nearest(tree: Any, points: np.ndarray) -> np.ndarray:
    """Distance of every point to the nearest point of ``tree`` (inf when it is empty)."""
    if not tree.n or not len(points):
        return np.full(len(points), np.inf)
    return np.asarray(tree.query(points, k=1)[0]).reshape(len(points))


def _disc_terms(rel: np.ndarray, dirs: np.ndarray, R: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per probe and disc (centres relative to the probes, n×m×2): where the probe's ray enters
    and leaves the disc (mm along the ray), and whether it meets a disc within R + 1 mm at all."""
    along = np.einsum("nmk,nk->nm", rel, dirs)
    dist2 = np.einsum("nmk,nmk->nm", rel, rel)
    perp2 = dist2 - along * along
    inside = (perp2 <= R * R) & (dist2 <= (R + 1.0 - 1e-9) ** 2)
    root = np.sqrt(np.maximum(R * R - perp2, 0.0))
    return along - root, along + root, inside


def _window(tree: Any, coarse: np.ndarray, points: np.ndarray, stride: int = 1) -> np.ndarray:
    """The WINDOW coarse samples on either side of the one nearest each of ``points`` (n×(2W+1)).
    With ``stride``, the nearest sample is queried for every ``stride``-th point and interpolated
    between (consecutive points of a fan or along an element, no farther apart than the coarse
    samples, have neighbouring nearest samples), and queried for every point where the neighbouring
    answers are farther apart than that."""
    n = len(points)
    q = np.unique(np.append(np.arange(0, n, stride), n - 1)) if stride > 1 else np.arange(n)
    _, jq = tree.query(points[q], k=1)
    jq = np.asarray(jq, np.int64).reshape(len(q))
    if stride > 1:
        j = np.rint(np.interp(np.arange(n), q, jq)).astype(np.int64)
        jump = np.nonzero(np.abs(np.diff(jq)) > stride + 2)[0]  # (the points no farther apart than the samples)
        inner = _ids(q[jump] + 1, q[jump + 1] - 1)
        if len(inner):
            j[inner] = np.asarray(tree.query(points[inner], k=1)[1], np.int64).reshape(len(inner))
    else:
        j = jq
    return np.clip(j[:, None] + np.arange(-WINDOW, WINDOW + 1), 0, len(coarse) - 1)


def _bounds(tree: Any, coarse: np.ndarray, P: np.ndarray, D: np.ndarray, R: float, stride: int = 1) -> np.ndarray:
    """An upper bound of the material left at each candidate ``P`` (directions ``D``; mm, ``inf``
    where none is known): what the discs of the windows of coarse samples around its ideal centre
    (``P + R·D``) and around itself leave, those within R + 1 mm of it (fewer discs leave at least
    as much, and only discs within R + 1 mm of a probe count in its exact value,
    :func:`_exact_left`; a candidate inside a disc is swept). ``stride``: see :func:`_window`."""
    if not len(P):
        return np.zeros(0)
    idx = np.hstack((_window(tree, coarse, P + R * D, stride), _window(tree, coarse, P, stride)))
    entry, exit_, inside = _disc_terms(coarse[idx] - P[:, None, :], D, R)
    covered = np.any(inside & (entry <= 0.0) & (exit_ >= 0.0), axis=1)
    ahead = np.where(inside & (entry > 0.0), entry, np.inf).min(axis=1)
    return np.where(covered, 0.0, np.minimum(ahead, 10.0 * R + 1.0 + np.where(np.isfinite(ahead), 0.0, np.inf)))


def _block_bounds(tree: Any, coarse: np.ndarray, cands: _Candidates, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """An upper bound of the material left at every candidate of each block of a line's envelope
    points ``lo``–``hi`` (mm; ``inf`` where none is known). A block's candidates lie on one line
    with one direction: towards a disc, the distance across the ray grows linearly along the
    block (the distance along it is the same), so where the ray enters and leaves the disc is
    farthest at an end; a disc that meets the rays of both ends within R + 1 mm bounds every
    candidate of the block by the larger entry (or 0), and the bound is the least over the discs
    of the window around the block's middle (with 1e-12 mm for rounding)."""
    R = cands.R
    if not len(lo):
        return np.zeros(0)
    P0, D = cands.points(lo)
    P1, _ = cands.points(hi)
    mid = 0.5 * (P0 + P1) + R * D
    idx = _window(tree, coarse, mid, stride=4)
    q = coarse[idx]
    e0, x0, in0 = _disc_terms(q - P0[:, None, :], D, R)
    e1, x1, in1 = _disc_terms(q - P1[:, None, :], D, R)
    ok = in0 & in1 & (x0 >= 0.0) & (x1 >= 0.0)
    each = np.where(ok, np.maximum(np.maximum(e0, e1), 0.0) + 1e-12, np.inf)
    return np.minimum(each.min(axis=1), 10.0 * R + 1.0 + np.where(ok.any(axis=1), 0.0, np.inf))


def _left_over_bounded(
    tree: Any, probes: np.ndarray, dirs: np.ndarray, centres: np.ndarray, R: float, step: float, best: float
) -> tuple[float, np.ndarray | None]:
    """The largest material left at ``probes`` by discs around ``centres`` (in ``tree``: every
    sample within R + 1 mm of each probe) if it exceeds ``best``, through bounds of increasing
    cost."""
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
    # order of the bound, until no bound exceeds the largest exact value found (a probe without a
    # centre within R + 1 mm has the value 1 mm)
    floor = max(best, float((np.minimum(d0[open_, 0], R + 1.0) - R).max()))
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

