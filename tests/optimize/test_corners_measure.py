"""The shortcuts of the corner stage's measurements give what the straightforward computations give:
the cut-part deviation behind a parallel path (the whole search: ``test_corners_deviation.py``),
the probes of the exact cut boundary, the
samples of many elements at once, the programmed elements near the corners, the pairs of points and
elements within a distance, and the cycle-time estimate."""

from __future__ import annotations

import math
from itertools import accumulate, pairwise

import numpy as np
import pytest

from trcopt.config import DEFAULT_MACHINE
from trcopt.errors import SourceSpan
from trcopt.geometry import Arc, Line, Plane, Poly
from trcopt.geometry.poly import hermite_curve
from trcopt.modes import Side
from trcopt.optimize.corners import blend_corners, boundary, cut_deviation
from trcopt.optimize.corners.boundary import boundary_probes, element_samples
from trcopt.optimize.corners.chain_geometry import Elements
from trcopt.optimize.corners.samples import FAN, boxes, elements_samples, fans, path_samples
from trcopt.optimize.corners.sites import _PlaneGrids
from trcopt.optimize.corners.time_model import estimate_time
from trcopt.path import Role, Segment
from trcopt.pipeline import PlanOptions, plan
from trcopt.verify.model import point_distance

EPS = 0.01


def _freeform(chords: int) -> str:
    """A closed freeform contour r = 30 + 5 sin 5t + 2 cos 11t (mm) of ``chords`` G1 chords with
    ``G41.1 D2`` (LinuxCNC), entered and left from outside."""
    out = ["G21 G17 G90 G40 F6000", "G0 X50 Y0 Z1", "G1 Z0"]
    pts = []
    for i in range(chords + 1):
        t = 2 * math.pi * i / chords
        r = 30 + 5 * math.sin(5 * t) + 2 * math.cos(11 * t)
        pts.append((r * math.cos(t), r * math.sin(t)))
    out.append(f"G41.1 D2 G1 X{pts[0][0]:.5f} Y{pts[0][1]:.5f}")
    out += [f"G1 X{x:.5f} Y{y:.5f}" for x, y in pts[1:]]
    out.append("G40 G1 X50 Y0")
    return "\n".join([*out, "G0 Z5", "M2"]) + "\n"


@pytest.fixture(scope="module")
def blended():
    exact = plan(_freeform(200), file="cam.ngc", options=PlanOptions(timing=False))
    res = blend_corners(exact.toolpath, exact.programmed, tolerance_mm=EPS, mode="optimal")
    return exact, res


def _seg(g, feed=100.0, side=Side.OFF, radius=0.0, plane=Plane.G17, stop=False):
    return Segment(g, plane, Role.CONTOUR, SourceSpan("t", 1, 1), feed, side=side, radius=radius, stop=stop)


def test_the_material_left_behind_a_parallel_path_is_found_where_each_ray_meets_a_centre():
    # every probe's ray runs straight through a centre sample: the bound of the nearest discs
    # equals the distance to them less R, the lower bound of the largest value
    t = 0.004
    exact = [_seg(Line((0.0, 0.0, 0.0), (10.0, 0.0, 0.0)), side=Side.LEFT, radius=2.0)]
    programmed = [_seg(Line((0.0, -2.0, 0.0), (10.0, -2.0, 0.0)))]
    new = [_seg(Line((0.0, t, 0.0), (10.0, t, 0.0)), side=Side.LEFT, radius=2.0)]
    value, where = cut_deviation(programmed, exact, new, locate=True)
    assert value == pytest.approx(t, abs=1e-12)
    assert where is not None and where[1] == pytest.approx(-2.0)


def _fan(n1, n2, count):
    a1, a2 = math.atan2(n1[1], n1[0]), math.atan2(n2[1], n2[0])
    d = (a2 - a1 + math.pi) % (2 * math.pi) - math.pi
    ang = a1 + np.linspace(0.0, 1.0, count) * d
    return np.stack((np.cos(ang), np.sin(ang)), axis=1)


