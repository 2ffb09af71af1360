"""The whole-array verification equals the per-segment one exactly: the report of
``verify_plan`` is the reference's (tests/verify/reference_verify.py) float for float, and every
array building block equals the scalar function it replaces, bit for bit."""

from __future__ import annotations

import math
import random
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from reference_verify import reference_line_pair_distances, reference_verify_plan
from test_verify_plan import elements

from trcopt.errors import SourceSpan
from trcopt.geometry import Arc, Line, Plane
from trcopt.geometry.poly import Poly
from trcopt.modes import Side
from trcopt.path import Role, Segment
from trcopt.pipeline import PlanOptions, plan, plan_file
from trcopt.verify import verify_plan
from trcopt.verify.contour import contour_blocks, contour_rows
from trcopt.verify.index import BoxGrid
from trcopt.verify.model import bbox, element_distance, line_pair_distances
from trcopt.verify.pairs import arc_pair_distances
from trcopt.verify.report import FamilyResidual
from trcopt.verify.table import SegmentTable

PROBLEMS = Path(__file__).resolve().parents[2] / "problems"
PROGRAMS = sorted(p for p in PROBLEMS.rglob("*") if p.suffix in (".mpf", ".spf", ".h", ".ngc"))
SPAN = SourceSpan("t.mpf", 1, 1, "N1")


def _same(programmed, toolpath, moves=None, near=0.0):  # type: ignore[no-untyped-def]
    new = verify_plan(programmed, toolpath, moves, near_tangent_rad=near)
    ref = reference_verify_plan(programmed, toolpath, moves, near_tangent_rad=near)
    assert new.to_json() == ref.to_json()
    for name, f in new.families.items():  # the floats themselves, not only their JSON
        assert f.max_residual.hex() == ref.families[name].max_residual.hex(), name
    return new


def _jitter(toolpath, rng: random.Random, scale: float):  # type: ignore[no-untyped-def]
    """Every third segment moved by about ``scale`` mm: residuals of every size and family."""
    out = []
    for s in toolpath:
        g = s.geometry
        if rng.random() < 0.3:
            j = lambda: rng.gauss(0.0, scale)  # noqa: E731
            if isinstance(g, Line):
                g = Line((g.start[0] + j(), g.start[1] + j(), g.start[2]), (g.end[0] + j(), g.end[1] + j(), g.end[2]))
            elif isinstance(g, Arc):
                g = Arc((g.center[0] + j(), g.center[1] + j()), g.radius * (1 + j()), g.a0 + j(), g.sweep * (1 + j()))
            s = s.with_geometry(g)
        out.append(s)
    return out


@pytest.mark.parametrize("program", PROGRAMS, ids=[str(p.relative_to(PROBLEMS)) for p in PROGRAMS])
def test_problems_verify_as_the_reference(program: Path) -> None:
    r = plan_file(program, PlanOptions(timing=False, verify=False))
    rng = random.Random(program.name)
    for near in (0.0, 0.05):
        _same(r.programmed, r.toolpath, r.nc.moves, near)
        _same(r.programmed, _jitter(r.toolpath, rng, 1e-3), r.nc.moves, near)


def _cam_contour(chords: int, compensated: str = "G41.1 D2") -> str:
    pts = [(40 * math.cos(t) + 3 * math.sin(5 * t), 40 * math.sin(t)) for t in np.linspace(0, 2 * math.pi, chords + 1)]
    body = "".join(f"G1 X{x:.5f} Y{y:.5f}\n" for x, y in pts[1:])
    return f"G21 G17 G90 F600\nG0 X60 Y0\n{compensated} G1 X{pts[0][0]:.5f} Y{pts[0][1]:.5f}\n{body}G40 G1 X60 Y0\nM2\n"


@pytest.mark.parametrize("side", ["G41.1 D2", "G42.1 D2"])
def test_cam_contour_verifies_as_the_reference(side: str) -> None:
    # near-tangent continuations everywhere, corners where the chords turn more, the closing joint
    r = plan(_cam_contour(400, side), file="cam.ngc", options=PlanOptions(timing=False, verify=False))
    rep = _same(r.programmed, r.toolpath, r.nc.moves, 0.05)
    assert rep.families["clearance"].checks >= 400
    rng = random.Random(7)
    for scale in (1e-7, 1e-4, 0.02):
        _same(r.programmed, _jitter(r.toolpath, rng, scale), r.nc.moves, 0.05)


