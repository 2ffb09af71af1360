"""Tool-centre G-code writer: exact blocks for hand-built paths; the after-rounding arc check."""

from __future__ import annotations

import math

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from trcopt import controllers
from trcopt.errors import SourceSpan, TrcoptError
from trcopt.geometry import Arc, Line, Plane, hermite_curve
from trcopt.io.gcode import GcodeError, check_gcode_arcs
from trcopt.io.gcode import toolpath_to_gcode as _to_gcode
from trcopt.path import Role, Segment

SIEMENS, LINUXCNC = controllers.get("siemens").gcode, controllers.get("linuxcnc").gcode


def toolpath_to_gcode(segments, flavor=SIEMENS, **kw):
    """The writer with the SINUMERIK flavour unless another is given."""
    return _to_gcode(segments, flavor=flavor, **kw)


def span(block: str | None, line: int) -> SourceSpan:
    return SourceSpan("sq.mpf", line, 1, block)


def seg(
    geom, role=Role.CONTOUR, block="N20", line=2, feed_mm_min=600.0, plane=Plane.G17, radius=5.0
):
    feed = None if feed_mm_min is None else feed_mm_min / 60.0
    return Segment(geom, plane, role, span(block, line), feed, radius=radius)


def square_corner() -> list[Segment]:
    """Tool-centre path of the left edge of a square with a G2 corner arc, radius 5 tool."""
    return [
        seg(Line((-5.0, -10.0, 5.0), (-5.0, -10.0, -2.0)), Role.RAPID, "N10", 1, None, radius=0.0),
        seg(Line((-5.0, -10.0, -2.0), (-5.0, 0.0, -2.0)), Role.APPROACH, "N20", 2, 300.0),
        seg(Line((-5.0, 0.0, -2.0), (-5.0, 40.0, -2.0)), Role.CONTOUR, "N30", 3, 600.0),
        seg(Arc((0.0, 40.0), 5.0, math.pi, -math.pi / 2, -2.0, -2.0), Role.CORNER, "N40", 4, 600.0),
        seg(Line((0.0, 45.0, -2.0), (40.0, 45.0, -2.0)), Role.CONTOUR, "N40", 4, 600.0),
        seg(Line((40.0, 45.0, -2.0), (40.0, 45.0, 5.0)), Role.RAPID, "N50", 5, None, radius=0.0),
    ]


def body(text: str) -> list[str]:
    return [ln for ln in text.splitlines() if not ln.startswith((";", "("))]


def test_square_with_corner_arc_siemens_exact_blocks():
    text = toolpath_to_gcode(square_corner(), program_name="sq.mpf")
    assert text.splitlines()[0] == "; trcopt tool-centre path of sq.mpf"
    assert body(text) == [
        "N10 G71 G90 G94 G40 G17",
        "N20 G0 X-5 Y-10 Z5 ; start of path, N10 L1 rapid",
        "N30 G0 Z-2 ; N10 L1 rapid",
        "N40 G1 Y0 F300 ; N20 L2 approach",
        "N50 G1 Y40 F600 ; N30 L3 contour",
        "N60 G2 X0 Y45 I5 J0 ; N40 L4 corner",
        "N70 G1 X40 ; N40 L4 contour",
        "N80 G0 Z5 ; N50 L5 rapid",
        "N90 M30",
    ]
    assert check_gcode_arcs(text) == []


def test_square_with_corner_arc_rs274_exact_blocks():
    text = toolpath_to_gcode(square_corner(), flavor=LINUXCNC, program_name="sq (v2).ngc")
    lines = text.splitlines()
    assert lines[0] == "(trcopt tool-centre path of sq [v2].ngc)"
    assert body(text) == [
        "G21 G90 G94 G91.1 G40 G17",
        "G0 X-5.0 Y-10.0 Z5.0 (start of path, N10 L1 rapid)",
        "G0 Z-2.0 (N10 L1 rapid)",
        "G1 Y0.0 F300.0 (N20 L2 approach)",
        "G1 Y40.0 F600.0 (N30 L3 contour)",
        "G2 X0.0 Y45.0 I5.0 J0.0 (N40 L4 corner)",
        "G1 X40.0 (N40 L4 contour)",
        "G0 Z5.0 (N50 L5 rapid)",
        "M2",
    ]
    assert ";" not in text
    assert "G41" not in text and "G42" not in text


