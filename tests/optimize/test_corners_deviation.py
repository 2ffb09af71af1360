"""The cut-part deviation found through bounds is the largest value over every probe, measured one by
one: its candidates are those of the cut boundary, its centre samples those of the whole path, its
bounds bound the exact values; and the vertex distances of the run splines on a path without
compensation are those of a k-d tree over every sample."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial import cKDTree

from trcopt.optimize.corners import blend_corners, deviation
from trcopt.optimize.corners.boundary import _candidates, material_left
from trcopt.optimize.corners.centres import CentreSamples
from trcopt.optimize.corners.deviation import _block_bounds, _bounds, cut_deviation
from trcopt.optimize.corners.free_runs import _vertex_distances
from trcopt.optimize.corners.samples import path_samples
from trcopt.pipeline import PlanOptions, plan

EPS = 0.01


def _freeform(chords: int, turn: float = 2 * math.pi, compensated: bool = True) -> str:
    """The freeform contour r = 30 + 5 sin 5t + 2 cos 11t (mm) from t = 0 to ``turn`` in ``chords``
    G1 chords (LinuxCNC; with ``G41.1 D2`` when ``compensated``), entered and left from outside."""
    out = ["G21 G17 G90 G40 F6000", "G0 X50 Y0 Z1", "G1 Z0"]
    pts = []
    for i in range(chords + 1):
        t = turn * i / chords
        r = 30 + 5 * math.sin(5 * t) + 2 * math.cos(11 * t)
        pts.append((r * math.cos(t), r * math.sin(t)))
    out.append(f"{'G41.1 D2 ' if compensated else ''}G1 X{pts[0][0]:.5f} Y{pts[0][1]:.5f}")
    out += [f"G1 X{x:.5f} Y{y:.5f}" for x, y in pts[1:]]
    out.append(f"{'G40 ' if compensated else ''}G1 X50 Y{pts[-1][1]:.5f}")
    return "\n".join([*out, "G0 Z5", "M2"]) + "\n"


@pytest.fixture(scope="module")
def blended():
    exact = plan(_freeform(200), file="cam.ngc", options=PlanOptions(timing=False))
    res = blend_corners(exact.toolpath, exact.programmed, tolerance_mm=EPS, mode="optimal")
    return exact, res


@pytest.fixture(scope="module")
def short():
    # 40 chords over a sixth of the contour: few enough probes at the default 2 µm for the reference
    exact = plan(_freeform(40, math.pi / 3), file="cam.ngc", options=PlanOptions(timing=False))
    res = blend_corners(exact.toolpath, exact.programmed, tolerance_mm=EPS, mode="optimal")
    return exact, res


def _every_probe(cands, centres, R, step, best, probe):
    """The largest material left over every probe among the candidates, each measured exactly
    against every centre sample within R + 1 mm (what ``_left_over`` prunes its way to)."""
    P, D = cands.points(np.arange(cands.count))
    idx = np.nonzero(probe(P))[0]
    if not len(centres):
        return (1.0, P[idx[0]]) if len(idx) else (best, None)
    fine = centres.near(P, R + 1.0 + 1e-6 + 2.0 * step)
    tree = cKDTree(fine)
    d0 = tree.query(P[idx])[0] if len(idx) else np.zeros(0)
    where = None
    for i in idx[d0 > R + step * step / (4.0 * R) + 1e-9].tolist():
        near = tree.query_ball_point(P[i], R + 1.0)
        val = float(material_left(P[i : i + 1], D[i : i + 1], fine[near], R)[0]) if near else 1.0
        if val > best:
            best, where = val, P[i]
    return best, where


@pytest.mark.parametrize(("case", "step"), [("blended", 0.02), ("short", 0.002)])
def test_cut_deviation_is_the_largest_value_over_every_probe(case, step, request, monkeypatch):
    exact, res = request.getfixturevalue(case)
    fast = cut_deviation(exact.programmed, exact.toolpath, res.segments, step=step, locate=True)
    monkeypatch.setattr(deviation, "_left_over", _every_probe)
    slow = cut_deviation(exact.programmed, exact.toolpath, res.segments, step=step, locate=True)
    assert fast[0] > 0.0
    assert fast[0] == slow[0]
    assert np.array_equal(fast[1], slow[1])


def _chunks(exact, res, step, monkeypatch):
    """The arguments of every chunk's measurement."""
    seen = []
    real = deviation._left_over

    def keep(*args):
        seen.append(args)
        return real(*args)

    monkeypatch.setattr(deviation, "_left_over", keep)
    cut_deviation(exact.programmed, exact.toolpath, res.segments, step=step)
    assert seen
    return seen


