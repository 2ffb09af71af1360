"""Self-contained SVG preview of a plan: programmed contour, tool-centre path, tool, alarms and
omitted blocks, direction arrows, the start, axes in mm and a scale bar.

Drawn in the plane of the first segment (u, v; the applicate is ignored), +v up. Lines are
``L`` commands, arcs exact ``A`` commands (split so no piece reaches 180°), polys polylines; each
segment is one ``<path>`` carrying ``data-role``/``data-line``/``data-block`` attributes.
Segments in another plane are projected onto the drawing plane (arcs then as sampled polylines).
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Iterable, Sequence
from xml.sax.saxutils import escape as _xml_escape
from xml.sax.saxutils import quoteattr as _xml_quoteattr

from trcopt.errors import Diagnostic
from trcopt.geometry.plane import Plane
from trcopt.geometry.primitives import Arc, Line
from trcopt.geometry.vec import Vec2
from trcopt.io.marks import locate_diagnostics
from trcopt.io.scale import nice_step, tick_label
from trcopt.path import Role, Segment

# characters XML 1.0 does not allow (C0 controls other than tab, LF, CR; lone surrogates; U+FFFE/F):
# a program's comment or a diagnostic quoting a binary byte must not make the picture unreadable
_NOT_XML = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ud800-\udfff\ufffe\uffff]")


def escape(text: str) -> str:
    """``text`` as XML character data: markup escaped, characters XML forbids as U+FFFD."""
    return _xml_escape(_NOT_XML.sub("\ufffd", text))


def quoteattr(text: str) -> str:
    """``text`` as a quoted XML attribute value (characters XML forbids as U+FFFD)."""
    return _xml_quoteattr(_NOT_XML.sub("\ufffd", text))


__all__ = ["render_svg", "ROLE_COLOURS", "MAX_TOOL_CIRCLES", "MAX_ARROWS"]


MAX_TOOL_CIRCLES = 400
PROGRAMMED_COLOUR = "#000000"
ROLE_COLOURS = {
    Role.CONTOUR: "#1f5fd6",
    Role.CORNER: "#f28c00",
    Role.APPROACH: "#1a9e3a",
    Role.RETRACT: "#1a9e3a",
    Role.RAPID: "#8c8c8c",
    Role.POSITIONING: "#8c8c8c",
}
MARKER_COLOUR = "#d62020"
TOOL_COLOUR = "#1f5fd6"

_TITLE_PX = 28.0
_LEGEND_LINE_PX = 16.0
_PAD_PX = 8.0


def _n(x: float) -> str:
    """Compact number for SVG attributes (6 significant decimals, no -0)."""
    text = f"{x:.6f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


class _Projector:
    """Maps a segment's plane coordinates to drawing (u, v) and SVG (x, y = −v)."""

    def __init__(self, plane: Plane) -> None:
        self.plane = plane

    def uv(self, seg_plane: Plane, p: Sequence[float]) -> Vec2:
        if seg_plane is self.plane:
            return (p[0], p[1])
        q = self.plane.to_uvw(seg_plane.to_xyz((p[0], p[1], p[2] if len(p) > 2 else 0.0)))
        return (q[0], q[1])


def _arc_samples(arc: Arc, n: int = 0) -> list[tuple[float, float, float]]:
    n = n or max(8, int(abs(arc.sweep) / (math.pi / 64)) + 1)
    out = []
    for k in range(n + 1):
        lam = k / n
        p = arc.point2(lam)
        out.append((p[0], p[1], arc.w0 + lam * (arc.w1 - arc.w0)))
    return out


def _arc_extreme_points(arc: Arc) -> list[Vec2]:
    """Start, end and the axis extremes of the circle that lie within the sweep."""
    pts = [arc.point2(0.0), arc.point2(1.0)]
    lo, hi = sorted((arc.a0, arc.a0 + arc.sweep))
    for k in range(math.floor(lo / (math.pi / 2)), math.ceil(hi / (math.pi / 2)) + 1):
        a = k * math.pi / 2
        if lo <= a <= hi:
            pts.append(
                (arc.center[0] + arc.radius * math.cos(a), arc.center[1] + arc.radius * math.sin(a))
            )
    return pts