def test_g18_arc_and_helix_with_centre_words_of_the_plane():
    # G18: u = Z, v = X, w = Y. Quarter arc from X10 Z0 to X0 Z10 clockwise about the origin,
    # then a CCW helix in G17 climbing 2 mm over a half turn.
    g18 = Arc.from_points((0.0, 10.0, 0.0), (10.0, 0.0, 0.0), (0.0, 0.0), ccw=False)
    helix = Arc((0.0, 0.0), 10.0, math.pi / 2, math.pi, 10.0, 12.0)  # (0,10,10) -> (0,-10,12)
    segs = [
        seg(Line((20.0, 0.0, 0.0), (10.0, 0.0, 0.0)), block="N10", line=1),
        seg(g18, plane=Plane.G18, block="N20", line=2, feed_mm_min=1200.0),
        seg(Line((0.0, 0.0, 10.0), (0.0, 10.0, 10.0)), block="N30", line=3, feed_mm_min=1200.0),
        seg(helix, block="N40", line=4, feed_mm_min=1200.0),
    ]
    text = toolpath_to_gcode(segs)
    assert body(text)[0] == "N10 G71 G90 G94 G40 G18"
    assert body(text)[1:] == [
        "N20 G0 X20 Y0 Z0 ; start of path, N10 L1 contour",
        "N30 G1 X10 F600 ; N10 L1 contour",
        "N40 G2 X0 Z10 I-10 K0 F1200 ; N20 L2 contour",
        "N50 G1 Y10 ; N30 L3 contour",
        "N60 G17 G3 X0 Y-10 Z12 I0 J-10 ; N40 L4 contour",
        "N70 M30",
    ]
    assert check_gcode_arcs(text) == []


def test_g19_arc_centre_words_j_k():
    # G19: u = Y, v = Z. CCW quarter from Y5 Z0 to Y0 Z5 about (Y0, Z0).
    arc = Arc((0.0, 0.0), 5.0, 0.0, math.pi / 2, 3.0, 3.0)
    text = toolpath_to_gcode([seg(arc, plane=Plane.G19, block=None, line=7)], flavor=LINUXCNC)
    assert "G3 Y0.0 Z5.0 J-5.0 K0.0 F600.0 (L7 contour)" in text
    assert "G21 G90 G94 G91.1 G40 G19" in text


def test_full_circle_is_split_into_two_halves():
    circle = Arc((0.0, 0.0), 10.0, 0.0, -2 * math.pi, 0.0, -4.0)  # full CW helix turn
    text = toolpath_to_gcode([seg(circle, block="N10", line=1)])
    assert body(text)[1:] == [
        "N20 G0 X10 Y0 Z0 ; start of path, N10 L1 contour",
        "N30 G2 X-10 Y0 Z-2 I-10 J0 F600 ; N10 L1 contour",
        "N40 G2 X10 Y0 Z-4 I10 J0",
        "N50 M30",
    ]
    assert check_gcode_arcs(text) == []


def test_arc_over_180_degrees_stays_one_block():
    arc = Arc((0.0, 0.0), 10.0, 0.0, math.radians(270.0))
    text = toolpath_to_gcode([seg(arc, block="N10", line=1)])
    assert "N30 G3 X0 Y-10 I-10 J0 F600 ; N10 L1 contour" in text


def test_poly_becomes_g1_chords_through_its_samples():
    poly = hermite_curve((0.0, 0.0, 0.0), (10.0, 0.0, 0.0), (10.0, 10.0, 0.0), (0.0, 10.0, 0.0))
    text = toolpath_to_gcode([seg(poly, Role.CORNER, "N10", 1)], decimals=3)
    g1 = [ln for ln in body(text) if " G1 " in ln]
    assert len(g1) == len(poly.points) - 1
    assert g1[0].endswith("; N10 L1 corner")
    assert g1[-1].split()[-3:] == ["Y10", ";", "N10"] or g1[-1].split()[2].startswith(("X", "Y"))
    assert _final_position(text) == [10.0, 10.0, 0.0]


def test_feed_written_only_when_it_changes_and_never_on_g0():
    segs = [
        seg(Line((0.0, 0.0, 0.0), (1.0, 0.0, 0.0))),
        seg(Line((1.0, 0.0, 0.0), (2.0, 0.0, 0.0))),
        seg(Line((2.0, 0.0, 0.0), (3.0, 0.0, 0.0)), Role.RAPID, feed_mm_min=None),
        seg(Line((3.0, 0.0, 0.0), (4.0, 0.0, 0.0)), feed_mm_min=450.5),
    ]
    lines = body(toolpath_to_gcode(segs))
    assert [ln.split(";")[0].strip() for ln in lines[2:6]] == [
        "N30 G1 X1 F600",
        "N40 G1 X2",
        "N50 G0 X3",
        "N60 G1 X4 F450.5",
    ]