roles = st.sampled_from([Role.CONTOUR, Role.CONTOUR, Role.CORNER, Role.APPROACH, Role.RETRACT])


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(elements(30.0), elements(30.0), roles, st.sampled_from([Side.LEFT, Side.RIGHT])),
                min_size=1, max_size=25),
       st.floats(0.5, 6.0), st.sampled_from([0.0, 0.05]), st.booleans())  # fmt: skip
def test_random_paths_verify_as_the_reference(items, radius, near, chained) -> None:  # type: ignore[no-untyped-def]
    programmed, toolpath = [], []
    for k, (prog, tool, role, side) in enumerate(items):
        span = SourceSpan("random.mpf", k // 2 + 1 if chained else k + 1, 1, f"N{k + 1}")
        programmed.append(Segment(prog, Plane.G17, Role.CONTOUR, span, 10.0))
        if chained and toolpath and isinstance(tool, Line):  # joints that meet, some near-tangent
            tool = Line(toolpath[-1].geometry.end, tool.end)
        toolpath.append(Segment(tool, Plane.G17, role, span, 10.0, side, radius))
    _same(programmed, toolpath, None, near)


def _small_paths() -> list[tuple[list[Segment], list[Segment]]]:
    """Empty, one-segment and degenerate paths (zero-length lines, a zero sweep, no programmed
    elements, leads only)."""
    sp, sp2 = SPAN, SourceSpan("t.mpf", 2, 1, "N2")

    def seg(g: Line | Arc, role: Role = Role.CONTOUR, r: float = 1.0, span: SourceSpan = sp) -> Segment:
        return Segment(g, Plane.G17, role, span, 1.0, Side.LEFT, r)

    line, up = Line((0.0, 0.0, 0.0), (1.0, 0.0, 0.0)), Line((0.0, 1.0, 0.0), (1.0, 1.0, 0.0))
    nxt, nxt_up = Line((1.0, 0.0, 0.0), (2.0, 0.0, 0.0)), Line((1.0, 1.0, 0.0), (2.0, 1.0, 0.0))
    return [
        ([], []),
        ([seg(line, r=0.0)], []),
        ([], [seg(line)]),
        ([], [Segment(line, Plane.G17, Role.RAPID, sp, None)]),
        ([seg(line, r=0.0)], [seg(Line((0.0, 1.0, 0.0), (0.0, 1.0, 0.0)))]),
        ([seg(line, r=0.0)], [seg(Arc((0.0, 0.0), 1.0, 0.0, 0.0), Role.CORNER)]),
        ([seg(line, r=0.0)], [seg(Arc((0.0, 0.0), 1.0, 0.0, 1.0), Role.CORNER), seg(up, span=sp2)]),
        ([seg(line, r=0.0), seg(nxt, r=0.0, span=sp2)], [seg(up), seg(nxt_up, span=sp2)]),
        ([], [seg(line, Role.APPROACH), seg(line, Role.CORNER), seg(line, Role.RETRACT)]),
    ]


@pytest.mark.parametrize("case", range(len(_small_paths())))
def test_small_paths_verify_as_the_reference(case: int) -> None:
    programmed, toolpath = _small_paths()[case]
    for near in (0.0, 0.05):
        _same(programmed, toolpath, None, near)


def _sampled_arc(c: tuple[float, float], r: float, a0: float, a1: float, n: int = 9) -> Poly:
    angles = [a0 + (a1 - a0) * i / (n - 1) for i in range(n)]
    pts = tuple((c[0] + r * math.cos(a), c[1] + r * math.sin(a), 0.0) for a in angles)
    cum = [0.0]
    for a, b in zip(pts, pts[1:], strict=False):
        cum.append(cum[-1] + math.dist(a, b))
    return Poly(pts, tuple((-math.sin(a), math.cos(a), 0.0) for a in angles), tuple(cum))


def test_paths_with_curves_verify_as_the_reference() -> None:
    # polynomial curves (measured one by one) among lines and arcs, programmed and tool-centre
    rng = random.Random(2)
    for _ in range(60):
        programmed, toolpath = [], []
        for k in range(rng.randint(1, 8)):
            span = SourceSpan("p.mpf", k + 1, 1, f"N{k + 1}")
            c, r = (rng.uniform(-5, 5), rng.uniform(-5, 5)), rng.uniform(1, 4)
            a0 = rng.uniform(-3, 3)
            a1 = a0 + rng.uniform(-2, 2)
            line = Line((c[0], c[1], 0.0), (c[0] + 2, c[1] + 1, 0.0))
            prog = rng.choice([_sampled_arc(c, r, a0, a1), Arc(c, r, a0, a1 - a0), line])
            tool = rng.choice([_sampled_arc(c, r + 1, a0, a1), Arc(c, r + 1, a0, a1 - a0), line.offset(-1.0)])
            programmed.append(Segment(prog, Plane.G17, Role.CONTOUR, span, 1.0))
            role = rng.choice([Role.CONTOUR, Role.CORNER])
            toolpath.append(Segment(tool, Plane.G17, role, span, 1.0, Side.RIGHT, 1.0))
        for near in (0.0, 0.05):
            _same(programmed, toolpath, None, near)


# ---- the building blocks ------------------------------------------------------------------


def _tangent_or_concentric(rng: random.Random, a: Line | Arc) -> Line | Arc:
    """An element touching ``a``: concentric, tangent at a point, or through its end point."""
    if isinstance(a, Arc):
        c = rng.random()
        if c < 0.3:
            return Arc(a.center, a.radius + rng.choice([0.0, 1.0, 2.0, -0.25]), rng.uniform(-4, 4), rng.uniform(0.2, 6))
        if c < 0.6:
            p, t = a.point2(rng.choice([0.0, 0.5, 1.0])), a.tangent2(0.5)
            return Line((p[0], p[1], 0.0), (p[0] + 3 * t[0], p[1] + 3 * t[1], 0.0))
        return Arc((a.end[0] + 1.0, a.end[1]), 1.0, math.pi, rng.choice([-2.0, 2.0]))
    d = a.direction2()
    r = rng.choice([0.5, 1.0, 2.0])
    centre = (a.end[0] - d[1] * r, a.end[1] + d[0] * r)
    a0 = math.atan2(-d[0], d[1]) if rng.random() < 0.5 else rng.uniform(-4, 4)  # from the line's end, tangent
    return Arc(centre, r, a0, rng.uniform(-4, 4) or 1.0)


def _random_element(rng: random.Random) -> Line | Arc:
    q = lambda x: round(x * 4) / 4 if rng.random() < 0.5 else x  # noqa: E731  (exact coincidences)
    if rng.random() < 0.4:
        a = (q(rng.uniform(-5, 5)), q(rng.uniform(-5, 5)), 0.0)
        return Line(a, (a[0] + q(rng.uniform(-5, 5)) or 1.0, a[1] + q(rng.uniform(-5, 5)), 0.0))
    sweep = rng.choice([rng.uniform(0.001, 6.2), math.pi / 2, math.pi, 2 * math.pi]) * rng.choice([1, -1])
    return Arc((q(rng.uniform(-5, 5)), q(rng.uniform(-5, 5))), q(rng.uniform(0.25, 4)) or 0.5,
               rng.choice([rng.uniform(-4, 4), 0.0, -math.pi]), sweep)  # fmt: skip


def _segments(geoms: list) -> list[Segment]:  # type: ignore[type-arg]
    return [Segment(g, Plane.G17, Role.CONTOUR, SPAN, 1.0) for g in geoms]


def test_arc_pair_distances_equal_element_distance() -> None:
    rng = random.Random(3)
    tool, part = [], []
    while len(tool) < 6000:
        a = _random_element(rng)
        b = _tangent_or_concentric(rng, a) if rng.random() < 0.5 else _random_element(rng)
        a, b = (a, b) if rng.random() < 0.5 else (b, a)
        if (isinstance(a, Arc) or isinstance(b, Arc)) and a.plane_length > 0.0 and b.plane_length > 0.0:
            tool.append(a)
            part.append(b)
    rows = np.arange(len(tool))
    got, ok = arc_pair_distances(SegmentTable(_segments(tool)), SegmentTable(_segments(part)), rows, rows)
    want = np.array([element_distance(a, b)[0] for a, b in zip(tool, part, strict=True)])
    assert ok.all()
    assert got.tobytes() == want.tobytes()
    assert (want == 0.0).sum() > 1000 and (want > 0.0).sum() > 1000  # crossings, touches and gaps


def test_line_pair_distances_equal_the_row_form() -> None:
    rng = np.random.default_rng(11)
    n = 20000
    p0, q0 = rng.uniform(-5, 5, (n, 2)), rng.uniform(-5, 5, (n, 2))
    p1, q1 = p0 + rng.uniform(-3, 3, (n, 2)), q0 + rng.uniform(-3, 3, (n, 2))
    p1[::7], q0[::5], q1[::11] = p0[::7], p1[::5], q0[::11]  # zero-length lines, shared end points
    p0[::13] = np.round(p0[::13])  # exact coincidences and collinear pieces
    q0[::13], q1[::13] = np.round(q0[::13]), np.round(q1[::13])
    got = line_pair_distances(p0, p1, q0, q1)
    assert got.tobytes() == reference_line_pair_distances(p0, p1, q0, q1).tobytes()


def test_table_equals_the_geometry() -> None:
    rng = random.Random(5)
    geoms = [_random_element(rng) for _ in range(3000)] + [Line((1.0, 2.0, 0.0), (1.0, 2.0, 0.0))]
    t = SegmentTable(_segments(geoms))
    rows = np.arange(len(geoms))
    su, sv, eu, ev = t.tangents()
    boxes = t.bboxes(rows)
    for lam in (0.0, 0.5, 1.0):
        u, v = t.point2(rows, lam)
        assert [(a, b) for a, b in zip(u.tolist(), v.tolist(), strict=True)] == [g.point2(lam) for g in geoms]
    for k, g in enumerate(geoms):
        assert (t.sx[k], t.sy[k], t.sz[k]) == g.start and (t.ex[k], t.ey[k], t.ez[k]) == g.end
        assert t.plen[k] == g.plane_length and tuple(boxes[k]) == bbox(g)
        if g.plane_length > 0.0:
            assert (su[k], sv[k]) == g.start_tangent() and (eu[k], ev[k]) == g.end_tangent()


@settings(max_examples=200, deadline=None)
@given(st.lists(st.one_of(st.sampled_from([0.0, 1.0, math.nan]), st.floats(0.0, 2.0)), max_size=12),
       st.floats(0.0, 1.0))  # fmt: skip
def test_add_many_is_add_in_turn(values, start) -> None:  # type: ignore[no-untyped-def]
    segs = _segments([Line((0.0, 0.0, 0.0), (1.0, 0.0, 0.0))] * max(len(values), 1))
    for prefix in ([], [start]):
        one, many = FamilyResidual("radius"), FamilyResidual("radius")
        for v in prefix:
            one.add(v, 0, segs[0])
            many.add(v, 0, segs[0])
        for k, v in enumerate(values):
            one.add(v, k, segs[k])
        many.add_many(np.array(values, float), np.arange(len(values)), segs)
        assert (one.max_residual, one.segment, one.checks) == (many.max_residual, many.segment, many.checks)


coord = st.floats(-50, 50, allow_nan=False)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(coord, coord), max_size=40), st.lists(st.tuples(coord, coord), min_size=1, max_size=10))
def test_nearest_many_equals_nearest_distance(corners, points) -> None:  # type: ignore[no-untyped-def]
    grid = BoxGrid(np.array([[u, v, u, v] for u, v in corners], float).reshape(-1, 4))
    got = grid.nearest_many(np.array(points, float))
    assert got.tolist() == [grid.nearest_distance(p) for p in points]