def _segment_points(proj: _Projector, seg: Segment) -> list[Vec2]:
    """Points that bound the drawn segment (for the view box)."""
    g = seg.geometry
    if isinstance(g, Line):
        return [proj.uv(seg.plane, g.start), proj.uv(seg.plane, g.end)]
    if isinstance(g, Arc):
        if seg.plane is proj.plane:
            return _arc_extreme_points(g)
        return [proj.uv(seg.plane, p) for p in _arc_samples(g)]
    return [proj.uv(seg.plane, p) for p in g.points]


def _path_d(proj: _Projector, seg: Segment) -> str:
    g = seg.geometry

    def xy(p: Vec2) -> str:
        return f"{_n(p[0])} {_n(-p[1])}"

    if isinstance(g, Line):
        return f"M {xy(proj.uv(seg.plane, g.start))} L {xy(proj.uv(seg.plane, g.end))}"
    if isinstance(g, Arc) and seg.plane is proj.plane:
        pieces = max(1, math.ceil(abs(g.sweep) / (math.pi - 1e-6)))
        parts = [f"M {xy(g.point2(0.0))}"]
        # y is flipped, so a counter-clockwise arc is drawn with SVG sweep-flag 0
        flag = 0 if g.sweep > 0 else 1
        r = _n(g.radius)
        for k in range(1, pieces + 1):
            parts.append(f"A {r} {r} 0 0 {flag} {xy(g.point2(k / pieces))}")
        return " ".join(parts)
    pts = _arc_samples(g) if isinstance(g, Arc) else list(g.points)
    uv = [proj.uv(seg.plane, p) for p in pts]
    return "M " + xy(uv[0]) + " L " + " ".join(xy(p) for p in uv[1:])


def _tool_junctions(proj: _Projector, toolpath: Sequence[Segment]) -> list[tuple[Vec2, float]]:
    out: list[tuple[Vec2, float]] = []
    for i, seg in enumerate(toolpath):
        if i == 0 and seg.radius > 0:
            out.append((proj.uv(seg.plane, seg.geometry.start), seg.radius))
        if seg.radius > 0:
            out.append((proj.uv(seg.plane, seg.geometry.end), seg.radius))
    if len(out) > MAX_TOOL_CIRCLES:
        step = (len(out) - 1) / (MAX_TOOL_CIRCLES - 1)
        out = [out[round(k * step)] for k in range(MAX_TOOL_CIRCLES)]
    return out


def _fit(text: str, width_px: float, char_px: float = 6.6) -> str:
    """``text`` cut with an ellipsis so that it fits ``width_px`` (an estimate for a 12 px sans font)."""
    most = max(8, int(width_px / char_px))
    return text if len(text) <= most else text[: most - 1] + "…"


def _arrow_points(proj: _Projector, seg: Segment, size: float) -> list[Vec2] | None:
    """Arrowhead (tip, two back corners) at the middle of a segment, pointing along the travel."""
    g = seg.geometry
    length = g.length
    if length <= 0.0:
        return None
    a = proj.uv(seg.plane, g.point(0.45 * length))
    b = proj.uv(seg.plane, g.point(0.55 * length))
    d = math.hypot(b[0] - a[0], b[1] - a[1])
    if d <= 1e-12:
        return None
    ux, uy = (b[0] - a[0]) / d, (b[1] - a[1]) / d
    m = proj.uv(seg.plane, g.point(0.5 * length))
    tip = (m[0] + 0.5 * size * ux, m[1] + 0.5 * size * uy)
    back = (m[0] - 0.5 * size * ux, m[1] - 0.5 * size * uy)
    h = 0.5 * size
    return [tip, (back[0] - h * uy, back[1] + h * ux), (back[0] + h * uy, back[1] - h * ux)]


MAX_ARROWS = 200
START_COLOUR = "#12a150"
_AXIS_LEFT_PX, _AXIS_BOTTOM_PX, _RIGHT_PX = 52.0, 34.0, 14.0