def _probes_one_by_one(exact, programmed, R, sign, step):
    """Boundary probes element by element and joint by joint, kept by their distance to every
    element (no tree)."""

    def normal(t):
        return sign * np.array([-t[1], t[0]])

    pts, dirs = [], []
    for el in exact:
        p, tan = element_samples(el, step)
        n = sign * np.stack((-tan[:, 1], tan[:, 0]), axis=1)
        pts.append(p + R * n)
        dirs.append(-n)
    for e1, e2 in pairwise(exact):
        if math.dist(e1.end, e2.start) <= 1e-9:
            fan = _fan(normal(np.array(e1.end_tangent())), normal(np.array(e2.start_tangent())), FAN)
            pts.append(np.array(e1.point2(1.0))[None, :] + R * fan)
            dirs.append(-fan)
    for e1, e2 in pairwise(programmed):
        if math.dist(e1.end[:2], e2.start[:2]) <= 1e-9:
            fan = _fan(-normal(np.array(e1.end_tangent())), -normal(np.array(e2.start_tangent())), FAN)
            pts.append(np.repeat(np.array(e1.point2(1.0))[None, :], FAN, axis=0))
            dirs.append(fan)
    P, D = np.vstack(pts), np.vstack(dirs)
    E = Elements(exact)
    m = np.repeat(np.arange(len(P)), E.n)
    dmin = E.distances(np.tile(np.arange(E.n), len(P)), P[m]).reshape(len(P), E.n).min(axis=1)
    keep = np.abs(dmin - R) <= 1e-7 * max(R, 1.0)
    return P[keep], D[keep]


def test_boundary_probes_are_those_of_the_elements_one_by_one(blended):
    exact, _ = blended
    comp = [s for s in exact.toolpath if boundary.blendable(s)]
    els = [s.geometry for s in comp[10:60]]
    assert {type(e) for e in els} == {Line, Arc}
    prog = [s.geometry for s in exact.programmed if isinstance(s.geometry, Line) and s.role is Role.CONTOUR][10:40]
    R, sign = comp[0].radius, boundary.material_sign(comp[0])
    P, D = boundary_probes(els, prog, R, sign, 0.002)
    Q, E = _probes_one_by_one(els, prog, R, sign, 0.002)
    assert len(P) > 5000
    assert np.array_equal(P, Q) and np.array_equal(D, E)


def test_samples_of_many_elements_are_those_of_each_element():
    els = [
        Line((0.0, 0.0, 0.0), (0.7, 0.1, 0.0)),
        Arc((0.7, 2.1), 2.0, -math.pi / 2, 0.31),
        Arc((3.0, -1.0), 0.5, 2.0, -2.5),
        Line((0.2, 0.3, 0.0), (0.2003, 0.3001, 0.0)),
        Arc((1.0, 1.0), 1e-3, 0.3, 1e-4),
    ]
    for step in (0.002, 0.013, 1.0):
        P, T = elements_samples(els, step)
        p, t = (np.vstack(x) for x in zip(*(element_samples(e, step) for e in els), strict=True))
        assert np.array_equal(P, p) and np.array_equal(T, t)
    pairs = [(np.array([1.0, 0.0]), np.array([0.0, 1.0])), (np.array([0.6, -0.8]), np.array([-0.6, -0.8]))]
    assert np.array_equal(fans(pairs), np.vstack([_fan(a, b, FAN) for a, b in pairs]))


def test_path_samples_with_the_curves_arrays_kept_between_calls_are_those_without(blended):
    _, res = blended
    segs = [s for s in res.segments if not s.is_rapid]
    assert sum(isinstance(s.geometry, Poly) for s in segs) > 50
    arrays: dict = {}
    for lo in range(0, len(segs) - 30, 20):  # overlapping stretches, as the chunks of cut_deviation
        part = segs[lo : lo + 30]
        assert np.array_equal(path_samples(part, 0.002, arrays), path_samples(part, 0.002))
        assert len(arrays) <= 30


def test_boxes_of_curves_in_one_pass_are_those_of_each_curve(blended):
    _, res = blended
    geoms = [s.geometry for s in res.segments]
    assert sum(isinstance(g, Poly) for g in geoms) > 50 and sum(isinstance(g, Line) for g in geoms) > 1
    expected = []
    for g in geoms:
        if isinstance(g, Poly):
            p = np.array([q[:2] for q in g.sample_points()])
            expected.append((*p.min(axis=0), *p.max(axis=0)))
        elif isinstance(g, Arc):
            expected.append(tuple(boxes([g])[0]))
        else:
            expected.append((min(g.start[0], g.end[0]), min(g.start[1], g.end[1]), max(g.start[0], g.end[0]),
                             max(g.start[1], g.end[1])))  # fmt: skip
    assert np.array_equal(boxes(geoms), np.array(expected))


