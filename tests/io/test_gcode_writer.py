"""Tool-centre G-code writer: exact blocks for hand-built paths; the after-rounding arc check."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from trcopt import controllers
from trcopt.errors import SourceSpan, TrcoptError
from trcopt.geometry import Arc, Line, Plane, hermite_curve, spiral_curve
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
        # a path with transitions: no stop where the written digits leave a kink
        "N20 CTOL=0.001",
        "N30 G642",
        "N40 G0 X-5 Y-10 Z5 ; start of path, N10 L1 rapid",
        "N50 G0 Z-2 ; N10 L1 rapid",
        "N60 G1 Y0 F300 ; N20 L2 approach",
        "N70 G1 Y40 F600 ; N30 L3 contour",
        "N80 G2 X0 Y45 I5 J0 ; N40 L4 corner",
        "N90 G1 X40 ; N40 L4 contour",
        "N100 G0 Z5 ; N50 L5 rapid",
        "N110 M30",
    ]
    assert check_gcode_arcs(text) == []


def test_square_with_corner_arc_rs274_exact_blocks():
    text = toolpath_to_gcode(square_corner(), flavor=LINUXCNC, program_name="sq (v2).ngc")
    lines = text.splitlines()
    assert lines[0] == "(trcopt tool-centre path of sq [v2].ngc)"
    assert body(text) == [
        "G21 G90 G94 G91.1 G40 G17",
        "G64 P0.001 Q0",
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


def test_poly_becomes_g1_chords_through_its_samples_on_request():
    poly = hermite_curve((0.0, 0.0, 0.0), (10.0, 0.0, 0.0), (10.0, 10.0, 0.0), (0.0, 10.0, 0.0))
    text = toolpath_to_gcode([seg(poly, Role.CORNER, "N10", 1)], decimals=3, poly_output="chords")
    g1 = [ln for ln in body(text) if " G1 " in ln]
    assert len(g1) == len(poly.points) - 1
    assert "CTOL" not in text and "G642" not in text and " G2 " not in text and " G3 " not in text
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
    # the path starts where a program starts (the origin): no invented rapid before its first move
    assert [ln.split(";")[0].strip() for ln in lines[1:5]] == [
        "N20 G1 X1 F600",
        "N30 G1 X2",
        "N40 G0 X3",
        "N50 G1 X4 F450.5",
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


# --------------------------------------------------------------------------------------------
# smooth curves as arcs
# --------------------------------------------------------------------------------------------

HEIDENHAIN = controllers.get("heidenhain").gcode


def corner_transition(w: float = -2.0):
    """Tool-centre path: a line, a quintic G2 corner transition (a Poly), a line."""
    poly = hermite_curve((8.0, 0.0, w), (3.0, 0.0, 0.0), (10.0, 2.0, w), (0.0, 3.0, 0.0), (0.0, 0.0, 0.0),
                         (0.0, 0.0, 0.0), "corner")
    return poly, [
        seg(Line((0.0, 0.0, w), (8.0, 0.0, w)), block="N10", line=1),
        seg(poly, Role.CORNER, "N20", 2),
        seg(Line((10.0, 2.0, w), (10.0, 20.0, w)), block="N20", line=2),
    ]


def written_path(text: str, plane=Plane.G17) -> np.ndarray:
    """The path the program describes, as dense points (x, y, z): G1 lines and G2/G3 arcs (centre
    words incremental, in ``plane``), read from the text alone."""
    ui, vi, _ = plane.axes
    pos: list[float] | None = None
    motion, out = None, []
    for ln in body(text):
        code = re.sub(r"\([^)]*\)", "", ln).split(";")[0]
        words = dict(re.findall(r"([XYZIJK])(-?[\d.]+)", code))
        for g in re.findall(r"\bG(\d+)\b", code):
            if g in ("0", "1", "2", "3"):
                motion = g
        end = [float(words.get(a, pos[k] if pos else 0.0)) for k, a in enumerate("XYZ")]
        if pos is None or not any(a in words for a in "XYZ"):
            pos = end if any(a in words for a in "XYZ") else pos
            continue
        if motion in ("2", "3"):
            cu = pos[ui] + float(words.get("IJK"[ui], 0.0))
            cv = pos[vi] + float(words.get("IJK"[vi], 0.0))
            a0 = math.atan2(pos[vi] - cv, pos[ui] - cu)
            a1 = math.atan2(end[vi] - cv, end[ui] - cu)
            sweep = (a1 - a0) % (2 * math.pi) if motion == "3" else -((a0 - a1) % (2 * math.pi))
            r = math.hypot(pos[ui] - cu, pos[vi] - cv)
            lam = np.linspace(0.0, 1.0, max(2, math.ceil(abs(sweep) * r / 0.0005) + 1))
            pts = np.empty((len(lam), 3))
            pts[:, ui] = cu + r * np.cos(a0 + lam * sweep)
            pts[:, vi] = cv + r * np.sin(a0 + lam * sweep)
            w_axis = 3 - ui - vi
            pts[:, w_axis] = pos[w_axis] + lam * (end[w_axis] - pos[w_axis])
        else:
            lam = np.linspace(0.0, 1.0, max(2, math.ceil(math.dist(pos, end) / 0.0005) + 1))
            pts = np.array(pos) + lam[:, None] * (np.array(end) - np.array(pos))
        out.append(pts)
        pos = end
    return np.vstack(out)


def to_polyline(x: np.ndarray, c: np.ndarray) -> float:
    """Largest distance of the points x to the polyline c (through the nearest vertex and the
    two segments at it)."""
    from scipy.spatial import cKDTree

    keep = np.concatenate(([True], np.any(np.diff(c, axis=0) != 0.0, axis=1)))
    c = c[keep]  # no doubled vertex (it would hide a segment)
    _, i = cKDTree(c).query(x)
    best = np.full(len(x), np.inf)
    for k in (np.clip(i - 1, 0, len(c) - 2), np.clip(i, 0, len(c) - 2)):
        ab = c[k + 1] - c[k]
        lam = np.clip(np.sum((x - c[k]) * ab, axis=1) / np.maximum(np.sum(ab * ab, axis=1), 1e-300), 0.0, 1.0)
        best = np.minimum(best, np.linalg.norm(x - c[k] - lam[:, None] * ab, axis=1))
    return float(best.max())


def two_sided(a: np.ndarray, b: np.ndarray) -> float:
    """Largest distance of a point of one dense polyline to the other (both ways)."""
    return max(to_polyline(a, b), to_polyline(b, a))


def test_poly_is_written_as_tangent_arcs_with_the_siemens_path_control():
    poly, segs = corner_transition()
    text = toolpath_to_gcode(segs, program_name="c.mpf")
    lines = body(text)
    # the path-control words right after the preamble block
    assert lines[:3] == ["N10 G71 G90 G94 G40 G17", "N20 CTOL=0.001", "N30 G642"]
    arcs = [ln for ln in lines if " G2 " in ln or " G3 " in ln]
    assert 2 <= len(arcs) <= len(poly.points) // 4
    assert all(" G3 " in ln for ln in arcs)  # a left turn without inflection
    # the source note on the first piece only
    notes = [ln for ln in lines if ln.endswith("; N20 L2 corner")]
    assert len(notes) == 1 and notes[0] == arcs[0]
    assert check_gcode_arcs(text) == []
    assert _final_position(text) == [10.0, 20.0, -2.0]
    # the written arcs are within the fit tolerance (+ the output rounding) of the curve
    curve = np.array([poly.point(s) for s in np.linspace(0.0, poly.length, 4000)])
    written = written_path(text)
    near_corner = written[(written[:, 0] > 8.0 - 1e-9) & (written[:, 1] < 2.0 + 1e-9)]
    assert two_sided(curve, near_corner) <= 0.001 + 1e-4


def test_poly_arcs_linuxcnc_and_a_coarser_tolerance():
    poly, segs = corner_transition()
    fine = toolpath_to_gcode(segs, flavor=LINUXCNC)
    coarse = toolpath_to_gcode(segs, flavor=LINUXCNC, fit_tolerance_mm=0.02)
    assert body(fine)[:2] == ["G21 G90 G94 G91.1 G40 G17", "G64 P0.001 Q0"]
    assert body(coarse)[:2] == ["G21 G90 G94 G91.1 G40 G17", "G64 P0.02 Q0"]
    count = [sum(1 for ln in body(t) if ln.startswith(("G2 ", "G3 "))) for t in (fine, coarse)]
    assert 0 < count[1] < count[0]
    assert check_gcode_arcs(fine) == [] and check_gcode_arcs(coarse) == []
    curve = np.array([poly.point(s) for s in np.linspace(0.0, poly.length, 4000)])
    written = written_path(coarse)
    near_corner = written[(written[:, 0] > 8.0 - 1e-9) & (written[:, 1] < 2.0 + 1e-9)]
    assert 0.005 < two_sided(curve, near_corner) <= 0.02 + 1e-4


def test_path_control_only_with_transitions():
    # no transition (curve or corner arc): no path-control words
    for flavor in (SIEMENS, LINUXCNC):
        plain = [s for s in square_corner() if not isinstance(s.geometry, Arc)]
        text = toolpath_to_gcode(plain, flavor=flavor)
        assert "G64" not in text and "CTOL" not in text and "G642" not in text
    _, segs = corner_transition()
    text = toolpath_to_gcode(segs, flavor=LINUXCNC, poly_output="chords")
    assert "G64" not in text and " G2 " not in text and " G3 " not in text
    # a flavour without continuous-path words writes none, but the arcs
    text = toolpath_to_gcode(segs, flavor=HEIDENHAIN)
    assert body(text)[1].startswith("N20 G0 ") and " G3 " in text and check_gcode_arcs(text) == []


def test_helical_poly_in_g18():
    # a descending spiral in G18 (u = Z, v = X, w = Y): helical arcs with K/I words and Y moves
    spiral = spiral_curve((0.0, 0.0), 5.0, 8.0, 0.3, 4.0, 0.0, -3.0)
    text = toolpath_to_gcode([seg(spiral, plane=Plane.G18, block="N10", line=1)], flavor=LINUXCNC)
    arcs = [ln for ln in body(text) if ln.startswith(("G2 ", "G3 "))]
    assert arcs and all(" I" in ln and " K" in ln and " J" not in ln for ln in arcs)
    assert all(" Y" in ln for ln in arcs) and check_gcode_arcs(text) == []
    end = Plane.G18.to_xyz(spiral.end)
    assert max(abs(p - e) for p, e in zip(_final_position(text), end, strict=True)) <= 0.5e-4 + 1e-12
    curve = np.array([Plane.G18.to_xyz(spiral.point(s)) for s in np.linspace(0.0, spiral.length, 20000)])
    assert two_sided(curve, written_path(text, Plane.G18)) <= 0.001 + 1e-4


def test_invalid_poly_options():
    for bad in (0.0, -0.001, math.nan, math.inf, "fine", None, True):
        with pytest.raises(GcodeError, match="fit_tolerance_mm"):
            toolpath_to_gcode([], fit_tolerance_mm=bad)
    with pytest.raises(GcodeError, match="poly_output"):
        toolpath_to_gcode([], poly_output="splines")


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    st.tuples(st.floats(-50.0, 50.0), st.floats(-50.0, 50.0)),
    st.tuples(st.floats(-30.0, 30.0), st.floats(-30.0, 30.0)),
    st.tuples(st.floats(-30.0, 30.0), st.floats(-30.0, 30.0)),
    st.sampled_from(list(Plane)),
    st.sampled_from((2, 3, 4)),
    st.sampled_from((0.0005, 0.001, 0.01)),
)
def test_property_written_curve_arcs_are_consistent(p1, d0, d1, plane, decimals, tol):
    if math.hypot(*d0) < 1e-3 or math.hypot(*d1) < 1e-3:
        return
    poly = hermite_curve((1.0, 2.0, 0.5), (*d0, 0.0), (1.0 + p1[0], 2.0 + p1[1], 0.5), (*d1, 0.0))
    text = toolpath_to_gcode([seg(poly, plane=plane)], decimals=decimals, fit_tolerance_mm=tol)
    assert check_gcode_arcs(text, tolerance_mm=0.002) == []
    end = plane.to_xyz(poly.end)
    pos = _final_position(text)
    assert max(abs(p - e) for p, e in zip(pos, end, strict=True)) <= 0.5 * 10.0**-decimals + 1e-9