def test_rounding_moves_the_centre_onto_the_bisector():
    # with 2 decimals the naive rounded centre offset gives radii differing by ~0.006 mm
    arc = Arc((0.123456, 0.987654), 3.3333333, 0.3, 1.1)
    text = toolpath_to_gcode([seg(arc, block="N10", line=1)], decimals=2)
    assert check_gcode_arcs(text, tolerance_mm=0.002) == []
    assert " G3 " in text


def test_tiny_arc_is_not_written_as_full_circle():
    arc = Arc((5.0, 5.0), 0.0004, 0.0, math.radians(5.0))  # 0.035 µm long: rounds to a point
    text = toolpath_to_gcode([seg(Line((0, 0, 0), arc.start)), seg(arc)])
    assert " G2 " not in text and " G3 " not in text
    assert check_gcode_arcs(text) == []
    # a short but well-defined arc (0.2 µm chord) is still an arc, with consistent numbers
    arc = Arc((5.0, 5.0), 0.0004, 0.0, math.radians(30.0))
    text = toolpath_to_gcode([seg(Line((0, 0, 0), arc.start)), seg(arc)])
    assert check_gcode_arcs(text) == []


def test_invalid_options_name_the_valid_ones():
    with pytest.raises(GcodeError, match="GcodeFlavor"):
        toolpath_to_gcode([], flavor="fanuc")
    with pytest.raises(TrcoptError):
        toolpath_to_gcode([], decimals=9)


def test_check_gcode_arcs_finds_a_bad_arc():
    text = "N10 G17 G90\nN20 G1 X0 Y0 F100\nN30 G2 X10 Y0.5 I5 J0 ; bad\n(ok) G3 X0 Y0.5 I-5 J0\n"
    problems = check_gcode_arcs(text)
    assert len(problems) == 1 and problems[0].startswith("line 3: G2")


@st.composite
def awkward_arcs(draw):
    cu = draw(st.floats(-1000.0, 1000.0, allow_nan=False))
    cv = draw(st.floats(-1000.0, 1000.0, allow_nan=False))
    radius = 10.0 ** draw(st.floats(-2.0, 3.0))
    a0 = draw(st.floats(-math.pi, math.pi))
    sweep = math.radians(draw(st.floats(0.01, 359.0))) * draw(st.sampled_from((-1.0, 1.0)))
    dw = draw(st.sampled_from((0.0, 0.0, -1.2345678)))
    plane = draw(st.sampled_from(list(Plane)))
    decimals = draw(st.sampled_from((2, 3, 4)))
    flavor = draw(st.sampled_from((SIEMENS, LINUXCNC)))
    return Arc((cu, cv), radius, a0, sweep, 0.5, 0.5 + dw), plane, decimals, flavor


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(awkward_arcs())
def test_property_every_written_arc_is_consistent_after_rounding(case):
    arc, plane, decimals, flavor = case
    lead = Line((0.0, 0.0, 0.5), arc.start)
    segs = [seg(lead, plane=plane), seg(arc, plane=plane)]
    text = toolpath_to_gcode(segs, decimals=decimals, flavor=flavor)
    assert check_gcode_arcs(text, tolerance_mm=0.002) == []
    # the program still ends where the arc ends, within the output resolution
    last = [ln for ln in body(text) if " G" in ln][-1]
    assert last  # something was written
    pos = _final_position(text)
    end = plane.to_xyz(arc.end)
    assert max(abs(p - e) for p, e in zip(pos, end, strict=True)) <= 0.5 * 10.0**-decimals + 1e-9


def _final_position(text: str) -> list[float]:
    import re

    pos = [0.0, 0.0, 0.0]
    for ln in body(text):
        code = re.sub(r"\([^)]*\)", "", ln).split(";")[0]
        for axis, val in re.findall(r"([XYZ])(-?[\d.]+)", code):
            pos["XYZ".index(axis)] = float(val)
    return pos


def test_program_name_cannot_break_the_comment():
    text = toolpath_to_gcode([], program_name="a\nG0 X0")
    assert text.splitlines()[0] == "; trcopt tool-centre path of a G0 X0"
    assert body(text) == ["N10 G71 G90 G94 G40 G17", "N20 M30"]
