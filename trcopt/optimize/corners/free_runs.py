"""Smoothing splines across runs of CAM chords on a path without compensation (G40 CAM output).

A CAM program that describes the tool centre itself (G40) is a polyline of short chords. Its
corners get the largest circular blend within the tolerance (:func:`~.fillet.fillet_path`); a run
of small-deflection corners (:func:`~.chain.find_chains`) can instead take one G2 spline that stays
within ε of the polyline on both sides (:func:`~.chain.solve_chain` without a tool radius) and so
follows the curve the chords approximate rather than turning at every vertex.

:func:`run_splines` builds that plan: circular blends at the corners outside the runs, a spline
across every run whose spline is feasible; the caller keeps whichever of it and the all-circles
plan times faster.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from trcopt.geometry import Poly
from trcopt.geometry.poly import hermite_pieces
from trcopt.modes import CornerObjective
from trcopt.optimize.corners.assemble import TARGET_MARGIN, Spline, assemble
from trcopt.optimize.corners.chain import ChainSite, ChainSolution, find_chains, solve_chain
from trcopt.optimize.corners.curves import joint_turn
from trcopt.optimize.corners.fillet import FilletSpec, blend_joints, fillet_path
from trcopt.optimize.corners.records import CornerResult
from trcopt.optimize.corners.strategies import CornerJob
from trcopt.path import Segment
from trcopt.progress import iterate

__all__ = ["run_splines"]


def run_splines(job: CornerJob) -> CornerResult | None:
    """``job``'s uncompensated path with a G2 spline across every run of CAM chords whose spline is
    feasible and circular blends (B-spline corners under the jerk objective) at its other corners;
    None when the path has no such run."""
    segs = list(job.toolpath)
    joints = [k for k in blend_joints(segs) if segs[k].radius == 0.0]
    plane = [k for k in joints if _flat(segs[k]) and _flat(segs[k + 1])]
    runs = find_chains(segs, plane, set(joints), (), compensated=False)
    if job.objective is CornerObjective.CURVATURE:
        runs = [chain for chain in runs if _circles_limit_speed(job, segs, chain)]
    if not runs:
        return None
    in_runs = {k for chain in runs for k in chain.joints}
    specs = {k: FilletSpec((1.0 - TARGET_MARGIN) * job.tolerance_at(k), job.kind) for k in joints if k not in in_runs}
    g2 = job.objective is CornerObjective.JERK
    filleted = fillet_path(segs, specs, job.strategy, g2=g2) if specs else job.unchanged()
    first = _first_of(filleted.origin or list(range(len(filleted.segments))))
    # the runs on the filleted path (their joints kept their lines; only the end lines are trimmed)
    moved = [first[k] for k in sorted(in_runs)]
    chains = find_chains(filleted.segments, moved, set(moved), (), compensated=False)
    splines: list[Spline] = []
    tasks = []
    for chain in chains:
        old = [_old_joint(filleted.origin, k) for k in chain.joints]
        eps = (1.0 - TARGET_MARGIN) * min(job.tolerance_at(k) for k in old)
        tasks.append((chain, eps))
    for (chain, eps), sol in zip(tasks, _solutions(tasks, job.workers), strict=True):
        if sol.ok:
            splines.append((chain, sol, eps))
    if not splines:
        return None
    out = assemble(filleted.segments, [], {}, {}, job.strategy, chains=splines)
    origin1 = filleted.origin or list(range(len(filleted.segments)))
    origin2 = out.origin or list(range(len(out.segments)))
    measured = _distances(splines)
    records = [replace(r, index=origin1[r.index], **measured.get(r.index, {})) for r in out.corners]
    corners = filleted.corners + records
    deviation = max([filleted.max_deviation_mm] + [sol.max_offset for _, sol, _ in splines])
    on_spline = {k for chain, _, _ in splines for k in chain.joints}
    # the corners of a run whose spline is infeasible get their circular blends on the result
    failed = {origin1[k]: _first_of(origin2)[k] for k in moved if k not in on_spline}
    if failed:
        specs = {j: FilletSpec((1.0 - TARGET_MARGIN) * job.tolerance_at(k), job.kind) for k, j in failed.items()}
        last = fillet_path(out.segments, specs, job.strategy, g2=g2)
        to_exact = [origin1[origin2[i]] for i in range(len(origin2))]
        corners += [replace(r, index=to_exact[r.index]) for r in last.corners]
        deviation = max(deviation, last.max_deviation_mm)
        origin3 = last.origin or list(range(len(last.segments)))
        out = CornerResult(last.segments, [], 0.0, job.strategy, origin=[to_exact[i] for i in origin3])
    else:
        out.origin = [origin1[i] for i in origin2]
    out.corners = sorted(corners, key=lambda r: r.index)
    out.max_deviation_mm = deviation
    return out


def _circles_limit_speed(job: CornerJob, segs: Sequence[Segment], chain: ChainSite) -> bool:
    """Whether a spline across ``chain`` could carry more speed than the circular blends at its
    joints under acceleration limits: the largest circle within ε at a joint turning by θ between
    chords of lengths a and b has the radius min(ε·cos(θ/2)/(1 − cos(θ/2)), min(a, b)/2 / tan(θ/2));
    the spline's peak curvature is at least the run's net turn over its length. Only where a
    circle is both more curved than that and slower than the feed can the spline gain."""
    from trcopt.config import DEFAULT_MACHINE

    m = job.machine or DEFAULT_MACHINE
    a_lat = min(m.axis("X").amax_mm_s2, m.axis("Y").amax_mm_s2)
    theta_sum, worst = 0.0, 0.0
    for k in chain.joints:
        a, b = segs[k].geometry, segs[k + 1].geometry
        theta = abs(joint_turn(a, b))
        theta_sum += theta
        if theta <= 1e-12:
            continue
        c = math.cos(0.5 * theta)
        eps = job.tolerance_at(k)
        r = min(eps * c / max(1.0 - c, 1e-300), 0.5 * min(a.plane_length, b.plane_length) / math.tan(0.5 * theta))
        feed = segs[k].feed_mm_s or m.rapid_mm_s
        kappa = 1.0 / max(r, 1e-300)
        if kappa * feed * feed > a_lat:  # the circle is slower than the feed
            worst = max(worst, kappa)
    length = sum(e.plane_length for e in chain.full)
    return worst > 0.0 and (length <= 0.0 or worst > theta_sum / length)


def _distances(splines: list[Spline]) -> dict[int, dict[str, float]]:
    """Per joint on a spline: the distance of the spline from the polyline (``contour_mm``, the
    largest over the run, measured on the spline's dense samples) and from the run's vertices
    (``vertex_mm``, each vertex to the spline sampled every 2 µm: :func:`_vertex_distances`)."""
    out: dict[int, dict[str, float]] = {}
    for chain, sol, _ in splines:
        vertices = np.array([e.point2(1.0) for e in chain.full[:-1]], float)
        far = _vertex_distances(sol.pieces, vertices)
        for k, d in zip(chain.joints, far, strict=True):
            out[k] = {"vertex_mm": float(d), "contour_mm": float(sol.max_offset)}
    return out


SAMPLE_MM = 2e-3  # spacing of the spline samples of the vertex distances


def _vertex_distances(pieces: Sequence[Poly], vertices: np.ndarray) -> np.ndarray:
    """The distance of each vertex (the joint between pieces i and i + 1 of a run's spline) to the
    nearest of the spline's samples (every piece at ``np.linspace(0, length, length // 2 µm + 2)``).

    The spline passes within ε of every vertex where its two pieces meet, so the samples near
    that end are measured first; a sample s farther along a piece from its end than four times
    that distance (and two samples) is no nearer (the pieces are parametrised by arc length and
    bend little over a few µm), nor is a sample of a piece whose samples' box lies farther away
    (less half the sample spacing and a µm of Hermite bulge); the others are measured too. The
    distances are those of a k-d tree over every sample (the same sum of squares), found among
    fewer."""
    arrays = [p.arrays() for p in pieces]
    length = np.array([a[0][-1] for a in arrays])
    count = (length / SAMPLE_MM).astype(int) + 2
    size = np.array([len(a[0]) for a in arrays])
    first = np.concatenate(([0], np.cumsum(size)))[:-1]
    cum, pts, tans = (np.concatenate([a[m] for a in arrays]) for m in range(3))
    joined: tuple[Any, Any, Any, Any] = (
        cum,
        pts,
        tans,
        None if arrays[0][3] is None else np.concatenate([a[3] for a in arrays]),
    )
    box = np.array([(*a[1][:, :2].min(axis=0), *a[1][:, :2].max(axis=0)) for a in arrays])

    def samples(piece: np.ndarray, j: np.ndarray) -> np.ndarray:
        # Poly.points_at(np.linspace(0, L, n))[j] of every (piece, j): hermite_at on each piece's
        # own arrays (its intervals found piece by piece), evaluated in one pass
        L, n = length[piece], count[piece]
        s = j * (L / (n - 1))
        s[j == n - 1] = L[j == n - 1]
        i = np.empty(len(s), np.int64)
        for q in np.unique(piece).tolist():
            at = piece == q
            cum = arrays[q][0]
            i[at] = first[q] + np.clip(np.searchsorted(cum, np.clip(s[at], 0.0, cum[-1]), side="right") - 1, 0,
                                       size[q] - 2)  # fmt: skip
        return hermite_pieces(joined, i, np.clip(s, 0.0, length[piece]), 0)[:, :2]

    k = np.arange(len(vertices))
    ends = samples(np.concatenate((k, k + 1)), np.concatenate((count[k] - 1, np.zeros(len(k), np.int64))))
    d2 = ((ends - np.vstack((vertices, vertices))) ** 2).sum(axis=1)
    d0 = np.sqrt(np.minimum(d2[: len(k)], d2[len(k) :]))
    # per vertex: the samples of its two pieces near their common end, and every sample of the
    # other pieces whose boxes come near
    w0 = (4.0 * d0 / (length[k] / (count[k] - 1))).astype(int) + 2
    w1 = (4.0 * d0 / (length[k + 1] / (count[k + 1] - 1))).astype(int) + 2
    lo0, hi1 = np.maximum(count[k] - 1 - w0, 0), np.minimum(w1, count[k + 1] - 1)
    whose, piece, j = [], [], []
    for kk, a, b in zip(k.tolist(), lo0.tolist(), hi1.tolist(), strict=True):
        n0 = count[kk] - a
        whose.append(np.full(n0 + b + 1, kk))
        piece.append(np.concatenate((np.full(n0, kk), np.full(b + 1, kk + 1))))
        j.append(np.concatenate((np.arange(a, count[kk]), np.arange(b + 1))))
    gap = np.maximum(np.maximum(box[None, :, :2] - vertices[:, None, :], vertices[:, None, :] - box[None, :, 2:]), 0.0)
    near = np.hypot(gap[..., 0], gap[..., 1]) <= (d0 + 0.5 * SAMPLE_MM + 1e-3)[:, None]
    near[k, k] = near[k, k + 1] = False
    for kk, q in zip(*np.nonzero(near), strict=True):
        whose.append(np.full(count[q], kk))
        piece.append(np.full(count[q], q))
        j.append(np.arange(count[q]))
    whose_a, piece_a, j_a = (np.concatenate(x) for x in (whose, piece, j))
    rel = samples(piece_a, j_a) - vertices[whose_a]
    dist2 = rel[:, 0] * rel[:, 0] + rel[:, 1] * rel[:, 1]
    out = np.full(len(vertices), np.inf)
    np.minimum.at(out, whose_a, dist2)
    return np.sqrt(out)


def _flat(seg: Segment) -> bool:
    """A feed move in its plane at one applicate, of non-zero plane length."""
    g = seg.geometry
    return not seg.is_rapid and g.plane_length > 1e-9 and abs(g.start[2] - g.end[2]) <= 1e-12


def _first_of(origin: Sequence[int]) -> dict[int, int]:
    """For every old segment, the first new segment that comes from it."""
    first: dict[int, int] = {}
    for j, i in enumerate(origin):
        first.setdefault(i, j)
    return first


def _old_joint(origin: Sequence[int] | None, k: int) -> int:
    """The exact path's joint of joint ``k`` of a blended path (``origin``: its segments' sources)."""
    return k if origin is None else origin[k]


def _solve(task: tuple[ChainSite, float]) -> ChainSolution:
    return solve_chain(*task)


def _solutions(tasks: list[tuple[ChainSite, float]], workers: int) -> list[ChainSolution]:
    """The spline of every run, in order: in ``workers`` processes when there are several."""
    if workers > 1 and len(tasks) > 1:
        from concurrent.futures import ProcessPoolExecutor

        with ProcessPoolExecutor(max_workers=min(workers, len(tasks))) as pool:
            return list(iterate(pool.map(_solve, tasks), "corner splines", len(tasks)))
    return list(iterate(map(_solve, tasks), "corner splines", len(tasks)))
