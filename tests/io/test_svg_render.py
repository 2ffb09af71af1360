"""SVG preview: valid XML, one path per segment, exact arcs, view box, tool circles, markers."""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET

from trcopt.errors import Diagnostic, Severity, SourceSpan
from trcopt.geometry import Arc, Line, Plane, hermite_curve
from trcopt.io.svg import MAX_TOOL_CIRCLES, render_svg
from trcopt.path import Role, Segment

NS = {"s": "http://www.w3.org/2000/svg"}


def seg(geom, role=Role.CONTOUR, line=1, feed=10.0, radius=5.0, plane=Plane.G17, block=None):
    return Segment(geom, plane, role, SourceSpan("sq.mpf", line, 1, block), feed, radius=radius)


def square():
    programmed = [
        seg(Line((0, 0, 0), (0, 40, 0)), line=3, radius=0.0),
        seg(Line((0, 40, 0), (40, 40, 0)), line=4, radius=0.0),
    ]
    toolpath = [
        seg(Line((-5, -10, 0), (-5, 0, 0)), Role.APPROACH, line=2),
        seg(Line((-5, 0, 0), (-5, 40, 0)), line=3, block="N30"),
        seg(Arc((0, 40), 5.0, math.pi, -math.pi / 2), Role.CORNER, line=4),
        seg(Line((0, 45, 0), (40, 45, 0)), line=4),
        seg(Line((40, 45, 0), (60, 60, 0)), Role.RAPID, line=5, feed=None, radius=0.0),
    ]
    return programmed, toolpath


def parse(text: str) -> ET.Element:
    return ET.fromstring(text.encode("utf-8"))


def test_svg_is_valid_xml_with_one_path_per_segment():
    programmed, toolpath = square()
    text = render_svg(programmed, toolpath, title="square <1> & co")
    root = parse(text)
    paths = [
        p for p in root.iter("{http://www.w3.org/2000/svg}path") if "seg" in p.get("class", "")
    ]
    assert len(paths) == len(programmed) + len(toolpath)
    roles = [p.get("data-role") for p in paths]
    assert roles == ["contour", "contour", "approach", "contour", "corner", "contour", "rapid"]
    assert "square &lt;1&gt; &amp; co" in text


def test_arc_is_an_exact_clockwise_svg_arc_in_y_up_drawing():
    programmed, toolpath = square()
    root = parse(render_svg(programmed, toolpath))
    corner = next(
        p for p in root.iter("{http://www.w3.org/2000/svg}path") if p.get("data-role") == "corner"
    )
    # G2 (-5, 40) -> (0, 45): y flipped -> SVG (-5,-40) to (0,-45), clockwise on screen = flag 1
    assert corner.get("d") == "M -5 -40 A 5 5 0 0 1 0 -45"
    rapid = next(
        p for p in root.iter("{http://www.w3.org/2000/svg}path") if p.get("data-role") == "rapid"
    )
    assert rapid.get("stroke-dasharray")
    assert rapid.get("stroke") == "#8c8c8c"


def test_arcs_of_180_degrees_and_more_are_split():
    full = seg(Arc((0, 0), 10.0, 0.0, 2 * math.pi))
    half = seg(Arc((0, 0), 10.0, 0.0, -math.pi))
    root = parse(render_svg([], [full, half]))
    ds = [
        p.get("d")
        for p in root.iter("{http://www.w3.org/2000/svg}path")
        if "seg" in p.get("class", "")
    ]
    assert ds[0].count("A ") == 3 and ds[1].count("A ") == 2
    assert all(" 0 0 1 " in d or " 0 0 0 " in d for d in ds)  # never a large-arc flag


def test_view_box_contains_paths_and_tool_circles():
    programmed, toolpath = square()
    root = parse(render_svg(programmed, toolpath))
    inner = root.find("s:svg", NS)
    x, y, w, h = (float(t) for t in inner.get("viewBox").split())
    # tool circles reach u = -10 (radius 5 at x = -5) and v = 50; the rapid ends at (60, 60)
    assert x < -10.0 and x + w > 60.0
    assert y < -60.0 and y + h > 10.0 + 5.0 - 0.01  # -v of the lowest tool circle (v = -15)
    circles = inner.findall("s:g[@class='tool']/s:circle", NS)
    assert len(circles) == 5  # start + 4 ends with radius > 0 (the rapid has radius 0)
    assert {c.get("r") for c in circles} == {"5"}


def test_tool_circles_are_thinned_to_the_limit():
    segs = [seg(Line((i, 0, 0), (i + 1, 0, 0)), radius=0.5) for i in range(1000)]
    root = parse(render_svg([], segs))
    assert len(root.findall(".//s:g[@class='tool']/s:circle", NS)) == MAX_TOOL_CIRCLES
    root = parse(render_svg([], segs, show_tool=False))
    assert root.findall(".//s:g[@class='tool']", NS) == []


def test_markers_for_located_diagnostics_and_explicit_points():
    programmed, toolpath = square()
    diags = [
        Diagnostic(
            Severity.WARNING, "10763", "path shortened", SourceSpan("sq.mpf", 4, 1, "N40"), 10763
        ),
        Diagnostic(
            Severity.ERROR, "10751", "collision", SourceSpan("sq.mpf", 99, 1, "N990"), 10751
        ),
        Diagnostic(Severity.INFO, "LCNC-TOOL-TABLE", "note", SourceSpan("sq.mpf", 3, 1)),
    ]
    text = render_svg(programmed, toolpath, diags, markers=[(20.0, 20.0, "mine")])
    root = parse(text)
    marks = root.findall(".//s:g[@class='markers']/s:circle", NS)
    centres = sorted((float(m.get("cx")), float(m.get("cy"))) for m in marks)
    # the warning sits at the start of the first toolpath segment of line 4 (the corner arc)
    assert centres == [(-5.0, -40.0), (20.0, -20.0)]
    assert "warning 10763 (N40)" in text
    assert "not located" in text and "10751" in text


def test_other_plane_segments_are_projected_and_polys_are_polylines():
    poly = hermite_curve((0, 0, 0), (5, 0, 0), (5, 5, 0), (0, 5, 0))
    g18 = Arc((0, 0), 5.0, 0.0, math.pi / 2)  # in G18 (Z, X)
    root = parse(render_svg([], [seg(poly), seg(g18, plane=Plane.G18)]))
    ds = [
        p.get("d")
        for p in root.iter("{http://www.w3.org/2000/svg}path")
        if "seg" in p.get("class", "")
    ]
    assert len(ds) == 2
    assert ds[0].count(" ") >= 2 * len(poly.points) and "A" not in ds[0]
    assert "A" not in ds[1]
    assert re.match(r"M -?[\d.]+ -?[\d.]+ L ", ds[1])


def test_empty_plan_still_renders():
    parse(render_svg([], []))