def test_bounds_are_upper_bounds_of_the_exact_values(blended, monkeypatch):
    exact, res = blended
    checked = 0
    for cands, centres, R, _, _, _ in _chunks(exact, res, 0.002, monkeypatch):
        coarse = centres.coarse(8)
        tree = cKDTree(coarse)
        lo, hi = cands.blocks()
        block = _block_bounds(tree, coarse, cands, lo, hi)
        other = _bounds(tree, coarse, cands.other, cands.other_dirs, R, stride=8)
        ids = np.arange(0, cands.count, 23)
        P, D = cands.points(ids)
        fine = centres.near(P, R + 1.01)
        ftree = cKDTree(fine)
        own = _bounds(tree, coarse, P, D, R, stride=8)
        for i, p, d, b in zip(ids.tolist(), P, D, own.tolist(), strict=True):
            near = ftree.query_ball_point(p, R + 1.0)
            value = float(material_left(p[None, :], d[None, :], fine[near], R)[0]) if near else 1.0
            unit = block[np.searchsorted(lo, i, side="right") - 1] if i < cands.lines else other[i - cands.lines]
            assert b >= value and unit >= value
            checked += 1
    assert checked > 4000


def test_candidates_and_centre_samples_are_those_of_the_whole_chunk(blended, monkeypatch):
    exact, res = blended
    chunks = _chunks(exact, res, 0.002, monkeypatch)
    segs = [s for s in res.segments if not s.is_rapid and s.radius > 0]
    for cands, centres, _, _, _, _ in chunks[:3]:
        P, D = cands.points(np.arange(cands.count))
        assert cands.count > 10000
        # every sample of the chunk's elements (the curves joined as path_samples joins them)
        every = centres.near(P, 1e3)
        assert len(every) > 10000 and np.isin(centres.coarse(8), every).all()
    # the samples of a stretch of the new path, element by element and as path_samples gives them
    part = segs[40:90]
    ours = CentreSamples(part, 0.002).near(np.zeros((1, 2)), 1e3)
    theirs = path_samples(part, 0.002)
    assert np.array_equal(np.unique(ours, axis=0), np.unique(theirs, axis=0)) and len(ours) == len(theirs)


def test_chunk_candidates_are_the_cut_boundary_candidates():
    exact = plan(_freeform(200), file="cam.ngc", options=PlanOptions(timing=False))
    comp = [s for s in exact.toolpath if s.radius > 0 and not s.is_rapid][5:60]
    els = [s.geometry for s in comp]
    prog = [s.geometry for s in exact.programmed][10:50]
    R = comp[0].radius
    cands = deviation._Candidates(els, prog, R, -1.0, 0.002)
    P, D = cands.points(np.arange(cands.count))
    Q, E = _candidates(els, prog, R, -1.0, 0.002)
    ours, theirs = np.hstack((P, D)), np.hstack((Q, E))
    assert len(ours) == len(theirs) > 10000
    assert np.array_equal(ours[np.lexsort(ours.T)], theirs[np.lexsort(theirs.T)])


def test_vertex_distances_are_those_of_every_sample():
    exact = plan(_freeform(300, compensated=False), file="cam.ngc", options=PlanOptions(timing=False))
    from trcopt.optimize.corners import free_runs

    seen = []
    real = free_runs._distances
    free_runs._distances = lambda splines: seen.extend(splines) or real(splines)
    try:
        blend_corners(exact.toolpath, exact.programmed, tolerance_mm=EPS, mode="optimal")
    finally:
        free_runs._distances = real
    assert seen
    for chain, sol, _ in seen:
        pts = np.vstack([p.points_at(np.linspace(0.0, p.length, int(p.length / 2e-3) + 2))[:, :2] for p in sol.pieces])
        vertices = np.array([e.point2(1.0) for e in chain.full[:-1]], float)
        assert np.array_equal(_vertex_distances(sol.pieces, vertices), cKDTree(pts).query(vertices)[0])
