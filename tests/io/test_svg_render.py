"""SVG preview: valid XML, one path per segment, exact arcs, view box, tool circles, markers."""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET

import pytest

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
        Diagnostic(Severity.WARNING, "10751", "collision", SourceSpan("sq.mpf", 3, 1, "N30"), 10751),
        Diagnostic(Severity.WARNING, "10763", "path shortened", SourceSpan("sq.mpf", 4, 1, "N40"), 10763),
        Diagnostic(Severity.ERROR, "10751", "collision", SourceSpan("sq.mpf", 99, 1, "N990"), 10751),
        Diagnostic(Severity.WARNING, "TRC-CONTOUR-VIOLATION", "elsewhere", SourceSpan("sq.mpf", 77, 1)),
        Diagnostic(Severity.INFO, "LCNC-TOOL-TABLE", "note", SourceSpan("sq.mpf", 3, 1)),
    ]
    text = render_svg(programmed, toolpath, diags, markers=[(20.0, 20.0, "mine")])
    root = parse(text)
    marks = root.findall(".//s:g[@class='markers']/s:circle", NS)
    centres = [(float(m.get("cx")), float(m.get("cy"))) for m in marks]
    assert centres == [
        (20.0, -20.0),  # the explicit marker
        (-5.0, -0.0),  # a warning: the start of the first tool-path segment of its line (N30)
        (20.0, -40.0),  # the omitted block N40 (10763): the middle of its programmed block
        (60.0, -60.0),  # an error no segment carries: where the path ends (the program stopped)
    ]
    omitted = root.findall(".//s:g[@class='omitted']/s:path", NS)
    assert [p.get("data-line") for p in omitted] == ["4"] and omitted[0].get("stroke-dasharray")
    labels = [t.text for t in root.findall(".//s:g[@class='labels']/s:text", NS)]
    assert labels == ["start", "mine", "1. warning 10751 (N30)", "2. omitted: warning 10763 (N40)",
                      "3. stopped: error 10751 (N990)"]
    notes = [t.text for t in root.findall(".//s:g[@class='legend']/s:text", NS)]
    assert "2. sq.mpf:4:1: warning 10763 (N40): path shortened — omitted block" in notes
    assert "3. sq.mpf:99:1: error 10751 (N990): collision — stopped here" in notes
    assert "4. not located: sq.mpf:77:1: warning TRC-CONTOUR-VIOLATION: elsewhere" in notes
    assert "note" not in " ".join(notes)  # an info is not marked


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


def _inner_to_px(root: ET.Element):
    """The map from drawing coordinates (u, v) to picture px of the inner view box (xMidYMid meet)."""
    inner = root.find("s:svg", NS)
    x, y, w, h = (float(inner.get(k)) for k in ("x", "y", "width", "height"))
    bx, by, bw, bh = (float(t) for t in inner.get("viewBox").split())
    s = min(w / bw, h / bh)
    ox, oy = x + (w - bw * s) / 2, y + (h - bh * s) / 2
    return lambda u, v: (ox + (u - bx) * s, oy + (-v - by) * s), s


def test_axes_are_in_mm_at_the_right_places_with_a_scale_bar():
    programmed, toolpath = square()
    root = parse(render_svg(programmed, toolpath))
    to_px, px_per_mm = _inner_to_px(root)
    axes = root.find("s:g[@class='axes']", NS)
    names = [t.text for t in axes.findall("s:text[@class='axis-name']", NS)]
    assert names == ["X [mm]", "Y [mm]"]
    # every x tick label sits under its value: "0" under u = 0, "20" under u = 20
    ticks = {t.text: float(t.get("x")) for t in axes.findall("s:text[@text-anchor='middle']", NS)}
    assert ticks["0"] == pytest.approx(to_px(0.0, 0.0)[0], abs=0.01)
    assert ticks["20"] == pytest.approx(to_px(20.0, 0.0)[0], abs=0.01)
    ys = {t.text: float(t.get("y")) - 3.5 for t in axes.findall("s:text[@text-anchor='end']", NS)}
    assert ys["40"] == pytest.approx(to_px(0.0, 40.0)[1], abs=0.01)
    bar = axes.find("s:path[@class='scale-bar']", NS).get("d").split()
    label = axes.find("s:text[@class='scale-bar']", NS).text
    assert label.endswith(" mm") and float(bar[6]) == pytest.approx(float(label.split()[0]) * px_per_mm, abs=0.01)
    # the plane names the axes: G18 draws Z across and X up
    g18 = [seg(Line((0, 0, 0), (10, 5, 0)), plane=Plane.G18)]
    names = [t.text for t in parse(render_svg([], g18)).findall(".//s:text[@class='axis-name']", NS)]
    assert names == ["Z [mm]", "X [mm]"]


def test_direction_arrows_point_along_the_travel_and_the_start_is_marked():
    programmed, toolpath = square()
    root = parse(render_svg(programmed, toolpath))
    arrows = root.findall(".//s:g[@class='arrows']/s:polygon", NS)
    assert len(arrows) == len(toolpath)
    # the second segment runs up (+v) along u = -5: its arrow tip is the highest point (smallest SVG y)
    tri = [tuple(float(c) for c in p.split(",")) for p in arrows[1].get("points").split()]
    assert tri[0][1] == min(y for _, y in tri) and all(x == pytest.approx(-5.0, abs=2.0) for x, _ in tri)
    assert sum(y for _, y in tri) / 3 == pytest.approx(-20.0, abs=0.5)  # at the middle of (-5, 0) → (-5, 40)
    start = root.find(".//s:g[@class='start']/s:polygon", NS)
    assert [float(c) for c in start.get("points").split()[1].split(",")][1] == pytest.approx(10.0)  # at (-5, -10)


def test_labels_are_never_clipped_at_the_right_edge():
    # a mark at the right border of the drawing: its label goes to the left, inside the picture
    toolpath = [seg(Line((0, 0, 0), (100, 0, 0)), line=1), seg(Line((100, 0, 0), (100, 1, 0)), line=2)]
    diag = Diagnostic(Severity.ERROR, "10751", "collision danger", SourceSpan("sq.mpf", 2, 1, "N20"), 10751)
    root = parse(render_svg([], toolpath, [diag], width_px=400))
    (label,) = [t for t in root.findall(".//s:g[@class='labels']/s:text", NS) if "10751" in t.text]
    assert label.text == "1. error 10751 (N20)"  # the full label, not clipped to "error"
    assert label.get("text-anchor") == "end" and 6.2 * len(label.text) <= float(label.get("x")) <= 400
    assert root.find("s:svg", NS).find("s:g[@class='markers']", NS) is not None
    assert not root.find("s:svg", NS).findall(".//s:text", NS)  # no text inside the clipping view box


def test_overlays_are_drawn_and_named_in_the_legend():
    programmed, toolpath = square()
    sar = [seg(Line((-20, -20, 0), (-5, -10, 0)), Role.APPROACH)]
    root = parse(render_svg(programmed, toolpath, overlays=[("G147 (SAR default)", "#1f77b4", sar)]))
    (group,) = root.findall(".//s:g[@class='overlay']", NS)
    assert group.get("data-label") == "G147 (SAR default)" and group.find("s:path", NS).get("stroke") == "#1f77b4"
    assert "G147 (SAR default)" in [t.text for t in root.findall(".//s:g[@class='legend']/s:text", NS)]