@pytest.mark.parametrize("program", PROGRAMS[::3], ids=[str(p.relative_to(PROBLEMS)) for p in PROGRAMS[::3]])
def test_contour_rows_equal_contour_blocks(program: Path) -> None:
    r = plan_file(program, PlanOptions(timing=False, verify=False))
    blocks = contour_blocks(r.programmed, r.toolpath)
    rows, comp_rows, part_rows = contour_rows(r.programmed, SegmentTable(r.toolpath), SegmentTable(r.programmed))
    assert rows == blocks
    assert [r.programmed[j] for j in comp_rows] == blocks.compensated
    assert [r.programmed[j] for j in part_rows] == blocks.part


def test_a_tool_element_starting_at_its_arcs_centre() -> None:
    # the programmed arc's tangent is undefined there: the verification takes its start tangent
    span = SourceSpan("random.mpf", 1, 1, "N1")
    programmed = [Segment(Arc((0.0, 0.0), 1.0, 0.0, 1.0), Plane.G17, Role.CONTOUR, span, 10.0)]
    toolpath = [Segment(Line((0.0, 0.0, 0.0), (1.0, 0.0, 0.0)), Plane.G17, Role.CONTOUR, span, 10.0, Side.LEFT, 1.0)]
    _same(programmed, toolpath, None, 0.0)