def render_svg(
    programmed: Sequence[Segment],
    toolpath: Sequence[Segment],
    diagnostics: Iterable[Diagnostic] = (),
    *,
    title: str | None = None,
    show_tool: bool = True,
    width_px: int = 900,
    markers: Iterable[tuple[float, float, str]] = (),
    overlays: Iterable[tuple[str, str, Sequence[Segment]]] = (),
) -> str:
    """Render a plan as a standalone SVG document.

    Parameters
    ----------
    programmed:
        Programmed contour (black, thin; rapids dotted).
    toolpath:
        Tool-centre path: contour blue, corner elements orange, approach/retract green, rapids and
        positioning grey dashed; an arrowhead in the middle of each segment (at most 200, evenly
        chosen) shows the direction of travel, a green triangle its start.
    diagnostics:
        Error/warning diagnostics are marked (red, numbered) where
        :func:`trcopt.io.marks.locate_diagnostics` places them: an omitted block (alarm 10763) on its
        programmed block, drawn red dashed; an error no segment carries at the end of the tool
        path (the program stopped there). Every one is listed under the legend with its message;
        the ones that cannot be located say so.
    title:
        Heading (default ``"trcopt plan"``).
    show_tool:
        Draw the tool (faint circle of ``segment.radius``, mm) at every junction of the
        tool-centre path where the radius is > 0 (at most 400, evenly chosen).
    width_px:
        Width of the picture, px; the height follows the aspect ratio of the drawing.
    markers:
        Extra red markers ``(u, v, label)`` in drawing-plane coordinates (x, y for G17), mm.
    overlays:
        Further paths ``(label, colour, segments)`` drawn solid in that colour and named in the
        legend (e.g. the SAR leads beside an optimal lead-in).

    Returns
    -------
    str
        The SVG document (UTF-8 XML). The drawing has axes in mm (the plane's abscissa and
        ordinate, +v up) and a scale bar.
    """
    programmed = list(programmed)
    toolpath = list(toolpath)
    overlays = [(str(label), colour, list(segs)) for label, colour, segs in overlays]
    everything = toolpath or programmed or [s for _, _, segs in overlays for s in segs]
    proj = _Projector(everything[0].plane if everything else Plane.G17)

    tools = _tool_junctions(proj, toolpath) if show_tool else []
    # (u, v), label, the number in the list below the legend (0: an explicit marker)
    marks: list[tuple[Vec2, str, int]] = [((float(u), float(v)), str(label), 0) for u, v, label in markers]
    listed: list[str] = []
    omitted: list[Segment] = []
    for mark in locate_diagnostics(programmed, toolpath, diagnostics):
        d = mark.diagnostic
        label = f"{d.severity.value} {d.alarm if d.alarm is not None else d.code}"
        if d.span.block:
            label += f" ({d.span.block})"
        if mark.point is None:
            listed.append(f"not located: {d.format()}")
            continue
        tail = {"omitted": " — omitted block", "stop": " — stopped here"}.get(mark.kind, "")
        listed.append(d.format() + tail)
        if mark.kind == "omitted":
            omitted.append(programmed[mark.index or 0])
            label = "omitted: " + label
        elif mark.kind == "stop":
            label = "stopped: " + label
        q = proj.plane.to_uvw(mark.point)
        marks.append(((q[0], q[1]), f"{len(listed)}. {label}", len(listed)))

    # bounding box in drawing coordinates
    pts: list[Vec2] = []
    for seg in [*programmed, *toolpath, *(s for _, _, segs in overlays for s in segs)]:
        pts += _segment_points(proj, seg)
    for (u, v), r in tools:
        pts += [(u - r, v - r), (u + r, v + r)]
    pts += [p for p, _, _ in marks]
    if not pts:
        pts = [(0.0, 0.0)]
    umin, umax = min(p[0] for p in pts), max(p[0] for p in pts)
    vmin, vmax = min(p[1] for p in pts), max(p[1] for p in pts)
    size = max(umax - umin, vmax - vmin, 1e-3)
    margin = 0.04 * size
    vb_x, vb_y = umin - margin, -(vmax + margin)
    vb_w, vb_h = (umax - umin) + 2 * margin, (vmax - vmin) + 2 * margin
    vb_w, vb_h = max(vb_w, 1e-3), max(vb_h, 1e-3)

    width = float(width_px)
    draw_w = width - _AXIS_LEFT_PX - _RIGHT_PX
    draw_h = min(draw_w * vb_h / vb_w, 4.0 * width)
    px_per_mm = min(draw_w / vb_w, draw_h / vb_h)
    mm_per_px = 1.0 / px_per_mm
    # where a drawing point lands in the picture (the inner view box is centred: xMidYMid meet)
    off_x = _AXIS_LEFT_PX + (draw_w - vb_w * px_per_mm) / 2
    off_y = _TITLE_PX + (draw_h - vb_h * px_per_mm) / 2

    def to_px(u: float, v: float) -> tuple[float, float]:
        return off_x + (u - vb_x) * px_per_mm, off_y + (-v - vb_y) * px_per_mm

    legend = [
        ("programmed contour", PROGRAMMED_COLOUR, None),
        ("tool-centre path", ROLE_COLOURS[Role.CONTOUR], None),
        ("corner element", ROLE_COLOURS[Role.CORNER], None),
        ("approach / retract", ROLE_COLOURS[Role.APPROACH], None),
        ("rapid / positioning", ROLE_COLOURS[Role.RAPID], "4 3"),
    ]
    legend += [(label, colour, None) for label, colour, _ in overlays]
    legend.append(("direction of travel, start", START_COLOUR, "arrow"))
    if tools:
        legend.append(("tool", TOOL_COLOUR, "circle"))
    if omitted:
        legend.append(("omitted block (not traversed)", MARKER_COLOUR, "omitted"))
    if listed:
        legend.append(("alarm / warning (numbered below)", MARKER_COLOUR, "marker"))
    elif marks:
        legend.append(("marked point", MARKER_COLOUR, "marker"))
    notes = ["units: mm (axes and scale bar)"]
    notes += [_fit(f"{k}. {t}", width - 2 * _PAD_PX, 6.2) for k, t in enumerate(listed, 1)]
    legend_h = _PAD_PX + _LEGEND_LINE_PX * (len(legend) + len(notes)) + _PAD_PX
    total_h = _TITLE_PX + draw_h + _AXIS_BOTTOM_PX + legend_h

    out: list[str] = []
    a = out.append
    a('<?xml version="1.0" encoding="UTF-8"?>')
    a(
        f'<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{_n(width)}" '
        f'height="{_n(total_h)}" viewBox="0 0 {_n(width)} {_n(total_h)}" '
        'font-family="sans-serif" font-size="12">'
    )
    heading = title if title is not None else "trcopt plan"
    a(f"<title>{escape(heading)}</title>")
    a(f'<rect x="0" y="0" width="{_n(width)}" height="{_n(total_h)}" fill="#ffffff"/>')
    a(
        f'<text x="{_n(_PAD_PX)}" y="19" font-size="15" font-weight="bold">'
        f"{escape(_fit(heading, width - 2 * _PAD_PX, 8.5))}</text>"
    )
    out += _axes(proj, (vb_x, vb_y, vb_w, vb_h), px_per_mm, to_px, draw_h)

    # the drawing, in mm, y flipped by construction (SVG y = -v)
    a(
        f'<svg x="{_n(_AXIS_LEFT_PX)}" y="{_n(_TITLE_PX)}" width="{_n(draw_w)}" height="{_n(draw_h)}" '
        f'viewBox="{_n(vb_x)} {_n(vb_y)} {_n(vb_w)} {_n(vb_h)}" '
        'preserveAspectRatio="xMidYMid meet">'
    )
    if tools:
        a(f'<g class="tool" fill="none" stroke="{TOOL_COLOUR}" stroke-opacity="0.25">')
        for (u, v), r in tools:
            a(f'<circle cx="{_n(u)}" cy="{_n(-v)}" r="{_n(r)}" stroke-width="{_n(mm_per_px)}"/>')
        a("</g>")

    def seg_path(seg: Segment, colour: str, width_px_: float, dash: str | None, cls: str) -> str:
        dashes = f' stroke-dasharray="{" ".join(_n(float(k) * mm_per_px) for k in dash.split())}"' if dash else ""
        block = f" data-block={quoteattr(seg.span.block)}" if seg.span.block else ""
        return (
            f'<path class="{cls}" d="{_path_d(proj, seg)}" fill="none" stroke="{colour}" '
            f'stroke-width="{_n(width_px_ * mm_per_px)}"{dashes} '
            f'data-role="{seg.role.value}" data-line="{seg.span.line}"{block}/>'
        )

    a('<g class="programmed">')
    for seg in programmed:
        a(seg_path(seg, PROGRAMMED_COLOUR, 0.8, "1.5 2.5" if seg.is_rapid else None, "seg programmed"))
    a("</g>")
    if omitted:
        a('<g class="omitted" stroke-opacity="0.55">')
        for seg in omitted:
            a(seg_path(seg, MARKER_COLOUR, 4.0, "6 4", "omitted"))
        a("</g>")
    for label, colour, segs in overlays:
        a(f"<g class=\"overlay\" data-label={quoteattr(label)}>")
        for seg in segs:
            a(seg_path(seg, colour, 1.2, None, "overlay"))
        a("</g>")
    a('<g class="toolpath">')
    for seg in toolpath:
        dashed = seg.is_rapid or seg.role in (Role.RAPID, Role.POSITIONING)
        colour = ROLE_COLOURS[Role.RAPID] if dashed else ROLE_COLOURS[seg.role]
        a(seg_path(seg, colour, 1.6, "4 3" if dashed else None, "seg toolpath"))
    a("</g>")
    arrows = [p for p in (_arrow_points(proj, s, 9 * mm_per_px) for s in toolpath if s.length > 24 * mm_per_px) if p]
    if len(arrows) > MAX_ARROWS:
        arrows = [arrows[round(k * (len(arrows) - 1) / (MAX_ARROWS - 1))] for k in range(MAX_ARROWS)]
    if arrows:
        a('<g class="arrows" fill="#333333" stroke="none">')
        for tri in arrows:
            a('<polygon points="' + " ".join(f"{_n(u)},{_n(-v)}" for u, v in tri) + '"/>')
        a("</g>")
    start = everything[0] if everything else None
    if start is not None:
        su, sv = proj.uv(start.plane, start.geometry.start)
        r = 6 * mm_per_px
        a(
            f'<g class="start"><polygon fill="{START_COLOUR}" stroke="#ffffff" stroke-width="{_n(mm_per_px)}" '
            f'points="{_n(su - r)},{_n(-sv - r)} {_n(su + 1.3 * r)},{_n(-sv)} {_n(su - r)},{_n(-sv + r)}"/></g>'
        )
    if marks:
        r_mark = 5.0 * mm_per_px
        a(f'<g class="markers" fill="{MARKER_COLOUR}" stroke="{MARKER_COLOUR}">')
        for (u, v), label, _ in marks:
            a(
                f'<circle cx="{_n(u)}" cy="{_n(-v)}" r="{_n(r_mark)}" fill-opacity="0.5">'
                f"<title>{escape(label)}</title></circle>"
            )
        a("</g>")
    a("</svg>")

    # labels in px on top of the drawing: never clipped by it, kept inside the picture
    a('<g class="labels" font-size="11" stroke="#ffffff" stroke-width="3" paint-order="stroke">')
    if start is not None:
        x, y = to_px(su, sv)
        a(f'<text x="{_n(x + 9)}" y="{_n(y - 7)}" fill="{START_COLOUR}">start</text>')
    placed: list[tuple[float, float, float]] = []
    for (u, v), label, _ in marks:
        x, y = to_px(u, v)
        text = _fit(label, width - 2 * _PAD_PX, 6.2)
        w = 6.2 * len(text)
        tx, anchor = x + 8, "start"
        if tx + w > width - _PAD_PX:
            tx, anchor = max(x - 8, _PAD_PX + w), "end"
        ty = y - 8
        left = tx if anchor == "start" else tx - w
        while any(abs(ty - py) < 13 and left < px1 and left + w > px0 for px0, px1, py in placed):
            ty -= 13
        ty = max(_TITLE_PX + 11, ty)
        placed.append((left, left + w, ty))
        a(f'<text x="{_n(tx)}" y="{_n(ty)}" text-anchor="{anchor}" fill="{MARKER_COLOUR}">{escape(text)}</text>')
    a("</g>")

    # legend, in px below the drawing and its axis
    y0 = _TITLE_PX + draw_h + _AXIS_BOTTOM_PX + _PAD_PX
    a(f'<g class="legend" transform="translate({_n(_PAD_PX)} {_n(y0)})">')
    for k, (label, colour, style) in enumerate(legend):
        yl = _n(k * _LEGEND_LINE_PX + 8)
        if style == "circle":
            a(f'<circle cx="14" cy="{yl}" r="6" fill="none" stroke="{colour}" stroke-opacity="0.4"/>')
        elif style == "marker":
            a(f'<circle cx="14" cy="{yl}" r="5" fill="{colour}" fill-opacity="0.5" stroke="{colour}"/>')
        elif style == "arrow":
            yc = k * _LEGEND_LINE_PX + 8
            a(f'<polygon points="2,{_n(yc - 5)} 12,{_n(yc)} 2,{_n(yc + 5)}" fill="{colour}"/>')
            a(f'<polygon points="18,{_n(yc - 4)} 27,{_n(yc)} 18,{_n(yc + 4)}" fill="#333333"/>')
        elif style == "omitted":
            a(f'<line x1="0" y1="{yl}" x2="28" y2="{yl}" stroke="{colour}" stroke-width="4" stroke-opacity="0.55" '
              'stroke-dasharray="6 4"/>')
        else:
            dash = f' stroke-dasharray="{style}"' if style else ""
            a(f'<line x1="0" y1="{yl}" x2="28" y2="{yl}" stroke="{colour}" stroke-width="2"{dash}/>')
        a(f'<text x="36" y="{_n(k * _LEGEND_LINE_PX + 12)}">{escape(label)}</text>')
    for k, note in enumerate(notes):
        y_note = (len(legend) + k) * _LEGEND_LINE_PX + 12
        colour = "#444444" if k == 0 else MARKER_COLOUR
        a(f'<text x="0" y="{_n(y_note)}" fill="{colour}">{escape(note)}<title>{escape(note)}</title></text>')
    a("</g>")
    a("</svg>")
    return "\n".join(out) + "\n"