def test_running_sums_of_the_spline_pieces_are_those_of_numpy():
    # the pieces of a run's spline sum their interval lengths one by one, as np.cumsum does
    x = np.random.default_rng(5).uniform(0.0, 0.3, 5000) ** 3
    assert tuple(accumulate(x.tolist(), initial=0.0)) == tuple(np.concatenate(([0.0], np.cumsum(x))).tolist())


def test_the_box_of_an_arc_holds_its_samples_and_not_much_more():
    rng = np.random.default_rng(11)
    for _ in range(300):
        r = float(10.0 ** rng.uniform(-2, 5))
        arc = Arc(tuple(rng.uniform(-50, 50, 2)), r, float(rng.uniform(-7, 7)), float(rng.uniform(-7, 7)))
        box = boxes([arc])[0]
        pts = element_samples(arc, arc.plane_length / 997.0)[0]
        assert (pts[:, 0] >= box[0]).all() and (pts[:, 1] >= box[1]).all()
        assert (pts[:, 0] <= box[2]).all() and (pts[:, 1] <= box[3]).all()
        # (at most a sample spacing and the rounding pad beyond the samples' own box)
        slack = arc.plane_length / 997.0 + 1e-8 * (1.0 + r + 100.0)
        assert np.all(np.abs(box - (*pts.min(axis=0), *pts.max(axis=0))) <= slack)


def test_programmed_elements_near_the_corners_are_those_within_reach_one_by_one(blended):
    exact, _ = blended
    els = [s.geometry for s in exact.programmed if isinstance(s.geometry, Line | Arc) and not s.is_rapid]
    grids = _PlaneGrids([(Plane.G17, g) for g in els])
    rng = np.random.default_rng(7)
    points = rng.uniform(-40.0, 40.0, (300, 2))
    radii = rng.uniform(0.5, 12.0, 300)
    # radii exactly at an element's distance: decided by the scalar distance
    radii[:20] = [point_distance(els[i], tuple(points[k])) for k, i in enumerate(rng.integers(0, len(els), 20))]
    found = grids.within(Plane.G17, points, radii)
    for p, r, got in zip(points, radii, found, strict=True):
        assert got == tuple(g for g in els if point_distance(g, (float(p[0]), float(p[1]))) <= r)
    assert sum(map(len, found)) > 1000


def test_pairs_within_a_distance_are_those_of_every_pair():
    rng = np.random.default_rng(3)
    els = [Line((*rng.uniform(0, 5, 2), 0.0), (*rng.uniform(0, 5, 2), 0.0)) for _ in range(20)]
    els += [Arc(tuple(rng.uniform(0, 5, 2)), float(rng.uniform(0.2, 2)), float(rng.uniform(-3, 3)),
                float(rng.uniform(-6, 6))) for _ in range(20)]  # fmt: skip
    E = Elements(els)
    pts = rng.uniform(-1, 6, (2000, 2))
    m, e, d = E.near_distances(pts, 0.3)
    mm, ee = np.repeat(np.arange(len(pts)), E.n), np.tile(np.arange(E.n), len(pts))
    dd = E.distances(ee, pts[mm])
    ok = dd <= 0.3
    found = sorted(zip(m.tolist(), e.tolist(), d.tolist(), strict=True))
    assert found == sorted(zip(mm[ok].tolist(), ee[ok].tolist(), dd[ok].tolist(), strict=True))
    assert len(m) > 500


