"""The by-interval limit check, jerk measure and section assembly give the values of sampling
(and assembling) everything, bit for bit."""

from __future__ import annotations

import math

import numpy as np
import pytest

from trcopt import Arc, AxisLimits, Line, Machine, Plane, Role, Segment, SourceSpan
from trcopt.config import DEFAULT_MACHINE, PathLimits
from trcopt.timing import time_parameterize
from trcopt.timing.checks import max_jerk, path_deviation, path_ratios, sample_chunks
from trcopt.timing.path import PathArrays, SegmentEval
from trcopt.timing.profiles import Profiles, ranges
from trcopt.timing.sections import axis_limits

AXES = (("X", AxisLimits(250.0, 2000.0)), ("Y", AxisLimits(200.0, 1500.0)), ("Z", AxisLimits(100.0, 1000.0)))
VECTOR = Machine(name="vector", rapid_mm_min=60000.0, axes=AXES, path=PathLimits(120.0, 1800.0))


def seg(g, feed: float | None, plane: Plane = Plane.G17, n: int = 0) -> Segment:
    return Segment(g, plane, Role.CONTOUR, SourceSpan("t.ngc", n + 1, 1, f"N{10 * (n + 1)}"), feed)


def mixed_path(n: int, seed: int, plane: Plane = Plane.G17) -> list[Segment]:
    """Lines and arcs, half of the joints sharp, some rapids, feeds changing."""
    rng = np.random.default_rng(seed)
    p = np.zeros(2)
    heading = 0.0
    out: list[Segment] = []
    for i in range(n):
        feed = None if rng.random() < 0.1 else float(rng.choice([20.0, 83.3, 250.0]))
        if i and rng.random() < 0.5:
            heading += float(rng.uniform(0.3, 2.5)) * float(rng.choice([-1, 1]))
        length = float(np.exp(rng.uniform(math.log(0.05), math.log(30.0))))
        if feed is None or rng.random() < 0.5:
            q = p + length * np.array([math.cos(heading), math.sin(heading)])
            out.append(seg(Line((p[0], p[1], 0.0), (q[0], q[1], float(rng.uniform(-1, 1)))), feed, plane, i))
            p = q
        else:
            sweep = float(rng.uniform(0.2, 3.0)) * float(rng.choice([-1, 1]))
            r = length / abs(sweep)
            side = 1.0 if sweep > 0 else -1.0
            c = p + r * side * np.array([-math.sin(heading), math.cos(heading)])
            a0 = math.atan2(p[1] - c[1], p[0] - c[0])
            arc = Arc((float(c[0]), float(c[1])), r, a0, sweep, 0.0, float(rng.uniform(-0.5, 0.5)))
            out.append(seg(arc, feed, plane, i))
            p = np.array(arc.end[:2])
            heading += sweep
    # the Z moves of the lines leave the path discontinuous: rebuild it joined
    joined: list[Segment] = []
    end = np.zeros(3)
    for s in out:
        g = s.geometry
        if isinstance(g, Line):
            d = np.subtract(g.end, g.start)
            g = Line(tuple(end), tuple(end + d))
            end = end + d
        else:
            shift = end - np.array(g.start)
            g = Arc((g.center[0] + shift[0], g.center[1] + shift[1]), g.radius, g.a0, g.sweep, end[2],
                    end[2] + g.w1 - g.w0)
            end = np.array(g.end)
        joined.append(Segment(g, s.plane, s.role, s.span, s.feed_mm_s))
    return joined


def reference_check(traj, dt: float):
    """The maxima of the limit check over every sample and every grid end (all states evaluated)."""
    vmax, amax = axis_limits(traj.machine)
    vr, ar, fr, pv, pa = np.zeros(3), np.zeros(3), 0.0, None, None
    grid = traj.grid_states()
    for smp in [traj.evaluate(ts) for ts in sample_chunks(traj.duration, dt)] + [grid]:
        vr = np.maximum(vr, (np.abs(smp.v) / vmax).max(axis=0))
        ar = np.maximum(ar, (np.abs(smp.a) / amax).max(axis=0))
        fr = max(fr, float((smp.speed / traj.feeds[smp.segment]).max()))
        p1, a1, _ = path_ratios(traj.machine.path, smp)
        pv = p1 if pv is None else max(pv, p1)
        pa = a1 if pa is None else max(pa, a1)
    dev = path_deviation(traj.segments, traj.arrays.start, grid)
    return tuple(vr), tuple(ar), fr, pv, pa, dev, grid.t.shape[0]


def reference_binding(traj) -> list[str]:
    """Per section, the constraint active for the largest share of time, one section at a time."""
    vmax, amax = axis_limits(traj.machine)
    smp = traj.evaluate(0.5 * (traj.t[:-1] + traj.t[1:]))
    columns = [smp.speed / traj.feeds[smp.segment], np.abs(smp.v) / vmax, np.abs(smp.a) / amax]
    names = ["feed", "velocity X", "velocity Y", "velocity Z", "acceleration X", "acceleration Y", "acceleration Z"]
    path = traj.machine.path
    if path.vmax_mm_s is not None:
        columns.append(smp.speed / path.vmax_mm_s)
        names.append("path velocity")
    if path.amax_mm_s2 is not None:
        columns.append(np.linalg.norm(smp.a, axis=1) / path.amax_mm_s2)
        names.append("path acceleration")
    which = np.column_stack(columns).argmax(axis=1)
    w = np.diff(traj.t)
    out = []
    for k in range(len(traj.sections)):
        a, b = traj.section_points[k], traj.section_points[k + 1]
        out.append(names[int(np.bincount(which[a:b], weights=w[a:b], minlength=len(names)).argmax())])
    return out