def _axes(
    proj: _Projector,
    box: tuple[float, float, float, float],
    px_per_mm: float,
    to_px: Callable[[float, float], tuple[float, float]],
    draw_h: float,
) -> list[str]:
    """Frame, grid, ticks in mm and axis names around the drawing, and a scale bar (px)."""
    vb_x, vb_y, vb_w, vb_h = box
    step = nice_step(80.0 / px_per_mm)
    (x0, y1), (x1, y0) = to_px(vb_x, -vb_y), to_px(vb_x + vb_w, -(vb_y + vb_h))
    bottom = _TITLE_PX + draw_h
    names = proj.plane.axis_names
    out = ['<g class="axes" font-size="10.5" fill="#444444">']
    out.append(
        f'<rect x="{_n(x0)}" y="{_n(y1)}" width="{_n(x1 - x0)}" height="{_n(y0 - y1)}" fill="none" stroke="#999999"/>'
    )
    u = math.ceil(vb_x / step) * step
    while u <= vb_x + vb_w + 1e-9:
        x, _ = to_px(u, 0.0)
        out.append(f'<line x1="{_n(x)}" y1="{_n(y1)}" x2="{_n(x)}" y2="{_n(y0)}" stroke="#eeeeee"/>')
        out.append(f'<line x1="{_n(x)}" y1="{_n(y0)}" x2="{_n(x)}" y2="{_n(y0 + 4)}" stroke="#999999"/>')
        out.append(f'<text x="{_n(x)}" y="{_n(y0 + 15)}" text-anchor="middle">{tick_label(u, step)}</text>')
        u += step
    v = math.ceil(-(vb_y + vb_h) / step) * step
    while v <= -vb_y + 1e-9:
        _, y = to_px(0.0, v)
        out.append(f'<line x1="{_n(x0)}" y1="{_n(y)}" x2="{_n(x1)}" y2="{_n(y)}" stroke="#eeeeee"/>')
        out.append(f'<line x1="{_n(x0 - 4)}" y1="{_n(y)}" x2="{_n(x0)}" y2="{_n(y)}" stroke="#999999"/>')
        out.append(f'<text x="{_n(x0 - 6)}" y="{_n(y + 3.5)}" text-anchor="end">{tick_label(v, step)}</text>')
        v += step
    out.append(
        f'<text class="axis-name" x="{_n(x1)}" y="{_n(bottom + 28)}" text-anchor="end" font-weight="bold">'
        f"{names[0]} [mm]</text>"
    )
    out.append(
        f'<text class="axis-name" x="{_n(_PAD_PX)}" y="{_n(_TITLE_PX + 10)}" font-weight="bold">{names[1]} [mm]</text>'
    )
    bar = step * px_per_mm
    bx, by = x1 - 10 - bar, y0 - 10
    out.append(
        f'<path class="scale-bar" d="M {_n(bx)} {_n(by - 4)} v 4 h {_n(bar)} v -4" fill="none" stroke="#222222" '
        'stroke-width="1.5"/>'
    )
    out.append(
        f'<text class="scale-bar" x="{_n(bx + bar / 2)}" y="{_n(by - 7)}" text-anchor="middle">'
        f"{tick_label(step, step)} mm</text>"
    )
    out.append("</g>")
    return out
