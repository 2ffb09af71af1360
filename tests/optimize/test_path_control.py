"""The program's path-control mode: read by every controller, planned by default, measured
independently (trcopt.verify.deviation)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from trcopt import PlanOptions, controllers, plan
from trcopt.cli import main
from trcopt.errors import SourceSpan
from trcopt.geometry import Line, Plane
from trcopt.io.schema import validate_plan
from trcopt.modes import PathMode, ToleranceKind
from trcopt.optimize.corners.fillet import FilletSpec, blend_distances, blend_joints, fillet_path, line_joints
from trcopt.optimize.corners.program import merge_collinear
from trcopt.path import Role, Segment
from trcopt.verify.deviation import measure_transitions


def read(text: str, dialect: str):
    return controllers.read_program(text, file=f"t.{dialect}", dialect=dialect)


def zigzag_ngc(mode: str, rows: int = 12) -> str:
    lines = ["G21 G17 G90 G40 " + mode, "G0 X0 Y0 Z1", "G1 Z0 F3000"]
    for i in range(rows):
        lines.append(f"G1 X{20 if i % 2 == 0 else 0} Y{i * 2}")
        lines.append(f"G1 Y{i * 2 + 2}")
    return "\n".join([*lines, "M2"]) + "\n"


# ------------------------------------------------------------------------------------------ reading
def test_linuxcnc_modes() -> None:
    text = "G21 G64 P0.02 Q0\nG1 X1 F100\nG61.1\nG1 X2\nG61\nG1 X3\nG64\nG1 X4\nG20 G64 P0.001\nG1 X5\nM2\n"
    nc = read(text, "rs274")
    got = [(m.control.mode, m.control.tolerance_mm, m.control.merge_mm) for m in nc.moves if m.kind.value == "line"]
    assert got == [
        (PathMode.BLEND, 0.02, None),
        (PathMode.EXACT_STOP, None, None),
        (PathMode.EXACT_PATH, None, None),
        (PathMode.BLEND, None, None),  # no P: the largest blend the moves allow (a quarter of each)
        (PathMode.BLEND, pytest.approx(0.0254), pytest.approx(0.0254)),  # inch; Q defaults to P
    ]
    assert all(m.control.kind is ToleranceKind.VERTEX for m in nc.moves if m.control.blends)
    assert nc.moves[0].control.length_share == 0.25


def test_linuxcnc_mode_change_with_compensation_on_is_an_error() -> None:
    nc = read("G21 G1 F100 X0 Y0\nG41.1 D2 X10\nG64 P0.01 X20\nM2\n", "rs274")
    (err,) = nc.diagnostics
    assert err.code == "LCNC-CONTROL-MODE" and err.span.line == 3 and err.span.column == 1
    assert err.message == "Cannot change control mode with cutter radius compensation on"


def test_sinumerik_modes() -> None:
    text = (
        "N10 G1 X1 F100\nN20 CYCLE832(0.02,_FINISH,1)\nN30 X2\nN40 X3 G9\nN50 G60 X4\nN60 G641 ADIS=0.5 X5\n"
        "N70 G642 CTOL=0.03 X6\nN80 G64 X7\nN90 CYCLE832()\nN100 X8\nN110 G645 X9\nM30\n"
    )
    nc = read(text, "siemens")
    lines = [m for m in nc.moves if m.kind.value == "line"]
    got = [(m.control.mode, m.control.tolerance_mm, m.control.kind) for m in lines]
    assert got == [
        (PathMode.EXACT_PATH, None, ToleranceKind.CONTOUR),
        (PathMode.BLEND, 0.02, ToleranceKind.CONTOUR),
        (PathMode.EXACT_STOP, None, ToleranceKind.CONTOUR),  # G9: this block only
        (PathMode.EXACT_STOP, None, ToleranceKind.CONTOUR),
        (PathMode.BLEND, 0.5, ToleranceKind.DISTANCE),
        (PathMode.BLEND, 0.03, ToleranceKind.CONTOUR),
        (PathMode.EXACT_PATH, None, ToleranceKind.CONTOUR),  # G64: no rounding
        (PathMode.EXACT_STOP, None, ToleranceKind.CONTOUR),  # CYCLE832(): deselected
        (PathMode.BLEND, 0.05, ToleranceKind.CONTOUR),  # the deselection reset CTOL: the machine's default
    ]
    assert not [d for d in nc.diagnostics if d.severity.value != "info"]
    bad = read("N10 CYCLE832(abc)\nM30\n", "siemens").diagnostics[0]
    assert bad.code == "NC-SYNTAX" and bad.span.column == 5


def test_heidenhain_cycle_32_and_m90() -> None:
    text = (
        "0 BEGIN PGM T MM\n1 TOOL DEF 1 L+0 R+3\n2 TOOL CALL 1 Z S3000\n3 L X+0 Y+0 Z+1 R0 FMAX\n"
        "4 CYCL DEF 32.0 TOLERANCE\n5 CYCL DEF 32.1 T0.02\n6 L Z+0 F3000\n7 L X+50 M90\n"
        "8 CYCL DEF 32.0 TOLERANCE\n9 CYCL DEF 32.1\n10 L Y+5\n11 END PGM T MM\n"
    )
    nc = read(text, "heidenhain")
    got = [(m.span.line, m.control.mode, m.control.tolerance_mm) for m in nc.moves]
    assert got == [
        (4, PathMode.EXACT_PATH, None),
        (7, PathMode.BLEND, 0.02),
        (8, PathMode.BLEND, 0.02),
        (11, PathMode.EXACT_PATH, None),
    ]
    (warn,) = nc.diagnostics
    assert warn.code == "NC-PATH-CONTROL" and warn.span.line == 8 and "M90" in warn.message
    err = read("0 BEGIN PGM T MM\n1 CYCL DEF 1.0 PECKING\n2 END PGM T MM\n", "heidenhain").diagnostics[0]
    assert err.severity.value == "error" and err.span.line == 2 and "not modelled" in err.message


# ------------------------------------------------------------------------------ blends, measured
def _polyline(points: list[tuple[float, float, float]]) -> list[Segment]:
    span = SourceSpan("t", 1, 1)
    return [
        Segment(Line(a, b), Plane.G17, Role.CONTOUR, SourceSpan("t", i + 1, 1), 50.0)
        for i, (a, b) in enumerate(zip(points, points[1:], strict=False))
    ] or [Segment(Line((0, 0, 0), (1, 0, 0)), Plane.G17, Role.CONTOUR, span, 50.0)]


points_3d = st.lists(
    st.tuples(*(st.floats(-20, 20, allow_nan=False) for _ in range(2)), st.floats(-2, 2, allow_nan=False)),
    min_size=3,
    max_size=12,
)


@settings(max_examples=60, deadline=None)
@given(points_3d, st.floats(0.001, 2.0), st.sampled_from(list(ToleranceKind)), st.booleans(), st.booleans())
def test_blends_stay_within_their_tolerance_measured_independently(points, tol, kind, flat, g2) -> None:
    if flat:
        points = [(x, y, 0.0) for x, y, _ in points]
    kept = [points[0]]
    for p in points[1:]:
        if math.dist(p, kept[-1]) > 1e-3:
            kept.append(p)
    segs = _polyline(kept)
    joints = line_joints(segs)
    # g2: the curvature-continuous B-spline transitions (zero curvature where they meet the lines)
    result = fillet_path(segs, {k: FilletSpec(tol, kind) for k in joints}, g2=g2)
    measured = {m.joint: m for m in measure_transitions(segs, result.segments, result.origin)}
    blended = [c for c in result.corners if c.blended]
    for s_ in result.segments:
        if g2 and s_.role is Role.CORNER:
            curv = s_.geometry.curvatures
            assert max(map(abs, curv[0] + curv[-1])) < 1e-9
    assert set(measured) == {c.index for c in blended}
    for c in blended:
        m = measured[c.index]
        assert m.contour_mm == pytest.approx(c.contour_mm, rel=1e-4, abs=1e-7)
        assert m.vertex_mm == pytest.approx(c.vertex_mm, rel=1e-4, abs=1e-7)
        bound = {ToleranceKind.CONTOUR: m.contour_mm, ToleranceKind.VERTEX: m.vertex_mm}.get(kind)
        if bound is not None:
            assert bound <= tol * (1 + 1e-4) + 1e-9
        else:  # the rounding distance: the tangent length
            assert c.span_mm / 2 <= tol * (1 + 1e-9)
    # the new path is continuous and tangent wherever a blend was put
    new = result.segments
    for s1, s2 in zip(new, new[1:], strict=False):
        assert math.dist(s1.geometry.end, s2.geometry.start) < 1e-9
        assert s1.geometry.length > 0
    assert sum(1 for s in new if s.role is Role.CORNER) == len(blended)


def test_blend_distances_closed_form() -> None:
    v, c = blend_distances(1.0, math.pi / 2)
    assert v == pytest.approx(math.sqrt(2) - 1) and c == pytest.approx(1 - math.sqrt(0.5))
    # LinuxCNC's rule: the vertex tolerance is at most a quarter of the shorter move
    segs = _polyline([(0, 0, 0), (1, 0, 0), (1, 10, 0)])
    (rec,) = fillet_path(segs, {0: FilletSpec(None, ToleranceKind.VERTEX, length_share=0.25)}).corners
    assert rec.vertex_mm == pytest.approx(0.25)


def test_naive_cam_merging() -> None:
    text = "G21 G64 P0.01 Q0.005\nG1 F600 X1 Y0.004\nX2 Y0\nX3 Y0.004\nX4 Y0.02\nX5 Y0\nM2\n"
    nc = read(text, "rs274")
    r = plan(text, file="t.ngc", options=PlanOptions(timing=False, corners="exact"))
    merged = merge_collinear(r.toolpath, nc.moves)
    # the first three moves lie within Q of one line; the fourth leaves it
    assert [round(s.geometry.end[0], 9) for s in merged] == [3.0, 4.0, 5.0]
    assert merged[0].span.line == 4


# ----------------------------------------------------------------------------------- the pipeline
def test_the_program_mode_is_the_default_and_exact_forces_stops() -> None:
    text = zigzag_ngc("G64 P0.05 Q0")
    blended = plan(text, file="z.ngc")
    exact = plan(text, file="z.ngc", options=PlanOptions(corners="exact"))
    assert blended.ok and exact.ok
    corners = blended.extra["corners"]
    assert corners["mode"] == "program" and corners["path_control"] == ["G64 P0.05 Q0"]
    assert corners["blended"] == corners["arc"] == 24 and corners["tolerance_kind"] == "vertex"
    assert corners["max_vertex_mm"] <= 0.05 + 1e-12 and "corners" not in exact.extra
    assert blended.timing.duration < exact.timing.duration - 0.1
    validate_plan(json.loads(json.dumps(blended.to_json())))  # the corners report keeps the contract
    # the same program without a mode keeps the exact path
    plain = plan(zigzag_ngc(""), file="z.ngc")
    assert "corners" not in plain.extra and plain.timing.duration == pytest.approx(exact.timing.duration)


def test_a_blending_mode_without_tolerance_reports_none() -> None:
    # LinuxCNC G64 without P blends as far as the moves allow: no tolerance to report or to claim
    r = plan(zigzag_ngc("G64"), file="z.ngc", options=PlanOptions(timing=False))
    corners = r.extra["corners"]
    assert r.ok and corners["blended"] == 24 and corners["tolerance_mm"] is None
    assert corners["max_vertex_mm"] > 0.05
    validate_plan(json.loads(json.dumps(r.to_json())))
    assert "corners program without a tolerance (G64):" in r.summary()
    assert "within" not in r.summary().split("corners program")[1].split("\n")[0]


def test_exact_stop_modes_stop_where_the_path_is_tangent() -> None:
    body = "G1 X10 Y0 F3000\nG3 X20 Y10 I0 J10\nG1 Y30\nM2\n"
    path = plan("G21 G17 G0 X0 Y0\n" + body, file="t.ngc")
    stop = plan("G21 G17 G61.1 G0 X0 Y0\n" + body, file="t.ngc")
    assert stop.timing.duration > path.timing.duration + 0.01
    assert [s.stop for s in stop.toolpath] == [True] * len(stop.toolpath)


def test_sinumerik_cycle832_program_blends_within_ctol() -> None:
    rows = "\n".join(f"N{100 + 10 * i} G1 X{20 if i % 2 == 0 else 0} Y{i * 2}\nG1 Y{i * 2 + 2}" for i in range(8))
    text = f"N10 G0 X0 Y0 Z1\nN20 CYCLE832(0.01,_FINISH,1)\nN30 G1 Z0 F3000\n{rows}\nM30\n"
    r = plan(text, file="t.mpf")
    corners = r.extra["corners"]
    assert r.ok and corners["tolerance_kind"] == "contour" and corners["max_contour_mm"] <= 0.01 + 1e-12
    assert corners["blended"] == 16


def test_cli_tolerance_kind_and_json(tmp_path) -> None:
    prog = tmp_path / "g40.ngc"
    prog.write_text(zigzag_ngc(""))
    out = tmp_path / "p.json"
    assert main(["plan", str(prog), "--corners", "arc", "--tolerance", "0.02", "--tolerance-kind", "vertex",
                 "--json", str(out), "-q"]) == 0  # fmt: skip
    corners = json.loads(out.read_text())["corners"]
    assert corners["tolerance_kind"] == "vertex" and corners["blended"] == 24
    assert max(c["vertex_mm"] for c in corners["corners"] if c["blended"]) == pytest.approx(0.02 * (1 - 2e-3))
    with pytest.raises(SystemExit) as exc:
        main(["plan", str(prog), "--tolerance-kind", "distance"])
    assert exc.value.code == 2
    assert np.isfinite(corners["max_contour_mm"])
    # a tolerance larger than half the shortest line it could blend (the 2 mm steps) is a usage error
    assert main(["plan", str(prog), "--corners", "arc", "--tolerance", "1.5", "--json", str(tmp_path / "x.json")]) == 2
    assert not (tmp_path / "x.json").exists()


@settings(max_examples=40, deadline=None)
@given(
    st.lists(st.tuples(st.floats(2.0, 15.0), st.floats(-2.5, 2.5), st.booleans()), min_size=2, max_size=8),
    st.floats(0.002, 0.5),
    st.sampled_from([ToleranceKind.CONTOUR, ToleranceKind.VERTEX]),
)
def test_line_arc_corners_of_a_g40_path_are_blended_within_tolerance(moves, tol, kind) -> None:
    """Random G40 paths of lines and arcs (G2/G3 with R): every line–arc and arc–arc corner the
    blends round stays within the tolerance, measured by sampling against the exact elements."""
    lines, x, y, heading = ["G21 G17 G90 G40", "G0 X0 Y0", "G1 F3000 X5 Y0"], 5.0, 0.0, 0.0
    for length, turn, arc in moves:
        heading += turn
        nx, ny = x + length * math.cos(heading), y + length * math.sin(heading)
        lines.append(f"G{2 + int(turn > 0)} X{nx:.4f} Y{ny:.4f} R{length:.4f}" if arc else f"G1 X{nx:.4f} Y{ny:.4f}")
        x, y = nx, ny
    text = "\n".join([*lines, "M2"]) + "\n"
    exact = plan(text, file="r.ngc", options=PlanOptions(corners="exact", timing=False, verify=False))
    assume(exact.ok)
    joints = blend_joints(exact.toolpath)
    result = fillet_path(exact.toolpath, {k: FilletSpec(tol, kind) for k in joints})
    measured = {m.joint: m for m in measure_transitions(exact.toolpath, result.segments, result.origin)}
    for c in result.corners:
        if not c.blended:
            continue
        m = measured[c.index]
        got = m.vertex_mm if kind is ToleranceKind.VERTEX else m.contour_mm
        assert got <= tol * (1 + 1e-3) + 1e-9
    new = result.segments
    for s1, s2 in zip(new, new[1:], strict=False):
        assert math.dist(s1.geometry.end, s2.geometry.start) < 1e-7
        if s1.role is Role.CORNER or s2.role is Role.CORNER:  # the blends join tangentially
            t1, t2 = s1.geometry.derivatives(s1.geometry.length)[1], s2.geometry.derivatives(0.0)[1]
            assert sum(u * v for u, v in zip(t1, t2, strict=True)) > 1 - 1e-9