CASES = [
    (DEFAULT_MACHINE, 40, 1, Plane.G17),
    (VECTOR, 40, 2, Plane.G17),
    (DEFAULT_MACHINE, 30, 3, Plane.G18),
    (VECTOR, 30, 4, Plane.G19),
]


@pytest.mark.parametrize(("machine", "n", "seed", "plane"), CASES)
@pytest.mark.parametrize("dt", [1e-3, 3.7e-4])
def test_check_and_jerk_equal_those_of_every_sample(machine, n, seed, plane, dt):
    traj = time_parameterize(mixed_path(n, seed, plane), machine)
    assert len(traj.sections) > 3 and set(traj.arrays.kind.tolist()) == {0, 1}
    rep = traj.check_limits(dt)
    vr, ar, fr, pv, pa, dev, n_grid = reference_check(traj, dt)
    assert (rep.v_ratio, rep.a_ratio, rep.feed_ratio) == (vr, ar, fr)
    assert (rep.path_v_ratio, rep.path_a_ratio) == (pv, pa)
    assert rep.path_deviation_mm == dev and rep.samples == n_grid
    np.testing.assert_array_equal(traj.max_jerk(dt), max_jerk(traj, dt))
    assert traj.binding_constraints() == reference_binding(traj)


def test_lines_only_path_checks_as_every_sample():
    pts = [(0.0, 0.0), (10.0, 0.0), (10.0, 0.3), (0.5, 3.0), (0.5, 9.0), (7.0, 2.0), (1.0, 1.0), (1.2, 1.0)]
    path = [seg(Line((*a, 0.0), (*b, 0.0)), 150.0, n=i) for i, (a, b) in enumerate(zip(pts, pts[1:], strict=False))]
    traj = time_parameterize(path)
    rep = traj.check_limits(1e-3)
    vr, ar, fr, pv, pa, dev, n_grid = reference_check(traj, 1e-3)
    assert (rep.v_ratio, rep.a_ratio, rep.feed_ratio, rep.path_deviation_mm, rep.samples) == (vr, ar, fr, dev, n_grid)
    np.testing.assert_array_equal(traj.max_jerk(), max_jerk(traj))


@pytest.mark.parametrize("plane", [Plane.G17, Plane.G18, Plane.G19])
def test_path_arrays_hold_the_segment_evaluators_values(plane):
    path = mixed_path(30, 5, plane)
    arrays = PathArrays(path)
    assert arrays.identity == (plane is Plane.G17)
    for k, sg in enumerate(path):
        ev = SegmentEval(sg)
        assert arrays.length[k] == ev.length and arrays.evals[k].length == ev.length
        assert tuple(arrays.perm[k]) == sg.plane.axes
        if ev.kind == "line":
            np.testing.assert_array_equal(arrays.p0[k], ev._line[0])
            np.testing.assert_array_equal(arrays.d[k], ev._line[1])
        else:
            cu, cv, r, a0, sweep, w0, w1 = ev._arc
            assert arrays.sweep[k] == sweep
            np.testing.assert_array_equal(arrays.arc[k], (cu, cv, r, a0, sweep / ev.length, w0, (w1 - w0) / ev.length))


def test_lines_evaluate_as_the_general_formula():
    path = [seg(Line((0.0, 1.0, 2.0), (3.5, -1.0, 2.25)), 100.0), seg(Line((3.5, -1.0, 2.25), (3.5, 4.0, 0.0)), 100.0)]
    arrays = PathArrays(path)
    assert arrays.lines_only and arrays.identity
    iseg = np.array([0, 1, 1, 0])
    local = np.array([0.0, 0.3, 5.1, 1.7])
    p, d1, d2 = arrays.eval012(iseg, local)
    np.testing.assert_array_equal(p, arrays.p0[iseg] + local[:, None] * arrays.d[iseg])
    np.testing.assert_array_equal(d1, arrays.d[iseg])
    np.testing.assert_array_equal(d2, np.zeros((4, 3)))


def test_profiles_assemble_as_concatenating_the_sections():
    rng = np.random.default_rng(3)
    sizes = rng.integers(2, 9, 12)
    sections = {k: (np.cumsum(rng.uniform(0.1, 1.0, m)), rng.uniform(0, 9, m), rng.integers(0, 50, m - 1))
                for k, m in enumerate(sizes.tolist())}
    prof = Profiles()
    odd = [k for k in sections if k % 2]
    flat = [np.concatenate([sections[k][j] for k in odd]) for j in range(3)]
    pts = np.concatenate(([0], np.cumsum([sizes[k] for k in odd])))
    prof.add_block(np.array(odd), *flat, pts, pts - np.arange(len(pts)))
    for k in sections:
        if not k % 2:
            prof.add(k, *sections[k])
    assert sorted(prof) == list(sections) and len(prof) == len(sections)
    for k, parts in sections.items():
        for a, b in zip(prof[k], parts, strict=True):
            np.testing.assert_array_equal(a, b)
    s, x, iseg, starts = prof.assembled(list(sections))
    np.testing.assert_array_equal(s, np.concatenate([sections[0][0]] + [sections[k][0][1:] for k in range(1, 12)]))
    np.testing.assert_array_equal(x, np.concatenate([sections[0][1]] + [sections[k][1][1:] for k in range(1, 12)]))
    np.testing.assert_array_equal(iseg, np.concatenate([sections[k][2] for k in range(12)]))
    n = np.cumsum(sizes - 1)
    np.testing.assert_array_equal(starts, np.concatenate(([0], n)))
    np.testing.assert_array_equal(ranges(np.array([5, 0, 9]), np.array([2, 0, 3])), [5, 6, 9, 10, 11])