def _estimate_one_by_one(segs, machine):
    """The cycle-time estimate interval by interval, segment by segment."""
    from trcopt.geometry.poly import hermite_at
    from trcopt.optimize.corners.time_model import _interval_times
    from trcopt.timing.path import PathArrays
    from trcopt.timing.sections import path_speed_caps, segment_feeds, split_sections

    feeds = path_speed_caps(segment_feeds(segs, machine), machine)
    ends = {sec.last for sec in split_sections(segs, PathArrays(segs))}
    acc = min(machine.axis("X").amax_mm_s2, machine.axis("Y").amax_mm_s2)
    if machine.path.amax_mm_s2 is not None:
        acc = min(acc, machine.path.amax_mm_s2)
    vmax = np.array([machine.axis(k).vmax_mm_s for k in "XYZ"])
    lengths, caps, node_caps = [], [], [np.zeros(1)]
    for i, seg in enumerate(segs):
        g = seg.geometry
        if isinstance(g, Line):
            ds, kappa = np.array([g.length]), np.zeros(2)
        elif isinstance(g, Arc):
            k = (g.plane_length / g.length) ** 2 / g.radius if g.length > 0 else 0.0
            ds, kappa = np.array([g.length]), np.full(2, k)
        else:
            cum = np.asarray(g.cum, dtype=float)
            K = np.asarray(g.curvatures, dtype=float) if g.curvatures is not None else hermite_at(g.arrays(), cum, 2)
            ds, kappa = np.diff(cum), np.sqrt(np.einsum("ij,ij->i", K, K))
        speed = float(vmax.min())
        if isinstance(g, Line) and g.length > 0:
            d = np.abs(np.array(g.end) - np.array(g.start)) / g.length
            limit = vmax[list(seg.plane.axes)]
            speed = float(np.min(np.where(d > 0, limit / np.maximum(d, 1e-300), math.inf)))
        v = min(float(feeds[i]), speed)
        cap = np.minimum(v * v, acc / np.maximum(np.maximum(kappa[:-1], kappa[1:]), 1e-300))
        lengths.append(ds)
        caps.append(cap)
        node_caps.append(np.minimum(cap[:-1], cap[1:]))
        node_caps.append(np.zeros(1) if i in ends else cap[-1:])
    L, C, N = np.concatenate(lengths), np.concatenate(caps), np.concatenate(node_caps)
    N[1:-1] = np.minimum(N[1:-1], C[1:])
    S = np.concatenate(([0.0], np.cumsum(L)))
    forward = 2.0 * acc * S + np.minimum.accumulate(N - 2.0 * acc * S)
    back = 2.0 * acc * (S[-1] - S)
    backward = back + np.minimum.accumulate((N - back)[::-1])[::-1]
    b = np.maximum(np.minimum(np.minimum(forward, backward), N), 0.0)
    return float(np.sum(_interval_times(b[:-1], b[1:], L, C, acc)))


def test_cycle_time_estimate_is_that_of_the_segments_one_by_one(blended):
    _, res = blended
    quintic = hermite_curve((3.0, 0.0, 0.0), (2.0, 0.5, 0.0), (5.0, 1.0, 0.0), (1.0, 2.0, 0.0),
                            (0.0, 1.0, 0.0), (-1.0, 0.0, 0.0))  # fmt: skip
    cubic = hermite_curve((5.0, 1.0, 0.0), (1.0, 2.0, 0.0), (5.0, 3.0, 0.0), (-1.0, 1.0, 0.0))
    assert quintic.curvatures is not None and cubic.curvatures is None
    path = [
        _seg(Line((0.0, 0.0, 0.0), (1.0, 0.0, 0.0)), feed=50.0),
        _seg(Arc((1.0, 1.0), 1.0, -math.pi / 2, math.pi / 2, 0.0, 0.4), feed=80.0),  # a helix
        _seg(Line((2.0, 1.0, 0.4), (3.0, 0.0, 0.0)), feed=120.0, stop=True),
        _seg(quintic, feed=90.0),
        _seg(cubic, feed=90.0),
        _seg(Line((5.0, 3.0, 0.0), (5.0, 3.0, 2.0)), feed=30.0, plane=Plane.G18),
        _seg(Line((5.0, 3.0, 2.0), (9.0, 4.0, 2.0)), feed=None),
    ]
    for segs in (path, list(res.segments)):
        assert estimate_time(segs, DEFAULT_MACHINE) == pytest.approx(_estimate_one_by_one(segs, DEFAULT_MACHINE),
                                                                     rel=1e-13)  # fmt: skip
